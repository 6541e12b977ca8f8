//! Study files (TOML): which parameters are fixed and which are drawn, how (distribution and
//! design), the seed, the variants and the default sample count. Parsed into plain data and
//! checked completely before any work starts; every error names the key and the accepted values.

use std::path::Path;

use crate::classify::WheelBudget;
use crate::model::Variant;
use crate::operating_points::OperatingPoints;
use crate::params::{ParamError, ParamId, ParamSpec, Params};
use crate::sampling::design::{
    grid_digits, Coordinates, Design, SALTELLI_MAX_AXES, SOBOL_MAX_AXES, SOBOL_MAX_SAMPLES,
};
use crate::sampling::distribution::Distribution;
use crate::toml_input::{self, Section, TomlError};

mod points;
use points::parse_operating_points;

/// Largest accepted seed (in study files and on the command line).
pub const SEED_MAX: u64 = u32::MAX as u64 * 1024;

/// The built-in default study: a highway fleet with moderate tire-structure uncertainty.
pub const DEFAULT_STUDY: &str = include_str!("../studies/default.toml");

/// One drawn parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawnParam {
    /// The parameter.
    pub param: ParamId,
    /// How it is drawn.
    pub dist: Distribution,
}

/// A parsed and checked study.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// The study's name (letters, digits, `_`, `-`): it names the default output directory.
    pub name: String,
    /// What the study is, in a sentence.
    pub description: String,
    /// Default seed when `--seed` is not given.
    pub seed: u64,
    /// Default sample count when `--samples` is not given (for a grid: its size).
    pub samples: u64,
    /// The sampling design.
    pub design: Design,
    /// The friction variants every sample is evaluated under.
    pub variants: Vec<Variant>,
    /// Samples per output file and resume unit.
    pub chunk_size: u64,
    /// Defaults with the study's fixed values applied.
    pub base: Params,
    /// The drawn parameters, in column order.
    pub drawn: Vec<DrawnParam>,
    /// The file's text, stored in every output's metadata.
    pub source: String,
    /// Work limits per wheel (`max_rhs_evals`, `max_wheel_seconds`; defaults when absent).
    pub budget: WheelBudget,
    /// Measured operating points (`[operating_points]`): each sample draws one row.
    pub operating_points: Option<OperatingPoints>,
}

