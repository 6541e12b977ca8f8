//! Study files (TOML): which parameters are fixed and which are drawn, how (distribution and
//! design), the seed, the variants and the default sample count. Parsed into plain data and
//! checked completely before any work starts; every error names the key and the accepted values.

use crate::model::Variant;
use crate::params::{spec, Params};
use crate::sampling::design::{grid_digits, Coordinates, Design, SOBOL_MAX_AXES};
use crate::sampling::distribution::Distribution;

/// The built-in default study: a highway fleet with moderate tire-structure uncertainty.
pub const DEFAULT_STUDY: &str = include_str!("../studies/default.toml");

/// One drawn parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawnParam {
    pub name: &'static str,
    pub dist: Distribution,
}

/// A parsed and checked study.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    pub name: String,
    pub description: String,
    pub seed: u64,
    /// Default sample count when `--samples` is not given (for a grid: its size).
    pub samples: u64,
    pub design: Design,
    pub variants: Vec<Variant>,
    /// Samples per output file and resume unit.
    pub chunk_size: u64,
    /// Defaults with the study's fixed values applied.
    pub base: Params,
    pub drawn: Vec<DrawnParam>,
    /// The file's text, stored in every output's metadata.
    pub source: String,
}

/// A study problem, with the key it concerns.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyError(pub String);

impl std::fmt::Display for StudyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for StudyError {}

fn err<T>(msg: impl Into<String>) -> Result<T, StudyError> {
    Err(StudyError(msg.into()))
}

const TOP_KEYS: &[&str] = &[
    "name",
    "description",
    "seed",
    "samples",
    "design",
    "variants",
    "chunk_size",
    "params",
];
const DISTS: &str = "uniform, normal, truncated_normal, lognormal, levels";

fn number(v: &toml::Value, key: &str) -> Result<f64, StudyError> {
    match v {
        toml::Value::Float(x) => Ok(*x),
        toml::Value::Integer(i) => Ok(*i as f64),
        _ => err(format!("`{key}` must be a number, got {}", v.type_str())),
    }
}

fn whole(v: &toml::Value, key: &str, lo: u64, hi: u64) -> Result<u64, StudyError> {
    let x = number(v, key)?;
    if x.fract() != 0.0 || x < lo as f64 || x > hi as f64 {
        return err(format!(
            "`{key}` = {x} must be a whole number in [{lo}, {hi}]"
        ));
    }
    Ok(x as u64)
}

fn text(v: &toml::Value, key: &str) -> Result<String, StudyError> {
    v.as_str()
        .map(String::from)
        .ok_or_else(|| StudyError(format!("`{key}` must be a string")))
}

/// Parses one `[params]` entry: a number (fixed) or an inline table with `dist`.
fn parse_param(
    name: &str,
    v: &toml::Value,
) -> Result<(Option<f64>, Option<Distribution>), StudyError> {
    let key = format!("params.{name}");
    if let Ok(x) = number(v, &key) {
        return Ok((Some(x), None));
    }
    let t = v.as_table().ok_or_else(|| {
        StudyError(format!(
            "`{key}` must be a number (fixed) or a table with `dist`"
        ))
    })?;
    let dist = t
        .get("dist")
        .ok_or_else(|| StudyError(format!("`{key}` needs `dist` (one of {DISTS})")))?;
    let dist = text(dist, &format!("{key}.dist"))?;
    let allowed: &[&str] = match dist.as_str() {
        "uniform" => &["dist", "min", "max", "count"],
        "normal" => &["dist", "mean", "sd"],
        "truncated_normal" => &["dist", "mean", "sd", "min", "max"],
        "lognormal" => &["dist", "median", "sigma"],
        "levels" => &["dist", "levels"],
        "fixed" => &["dist", "value"],
        other => {
            return err(format!(
                "`{key}.dist` = \"{other}\" is unknown; accepted: {DISTS}, fixed"
            ))
        }
    };
    for k in t.keys() {
        if !allowed.contains(&k.as_str()) {
            return err(format!(
                "`{key}.{k}` is not a key of a {dist} distribution; accepted: {}",
                allowed.join(", ")
            ));
        }
    }
    let get = |k: &str| -> Result<f64, StudyError> {
        let v = t
            .get(k)
            .ok_or_else(|| StudyError(format!("`{key}` ({dist}) needs `{k}`")))?;
        let x = number(v, &format!("{key}.{k}"))?;
        if !x.is_finite() {
            return err(format!("`{key}.{k}` must be finite"));
        }
        Ok(x)
    };
    let positive = |k: &str| -> Result<f64, StudyError> {
        let x = get(k)?;
        if x <= 0.0 {
            return err(format!("`{key}.{k}` = {x} must be positive"));
        }
        Ok(x)
    };
    let ordered = |lo: f64, hi: f64| -> Result<(), StudyError> {
        if lo >= hi {
            return err(format!("`{key}`: min = {lo} must be below max = {hi}"));
        }
        Ok(())
    };
    let d = match dist.as_str() {
        "fixed" => return Ok((Some(get("value")?), None)),
        "uniform" => {
            let (min, max) = (get("min")?, get("max")?);
            let count = match t.get("count") {
                Some(c) => Some(whole(c, &format!("{key}.count"), 1, 1_000_000)? as usize),
                None => None,
            };
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
            let levels = t
                .get("levels")
                .and_then(|l| l.as_array())
                .ok_or_else(|| StudyError(format!("`{key}.levels` must be an array of numbers")))?;
            let levels: Vec<f64> = levels
                .iter()
                .enumerate()
                .map(|(i, l)| number(l, &format!("{key}.levels[{i}]")))
                .collect::<Result<_, _>>()?;
            if levels.is_empty() {
                return err(format!("`{key}.levels` must not be empty"));
            }
            Distribution::Levels(levels)
        }
    };
    Ok((None, Some(d)))
}

