//! The calibration band (MODEL.md#the-calibration-band): the sets of the calibrated constants
//! the field facts allow, and every wear answer re-evaluated under each of them on the same
//! samples.
//!
//! One file per job: this one holds the band's types; [`mod@file`] reads, checks and writes a file
//! of calibrated sets (the shipped one is `data/calibration_band.toml`); [`fit`] finds the sets
//! by a space-filling design with a hard cut on the field facts' targets and writes that file;
//! [`evaluate`] re-evaluates a run's subsample under every set, into rows that `analyze` turns
//! into the band beside each sampling interval; [`long_term`] runs `wear`'s loop again under
//! chosen sets; the errors of a band file, a fit and a design table are typed in `error`.

mod error;
pub mod evaluate;
pub mod file;
pub mod fit;
pub mod long_term;

use polywear_core::params::{ParamId, Params};
use polywear_core::wear::FittedConstants;

use crate::safe_read::{read_text, Limit};
pub use error::{
    BandError, BandFileError, BandProblem, DesignTableError, FitError, NotALine, RangeProblem,
    SetProblem,
};

pub use file::MAX_TEXT_CHARS;

/// The shipped sets.
pub const SHIPPED: &str = include_str!("../../../../data/calibration_band.toml");
/// Their name in messages and metadata.
pub const SHIPPED_NAME: &str = "data/calibration_band.toml";

/// The most sets a file may hold: each costs a walk over the tread's life per wheel of the
/// band's subsample, and the band is their range, which 100 space-filling sets resolve.
pub(crate) const MAX_SETS: usize = 200;

/// One calibrated set: the calibrated constants, and what the fit found for it.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibratedSet {
    /// Its name in the band's rows.
    pub id: String,
    /// The set the shipped defaults are (exactly one per file).
    #[serde(default)]
    pub nominal: bool,
    /// φ_s.
    pub wear_share_straight: f64,
    /// σ_V \[km/h\].
    pub speed_spread_kmh: f64,
    /// k_d.
    pub wear_rate_driven_factor: f64,
    /// c.
    pub carcass_share: f64,
    /// μ_b.
    pub belt_mass_share: f64,
    /// The fit's median distance of the highway followers \[km\] (informative).
    #[serde(default)]
    pub highway_median_km: Option<f64>,
    /// The fit's median distance of the default study's wheels \[km\] (informative).
    #[serde(default)]
    pub fleet_median_km: Option<f64>,
    /// The fit's share of 10–20 sides among the visible polygons (informative).
    #[serde(default)]
    pub sides_share: Option<f64>,
}

impl CalibratedSet {
    /// The constants.
    pub fn constants(&self) -> FittedConstants {
        FittedConstants {
            wear_share_straight: self.wear_share_straight,
            speed_spread_kmh: self.speed_spread_kmh,
            wear_rate_driven_factor: self.wear_rate_driven_factor,
            carcass_share: self.carcass_share,
            belt_mass_share: self.belt_mass_share,
        }
    }
}

/// A calibrated constant's prior range: what its provenance allows (a published range, or a
/// judgement with its reason), searched whole and never widened to reach a target.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstantRange {
    /// The parameter, by name.
    pub param: String,
    /// The lowest value searched.
    pub min: f64,
    /// The highest value searched.
    pub max: f64,
    /// Where the range comes from.
    pub provenance: String,
}

/// How the sets were found: the design and what it was evaluated on.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitSettings {
    /// The design over the constants' ranges (`sobol`).
    pub design: String,
    /// Its points.
    pub points: u64,
    /// Samples of the default study whose wheels each point is evaluated on.
    pub fleet_samples: u64,
    /// The share of the visible polygons that must have the field's sides.
    pub sides_share_min: f64,
    /// Points that met every target.
    pub accepted: u64,
    /// How the shipped sets were chosen among the accepted points.
    pub shipped: String,
    /// Where the accepted region lies, in one sentence (the fit's finding).
    pub region: String,
}

/// A checked file of calibrated sets.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrationBand {
    /// How the sets were found, named (for the report).
    pub method: String,
    /// The command that regenerates the file.
    pub generated_by: String,
    /// The method's settings.
    pub fit: FitSettings,
    /// Each calibrated constant's prior range, once each.
    #[serde(rename = "range")]
    pub ranges: Vec<ConstantRange>,
    /// The sets, the nominal among them.
    #[serde(rename = "set")]
    pub sets: Vec<CalibratedSet>,
}

