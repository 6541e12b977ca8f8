//! The share of a normal speed spread inside a lock band (MODEL.md#growth-of-a-vibrating-wheel):
//! in closed form, and for a narrow band as a series in its width.

/// The share of speeds normal around `mean_mps` (deviation `spread_mps`) within ±`half_mps` of
/// `centre_mps`; with no spread, 1 inside the band and 0 outside.
pub(super) fn band_share(centre_mps: f64, half_mps: f64, mean_mps: f64, spread_mps: f64) -> f64 {
    if half_mps <= 0.0 {
        return 0.0;
    }
    if spread_mps <= 0.0 {
        return if (mean_mps - centre_mps).abs() <= half_mps {
            1.0
        } else {
            0.0
        };
    }
    // A band more than this many deviations from the mean holds under 1e-19 of the spread:
    // left out without the two error functions (the answer over the tread's life asks at
    // every node of every order).
    const FAR_DEVIATIONS: f64 = 9.0;
    if (centre_mps - half_mps - mean_mps) > FAR_DEVIATIONS * spread_mps
        || (centre_mps + half_mps - mean_mps) < -FAR_DEVIATIONS * spread_mps
    {
        return 0.0;
    }
    let eta = half_mps / spread_mps;
    if eta <= NARROW_BAND_DEVIATIONS {
        return NarrowBand::at((centre_mps - mean_mps) / spread_mps).share(eta);
    }
    let cdf = |x: f64| 0.5 * libm::erfc(-(x - mean_mps) / (std::f64::consts::SQRT_2 * spread_mps));
    cdf(centre_mps + half_mps) - cdf(centre_mps - half_mps)
}

/// A narrow band's share of a normal spread, for its centre m deviations from the mean:
/// Φ(m + η) − Φ(m − η) = 2φ(m) Σ_{k odd} He_{k−1}(m) η^k/k! for a half-width of η deviations, to
/// η⁹ (the first term left out is below 10⁻¹⁰ absolute at η ≤ [`NARROW_BAND_DEVIATIONS`]): one
/// exponential instead of two error functions, and the one the answer over the tread's life
/// shares between all the orders at a node (only η moves with the order).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct NarrowBand {
    /// φ(m).
    pub(super) density: f64,
    /// He₂(m)/3!, He₄(m)/5!, He₆(m)/7!, He₈(m)/9!.
    pub(super) hermite: [f64; 4],
}

impl NarrowBand {
    pub(super) fn at(m: f64) -> Self {
        let m2 = m * m;
        NarrowBand {
            density: (-0.5 * m2).exp() * FRAC_1_SQRT_2PI,
            hermite: [
                (m2 - 1.0) / 6.0,
                (m2 * (m2 - 6.0) + 3.0) / 120.0,
                (m2 * (m2 * (m2 - 15.0) + 45.0) - 15.0) / 5040.0,
                (m2 * (m2 * (m2 * (m2 - 28.0) + 210.0) - 420.0) + 105.0) / 362_880.0,
            ],
        }
    }

    /// The share within ±`eta` deviations (η ≤ [`NARROW_BAND_DEVIATIONS`]).
    pub(super) fn share(&self, eta: f64) -> f64 {
        let e2 = eta * eta;
        let [h2, h4, h6, h8] = self.hermite;
        2.0 * eta * self.density * (1.0 + e2 * (h2 + e2 * (h4 + e2 * (h6 + e2 * h8))))
    }
}

/// Half-widths up to this many deviations of the spread take [`band_share`]'s series.
pub(super) const NARROW_BAND_DEVIATIONS: f64 = 0.25;

/// 1/√(2π).
const FRAC_1_SQRT_2PI: f64 = 0.398_942_280_401_432_7;

#[cfg(test)]
mod band_tests {
    use super::*;

    /// The narrow band's series against the two error functions it replaces: within 10⁻¹⁰ of the
    /// spread (absolute) and 10⁻⁷ of the share wherever the share is above 10⁻⁶, for
    /// half-widths up to the series' bound, at every offset up to 9 deviations.
    #[test]
    fn the_narrow_band_series_is_the_error_functions() {
        let (mean, sd) = (30.0, 1.4);
        let exact = |centre: f64, half: f64| {
            let cdf = |x: f64| 0.5 * libm::erfc(-(x - mean) / (std::f64::consts::SQRT_2 * sd));
            cdf(centre + half) - cdf(centre - half)
        };
        let mut worst: f64 = 0.0;
        for i in 0..=50 {
            let half = sd * NARROW_BAND_DEVIATIONS * (0.02 + 0.98 * i as f64 / 50.0);
            for j in -180..=180 {
                let centre = mean + sd * 0.05 * j as f64;
                let (series, want) = (band_share(centre, half, mean, sd), exact(centre, half));
                assert!(
                    (series - want).abs() < 1e-10,
                    "{centre} {half}: {series} {want}"
                );
                if want > 1e-6 {
                    worst = worst.max((series / want - 1.0).abs());
                }
            }
        }
        assert!(worst < 1e-7, "{worst}");
        // Just past the bound the error functions take over.
        let half = 1.01 * NARROW_BAND_DEVIATIONS * sd;
        assert_eq!(
            band_share(mean + 0.3, half, mean, sd),
            exact(mean + 0.3, half)
        );
    }
}
