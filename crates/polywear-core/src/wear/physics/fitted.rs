//! The wear stage's calibrated constants as one value (MODEL.md#the-calibration-band): the
//! constants no measurement fixes, which the field calibration bounds only to a band, so that a
//! wear answer can be re-evaluated under each calibrated set on the same samples.

use crate::params::{ParamId, Params};

/// The constants no measurement fixes, which the field calibration bounds and a calibration
/// band varies: φ_s, σ_V and k_d (the share of even wear the vibration couples to, the cruising
/// speed's spread, the driven position's wear factor), and the two shares that set how the tread
/// frequency drifts as the tread wears, c (the carcass's share of the compliance) and μ_b (the
/// belt's share of the mode's mass, which does not wear).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FittedConstants {
    /// φ_s, `wear_share_straight` (field-fitted).
    pub wear_share_straight: f64,
    /// σ_V \[km/h\], `speed_spread_kmh` (field-fitted).
    pub speed_spread_kmh: f64,
    /// k_d, `wear_rate_driven_factor` (a published range).
    pub wear_rate_driven_factor: f64,
    /// c, `carcass_share` (judged).
    pub carcass_share: f64,
    /// μ_b, `belt_mass_share` (judged).
    pub belt_mass_share: f64,
}

impl FittedConstants {
    /// The constants polywear 0.5 shipped, before the calibration over five constants on the
    /// shipped level: φ_s 0.12, σ_V 5 km/h, k_d 1.75, c 0.5, μ_b 0. Tests that measured the
    /// estimator's mechanics at a point pin these, so that the shipped defaults can move (as
    /// the reference files pin R0).
    pub const VERSION_0_5: FittedConstants = FittedConstants {
        wear_share_straight: 0.12,
        speed_spread_kmh: 5.0,
        wear_rate_driven_factor: 1.75,
        carcass_share: 0.5,
        belt_mass_share: 0.0,
    };

    /// The parameters a set holds, in the order of [`FittedConstants::values`].
    pub const PARAMS: [ParamId; 5] = [
        ParamId::WearShareStraight,
        ParamId::SpeedSpreadKmh,
        ParamId::WearRateDrivenFactor,
        ParamId::CarcassShare,
        ParamId::BeltMassShare,
    ];

    /// The constants of `p`.
    pub fn of(p: &Params) -> Self {
        FittedConstants {
            wear_share_straight: p.wear_share_straight,
            speed_spread_kmh: p.speed_spread_kmh,
            wear_rate_driven_factor: p.wear_rate_driven_factor,
            carcass_share: p.carcass_share,
            belt_mass_share: p.belt_mass_share,
        }
    }

    /// The constants in [`FittedConstants::PARAMS`] order.
    pub fn from_values(v: [f64; 5]) -> Self {
        FittedConstants {
            wear_share_straight: v[0],
            speed_spread_kmh: v[1],
            wear_rate_driven_factor: v[2],
            carcass_share: v[3],
            belt_mass_share: v[4],
        }
    }

    /// `p` with these constants.
    pub fn applied_to(&self, p: &Params) -> Params {
        Params {
            wear_share_straight: self.wear_share_straight,
            speed_spread_kmh: self.speed_spread_kmh,
            wear_rate_driven_factor: self.wear_rate_driven_factor,
            carcass_share: self.carcass_share,
            belt_mass_share: self.belt_mass_share,
            ..*p
        }
    }

    /// Whether `p`'s tread ages as these constants say (the same carcass and belt shares):
    /// the drift of the tread frequency over the life is then `p`'s own.
    pub fn ages_as(&self, p: &Params) -> bool {
        self.carcass_share == p.carcass_share && self.belt_mass_share == p.belt_mass_share
    }

    /// Where these constants differ from `fitted`'s: each parameter with (this value, the
    /// fitted one), in [`FittedConstants::PARAMS`] order (empty where they are the same).
    pub fn departures_from(&self, fitted: &FittedConstants) -> Vec<(ParamId, f64, f64)> {
        Self::PARAMS
            .iter()
            .zip(self.values().into_iter().zip(fitted.values()))
            .filter(|(_, (a, b))| a != b)
            .map(|(&id, (a, b))| (id, a, b))
            .collect()
    }

    /// The values in [`FittedConstants::PARAMS`] order.
    pub fn values(&self) -> [f64; 5] {
        [
            self.wear_share_straight,
            self.speed_spread_kmh,
            self.wear_rate_driven_factor,
            self.carcass_share,
            self.belt_mass_share,
        ]
    }
}

/// The default parameters with the constants of polywear 0.5 ([`FittedConstants::VERSION_0_5`]):
/// what the estimator's unit tests measured their figures at.
#[cfg(test)]
pub(crate) fn pinned_params() -> Params {
    FittedConstants::VERSION_0_5.applied_to(&Params::default())
}

/// One wheel's wear answer over the tread's life under one set of fitted constants: what the
/// rows' wear columns say about it (MODEL.md#the-per-sample-estimator), and how near the
/// deepest order came.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LifeAnswer {
    /// The order that becomes visible first, or (none visible) the one that got deepest
    /// (`polygon_order_wear`); NaN where no order rose above its seed.
    pub polygon_order_wear: f64,
    /// Distance to a visible polygon \[km\] (+inf: none before the tire is worn out).
    pub distance_to_visible_km: f64,
    /// Distance until the tread is worn out \[km\].
    pub tread_life_km: f64,
    /// The deepest order's largest depth over the life, as a share of d_visible (1 where a
    /// polygon is visible).
    pub peak_share_of_visible: f64,
}

impl LifeAnswer {
    /// A wheel with no figures (no model, or past its wall-clock limit).
    pub const UNKNOWN: LifeAnswer = LifeAnswer {
        polygon_order_wear: f64::NAN,
        distance_to_visible_km: f64::NAN,
        tread_life_km: f64::NAN,
        peak_share_of_visible: f64::NAN,
    };

    /// The answer in words.
    pub fn outcome(&self) -> WearOutcome {
        WearOutcome::of(self.distance_to_visible_km, self.tread_life_km)
    }

    /// Whether the polygon is visible within `within_km` and before the tire is worn out (what
    /// every wear probability counts); None where unknown.
    pub fn visible_within(&self, within_km: f64) -> Option<bool> {
        match self.outcome() {
            WearOutcome::Unknown => None,
            _ => Some(
                self.distance_to_visible_km <= within_km
                    && self.distance_to_visible_km <= self.tread_life_km,
            ),
        }
    }
}

/// The wear outcome of a [`LifeAnswer`] in words ([`WearOutcome::as_str`]), so that a reader never
/// counts an unknown distance (NaN) as "no polygon" by comparing numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WearOutcome {
    /// The polygon is visible before the tread is worn out.
    Visible,
    /// The tread is worn out first, or every order levels out.
    NotWithinLife,
    /// No wear figures (failed, no traction, standstill, the stage did not run).
    Unknown,
}

impl WearOutcome {
    /// The outcome of a distance to a visible polygon against the tread's life \[km\].
    pub fn of(distance_to_visible_km: f64, tread_life_km: f64) -> Self {
        if distance_to_visible_km.is_nan() || tread_life_km.is_nan() {
            WearOutcome::Unknown
        } else if distance_to_visible_km <= tread_life_km {
            WearOutcome::Visible
        } else {
            WearOutcome::NotWithinLife
        }
    }

    /// The name in the rows.
    pub fn as_str(self) -> &'static str {
        match self {
            WearOutcome::Visible => "visible",
            WearOutcome::NotWithinLife => "not_within_life",
            WearOutcome::Unknown => "unknown",
        }
    }
}
