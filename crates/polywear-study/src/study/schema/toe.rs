//! The toe-in in `[params]` given as an alignment sheet gives it (`toe_mm`, `toe_total_deg`):
//! read as the per-wheel angle `toe_deg` (MODEL.md#operating-point-and-wheels) before the
//! typed pass checks it.

use serde::de;
use serde::Deserialize;

use super::{check_support, distribution, DistSpec, ParamEntry};
use crate::study::{DrawnParam, StudyError};
use crate::toml_input::finite_at;
use polywear_core::params::toe::{ToeForm, ToeInput};
use polywear_core::params::{ParamId, Params};
use polywear_core::sampling::distribution::Distribution;

/// A key of a study's `[params]`: a parameter, or the toe-in given another way (`toe_mm`,
/// `toe_total_deg`), read as `toe_deg`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(in crate::study) enum ParamKey {
    /// A parameter by its name.
    Param(ParamId),
    /// The toe-in in mm at the rim or as total toe.
    Toe(ToeInput),
}

impl<'de> Deserialize<'de> for ParamKey {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<ParamKey, D::Error> {
        let name = <std::borrow::Cow<'de, str>>::deserialize(d)?;
        match ToeInput::parse(&name) {
            Some(t) => Ok(ParamKey::Toe(t)),
            None => name.parse().map(ParamKey::Param).map_err(de::Error::custom),
        }
    }
}

/// A toe-in given in `[params]` as `toe_mm` (at the study's fixed `rim_diameter_mm`) or
/// `toe_total_deg`, set or drawn as the per-wheel angle `toe_deg`: a number or levels convert
/// value by value; a total toe's distribution halves; a continuous distribution in mm is refused,
/// since the arc tangent does not keep its shape.
pub(super) fn toe_as_angle(
    input: ToeInput,
    entry: &ParamEntry,
    base: &mut Params,
    drawn: &mut Vec<DrawnParam>,
    fixed: &mut Vec<ParamId>,
) -> Result<(), StudyError> {
    let key = format!("params.{input}");
    let toe = input.target();
    if fixed.contains(&toe) || drawn.iter().any(|d| d.param == toe) {
        return Err(StudyError::DrawnRule(format!(
            "`{key}` and `params.{toe}` both give the toe-in; give one"
        )));
    }
    if drawn.iter().any(|d| d.param == ParamId::RimDiameterMm) && input.form == ToeForm::Mm {
        return Err(StudyError::DrawnRule(format!(
            "`{key}` is read at the rim diameter, which the study draws; fix `params.rim_diameter_mm` or give `params.{toe}`"
        )));
    }
    let rim = base.rim_diameter_mm;
    let as_angle = |x: f64| input.to_deg(x, rim);
    let value = match entry {
        ParamEntry::Fixed(x) => Some(finite_at(*x, &key)?),
        ParamEntry::Table(DistSpec::Fixed { value }) => {
            Some(finite_at(*value, &format!("{key}.value"))?)
        }
        ParamEntry::Table(_) => None,
    };
    if let Some(x) = value {
        base.try_set(toe, as_angle(x))
            .map_err(|source| StudyError::Param {
                key: format!("{key} = {}", input.words(x, rim)),
                source,
            })?;
        fixed.push(toe);
        return Ok(());
    }
    let ParamEntry::Table(spec) = entry else {
        unreachable!("a number is a fixed value")
    };
    let half = |x: f64| x / 2.0;
    let dist = match (input.form, distribution(spec, &key)?) {
        (_, Distribution::Levels(levels)) => {
            Distribution::Levels(levels.into_iter().map(as_angle).collect())
        }
        (ToeForm::Mm, _) => {
            return Err(StudyError::DrawnRule(format!(
                "`{key}`: only a number or `levels` convert from mm at the rim to degrees (a distribution in mm is not the same one in degrees); draw `params.{toe}` instead ({})",
                input.words(1.0, rim)
            )))
        }
        (ToeForm::TotalDeg, Distribution::Uniform { min, max, count }) => Distribution::Uniform {
            min: half(min),
            max: half(max),
            count,
        },
        (ToeForm::TotalDeg, Distribution::Normal { mean, sd }) => Distribution::Normal {
            mean: half(mean),
            sd: half(sd),
        },
        (ToeForm::TotalDeg, Distribution::TruncatedNormal { mean, sd, min, max }) => {
            Distribution::TruncatedNormal {
                mean: half(mean),
                sd: half(sd),
                min: half(min),
                max: half(max),
            }
        }
        (ToeForm::TotalDeg, Distribution::LogNormal { median, sigma }) => {
            Distribution::LogNormal {
                median: half(median),
                sigma,
            }
        }
    };
    check_support(toe.spec(), &dist)?;
    drawn.push(DrawnParam { param: toe, dist });
    Ok(())
}
