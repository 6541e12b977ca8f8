//! Parameter distributions of a study, sampled by inverse CDF from a uniform coordinate.

use std::f64::consts::SQRT_2;

use rand::distr::Distribution as _;
use rand::RngExt;

/// How one parameter is drawn.
#[derive(Debug, Clone, PartialEq)]
pub enum Distribution {
    /// Uniform on [min, max]; in a grid design, `count` evenly spaced values from min to max.
    Uniform {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
        /// Values in a grid design (None outside grids).
        count: Option<usize>,
    },
    /// Normal(mean, sd), unbounded: only for parameters whose range is unbounded.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation.
        sd: f64,
    },
    /// Normal(mean, sd) restricted to [min, max].
    TruncatedNormal {
        /// Mean of the untruncated normal.
        mean: f64,
        /// Its standard deviation.
        sd: f64,
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// exp(N(ln median, sigma²)).
    LogNormal {
        /// Median.
        median: f64,
        /// Standard deviation of ln x.
        sigma: f64,
    },
    /// Each level equally likely; in a grid design, exactly these levels.
    Levels(Vec<f64>),
}

/// Standard normal CDF Φ(x).
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / SQRT_2)
}

/// ln √(2π).
const LN_SQRT_2PI: f64 = 0.918_938_533_204_672_8;

/// Natural log of the standard normal density, ln φ(x).
fn ln_normal_pdf(x: f64) -> f64 {
    -0.5 * x * x - LN_SQRT_2PI
}

/// ln Φ(x), accurate in both tails (SciPy's `log_ndtr`): through the complementary side for
/// x > 0, erfc down to x = -37 and the asymptotic (Mills-ratio) series of Φ below, where Φ itself
/// underflows (Abramowitz & Stegun 26.2.12).
pub fn ln_normal_cdf(x: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x > 0.0 {
        return (-normal_cdf(-x)).ln_1p();
    }
    if x > -37.0 {
        return normal_cdf(x).ln();
    }
    if x == f64::NEG_INFINITY {
        return f64::NEG_INFINITY;
    }
    // Φ(x) = φ(x)/(-x) · (1 - 1/x² + 3/x⁴ - 15/x⁶ + ...); at |x| ≥ 37 ten terms reach 1e-25.
    let r = 1.0 / (x * x);
    let (mut term, mut sum) = (1.0, 1.0);
    for k in 1..10 {
        term *= -((2 * k - 1) as f64) * r;
        sum += term;
    }
    ln_normal_pdf(x) - (-x).ln() + sum.ln()
}