/// A study problem, with the key it concerns.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StudyError {
    /// A per-wheel budget key out of its accepted range (the message names the key).
    #[error("{0}")]
    Budget(String),
    /// Syntax, unknown or missing keys, values of the wrong type.
    #[error(transparent)]
    Input(#[from] TomlError),
    /// A value refused by its parameter's accepted range, or an unknown parameter name.
    #[error("`{key}`: {source}")]
    Param {
        /// The key, in full.
        key: String,
        /// Why it was refused.
        source: ParamError,
    },
    /// The parameters of a parameter file do not fit together.
    #[error("{0}")]
    Inconsistent(ParamError),
    /// The study's fixed parameters do not fit together.
    #[error("fixed parameters: {0}")]
    FixedParams(ParamError),
    /// A `name` that cannot name a directory.
    #[error("`name` = \"{0}\" must be non-empty letters, digits, `_` or `-`")]
    BadName(String),
    /// A design that does not exist.
    #[error("`design` = \"{0}\" is unknown;{hint} accepted: random, lhs, sobol, grid, saltelli", hint = did_you_mean(.0, ["random", "lhs", "sobol", "grid", "saltelli"]))]
    UnknownDesign(String),
    /// A variant listed twice.
    #[error("`variants` lists \"{0}\" twice")]
    RepeatedVariant(String),
    /// A list or text that must not be empty.
    #[error("`{0}` must not be empty")]
    Empty(String),
    /// A parameter that is neither a number nor a distribution table.
    #[error("`{key}` must be a number (fixed) or a table with `dist`")]
    NotAParameter {
        /// The key, in full.
        key: String,
    },
    /// A distribution table without `dist`.
    #[error("`{key}` needs `dist` (one of {DISTS})")]
    NoDist {
        /// The key, in full.
        key: String,
    },
    /// A distribution that does not exist.
    #[error("`{key}.dist` = \"{dist}\" is unknown;{hint} accepted: {DISTS}, fixed", hint = did_you_mean(dist, DISTS.split(", ").chain(["fixed"])))]
    UnknownDist {
        /// The key, in full.
        key: String,
        /// The name given.
        dist: String,
    },
    /// A key the distribution does not take.
    #[error("`{key}.{field}` is not a key of a {dist} distribution;{hint} accepted: {accepted}", hint = did_you_mean(field, accepted.split(", ")))]
    NotADistKey {
        /// The parameter's key.
        key: String,
        /// The key it does not take.
        field: String,
        /// The distribution.
        dist: String,
        /// The keys it takes.
        accepted: String,
    },
    /// A distribution missing one of its keys.
    #[error("`{key}` ({dist}) needs `{field}`")]
    DistNeeds {
        /// The parameter's key.
        key: String,
        /// The distribution.
        dist: String,
        /// The missing key.
        field: String,
    },
    /// A spread (sd, sigma) that is not positive.
    #[error("`{key}` = {value} must be positive")]
    NotPositive {
        /// The key, in full.
        key: String,
        /// The value given.
        value: f64,
    },
    /// Bounds with min not below max.
    #[error("`{key}`: min = {min} must be below max = {max}")]
    Unordered {
        /// The parameter's key.
        key: String,
        /// The lower bound given.
        min: f64,
        /// The upper bound given.
        max: f64,
    },
    /// A distribution can produce values outside its parameter's accepted range.
    #[error("`{key}`: its {which} value is outside the accepted range ({source}){hint}")]
    TailOutOfRange {
        /// The parameter's key.
        key: String,
        /// Which end: `smallest` or `largest`.
        which: &'static str,
        /// The range check that failed.
        source: ParamError,
        /// How to fix it (e.g. use a truncated normal), or empty.
        hint: &'static str,
    },
    /// A grid design with a parameter that has no grid values.
    #[error("`{0}`: a grid design needs `levels` or a uniform `count` on every drawn parameter")]
    GridNeedsLevels(String),
    /// A grid of more than 2^40 points.
    #[error("`params`: the grid has more than 2^40 points")]
    GridTooLarge,
    /// `samples` that differs from the grid's size.
    #[error("`samples` = {samples} disagrees with the grid's size {size}")]
    GridSamples {
        /// The sample count given.
        samples: u64,
        /// The grid's size.
        size: u64,
    },
    /// More drawn parameters than the design supports.
    #[error(
        "`design` = \"{design}\" supports at most {max} drawn parameters, this study draws {drawn}"
    )]
    TooManyAxes {
        /// The design.
        design: &'static str,
        /// Its limit.
        max: usize,
        /// Parameters the study draws.
        drawn: usize,
    },
    /// A study that draws nothing.
    #[error("the study draws no parameter: give at least one a `dist` in [params]")]
    NothingDrawn,
    /// A problem with `[operating_points]` or its file (the message names file, row, column).
    #[error("[operating_points]: {0}")]
    OperatingPoints(String),
    /// A sample count of 0.
    #[error("--samples must be at least 1")]
    NoSamples,
    /// `--samples` that differs from the grid's size.
    #[error("--samples = {samples} disagrees with the grid's size {size}")]
    FlagGridSamples {
        /// The sample count given.
        samples: u64,
        /// The grid's size.
        size: u64,
    },
    /// More samples than the design can address.
    #[error("--samples: a {design} design supports at most {max} samples")]
    TooManySamples {
        /// The design.
        design: &'static str,
        /// Its limit, as people read it.
        max: &'static str,
    },
}

const TOP_KEYS: &[&str] = &[
    "name",
    "description",
    "seed",
    "samples",
    "design",
    "variants",
    "chunk_size",
    "max_rhs_evals",
    "max_wheel_seconds",
    "params",
    "operating_points",
];
use crate::wording::did_you_mean;

const DISTS: &str = "uniform, normal, truncated_normal, lognormal, levels";

/// One `[params]` entry: a fixed value or a distribution.
enum ParamEntry {
    Fixed(f64),
    Drawn(Distribution),
}