/// Reads a parameter file (`--params FILE`, as `polywear calibrate` writes): a `[params]` table
/// of numbers, applied on top of `base` and checked.
pub fn apply_param_file(base: &Params, text: &str) -> Result<Params, StudyError> {
    let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        StudyError(format!("malformed TOML: {}", e.to_string().trim()))
    })?;
    let mut p = *base;
    for (k, v) in &table {
        if k != "params" {
            return err(format!(
                "unknown key `{k}`; a parameter file holds only a [params] table"
            ));
        }
        let t = v
            .as_table()
            .ok_or_else(|| StudyError("`params` must be a table".into()))?;
        for (name, value) in t {
            let x = number(value, &format!("params.{name}"))?;
            p.set(name, x)
                .map_err(|e| StudyError(format!("`params.{name}`: {e}")))?;
        }
    }
    p.validate().map_err(|e| StudyError(e.to_string()))?;
    Ok(p)
}

impl Study {
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
        let table: toml::Table = source.parse().map_err(|e: toml::de::Error| {
            StudyError(format!("malformed TOML: {}", e.to_string().trim()))
        })?;
        for k in table.keys() {
            if !TOP_KEYS.contains(&k.as_str()) {
                return err(format!(
                    "unknown key `{k}`; accepted: {}",
                    TOP_KEYS.join(", ")
                ));
            }
        }
        let name = table
            .get("name")
            .map(|v| text(v, "name"))
            .transpose()?
            .unwrap_or_else(|| "study".into());
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            return err(format!(
                "`name` = \"{name}\" must be non-empty letters, digits, `_` or `-`"
            ));
        }
        let description = table
            .get("description")
            .map(|v| text(v, "description"))
            .transpose()?
            .unwrap_or_default();
        let seed = match table.get("seed") {
            Some(v) => whole(v, "seed", 0, u32::MAX as u64 * 1024)?,
            None => 1,
        };
        let design = match table.get("design") {
            Some(v) => {
                let s = text(v, "design")?;
                Design::parse(&s).ok_or_else(|| {
                    StudyError(format!(
                        "`design` = \"{s}\" is unknown; accepted: random, lhs, sobol, grid, saltelli"
                    ))
                })?
            }
            None => Design::Random,
        };
        let variants = match table.get("variants") {
            Some(v) => {
                let arr = v
                    .as_array()
                    .ok_or_else(|| StudyError("`variants` must be an array of strings".into()))?;
                let mut out = Vec::new();
                for (i, x) in arr.iter().enumerate() {
                    let s = text(x, &format!("variants[{i}]"))?;
                    let var: Variant = s
                        .parse()
                        .map_err(|e| StudyError(format!("`variants[{i}]`: {e}")))?;
                    if out.contains(&var) {
                        return err(format!("`variants` lists \"{s}\" twice"));
                    }
                    out.push(var);
                }
                if out.is_empty() {
                    return err("`variants` must not be empty");
                }
                out
            }
            None => vec![Variant::Paper],
        };
        let chunk_size = match table.get("chunk_size") {
            Some(v) => whole(v, "chunk_size", 1, 1 << 20)?,
            None => 4096,
        };

        let mut base = base;
        let mut drawn = Vec::new();
        if let Some(p) = table.get("params") {
            let p = p
                .as_table()
                .ok_or_else(|| StudyError("`params` must be a table".into()))?;
            for (name, v) in p {
                let s = spec(name).ok_or_else(|| {
                    StudyError(format!(
                        "`params.{name}`: {}",
                        crate::params::ParamError::Unknown { name: name.clone() }
                    ))
                })?;
                match parse_param(name, v)? {
                    (Some(x), _) => base
                        .set(s.name, x)
                        .map_err(|e| StudyError(format!("`params.{name}`: {e}")))?,
                    (_, Some(d)) => {
                        // Every value the sampler can produce must be acceptable: the quantiles
                        // at the extreme coordinates (normal tails reach about ±8.1 sd).
                        let (lo, hi) = (d.quantile(0.0), d.quantile(1.0 - f64::EPSILON));
                        for (which, x) in [("smallest", lo), ("largest", hi)] {
                            if let Err(e) = s.check(x) {
                                let hint = if matches!(d, Distribution::Normal { .. }) {
                                    "; normal tails reach mean ± 8.1 sd: use truncated_normal"
                                } else if matches!(d, Distribution::LogNormal { .. }) {
                                    "; lognormal tails reach median·exp(±8.1 sigma): use truncated_normal"
                                } else {
                                    ""
                                };
                                return err(format!("`params.{name}`: its {which} value is outside the accepted range ({e}){hint}"));
                            }
                        }
                        drawn.push(DrawnParam {
                            name: s.name,
                            dist: d,
                        });
                    }
                    _ => unreachable!("parse_param returns one of the two"),
                }
            }
        }
        // Canonical order (as in `polywear params`), independent of the file's key order.
        drawn.sort_by_key(|d| crate::params::SPECS.iter().position(|s| s.name == d.name));
        base.validate()
            .map_err(|e| StudyError(format!("fixed parameters: {e}")))?;

        let samples = match design {
            Design::Grid => {
                let mut size: u64 = 1;
                for d in &drawn {
                    let n = d.dist.grid_values().ok_or_else(|| {
                        StudyError(format!(
                            "`params.{}`: a grid design needs `levels` or a uniform `count` on every drawn parameter",
                            d.name
                        ))
                    })?;
                    size = size
                        .checked_mul(n.len() as u64)
                        .filter(|s| *s <= 1u64 << 40)
                        .ok_or_else(|| StudyError("the grid has more than 2^40 points".into()))?;
                }
                if let Some(v) = table.get("samples") {
                    let s = whole(v, "samples", 1, 1u64 << 40)?;
                    if s != size {
                        return err(format!(
                            "`samples` = {s} disagrees with the grid's size {size}"
                        ));
                    }
                }
                size
            }
            _ => match table.get("samples") {
                Some(v) => whole(v, "samples", 1, 1u64 << 40)?,
                None if design == Design::Saltelli => 1024,
                None => 10_000,
            },
        };
        if design == Design::Sobol && drawn.len() > SOBOL_MAX_AXES {
            return err(format!("a sobol design supports at most {SOBOL_MAX_AXES} drawn parameters, this study draws {}", drawn.len()));
        }
        if drawn.is_empty() {
            return err("the study draws no parameter: give at least one a `dist` in [params]");
        }
        Ok(Study {
            name,
            description,
            seed,
            samples,
            design,
            variants,
            chunk_size,
            base,
            drawn,
            source: source.to_string(),
        })
    }

    /// Checks a sample count for this study (`--samples`); grids accept only their size.
    pub fn check_samples(&self, samples: u64) -> Result<(), StudyError> {
        if samples == 0 {
            return err("--samples must be at least 1");
        }
        if self.design == Design::Grid && samples != self.samples {
            return err(format!(
                "--samples = {samples} disagrees with the grid's size {}",
                self.samples
            ));
        }
        if matches!(self.design, Design::Sobol | Design::Saltelli) && samples > u32::MAX as u64 {
            return err("a sobol design supports at most 2^32 samples");
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
        }
    }
}

/// Draws parameter sets: a pure function of (study, seed, samples, index).
pub struct Sampler<'a> {
    study: &'a Study,
    coords: Coordinates,
    grid: Vec<Vec<f64>>,
}

impl Sampler<'_> {
    /// Parameter set of sample `index`, and the drawn values in the study's `drawn` order.
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
                .map(|(dim, d)| d.dist.quantile(self.coords.coordinate(index, dim)))
                .collect()
        };
        for (d, v) in self.study.drawn.iter().zip(&values) {
            *p.get_mut(d.name).expect("drawn names are parameter names") = *v;
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
        assert!(s.drawn.iter().any(|d| d.name == "speed_kmh"));
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
