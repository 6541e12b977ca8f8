//! The wear stage's fitted constants as one value (MODEL.md#the-calibration-band): what the field
//! calibration fixes only to a band, so that a wear answer can be re-evaluated under each
//! calibrated set on the same samples.

use crate::params::{ParamId, Params};

/// The constants the field calibration fits or takes from a published range, and that a
/// calibration band varies: φ_s, σ_V and k_d.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FittedConstants {
    /// φ_s, `wear_share_straight` (field-fitted).
    pub wear_share_straight: f64,
    /// σ_V \[km/h\], `speed_spread_kmh` (field-fitted).
    pub speed_spread_kmh: f64,
    /// k_d, `wear_rate_driven_factor` (a published range).
    pub wear_rate_driven_factor: f64,
}

impl FittedConstants {
    /// The parameters a set holds, in the order of [`FittedConstants::values`].
    pub const PARAMS: [ParamId; 3] = [
        ParamId::WearShareStraight,
        ParamId::SpeedSpreadKmh,
        ParamId::WearRateDrivenFactor,
    ];

    /// The constants of `p`.
    pub fn of(p: &Params) -> Self {
        FittedConstants {
            wear_share_straight: p.wear_share_straight,
            speed_spread_kmh: p.speed_spread_kmh,
            wear_rate_driven_factor: p.wear_rate_driven_factor,
        }
    }

    /// `p` with these constants.
    pub fn applied_to(&self, p: &Params) -> Params {
        Params {
            wear_share_straight: self.wear_share_straight,
            speed_spread_kmh: self.speed_spread_kmh,
            wear_rate_driven_factor: self.wear_rate_driven_factor,
            ..*p
        }
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
    pub fn values(&self) -> [f64; 3] {
        [
            self.wear_share_straight,
            self.speed_spread_kmh,
            self.wear_rate_driven_factor,
        ]
    }
}

/// One wheel's wear answer: what the rows' wear columns say about it, under one set of
/// fitted constants.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WearAnswer {
    /// The order that grows fastest (`polygon_order_wear`).
    pub polygon_order_wear: f64,
    /// Distance to a visible polygon \[km\] (+inf: every order levels out).
    pub distance_to_visible_km: f64,
    /// Distance until the tread is worn out \[km\].
    pub tread_life_km: f64,
}

impl WearAnswer {
    /// A wheel with no figures.
    pub const UNKNOWN: WearAnswer = WearAnswer {
        polygon_order_wear: f64::NAN,
        distance_to_visible_km: f64::NAN,
        tread_life_km: f64::NAN,
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

/// The wear outcome of a wheel in words ([`WearOutcome::as_str`]), so that a reader never
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