/// Parses one `[params]` entry: a number (fixed) or an inline table with `dist`.
fn parse_param(name: &str, v: &toml::Value) -> Result<ParamEntry, StudyError> {
    let key = format!("params.{name}");
    if let Ok(x) = toml_input::number(v, &key) {
        return Ok(ParamEntry::Fixed(x));
    }
    let t = Section::of(v, &key, "a table")
        .map_err(|_| StudyError::NotAParameter { key: key.clone() })?;
    let dist = t
        .opt("dist", toml_input::text)?
        .ok_or_else(|| StudyError::NoDist { key: key.clone() })?;
    let allowed: &[&str] = match dist {
        "uniform" => &["dist", "min", "max", "count"],
        "normal" => &["dist", "mean", "sd"],
        "truncated_normal" => &["dist", "mean", "sd", "min", "max"],
        "lognormal" => &["dist", "median", "sigma"],
        "levels" => &["dist", "levels"],
        "fixed" => &["dist", "value"],
        other => {
            return Err(StudyError::UnknownDist {
                key: key.clone(),
                dist: other.to_string(),
            })
        }
    };
    if let Some(k) = t.table.keys().find(|k| !allowed.contains(&k.as_str())) {
        return Err(StudyError::NotADistKey {
            key: key.clone(),
            field: k.clone(),
            dist: dist.to_string(),
            accepted: allowed.join(", "),
        });
    }
    let get = |k: &str| -> Result<f64, StudyError> {
        let v = t.get(k).ok_or_else(|| StudyError::DistNeeds {
            key: key.clone(),
            dist: dist.to_string(),
            field: k.to_string(),
        })?;
        Ok(toml_input::finite(v, &t.key(k))?)
    };
    let positive = |k: &str| -> Result<f64, StudyError> {
        let value = get(k)?;
        if value <= 0.0 {
            return Err(StudyError::NotPositive {
                key: t.key(k),
                value,
            });
        }
        Ok(value)
    };
    let ordered = |min: f64, max: f64| -> Result<(), StudyError> {
        if min >= max {
            return Err(StudyError::Unordered {
                key: key.clone(),
                min,
                max,
            });
        }
        Ok(())
    };
    let d = match dist {
        "fixed" => return Ok(ParamEntry::Fixed(get("value")?)),
        "uniform" => {
            let (min, max) = (get("min")?, get("max")?);
            let count = t
                .opt("count", |v, k| toml_input::whole(v, k, 1, 1_000_000))?
                .map(|c| c as usize);
            if count != Some(1) {
                ordered(min, max)?;
            }
            Distribution::Uniform { min, max, count }
        }
        "normal" => Distribution::Normal {
            mean: get("mean")?,
            sd: positive("sd")?,
        },
        "truncated_normal" => {
            let (min, max) = (get("min")?, get("max")?);
            ordered(min, max)?;
            Distribution::TruncatedNormal {
                mean: get("mean")?,
                sd: positive("sd")?,
                min,
                max,
            }
        }
        "lognormal" => Distribution::LogNormal {
            median: positive("median")?,
            sigma: positive("sigma")?,
        },
        _ => {
            let levels = t.req("levels", |v, k| {
                toml_input::array(v, k, "an array of numbers")?
                    .iter()
                    .enumerate()
                    .map(|(i, l)| toml_input::finite(l, &format!("{k}[{i}]")))
                    .collect::<Result<Vec<f64>, _>>()
            })?;
            if levels.is_empty() {
                return Err(StudyError::Empty(t.key("levels")));
            }
            Distribution::Levels(levels)
        }
    };
    Ok(ParamEntry::Drawn(d))
}

/// Refuses a distribution that can produce a value outside parameter `s`'s accepted range: the
/// quantiles at the extreme coordinates (normal tails reach about ±8.1 sd), and every level.
fn check_support(s: &ParamSpec, d: &Distribution) -> Result<(), StudyError> {
    let key = format!("params.{}", s.name);
    // Levels are checked one by one, each named by its place in the list (counted from 0, as
    // every `levels[i]` in a message).
    if let Distribution::Levels(levels) = d {
        for (i, x) in levels.iter().enumerate() {
            s.check(*x).map_err(|source| StudyError::Param {
                key: format!("{key}.levels[{i}]"),
                source,
            })?;
        }
        return Ok(());
    }
    let (lo, hi) = (d.quantile(0.0), d.quantile(1.0 - f64::EPSILON));
    for (which, x) in [("smallest", lo), ("largest", hi)] {
        if let Err(source) = s.check(x) {
            let hint = match d {
                Distribution::Normal { .. } => {
                    "; normal tails reach mean ± 8.1 sd: use truncated_normal"
                }
                Distribution::LogNormal { .. } => {
                    "; lognormal tails reach median·exp(±8.1 sigma): use truncated_normal"
                }
                _ => "",
            };
            return Err(StudyError::TailOutOfRange {
                key,
                which,
                source,
                hint,
            });
        }
    }
    Ok(())
}

