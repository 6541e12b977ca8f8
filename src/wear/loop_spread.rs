//! The speed spread in the long-term loop (MODEL.md#the-long-term-loop): the loop drives a few
//! speeds of the spread, each with its own state (so that a speed inside a tongue locks and
//! prints as it does on the road), and adds, order by order, what those few speeds miss of the
//! linear closed loop's mean over the whole spread.
//!
//! Why the speeds alone do not do: an order's growth against speed goes through a resonance
//! about 1/δ (δ = ν − n) a few hundredths of an order wide, and its mean over a normal spread is
//! a principal value that a handful of speeds does not come near (five equal-share speeds gave
//! −0.41 per 1000 km for order 19 at the reference point, σ_V = 2 km/h, against the exact
//! +1.12). The wheel's linearisation is a sum of poles in the speed, whose normal mean is exact
//! ([`super::spread`]), and so is its value at each leg's speed: the difference, the linear
//! loop's mean over the spread minus its mean over the legs, is what the legs' quadrature
//! misses, and the loop adds it to the wear the legs lay (a control variate: where the legs'
//! own wear is the linear loop's, the sum is the exact mean; where a leg locks or the profile is
//! deep, the leg's own wear carries that). The wheel is classified and linearised again at the
//! mean speed whenever the tread height has moved.

use super::calibration::Calibration;
use super::estimator::{WearInputs, WearSettings, WheelGrowth};
use super::legs::Leg;
use super::zone::WearZone;
use super::{Complex64, WearError};
use crate::classify::budget::Meter;
use crate::classify::{classify_hinted, ClassifierOptions, CycleHint};
use crate::model::WheelModel;
use crate::params::Params;

/// A normal spread of the cruising speed in the long-term loop, and what its linear effect is
/// computed with.
#[derive(Debug, Clone, Copy)]
pub struct LoopSpread<'a> {
    /// The standard deviation of the cruising speed \[km/h\] (> 0), around the run's speed.
    pub spread_kmh: f64,
    /// The run's abradability (the estimator's even wear).
    pub calibration: &'a Calibration,
    /// How the wheel is classified again at each tread height.
    pub classifier: &'a ClassifierOptions,
}

impl LoopSpread<'_> {
    /// What the `legs` miss of the linear loop's mean over the spread, Δβ_n \[1/m\] for orders
    /// 1 ..= `orders` (index n − 1), for the wheel `model` at `params` (the mean speed and the
    /// run's tread height), classified with `hint` (the last one's cycle) as the shooting's
    /// guess; also returns this cycle's hint for the next.
    pub fn missed_growth_per_m(
        &self,
        params: &Params,
        model: &WheelModel,
        zone: WearZone,
        legs: &[Leg],
        orders: usize,
        hint: Option<CycleHint>,
    ) -> Result<(Vec<f64>, Option<CycleHint>), WearError> {
        let (verdict, next) = classify_hinted(
            &model.ode,
            WheelModel::rotation_hz(params),
            self.classifier,
            hint,
        );
        let built = Ok(*model);
        let meter = Meter::new(self.classifier.budget);
        let growth = WheelGrowth::new(
            &WearInputs {
                params,
                model: &built,
                verdict: &verdict,
                settings: &WearSettings { zone },
                calibration: self.calibration,
            },
            &meter,
        )?;
        let (share, spread_mps) = (params.wear_share_straight, self.spread_kmh / 3.6);
        let v = growth.speed_mps();
        let missed = (1..=orders as u32)
            .map(|n| {
                let over_legs: f64 = legs
                    .iter()
                    .map(|l| l.share * growth.linear_growth_per_m(n, share, l.speed_kmh / 3.6, 0.0))
                    .sum();
                growth.linear_growth_per_m(n, share, v, spread_mps) - over_legs
            })
            .map(|b| if b.is_finite() { b } else { 0.0 })
            .collect();
        Ok((missed, next.or(hint)))
    }
}

/// The depth rate per cell \[m/m\] that makes each harmonic `radius_harmonics[n − 1]` of the
/// radius grow by `growth_per_m[n − 1]` more: r gains Σ Δβ_n Re\[R_n e^{inθ_i}\] per metre at
/// the cell centres θ_i, the depth loses as much. Its mean is zero: no wear is added or taken,
/// only moved between orders.
pub fn depth_rate_m_per_m(
    growth_per_m: &[f64],
    radius_harmonics: &[Complex64],
    cells: usize,
) -> Vec<f64> {
    let d_theta = std::f64::consts::TAU / cells as f64;
    let mut rate = vec![0.0; cells];
    for (k, (beta, r_n)) in growth_per_m.iter().zip(radius_harmonics).enumerate() {
        let a = r_n * *beta;
        if a.norm() == 0.0 {
            continue;
        }
        let n = (k + 1) as f64;
        let step = Complex64::from_polar(1.0, n * d_theta);
        let mut phasor = a;
        for (i, r) in rate.iter_mut().enumerate() {
            if i % 64 == 0 {
                phasor = a * Complex64::from_polar(1.0, n * (i as f64 + 0.5) * d_theta);
            }
            *r -= phasor.re;
            phasor *= step;
        }
    }
    rate
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wear::profile::harmonics_of;

    /// The rate moves each harmonic by exactly Δβ_n R_n and leaves the mean alone.
    #[test]
    fn the_rate_grows_each_harmonic_by_its_own_beta() {
        let cells = 1024;
        let r: Vec<Complex64> = (1..=40)
            .map(|n| Complex64::from_polar(1e-6 * (1.0 + n as f64 / 10.0), 0.3 * n as f64))
            .collect();
        let beta: Vec<f64> = (1..=40).map(|n| 1e-7 * (n as f64 - 20.5)).collect();
        let rate = depth_rate_m_per_m(&beta, &r, cells);
        assert!(rate.iter().sum::<f64>().abs() < 1e-25 * cells as f64);
        let radius_rate: Vec<f64> = rate.iter().map(|d| -d).collect();
        let got = harmonics_of(&radius_rate, 41);
        for n in 0..40 {
            let want = r[n] * beta[n];
            assert!(
                (got[n] - want).norm() < 1e-12 * want.norm().max(1e-20),
                "{n}"
            );
        }
        assert!(got[40].norm() < 1e-25);
    }
}
