//! An optimisation's inputs from plain values, before [`super::Problem::new`] checks them
//! together: the study (a file or the built-in one) with its base parameters and work limits,
//! the calibration band asked for, and a varied parameter's box as typed (`toe_deg=0.05..0.40`).
//! Here so that a script builds the problem `polywear optimize` builds, with the same refusals.

use std::path::{Path, PathBuf};

use polywear_core::classify::WheelBudget;
use polywear_core::params::{ParamError, ParamId};
use polywear_core::wording::plain;

use super::{ProblemBand, DEFAULT_BAND_SAMPLES};
use crate::calibration_band::CalibrationBand;
use crate::param_sources::{param_file, Refusal};
use crate::study::{Study, DEFAULT_STUDY};

/// The study every setting is evaluated on: the file at `path` (a relative
/// `[operating_points]` file found beside it), or the built-in highway-fleet study, on top of
/// the defaults with the parameter file `params` applied. Implausible values are refused unless
/// `accept_implausible` or the study accepts them; `budget` sets the work limits on the study's.
/// Returns the study and where it came from, quoted in refusals.
pub fn read_study<E: From<Refusal>>(
    path: Option<&Path>,
    params: Option<&Path>,
    accept_implausible: bool,
    budget: &dyn Fn(WheelBudget) -> Result<WheelBudget, E>,
) -> Result<(Study, String), E> {
    let (source, origin) = match path {
        Some(path) => (
            Refusal::read_text("study", path)?,
            path.display().to_string(),
        ),
        None => (DEFAULT_STUDY.to_string(), "built-in default study".into()),
    };
    let (base, _) = param_file(params, accept_implausible)?;
    let dir = path
        .and_then(|p| p.parent().map(PathBuf::from))
        .unwrap_or_default();
    let mut study = Study::parse_at(&source, base, &dir).map_err(|e| Refusal::study(&origin, e))?;
    if !(accept_implausible || study.accept_implausible) {
        study
            .check_plausible()
            .map_err(|e| Refusal::study(&origin, e))?;
    }
    study.budget = budget(study.budget)?;
    Ok((study, origin))
}

impl ProblemBand {
    /// The band `asked` names (`--calibration-band`: a file, `off`, or the shipped sets when
    /// absent; see [`CalibrationBand::asked`]), evaluated on `samples` of the run's samples
    /// ([`DEFAULT_BAND_SAMPLES`] when absent; MODEL.md#the-calibration-band). A sample count
    /// with the band off is refused: it would not be used.
    pub fn asked(asked: Option<&str>, samples: Option<u64>) -> Result<Option<Self>, Refusal> {
        match CalibrationBand::asked(asked)? {
            None if samples.is_some() => Err(Refusal::BandSamplesWithBandOff {
                samples: samples.unwrap_or_default(),
            }),
            band => Ok(band.map(|(sets, source)| ProblemBand {
                sets,
                source,
                given: asked.is_some(),
                samples: samples.unwrap_or(DEFAULT_BAND_SAMPLES),
            })),
        }
    }
}

/// A varied parameter and its box as typed, `NAME=LO..HI` (names as `polywear params` lists
/// them); the box's meaning is checked against the study by [`super::Problem::new`]. A refusal
/// starts with the text quoted, for the caller to prefix with its flag.
pub fn parse_vary(s: &str) -> Result<(ParamId, f64, f64), VaryTextError> {
    let text = || s.to_string();
    let (name, range) = s
        .split_once('=')
        .ok_or_else(|| VaryTextError::Form(text()))?;
    let id: ParamId = name.trim().parse().map_err(|source| VaryTextError::Name {
        text: text(),
        source,
    })?;
    let (lo, hi) = range
        .split_once("..")
        .ok_or_else(|| VaryTextError::Form(text()))?;
    let num = |x: &str| {
        x.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| VaryTextError::NotFinite {
                text: text(),
                value: x.trim().to_string(),
            })
    };
    let (lo, hi) = (num(lo)?, num(hi)?);
    if lo >= hi {
        return Err(VaryTextError::EmptyBox {
            text: text(),
            id,
            lo: lo.min(hi),
            hi: lo.max(hi),
        });
    }
    Ok((id, lo, hi))
}

/// The form a varied parameter is typed in.
const VARY_FORM: &str = "expected NAME=LO..HI, e.g. toe_deg=0.05..0.40";

/// A varied parameter as typed (`NAME=LO..HI`) refused; the message starts with the text
/// quoted, for the caller to prefix with its flag.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VaryTextError {
    /// Not of the form NAME=LO..HI.
    #[error("`{0}`: {VARY_FORM}")]
    Form(String),
    /// No parameter of that name.
    #[error("`{text}`: {source}")]
    Name {
        /// The text typed.
        text: String,
        /// Why the name is refused.
        source: ParamError,
    },
    /// A bound that is not a finite number.
    #[error("`{text}`: `{value}` is not a finite number; {VARY_FORM}")]
    NotFinite {
        /// The text typed.
        text: String,
        /// The bound.
        value: String,
    },
    /// LO not below HI.
    #[error("`{text}`: the box is empty; accepted: LO below HI, e.g. {id}={}..{}", plain(*lo, 6), plain(*hi, 6))]
    EmptyBox {
        /// The text typed.
        text: String,
        /// The parameter.
        id: ParamId,
        /// The lower of the two bounds.
        lo: f64,
        /// The higher.
        hi: f64,
    },
}