/// Reads a parameter file (`--params FILE`, as `polywear calibrate` writes): a `[params]` table
/// of numbers, applied on top of `base` and checked.
pub fn apply_param_file(base: &Params, text: &str) -> Result<Params, StudyError> {
    let table = toml_input::parse(text)?;
    let top = Section::top(&table);
    top.deny_unknown_with(&["params"], "a parameter file holds only a [params] table")?;
    let mut p = *base;
    if let Some(v) = top.get("params") {
        let params = Section::of(v, "params", "a table")?;
        for (name, value) in params.table {
            let key = params.key(name);
            let x = toml_input::number(value, &key)?;
            let id: ParamId = name.parse().map_err(|source| StudyError::Param {
                key: key.clone(),
                source,
            })?;
            p.try_set(id, x)
                .map_err(|source| StudyError::Param { key, source })?;
        }
    }
    p.validate().map_err(StudyError::Inconsistent)?;
    Ok(p)
}

/// The study's settings other than its parameters.
struct Header {
    name: String,
    description: String,
    seed: u64,
    design: Design,
    variants: Vec<Variant>,
    chunk_size: u64,
    budget: WheelBudget,
}

impl Header {
    fn parse(top: &Section) -> Result<Header, StudyError> {
        let name = top
            .opt("name", toml_input::text)?
            .unwrap_or("study")
            .to_string();
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            return Err(StudyError::BadName(name));
        }
        let description = top
            .opt("description", toml_input::text)?
            .unwrap_or_default()
            .to_string();
        let seed = top
            .opt("seed", |v, k| toml_input::whole(v, k, 0, SEED_MAX))?
            .unwrap_or(1);
        let design = match top.opt("design", toml_input::text)? {
            Some(s) => Design::parse(s).ok_or_else(|| StudyError::UnknownDesign(s.to_string()))?,
            None => Design::Random,
        };
        let variants = match top.get("variants") {
            Some(v) => {
                let mut out = Vec::new();
                for (i, x) in toml_input::array(v, "variants", "an array of strings")?
                    .iter()
                    .enumerate()
                {
                    let var: Variant = toml_input::parsed(x, &format!("variants[{i}]"))?;
                    if out.contains(&var) {
                        return Err(StudyError::RepeatedVariant(var.to_string()));
                    }
                    out.push(var);
                }
                if out.is_empty() {
                    return Err(StudyError::Empty("variants".into()));
                }
                out
            }
            None => vec![Variant::DEFAULT],
        };
        let chunk_size = top
            .opt("chunk_size", |v, k| toml_input::whole(v, k, 1, 1 << 20))?
            .unwrap_or(4096);
        let mut budget = WheelBudget::default();
        let (lo, hi) = WheelBudget::RHS_EVALS_RANGE;
        if let Some(n) = top.opt("max_rhs_evals", |v, k| toml_input::whole(v, k, lo, hi))? {
            budget.max_rhs_evals = n;
        }
        if let Some(x) = top.opt("max_wheel_seconds", toml_input::number)? {
            budget.max_wheel_seconds = x;
        }
        budget
            .check()
            .map_err(|e| StudyError::Budget(e.to_string()))?;
        Ok(Header {
            name,
            description,
            seed,
            design,
            variants,
            chunk_size,
            budget,
        })
    }
}

/// Reads `[params]`: fixed values applied to `base`, drawn ones in canonical order (as in
/// `polywear params`, independent of the file's key order).
fn parse_params(top: &Section, mut base: Params) -> Result<(Params, Vec<DrawnParam>), StudyError> {
    let mut drawn = Vec::new();
    if let Some(v) = top.get("params") {
        let params = Section::of(v, "params", "a table")?;
        for (name, v) in params.table {
            let key = params.key(name);
            let param: ParamId = name.parse().map_err(|source| StudyError::Param {
                key: key.clone(),
                source,
            })?;
            match parse_param(name, v)? {
                ParamEntry::Fixed(x) => base
                    .try_set(param, x)
                    .map_err(|source| StudyError::Param { key, source })?,
                ParamEntry::Drawn(dist) => {
                    check_support(param.spec(), &dist)?;
                    drawn.push(DrawnParam { param, dist });
                }
            }
        }
    }
    drawn.sort_by_key(|d| d.param);
    base.validate().map_err(StudyError::FixedParams)?;
    Ok((base, drawn))
}

