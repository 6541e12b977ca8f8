//! Study files (TOML): which parameters are fixed and which are drawn, how (distribution and
//! design), the seed, the variants and the default sample count. Read into a derived schema
//! (`schema`), checked completely before any work starts in a typed pass whose every error names
//! the key and the accepted values (`error`), with the measured operating points of
//! `[operating_points]` (`points`); the `Sampler` (`sampler`) then draws the parameter sets.

use std::path::Path;

use crate::operating_points::OperatingPoints;
use crate::toml_input::{self, TomlError};
use polywear_core::classify::WheelBudget;
use polywear_core::model::Variant;
use polywear_core::params::{ParamId, Params};
use polywear_core::sampling::design::{
    Design, SALTELLI_MAX_AXES, SOBOL_MAX_AXES, SOBOL_MAX_SAMPLES,
};
use polywear_core::sampling::distribution::Distribution;
use polywear_core::wear::WearSettings;

mod change;
mod error;
mod plausible;
mod points;
mod sampler;
mod scenario;
mod scenario_rules;
mod schema;
pub use error::{ChangeOutOfRange, StudyError};
use points::operating_points;
pub use sampler::Sampler;
pub use scenario::{
    scenario_key, Change, ParamChange, Scenario, ValueRange, BASELINE, CHANGE_KINDS, COUNT_LIMIT,
};
pub use scenario_rules::BrokenRule;
use schema::ParamFile;

/// Largest accepted seed (in study files and on the command line).
pub const SEED_MAX: u64 = u32::MAX as u64 * 1024;

/// The built-in default study: a highway fleet with moderate tire-structure uncertainty.
pub const DEFAULT_STUDY: &str = include_str!("../../../studies/default.toml");

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
    /// The parameters the study fixes in `[params]`, in column order.
    pub fixed: Vec<ParamId>,
    /// The drawn parameters, in column order.
    pub drawn: Vec<DrawnParam>,
    /// The file's text, stored in every output's metadata.
    pub source: String,
    /// Work limits per wheel (`max_rhs_evals`, `max_wheel_seconds`; defaults when absent).
    pub budget: WheelBudget,
    /// Measured operating points (`[operating_points]`): each sample draws one row.
    pub operating_points: Option<OperatingPoints>,
    /// `accept_implausible = true`: values outside their plausible ranges are meant
    /// ([`Study::check_plausible`] passes).
    pub accept_implausible: bool,
    /// What-if scenarios (`[scenarios.NAME]`), in name order: each is evaluated on every
    /// sample beside the baseline.
    pub scenarios: Vec<Scenario>,
    /// The wear stage's settings (`wear_zone`), or `None` for `wear = false`: the rows then
    /// carry no wear columns (MODEL.md#the-per-sample-estimator).
    pub wear: Option<WearSettings>,
}

/// Reads a parameter file (`--params FILE`, as `polywear calibrate` writes): a `[params]` table
/// of numbers, applied on top of `base` and checked.
pub fn apply_param_file(base: &Params, text: &str) -> Result<Params, StudyError> {
    read_param_file(base, text).map(|(p, _)| p)
}

/// [`apply_param_file`], with the parameters the file names (in column order), so that a
/// command can refuse a parameter the file and another source both set.
pub fn read_param_file(base: &Params, text: &str) -> Result<(Params, Vec<ParamId>), StudyError> {
    read_param_file_keys(base, text)
        .map(|(p, keys)| (p, keys.into_iter().map(|(id, _)| id).collect()))
}

/// [`read_param_file`], with each parameter's key as typed: `params.g_mod`, or `params.toe_mm =
/// 20 mm at the 381 mm rim (rim_diameter_mm) = 3.005 deg per wheel` for a toe-in given another
/// way, so that a later refusal quotes what the user wrote.
pub(crate) fn read_param_file_keys(
    base: &Params,
    text: &str,
) -> Result<(Params, Vec<(ParamId, String)>), StudyError> {
    let file: ParamFile = toml_input::from_str(text).map_err(|e| match e {
        TomlError::UnknownKey { key, .. } if !key.contains('.') => TomlError::UnknownKey {
            key,
            accepted: "a parameter file holds only a [params] table".into(),
        },
        e => e,
    })?;
    let mut p = *base;
    let mut named = Vec::new();
    for (&key, &x) in file.params.iter().flatten() {
        let (id, value, key) = match key {
            schema::ParamKey::Param(id) => (id, x, format!("params.{id}")),
            // As an alignment sheet gives it, at the file's rim (set before: keys sort so).
            schema::ParamKey::Toe(input) => {
                let toe = input.target();
                if named.iter().any(|(id, _)| *id == toe) {
                    return Err(StudyError::DrawnRule(format!(
                        "`params.{input}` and `params.{toe}` both give the toe-in; give one"
                    )));
                }
                let rim = p.rim_diameter_mm;
                let key = format!("params.{input} = {}", input.words(x, rim));
                (toe, input.to_deg(x, rim), key)
            }
        };
        p.try_set(id, value).map_err(|source| StudyError::Param {
            key: key.clone(),
            source,
        })?;
        named.push((id, key));
    }
    let given: Vec<ParamId> = named.iter().map(|(id, _)| *id).collect();
    polywear_core::params::axle::check_one_place(&given, "the parameter file")
        .map_err(StudyError::Inconsistent)?;
    p.validate().map_err(StudyError::Inconsistent)?;
    Ok((p, named))
}

