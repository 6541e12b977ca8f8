//! The wear stage's category settings and the inputs of one wheel's estimate
//! (MODEL.md#the-per-sample-estimator): where the friction power wears and which power it is,
//! the one answer's recorded name, and the answers retired.

use super::*;

/// The wear stage's settings that are categories, not numbers (the numbers are parameters).
/// Every sample gets one wear answer, over the tread's life with each speed's print saturated
/// (MODEL.md#the-forced-response-saturates): the level that agrees with the long-term loop. The
/// new tire's answer and the unsaturated one were retired as answers (`wear_estimate` of a run
/// recorded by polywear 0.5 and before); the walks they were made of serve the shipped one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct WearSettings {
    /// Where the friction power wears the tread.
    pub zone: WearZone,
    /// Which friction power wears it: the lateral alone, or with the driving wheel's slip.
    pub power: WearPower,
}

/// Written as a run records its wear stage: `wear_zone`, `wear_power`, and the one answer's
/// name as `wear_estimate` (what a reader of the run, and polywear, tell it apart by from a
/// run of a retired answer).
impl serde::Serialize for WearSettings {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(3))?;
        m.serialize_entry("wear_estimate", SHIPPED_LEVEL)?;
        m.serialize_entry("wear_power", &self.power)?;
        m.serialize_entry("wear_zone", &self.zone)?;
        m.end()
    }
}

/// The name polywear 0.5 and before recorded for the one answer it now gives (`wear_estimate`
/// in a run's `wear` metadata): a run that recorded another was answered on a retired level.
pub const SHIPPED_LEVEL: &str = "tread_life_saturated";

/// The answers retired, with what replaced them, for a run, a study or a flag that names one.
pub fn retired_level(name: &str) -> Option<String> {
    matches!(name, "new_tire" | "tread_life").then(|| {
        format!(
            "the wear answer `{name}` was retired: every sample carries one wear answer, over the tread's life with each speed's print saturated (`{SHIPPED_LEVEL}`, the level that agrees with the long-term loop)"
        )
    })
}

impl Default for WearZone {
    fn default() -> Self {
        WearZone::DEFAULT
    }
}

/// What the estimator needs about one wheel.
#[derive(Debug, Clone, Copy)]
pub struct WearProblem<'a> {
    /// The sample's parameters (operating point, tire, wear constants), as the wheel sees them
    /// (its axle's toe-in, load and pressure: [`Params::at_wheel`]).
    pub params: Params,
    /// Steps 1–8 for the wheel, or why there is no model.
    pub model: &'a Result<WheelModel, ModelFailure>,
    /// The classifier's verdict (step 9).
    pub verdict: &'a WheelVerdict,
    /// The wear zone.
    pub settings: &'a WearSettings,
    /// The run's abradability.
    pub calibration: &'a Calibration,
}