/// The default sample count: `samples`, or the grid's size (which `samples` must then equal).
fn sample_count(top: &Section, design: Design, drawn: &[DrawnParam]) -> Result<u64, StudyError> {
    let given = top.opt("samples", |v, k| toml_input::whole(v, k, 1, 1u64 << 40))?;
    Ok(match design {
        Design::Grid => {
            let mut size: u64 = 1;
            for d in drawn {
                let n = d
                    .dist
                    .grid_values()
                    .ok_or_else(|| StudyError::GridNeedsLevels(format!("params.{}", d.param)))?;
                size = size
                    .checked_mul(n.len() as u64)
                    .filter(|s| *s <= 1u64 << 40)
                    .ok_or(StudyError::GridTooLarge)?;
            }
            if let Some(samples) = given.filter(|s| *s != size) {
                return Err(StudyError::GridSamples { samples, size });
            }
            size
        }
        Design::Saltelli => given.unwrap_or(1024),
        _ => given.unwrap_or(10_000),
    })
}

impl DrawnParam {
    /// The distribution as JSON, in the study file's own terms, e.g.
    /// `{"name":"speed_kmh","dist":"uniform","min":60.0,"max":200.0}`.
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::json;
        let mut v = match &self.dist {
            Distribution::Uniform { min, max, count } => {
                let mut v = json!({"dist": "uniform", "min": min, "max": max});
                if let Some(c) = count {
                    v["count"] = json!(c);
                }
                v
            }
            Distribution::Normal { mean, sd } => json!({"dist": "normal", "mean": mean, "sd": sd}),
            Distribution::TruncatedNormal { mean, sd, min, max } => json!({
                "dist": "truncated_normal", "mean": mean, "sd": sd, "min": min, "max": max
            }),
            Distribution::LogNormal { median, sigma } => {
                json!({"dist": "lognormal", "median": median, "sigma": sigma})
            }
            Distribution::Levels(levels) => json!({"dist": "levels", "levels": levels}),
        };
        v["name"] = json!(self.param.name());
        v
    }
}

impl Study {
    /// The drawn parameters as a JSON array (the `drawn` metadata of every chunk).
    pub fn drawn_json(&self) -> serde_json::Value {
        serde_json::Value::Array(self.drawn.iter().map(DrawnParam::to_json).collect())
    }

    /// A stable fingerprint of the study text (64-bit FNV-1a, hex), written into every chunk's
    /// metadata as `study_hash` so that files of different studies are told apart cheaply.
    pub fn source_hash(&self) -> String {
        text_hash(&self.source)
    }

    /// Parses and checks a study file's text.
    pub fn parse(source: &str) -> Result<Study, StudyError> {
        Self::parse_with_base(source, Params::default())
    }

    /// Parses a study whose unnamed parameters take their values from `base` (defaults, or a
    /// `--params` file) instead of the built-in defaults.
    pub fn parse_with_base(source: &str, base: Params) -> Result<Study, StudyError> {
        Self::parse_at(source, base, Path::new(""))
    }

    /// [`Study::parse_with_base`] for a study file in folder `dir`: the relative path of an
    /// `[operating_points]` file is resolved against it, and the file is read and checked.
    pub fn parse_at(source: &str, base: Params, dir: &Path) -> Result<Study, StudyError> {
        let table = toml_input::parse(source)?;
        let top = Section::top(&table);
        top.deny_unknown(TOP_KEYS)?;
        let header = Header::parse(&top)?;
        let (base, drawn) = parse_params(&top, base)?;
        let samples = sample_count(&top, header.design, &drawn)?;
        let max_axes = match header.design {
            Design::Sobol => SOBOL_MAX_AXES,
            Design::Saltelli => SALTELLI_MAX_AXES,
            _ => usize::MAX,
        };
        if drawn.len() > max_axes {
            return Err(StudyError::TooManyAxes {
                design: header.design.as_str(),
                max: max_axes,
                drawn: drawn.len(),
            });
        }
        let operating_points = parse_operating_points(&top, &base, &drawn, header.design, dir)?;
        if drawn.is_empty() && operating_points.is_none() {
            return Err(StudyError::NothingDrawn);
        }
        Ok(Study {
            name: header.name,
            description: header.description,
            seed: header.seed,
            samples,
            design: header.design,
            variants: header.variants,
            chunk_size: header.chunk_size,
            base,
            drawn,
            source: source.to_string(),
            budget: header.budget,
            operating_points,
        })
    }

