//! Parameter distributions of a study, sampled by inverse CDF from a uniform coordinate.

use std::f64::consts::{PI, SQRT_2};

/// How one parameter is drawn.
#[derive(Debug, Clone, PartialEq)]
pub enum Distribution {
    /// Uniform on [min, max]; in a grid design, `count` evenly spaced values from min to max.
    Uniform {
        min: f64,
        max: f64,
        count: Option<usize>,
    },
    Normal {
        mean: f64,
        sd: f64,
    },
    /// Normal(mean, sd) restricted to [min, max].
    TruncatedNormal {
        mean: f64,
        sd: f64,
        min: f64,
        max: f64,
    },
    /// exp(N(ln median, sigma²)).
    LogNormal {
        median: f64,
        sigma: f64,
    },
    /// Each level equally likely; in a grid design, exactly these levels.
    Levels(Vec<f64>),
}

/// Standard normal CDF Φ(x).
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / SQRT_2)
}

/// Standard normal quantile Φ⁻¹(p) for p in (0, 1): Acklam's rational approximation refined
/// by one Halley step on erfc, accurate to about 1e-15.
pub fn normal_quantile(p: f64) -> f64 {
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
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let x = if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    };
    // Halley refinement.
    let e = normal_cdf(x) - p;
    let u = e * (2.0 * PI).sqrt() * (x * x / 2.0).exp();
    x - u / (1.0 + x * u / 2.0)
}

impl Distribution {
    /// The value at uniform coordinate `u` in [0, 1).
    pub fn quantile(&self, u: f64) -> f64 {
        // Keep u strictly inside (0, 1) for the unbounded distributions.
        let u_open = u.clamp(f64::EPSILON, 1.0 - f64::EPSILON);
        match self {
            Distribution::Uniform { min, max, .. } => min + u * (max - min),
            Distribution::Normal { mean, sd } => mean + sd * normal_quantile(u_open),
            Distribution::TruncatedNormal { mean, sd, min, max } => {
                let (a, b) = (normal_cdf((min - mean) / sd), normal_cdf((max - mean) / sd));
                (mean + sd * normal_quantile(a + u_open * (b - a))).clamp(*min, *max)
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
                let (a, b) = ((min - mean) / sd, (max - mean) / sd);
                let pdf = |x: f64| (-0.5 * x * x).exp() / (2.0 * PI).sqrt();
                let z = normal_cdf(b) - normal_cdf(a);
                let m = mean + sd * (pdf(a) - pdf(b)) / z;
                let v = sd
                    * sd
                    * (1.0 + (a * pdf(a) - b * pdf(b)) / z - ((pdf(a) - pdf(b)) / z).powi(2));
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
}