impl CalibrationBand {
    /// The shipped sets (checked by the tests, so this cannot fail on a build that passed them).
    pub fn shipped() -> Self {
        Self::parse(SHIPPED, SHIPPED_NAME)
            .expect("the shipped calibration band is checked by tests")
    }

    /// The band a command's `--calibration-band` asks for, read before any work: the shipped
    /// sets when absent, none for `off`, else the file's (MODEL.md#the-calibration-band).
    /// Returns the sets and where they come from, the name every line about the band quotes.
    /// A file that cannot be read or holds no calibrated sets is refused naming the flag, as
    /// `explore`, `cycle`, `optimize` and `wear` all take it.
    pub fn asked(asked: Option<&str>) -> Result<Option<(Self, String)>, BandFileError> {
        match asked {
            Some("off") => Ok(None),
            None => Ok(Some((Self::shipped(), SHIPPED_NAME.to_string()))),
            Some(file) => {
                let text = read_text(std::path::Path::new(file), Limit::Text)
                    .map_err(BandFileError::Unreadable)?;
                let band =
                    Self::parse(&text, file).map_err(|e| BandFileError::Band(Box::new(e)))?;
                Ok(Some((band, file.to_string())))
            }
        }
    }

    /// Refuses a band whose sets a scenario of `study` takes outside a parameter's accepted
    /// range: a scenario's changes are made to each set's constants as to the run's
    /// ([`evaluate::BandPlan`]), so `wear_share_straight = { scale = 5 }` takes a set at
    /// φ_s = 0.23 to 1.15, outside (0, 1], even where the run's own value stays inside. Named:
    /// the file, the scenario's key, the set and the range.
    pub fn check_scenarios(
        &self,
        study: &crate::study::Study,
        file: &str,
    ) -> Result<(), BandError> {
        for scenario in &study.scenarios {
            for change in &scenario.changes {
                let Some(k) = FittedConstants::PARAMS
                    .iter()
                    .position(|&id| id == change.param)
                else {
                    continue;
                };
                let spec = change.param.spec();
                let out: Vec<(&CalibratedSet, f64, f64)> = self
                    .sets
                    .iter()
                    .map(|set| {
                        let from = set.constants().values()[k];
                        (set, from, change.change.apply(from))
                    })
                    .filter(|(_, _, to)| spec.check(*to).is_err())
                    .collect();
                if let Some(&(set, from, to)) = out.first() {
                    return Err(BandError {
                        file: file.to_string(),
                        what: Box::new(BandProblem::ScenarioOutside {
                            scenario_key: scenario.key(change.param),
                            change: *change,
                            out: out.len(),
                            sets: self.sets.len(),
                            set: set.id.clone(),
                            from,
                            to,
                        }),
                    });
                }
            }
        }
        Ok(())
    }

    /// The nominal set.
    pub fn nominal(&self) -> &CalibratedSet {
        self.sets
            .iter()
            .find(|s| s.nominal)
            .expect("a checked band has one nominal set")
    }

    /// Whether `p`'s calibrated constants are the nominal set's.
    pub fn nominal_is(&self, p: &Params) -> bool {
        self.nominal().constants() == FittedConstants::of(p)
    }

    /// Each constant's range over the sets ([`constant_ranges`]).
    pub fn ranges(&self) -> Vec<(ParamId, f64, f64)> {
        constant_ranges(&self.sets)
    }

    /// The prior range of `id` the file states.
    pub fn prior_range(&self, id: ParamId) -> Option<&ConstantRange> {
        self.ranges.iter().find(|r| r.param == id.name())
    }
}

/// Each constant's (lowest, highest) over `sets`, in [`FittedConstants::PARAMS`] order.
pub fn constant_ranges(sets: &[CalibratedSet]) -> Vec<(ParamId, f64, f64)> {
    FittedConstants::PARAMS
        .iter()
        .enumerate()
        .map(|(k, &id)| {
            let v = sets.iter().map(|s| s.constants().values()[k]);
            let lo = v.clone().fold(f64::INFINITY, f64::min);
            let hi = v.fold(f64::NEG_INFINITY, f64::max);
            (id, lo, hi)
        })
        .collect()
}