    /// Checks a sample count for this study (`--samples`); grids accept only their size.
    pub fn check_samples(&self, samples: u64) -> Result<(), StudyError> {
        if samples == 0 {
            return Err(StudyError::NoSamples);
        }
        if self.design == Design::Grid && samples != self.samples {
            return Err(StudyError::FlagGridSamples {
                samples,
                size: self.samples,
            });
        }
        if matches!(self.design, Design::Sobol | Design::Saltelli) && samples > SOBOL_MAX_SAMPLES {
            return Err(StudyError::TooManySamples {
                design: self.design.as_str(),
                max: "2^32",
            });
        }
        Ok(())
    }

    /// Model evaluations (sample indices) for `samples`: the same number, except for a Saltelli
    /// design, where `samples` counts base points and each needs k + 2 evaluations.
    pub fn evaluations(&self, samples: u64) -> u64 {
        match self.design {
            Design::Saltelli => samples * (self.drawn.len() as u64 + 2),
            _ => samples,
        }
    }

    /// The sampler for a run of `samples` points with `seed`.
    pub fn sampler(&self, seed: u64, samples: u64) -> Sampler<'_> {
        let grid = if self.design == Design::Grid {
            self.drawn
                .iter()
                .map(|d| d.dist.grid_values().unwrap_or_default())
                .collect()
        } else {
            Vec::new()
        };
        Sampler {
            study: self,
            coords: Coordinates::new(self.design, seed, samples, self.drawn.len()),
            grid,
            streams: crate::sampling::Streams::new(seed),
        }
    }
}

/// Draws parameter sets: a pure function of (study, seed, samples, index).
pub struct Sampler<'a> {
    study: &'a Study,
    coords: Coordinates,
    grid: Vec<Vec<f64>>,
    streams: crate::sampling::Streams,
}

impl Sampler<'_> {
    /// Parameter set of sample `index`, and the drawn values in the study's `drawn` order
    /// (without the operating-point row: see [`Sampler::sample_with_row`]).
    pub fn sample(&self, index: u64) -> (Params, Vec<f64>) {
        let mut p = self.study.base;
        let values: Vec<f64> = if self.study.design == Design::Grid {
            let sizes: Vec<usize> = self.grid.iter().map(Vec::len).collect();
            grid_digits(index, &sizes)
                .iter()
                .zip(&self.grid)
                .map(|(k, levels)| levels[*k])
                .collect()
        } else {
            self.study
                .drawn
                .iter()
                .enumerate()
                .map(|(dim, d)| self.coords.value(index, dim, &d.dist))
                .collect()
        };
        for (d, v) in self.study.drawn.iter().zip(&values) {
            p[d.param] = *v;
        }
        (p, values)
    }
}

/// 64-bit FNV-1a of a text, as 16 hex digits: a fingerprint, not a cryptographic hash.
pub fn text_hash(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_study_parses() {
        let s = Study::parse(DEFAULT_STUDY).unwrap();
        assert_eq!(s.name, "highway_fleet");
        assert!(s.drawn.iter().any(|d| d.param == ParamId::SpeedKmh));
    }

    #[test]
    fn grid_covers_exactly_its_levels() {
        let s = Study::parse(
            r#"design = "grid"
               [params]
               speed_kmh = { dist = "uniform", min = 60, max = 180, count = 3 }
               toe_deg = { dist = "levels", levels = [0.1, 0.3] }"#,
        )
        .unwrap();
        assert_eq!(s.samples, 6);
        let sampler = s.sampler(s.seed, s.samples);
        let pts: Vec<(f64, f64)> = (0..6)
            .map(|i| sampler.sample(i).0)
            .map(|p| (p.speed_kmh, p.toe_deg))
            .collect();
        assert_eq!(
            pts,
            vec![
                (60.0, 0.1),
                (60.0, 0.3),
                (120.0, 0.1),
                (120.0, 0.3),
                (180.0, 0.1),
                (180.0, 0.3)
            ]
        );
    }
}