/// Acklam's rational approximation of Φ⁻¹(p) for p in (0, 0.5] (relative error 1.15e-9).
fn acklam_lower(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.38357751867269e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    if p < 0.02425 {
        let q = (-2.0 * p.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// Φ⁻¹(p) for p in (0, 0.5]: Acklam's approximation refined by Halley steps. The residual is
/// taken where it is exact: on erf (Φ(x) - ½ against p - ½) near the centre, so that x keeps its
/// relative accuracy as it approaches 0, and on erfc (Φ(x) against p) in the tail.
fn normal_quantile_lower(p: f64) -> f64 {
    let mut x = acklam_lower(p);
    for _ in 0..2 {
        let e = if p > 0.25 {
            0.5 * libm::erf(x / SQRT_2) - (p - 0.5)
        } else {
            normal_cdf(x) - p
        };
        let pdf = ln_normal_pdf(x).exp();
        if e == 0.0 || pdf == 0.0 {
            break;
        }
        let u = e / pdf;
        x -= u / (1.0 + x * u / 2.0);
    }
    x
}

/// Standard normal quantile Φ⁻¹(p) for p in (0, 1), accurate to a few ulp in both tails: the
/// upper half is computed as -Φ⁻¹(1 - p), 1 - p being exact there (SciPy's `ndtri`).
pub fn normal_quantile(p: f64) -> f64 {
    if p.is_nan() {
        return f64::NAN;
    }
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    if p > 0.5 {
        -normal_quantile_lower(1.0 - p)
    } else {
        normal_quantile_lower(p)
    }
}

/// The x with ln Φ(x) = `ln_p` (SciPy's `ndtri_exp`), for ln_p ≤ 0: the quantile of a
/// probability given by its logarithm, so that tails far beyond f64's smallest probability
/// keep full accuracy. Newton's method on ln Φ below p = e^-700.
pub fn normal_quantile_of_ln(ln_p: f64) -> f64 {
    if ln_p.is_nan() {
        return f64::NAN;
    }
    if ln_p >= 0.0 {
        return f64::INFINITY;
    }
    if ln_p == f64::NEG_INFINITY {
        return f64::NEG_INFINITY;
    }
    if ln_p > -std::f64::consts::LN_2 {
        // p > ½: 1 - p = -expm1(ln p) without cancellation.
        return -normal_quantile_lower(-ln_p.exp_m1());
    }
    if ln_p > -700.0 {
        return normal_quantile_lower(ln_p.exp());
    }
    // ln Φ(x) ≈ -x²/2 - ln(-x) - ln √(2π); start from the leading term and refine.
    let mut x = -(-2.0 * ln_p).sqrt();
    for _ in 0..100 {
        let f = ln_normal_cdf(x) - ln_p;
        // d ln Φ / dx = φ(x) / Φ(x)
        let slope = (ln_normal_pdf(x) - ln_normal_cdf(x)).exp();
        let step = f / slope;
        x -= step;
        if step.abs() <= 1e-16 * x.abs() {
            break;
        }
    }
    x
}

/// ln(e^a + e^b).
fn ln_add_exp(a: f64, b: f64) -> f64 {
    let (hi, lo) = if a > b { (a, b) } else { (b, a) };
    if lo == f64::NEG_INFINITY {
        return hi;
    }
    hi + (lo - hi).exp().ln_1p()
}

/// ln(1 - e^a) for a ≤ 0 (Mächler 2012).
fn ln_1m_exp(a: f64) -> f64 {
    if a > -std::f64::consts::LN_2 {
        (-a.exp_m1()).ln()
    } else {
        (-a.exp()).ln_1p()
    }
}

/// ln(Φ(b) - Φ(a)) for a < b, computed on the side where both are small (SciPy's
/// `_log_gauss_mass`).
pub fn ln_normal_mass(a: f64, b: f64) -> f64 {
    if b <= 0.0 {
        let lb = ln_normal_cdf(b);
        lb + ln_1m_exp(ln_normal_cdf(a) - lb)
    } else if a >= 0.0 {
        let la = ln_normal_cdf(-a);
        la + ln_1m_exp(ln_normal_cdf(-b) - la)
    } else {
        (-normal_cdf(a) - normal_cdf(-b)).ln_1p()
    }
}

/// Quantile of the standard normal truncated to [a, b] at `u` in [0, 1], accurate in both tails
/// (after SciPy's `truncnorm._ppf`): below the median ln Φ(x) = ln(Φ(a) + u·(Φ(b) - Φ(a))),
/// above it the same on the survival function, ln Φ(-x) = ln(Φ(-b) + (1 - u)·(Φ(b) - Φ(a))),
/// every term in log space, so that neither tail is computed as a difference near 1.
pub fn truncated_normal_quantile(a: f64, b: f64, u: f64) -> f64 {
    let ln_mass = ln_normal_mass(a, b);
    // ln Φ(x) from below, or ln Φ(-x) = ln(1 - Φ(x)) from above.
    let from_below = || ln_add_exp(ln_normal_cdf(a), u.ln() + ln_mass);
    let from_above = || ln_add_exp(ln_normal_cdf(-b), (-u).ln_1p() + ln_mass);
    let x = if a >= 0.0 {
        -normal_quantile_of_ln(from_above())
    } else {
        match from_below() {
            // Past the median the upper tail 1 - Φ(x) is the small, accurate side.
            ln_p if ln_p > -std::f64::consts::LN_2 && b > 0.0 => {
                -normal_quantile_of_ln(from_above())
            }
            ln_p => normal_quantile_of_ln(ln_p),
        }
    };
    x.clamp(a, b)
}

/// Below this change of the log-density across the interval, a truncated normal is sampled
/// through the series of [`near_uniform_quantile`] (exact to about 1e-18 there), not through
/// Φ: the interval is then so narrow against sd that Φ(a) and Φ(b) agree to most of their digits.
pub(crate) const NEAR_UNIFORM: f64 = 1e-2;

/// The value at `u` in [0, 1] of Normal(mean, sd) truncated to [min, max], for any finite sd:
/// as sd grows the distribution tends to the uniform on [min, max], and so do the values.
/// Where the interval is wide against sd, [`truncated_normal_quantile`] on the standardised
/// bounds; where the density is nearly flat over it (a change of its logarithm below
/// [`NEAR_UNIFORM`]), [`near_uniform_quantile`] in the interval's own coordinate, so that no
/// digit is lost to the standardisation. Bounds infinitely far on one side of the mean (an
/// overflow of (min − mean)/sd) put the mass at the nearer bound.
pub(crate) fn truncated_normal_value(mean: f64, sd: f64, min: f64, max: f64, u: f64) -> f64 {
    let (mut a, mut b) = ((min - mean) / sd, (max - mean) / sd);
    if !(a.is_finite() && b.is_finite()) {
        // A difference that overflows: the same bounds, each divided first.
        (a, b) = (min / sd - mean / sd, max / sd - mean / sd);
    }
    if b == f64::NEG_INFINITY {
        return max;
    }
    if a == f64::INFINITY {
        return min;
    }
    // The interval in units of sd, without the cancellation of b − a.
    let w = match (max - min) / sd {
        w if w.is_finite() => w,
        _ => max / sd - min / sd,
    };
    // Over the interval, ln φ changes by at most w·max(|a|, |b|) + w²/2.
    let variation = w * a.abs().max(b.abs()) + 0.5 * w * w;
    if variation <= NEAR_UNIFORM {
        let t = near_uniform_quantile(a * w, 0.5 * w * w, u);
        let span = max - min;
        let x = if span.is_finite() {
            min + t * span
        } else {
            min * (1.0 - t) + max * t
        };
        return x.clamp(min, max);
    }
    let z = truncated_normal_quantile(a, b, u);
    (mean + sd * z).clamp(min, max)
}

/// The t in [0, 1] where the density ∝ exp(−(c·s + d·s²)) on [0, 1] reaches probability `u`:
/// a truncated normal in the coordinate s of its interval (x = a + w·s, c = a·w, d = w²/2).
/// For |c| + d ≤ [`NEAR_UNIFORM`] the exponential is its Taylor series to the 6th power (the
/// remainder below 1e-17), integrated exactly, and the CDF inverted by Newton's method from
/// t = u; c = d = 0 gives t = u, the uniform.
pub(crate) fn near_uniform_quantile(c: f64, d: f64, u: f64) -> f64 {
    const TERMS: usize = 6;
    // Coefficients of exp(−g(s)) in powers of s, g(s) = c·s + d·s².
    let mut density = [0.0; 2 * TERMS + 1];
    let mut term = [0.0; 2 * TERMS + 1];
    density[0] = 1.0;
    term[0] = 1.0;
    for k in 1..=TERMS {
        let mut next = [0.0; 2 * TERMS + 1];
        for (j, &t) in term.iter().enumerate().take(2 * k - 1) {
            next[j + 1] -= t * c / k as f64;
            next[j + 2] -= t * d / k as f64;
        }
        term = next;
        for (p, t) in density.iter_mut().zip(&term) {
            *p += t;
        }
    }
    let pdf = |t: f64| density.iter().rev().fold(0.0, |acc, p| acc * t + p);
    let cdf = |t: f64| {
        density
            .iter()
            .enumerate()
            .rev()
            .fold(0.0, |acc, (j, p)| acc * t + p / (j + 1) as f64)
            * t
    };
    let target = u.clamp(0.0, 1.0) * cdf(1.0);
    let mut t = u.clamp(0.0, 1.0);
    for _ in 0..8 {
        let step = (cdf(t) - target) / pdf(t);
        t = (t - step).clamp(0.0, 1.0);
        if step.abs() <= 1e-17 {
            break;
        }
    }
    t
}

impl Distribution {
    /// The value at uniform coordinate `u` in [0, 1): the inverse CDF, used by the stratified
    /// designs (LHS, Sobol, Saltelli) so that they keep their stratification.
    pub fn quantile(&self, u: f64) -> f64 {
        // Keep u strictly inside (0, 1) for the unbounded distributions.
        let u_open = u.clamp(f64::EPSILON, 1.0 - f64::EPSILON);
        match self {
            Distribution::Uniform { min, max, .. } => min + u * (max - min),
            Distribution::Normal { mean, sd } => mean + sd * normal_quantile(u_open),
            Distribution::TruncatedNormal { mean, sd, min, max } => {
                truncated_normal_value(*mean, *sd, *min, *max, u)
            }
            Distribution::LogNormal { median, sigma } => {
                median * (sigma * normal_quantile(u_open)).exp()
            }
            Distribution::Levels(levels) => {
                let k = ((u * levels.len() as f64) as usize).min(levels.len() - 1);
                levels[k]
            }
        }
    }

    /// A direct draw for the random design, from `rng` (the sample's stream of this axis):
    /// `rand_distr`'s samplers where one exists (uniform, normal and lognormal by ziggurat,
    /// levels by rand's unbiased integer range); the truncated normal by its inverse CDF, which
    /// unlike rejection stays exact and fast however far in a tail the interval lies. Normal and
    /// lognormal draws are held to the values [`Distribution::quantile`] can give (mean ± 8.1 sd),
    /// the range the study's range check covers; a draw beyond it has probability below 1e-15.
    pub fn draw<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> f64 {
        match self {
            Distribution::Uniform { min, max, .. } => match rand::distr::Uniform::new(*min, *max) {
                Ok(d) => d.sample(rng),
                Err(_) => self.quantile(rng.random::<f64>()),
            },
            Distribution::Normal { mean, sd } => {
                let d = rand_distr::Normal::new(*mean, *sd).expect("sd checked positive");
                let (lo, hi) = self.draw_range();
                d.sample(rng).clamp(lo, hi)
            }
            Distribution::LogNormal { median, sigma } => {
                let d = rand_distr::LogNormal::new(median.ln(), *sigma)
                    .expect("sigma checked positive");
                let (lo, hi) = self.draw_range();
                d.sample(rng).clamp(lo, hi)
            }
            Distribution::TruncatedNormal { .. } => self.quantile(rng.random::<f64>()),
            Distribution::Levels(levels) => levels[rng.random_range(0..levels.len())],
        }
    }

    /// Smallest and largest value [`Distribution::quantile`] gives (the extreme coordinates).
    pub fn draw_range(&self) -> (f64, f64) {
        (self.quantile(0.0), self.quantile(1.0 - f64::EPSILON))
    }

    /// Grid values of this axis (uniform with a count, or levels); None if it has none.
    pub fn grid_values(&self) -> Option<Vec<f64>> {
        match self {
            Distribution::Uniform {
                min,
                max,
                count: Some(n),
            } => Some(if *n == 1 {
                vec![0.5 * (min + max)]
            } else {
                (0..*n)
                    .map(|i| min + (max - min) * i as f64 / (*n - 1) as f64)
                    .collect()
            }),
            Distribution::Levels(l) => Some(l.clone()),
            _ => None,
        }
    }

    /// Smallest and largest value the distribution can produce (infinite for unbounded ones).
    pub fn support(&self) -> (f64, f64) {
        match self {
            Distribution::Uniform { min, max, .. }
            | Distribution::TruncatedNormal { min, max, .. } => (*min, *max),
            Distribution::Normal { .. } => (f64::NEG_INFINITY, f64::INFINITY),
            Distribution::LogNormal { .. } => (0.0, f64::INFINITY),
            Distribution::Levels(l) => (
                l.iter().cloned().fold(f64::INFINITY, f64::min),
                l.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
            ),
        }
    }

    /// Mean and variance (for tests and documentation).
    pub fn moments(&self) -> (f64, f64) {
        match self {
            Distribution::Uniform { min, max, .. } => {
                (0.5 * (min + max), (max - min).powi(2) / 12.0)
            }
            Distribution::Normal { mean, sd } => (*mean, sd * sd),
            Distribution::TruncatedNormal { mean, sd, min, max } => {
                // Density at the bounds over the mass, each ratio formed in log space.
                let (a, b) = ((min - mean) / sd, (max - mean) / sd);
                let ln_z = ln_normal_mass(a, b);
                let (ra, rb) = (
                    (ln_normal_pdf(a) - ln_z).exp(),
                    (ln_normal_pdf(b) - ln_z).exp(),
                );
                let m = mean + sd * (ra - rb);
                let v = sd * sd * (1.0 + a * ra - b * rb - (ra - rb).powi(2));
                (m, v)
            }
            Distribution::LogNormal { median, sigma } => {
                let s2 = sigma * sigma;
                (
                    median * (s2 / 2.0).exp(),
                    median * median * s2.exp() * (s2.exp() - 1.0),
                )
            }
            Distribution::Levels(l) => {
                let n = l.len() as f64;
                let m = l.iter().sum::<f64>() / n;
                (m, l.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantile_inverts_cdf() {
        for i in 1..2000 {
            let p = i as f64 / 2000.0;
            let x = normal_quantile(p);
            assert!((normal_cdf(x) - p).abs() < 1e-14, "p {p}: {x}");
        }
        for p in [1e-12, 1e-8, 1e-4, 1.0 - 1e-4, 1.0 - 1e-8] {
            let x = normal_quantile(p);
            assert!(
                ((normal_cdf(x) - p) / p.min(1.0 - p)).abs() < 1e-9,
                "p {p}: {x}"
            );
        }
        assert!((normal_quantile(0.975) - 1.959963984540054).abs() < 1e-13);
    }

    #[test]
    fn marginal_moments_match_each_distribution() {
        let dists = [
            Distribution::Uniform {
                min: 2.0,
                max: 5.0,
                count: None,
            },
            Distribution::Normal {
                mean: 4000.0,
                sd: 500.0,
            },
            Distribution::TruncatedNormal {
                mean: 0.25,
                sd: 0.15,
                min: 0.05,
                max: 0.6,
            },
            Distribution::LogNormal {
                median: 0.8645e6,
                sigma: 0.1,
            },
            Distribution::Levels(vec![200.0, 240.0, 280.0]),
        ];
        let n = 100_000u64;
        for (k, d) in dists.iter().enumerate() {
            let xs: Vec<f64> = (0..n)
                .map(|i| d.quantile(crate::sampling::uniform01(99, i, k as u64)))
                .collect();
            let mean = xs.iter().sum::<f64>() / n as f64;
            let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
            let (m, v) = d.moments();
            // Mean within 4 standard errors, variance within 3%.
            assert!(
                (mean - m).abs() < 4.0 * (v / n as f64).sqrt(),
                "{d:?}: mean {mean} vs {m}"
            );
            assert!((var / v - 1.0).abs() < 0.03, "{d:?}: var {var} vs {v}");
            let (lo, hi) = d.support();
            assert!(
                xs.iter().all(|x| *x >= lo && *x <= hi),
                "{d:?} left its support"
            );
        }
    }

    /// The CDF of Normal(mean, sd) truncated to [min, max] in closed form, on erf where both
    /// bounds are near the mean (no cancellation: erf keeps its relative accuracy at 0) and on
    /// erfc in the upper tail.
    fn truncated_cdf(mean: f64, sd: f64, min: f64, max: f64, x: f64) -> f64 {
        let z = |v: f64| (v - mean) / (sd * SQRT_2);
        if min >= mean {
            let (ea, ex, eb) = (libm::erfc(z(min)), libm::erfc(z(x)), libm::erfc(z(max)));
            (ea - ex) / (ea - eb)
        } else {
            let (ea, ex, eb) = (libm::erf(z(min)), libm::erf(z(x)), libm::erf(z(max)));
            (ex - ea) / (eb - ea)
        }
    }

    #[test]
    fn a_truncated_normal_tends_to_the_uniform_as_sd_grows() {
        // sd = 1e20 over [0, 1]: the closed-form CDF is (x − min)/(max − min) to 1e-20.
        for (mean, sd) in [(0.5, 1e20), (0.5, 1e15), (1e300, 1e300), (-3.0, 1e300)] {
            let d = Distribution::TruncatedNormal {
                mean,
                sd,
                min: 0.0,
                max: 1.0,
            };
            let xs: Vec<f64> = (0..2000)
                .map(|i| d.quantile((i as f64 + 0.5) / 2000.0))
                .collect();
            for (i, x) in xs.iter().enumerate() {
                let u = (i as f64 + 0.5) / 2000.0;
                assert!((x - u).abs() < 1e-12, "mean {mean} sd {sd}: F⁻¹({u}) = {x}");
            }
        }
        // Narrow intervals against sd, where the series replaces Φ: at the mean, and 5 sd out.
        for (mean, sd, min, max) in [(0.0, 10.0, -0.05, 0.05), (0.0, 1.0, 5.0, 5.001)] {
            let d = Distribution::TruncatedNormal { mean, sd, min, max };
            for i in 0..=100 {
                let u = i as f64 / 100.0;
                let f = truncated_cdf(mean, sd, min, max, d.quantile(u));
                assert!(
                    (f - u).abs() < 1e-9,
                    "[{min}, {max}] sd {sd}: F(F⁻¹({u})) = {f}"
                );
            }
        }
        // Wide against sd, Φ as before: the values are those of the standardised quantile.
        let z = truncated_normal_quantile(-1.0, 2.0, 0.3);
        let d = Distribution::TruncatedNormal {
            mean: 1.0,
            sd: 0.5,
            min: 0.5,
            max: 2.0,
        };
        assert_eq!(d.quantile(0.3), (1.0 + 0.5 * z).clamp(0.5, 2.0));
    }
}