/// The default sample count: `samples`, or the grid's size (which `samples` must then equal).
fn sample_count(
    samples: Option<f64>,
    design: Design,
    drawn: &[DrawnParam],
) -> Result<u64, StudyError> {
    let given = samples
        .map(|x| toml_input::whole_at(x, "samples", 1, 1u64 << 40))
        .transpose()?;
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
    /// How the study sets parameter `id`, for messages: "fixes it (`params.toe_deg`)", "draws
    /// it (`params.toe_deg`)" or "gives it per row (column `toe_deg` of its operating-point file
    /// fleet.csv)"; None where it does not.
    pub fn sets(&self, id: ParamId) -> Option<String> {
        if self.fixed.contains(&id) {
            return Some(format!("fixes it (`params.{id}`)"));
        }
        if self.drawn.iter().any(|d| d.param == id) {
            return Some(format!("draws it (`params.{id}`)"));
        }
        let op = self.operating_points.as_ref()?;
        op.names.contains(&id.name()).then(|| {
            format!(
                "gives it per row (column `{id}` of its operating-point file {})",
                op.file
            )
        })
    }

    /// The drawn parameters as a JSON array (the `drawn` metadata of every chunk).
    pub fn drawn_json(&self) -> serde_json::Value {
        serde_json::Value::Array(self.drawn.iter().map(DrawnParam::to_json).collect())
    }

    /// The value the study file gives the top-level `key`, as written (a string without its
    /// quotes), or None where it gives none: what a flag that overrides it names in its note.
    pub fn key_text(&self, key: &str) -> Option<String> {
        let table = toml_input::parse(&self.source).ok()?;
        table.get(key).map(|v| match v {
            toml::Value::String(s) => s.clone(),
            toml::Value::Integer(i) => i.to_string(),
            toml::Value::Float(x) => polywear_core::wording::plain(*x, 12),
            toml::Value::Boolean(b) => b.to_string(),
            v => format!("{v:?}"),
        })
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
        let raw = toml::Value::Table(toml_input::parse(source).map_err(repeated_scenario)?);
        let file = schema::read_study(&raw)?;
        let header = file.header()?;
        let (base, drawn, fixed) = file.params(base)?;
        let scenarios = match &file.scenarios {
            Some(tables) => scenario::scenarios(tables, &base, &drawn)?,
            None => Vec::new(),
        };
        let samples = sample_count(file.samples, header.design, &drawn)?;
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
        let operating_points = match &file.operating_points {
            Some(section) => Some(operating_points(
                section,
                &base,
                &drawn,
                &fixed,
                header.design,
                dir,
            )?),
            None => None,
        };
        if drawn.is_empty() && operating_points.is_none() {
            return Err(StudyError::NothingDrawn);
        }
        let study = Study {
            name: header.name,
            description: header.description,
            seed: header.seed,
            samples,
            design: header.design,
            variants: header.variants,
            chunk_size: header.chunk_size,
            base,
            fixed,
            drawn,
            source: source.to_string(),
            budget: header.budget,
            operating_points,
            accept_implausible: header.accept_implausible,
            scenarios,
            wear: header.wear,
        };
        // [params] and the operating-point file together give each quantity in one place.
        let given: Vec<ParamId> = ParamId::ALL
            .iter()
            .copied()
            .filter(|&id| study.sets(id).is_some())
            .collect();
        let place = "the study ([params] and its operating-point file together)";
        polywear_core::params::axle::check_one_place(&given, place)
            .map_err(StudyError::Inconsistent)?;
        Ok(study)
    }

    /// Checks a sample count for a run of this study; grids accept only their size. The error
    /// does not name the flag: the command line says which of its flags gave the count.
    pub fn check_samples(&self, samples: u64) -> Result<(), StudyError> {
        if samples == 0 {
            return Err(StudyError::NoSamples);
        }
        if self.design == Design::Grid && samples != self.samples {
            return Err(StudyError::SamplesNotGridSize {
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
}

/// A TOML table defined twice under `[scenarios]` is a scenario name used twice: said so, with
/// the parser's line.
fn repeated_scenario(e: TomlError) -> StudyError {
    let TomlError::Malformed(text) = &e else {
        return e.into();
    };
    let Some(name) = text
        .split_once("duplicate key `")
        .filter(|_| text.contains("in table `scenarios`"))
        .and_then(|(_, rest)| rest.split_once('`'))
        .map(|(name, _)| name.trim_matches('"').to_string())
    else {
        return e.into();
    };
    let line = text
        .split_once("at line ")
        .map(|(_, r)| r.split(',').next().unwrap_or(r).to_string())
        .map(|l| format!(" (again at line {l})"))
        .unwrap_or_default();
    StudyError::RepeatedScenario {
        name,
        why: format!("the study file defines `[scenarios.…]` with this name twice{line}"),
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
    fn a_grid_axis_of_one_level_samples_the_middle_its_levels_name() {
        let s = Study::parse(
            r#"design = "grid"
               [params]
               toe_deg = { dist = "uniform", min = 0.2, max = 0.4, count = 1 }"#,
        )
        .unwrap();
        assert_eq!(s.samples, 1);
        // One source: the sampler's value is the level the analysis labels it with.
        let levels = s.drawn[0].dist.grid_values().unwrap();
        assert_eq!(levels.len(), 1);
        assert!((levels[0] - 0.3).abs() < 1e-15, "{levels:?}");
        let sampler = s.sampler(s.seed, s.samples);
        assert_eq!(sampler.sample(0).0.toe_deg, levels[0]);
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
