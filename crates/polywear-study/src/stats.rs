//! Statistics of the analysis: Wilson score intervals, intervals for the difference of two
//! proportions (Newcombe's square-and-add, paired and independent), McNemar's test for paired
//! outcomes, and Sobol sensitivity indices (Saltelli/Jansen estimators) with bootstrap intervals.

/// A p-value for people: below 1e-300 it reads "< 1e-300" rather than an underflowed 0, and
/// "n/a" where the test had no data (NaN).
pub fn format_p(p: f64) -> String {
    if p.is_nan() {
        "n/a".into()
    } else if p < 1e-300 {
        "< 1e-300".into()
    } else {
        format!("{p:.3e}")
    }
}

/// The method of a test that had no data to test.
pub(crate) const NO_TEST: &str = "none";

/// z for a two-sided 95% interval.
pub const Z95: f64 = 1.959_963_984_540_054;

/// Wilson score interval for `k` successes in `n` trials (95%); (NaN, NaN) when n = 0.
pub fn wilson(k: u64, n: u64) -> (f64, f64) {
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    wilson_share(k as f64 / n as f64, n as f64)
}

/// Wilson score interval (95%) of a share `p` observed on `n` trials, `n` a count or an
/// effective count of weighted trials (Kish); (NaN, NaN) when n ≤ 0.
pub fn wilson_share(p: f64, n: f64) -> (f64, f64) {
    if n.is_nan() || n <= 0.0 {
        return (f64::NAN, f64::NAN);
    }
    let z2 = Z95 * Z95;
    let denom = 1.0 + z2 / n;
    let center = (p + z2 / (2.0 * n)) / denom;
    let half = Z95 / denom * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    ((center - half).max(0.0), (center + half).min(1.0))
}

/// 95% interval for the difference p₁ − p₂ of two proportions measured on the same samples:
/// Newcombe's square-and-add interval for paired data (Newcombe 1998, Stat. Med. 17:2635,
/// method 10), built from the Wilson intervals of both proportions and the correlation φ of the
/// paired outcomes (corrected: φ = (ad − bc − n/2)/√(…) when ad − bc > n/2, 0 up to n/2,
/// uncorrected when negative). `a`: samples where both are yes, `b`: only the first, `c`: only
/// the second, `d`: neither. (NaN, NaN) without samples.
pub fn newcombe_paired(a: u64, b: u64, c: u64, d: u64) -> (f64, f64) {
    let n = a + b + c + d;
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let nf = n as f64;
    let (p1, p2) = ((a + b) as f64 / nf, (a + c) as f64 / nf);
    let ((l1, u1), (l2, u2)) = (wilson(a + b, n), wilson(a + c, n));
    let margins = [
        (a + b) as f64,
        (c + d) as f64,
        (a + c) as f64,
        (b + d) as f64,
    ];
    let phi = if margins.contains(&0.0) {
        0.0
    } else {
        let cross = a as f64 * d as f64 - b as f64 * c as f64;
        let num = if cross > nf / 2.0 {
            cross - nf / 2.0
        } else if cross >= 0.0 {
            0.0
        } else {
            cross
        };
        num / margins.iter().product::<f64>().sqrt()
    };
    let theta = p1 - p2;
    let (dl1, du2) = (p1 - l1, u2 - p2);
    let (dl2, du1) = (p2 - l2, u1 - p1);
    let lo = theta
        - (dl1 * dl1 + du2 * du2 - 2.0 * phi * dl1 * du2)
            .max(0.0)
            .sqrt();
    let hi = theta
        + (dl2 * dl2 + du1 * du1 - 2.0 * phi * dl2 * du1)
            .max(0.0)
            .sqrt();
    (lo.max(-1.0), hi.min(1.0))
}

/// 95% interval for p₁ − p₂ of two independent proportions k₁/n₁ and k₂/n₂: Newcombe's hybrid
/// score interval (Newcombe 1998, Stat. Med. 17:873, method 10), the paired interval with φ = 0.
/// What two separate runs of the same size would give.
pub fn newcombe_independent(k1: u64, n1: u64, k2: u64, n2: u64) -> (f64, f64) {
    if n1 == 0 || n2 == 0 {
        return (f64::NAN, f64::NAN);
    }
    let (p1, p2) = (k1 as f64 / n1 as f64, k2 as f64 / n2 as f64);
    let ((l1, u1), (l2, u2)) = (wilson(k1, n1), wilson(k2, n2));
    let theta = p1 - p2;
    (
        theta - ((p1 - l1).powi(2) + (u2 - p2).powi(2)).sqrt(),
        theta + ((u1 - p1).powi(2) + (p2 - l2).powi(2)).sqrt(),
    )
}

/// McNemar's test on the discordant pairs `b` (only the first vibrates) and `c` (only the
/// second): the exact two-sided binomial p-value up to 10,000 discordant pairs, the
/// continuity-corrected chi-square beyond. Returns (statistic, p-value, method). Without a
/// discordant pair there is nothing to test: NaN for both, method `NO_TEST`.
pub fn mcnemar(b: u64, c: u64) -> (f64, f64, &'static str) {
    let n = b + c;
    if n == 0 {
        return (f64::NAN, f64::NAN, NO_TEST);
    }
    let chi2 = ((b as f64 - c as f64).abs() - 1.0).max(0.0).powi(2) / n as f64;
    if n <= 10_000 {
        // 2 * P(X <= min(b, c)) for X ~ Binomial(n, 1/2), summed in log space.
        let k = b.min(c);
        let ln_half_n = n as f64 * 0.5f64.ln();
        let ln_choose = |i: u64| {
            libm::lgamma(n as f64 + 1.0)
                - libm::lgamma(i as f64 + 1.0)
                - libm::lgamma((n - i) as f64 + 1.0)
        };
        let tail: f64 = (0..=k).map(|i| (ln_choose(i) + ln_half_n).exp()).sum();
        (chi2, (2.0 * tail).min(1.0), "exact")
    } else {
        (chi2, libm::erfc((chi2 / 2.0).sqrt()), "chi2")
    }
}

/// First-order and total Sobol indices of one input from a Saltelli design:
/// `f_a`, `f_b` the outputs on the two base matrices and `f_ab` on A with column i from B.
/// First order: Saltelli et al. (2010), mean(f_B (f_ABi − f_A)) / V; total: Jansen (1999),
/// mean((f_A − f_ABi)²) / 2V; V the variance of f_A and f_B together. The first-order estimator
/// is not shift-invariant: callers centre the outputs on the mean of all evaluated rows first, as
/// SALib does.
pub(crate) fn sobol_indices(f_a: &[f64], f_b: &[f64], f_ab: &[f64]) -> (f64, f64) {
    let n = f_a.len() as f64;
    let all = f_a.iter().chain(f_b);
    let mean = all.clone().sum::<f64>() / (2.0 * n);
    let var = all.map(|y| (y - mean).powi(2)).sum::<f64>() / (2.0 * n);
    if var == 0.0 {
        return (f64::NAN, f64::NAN);
    }
    let mut first = 0.0;
    let mut total = 0.0;
    for j in 0..f_a.len() {
        first += f_b[j] * (f_ab[j] - f_a[j]);
        total += (f_a[j] - f_ab[j]).powi(2);
    }
    (first / n / var, total / (2.0 * n) / var)
}

/// Sobol indices with percentile bootstrap 95% intervals (resampling the base rows).
/// Returns ((S, lo, hi), (ST, lo, hi)).
pub fn sobol_with_bootstrap(
    f_a: &[f64],
    f_b: &[f64],
    f_ab: &[f64],
    resamples: usize,
    seed: u64,
) -> ((f64, f64, f64), (f64, f64, f64)) {
    let (s, st) = sobol_indices(f_a, f_b, f_ab);
    let n = f_a.len();
    let mut ss = Vec::with_capacity(resamples);
    let mut sts = Vec::with_capacity(resamples);
    let (mut a, mut b, mut ab) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let streams = polywear_core::sampling::Streams::new(seed);
    for r in 0..resamples {
        // One ChaCha12 stream per resample, drawn in sequence; rand's unbiased index.
        let mut rng = streams.at(r as u64, 0);
        for j in 0..n {
            let k = rand::RngExt::random_range(&mut rng, 0..n);
            a[j] = f_a[k];
            b[j] = f_b[k];
            ab[j] = f_ab[k];
        }
        let (x, y) = sobol_indices(&a, &b, &ab);
        if x.is_finite() && y.is_finite() {
            ss.push(x);
            sts.push(y);
        }
    }
    let pct = |v: &mut Vec<f64>, q: f64| {
        if v.is_empty() {
            return f64::NAN;
        }
        v.sort_by(f64::total_cmp);
        v[((q * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)]
    };
    (
        (s, pct(&mut ss, 0.025), pct(&mut ss, 0.975)),
        (st, pct(&mut sts, 0.025), pct(&mut sts, 0.975)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_matches_newcombe_1998() {
        // Newcombe, Stat. Med. 17 (1998) 857-872, Table I, method 3 (score, no correction).
        for (k, n, lo, hi) in [
            (81, 263, 0.2553, 0.3662),
            (15, 148, 0.0624, 0.1605),
            (0, 20, 0.0, 0.1611),
            (1, 29, 0.0061, 0.1718),
        ] {
            let (a, b) = wilson(k, n);
            assert!(
                (a - lo).abs() < 5e-5 && (b - hi).abs() < 5e-5,
                "{k}/{n}: ({a:.4}, {b:.4}) vs ({lo}, {hi})"
            );
        }
        assert!(wilson(0, 0).0.is_nan());
    }

    #[test]
    fn paired_interval_matches_the_published_example() {
        // Cavo et al. (2012) as Fagerland, Lydersen & Laake (2017, ch. 8) tabulate it: 59 both,
        // 6 only before, 16 only after, 80 neither; Newcombe's square-and-add interval
        // -0.0621 (-0.1186 to -0.0046).
        let (lo, hi) = newcombe_paired(59, 6, 16, 80);
        assert!(
            (lo + 0.1186).abs() < 5e-5 && (hi + 0.0046).abs() < 5e-5,
            "{lo} {hi}"
        );
        // No change at all: exactly zero width is not claimed, but the interval holds 0 and is
        // symmetric about it.
        let (lo, hi) = newcombe_paired(30, 0, 0, 70);
        assert!(lo < 0.0 && hi > 0.0 && (lo + hi).abs() < 1e-12, "{lo} {hi}");
        // The independent interval is the paired one without the correlation.
        let (lo, hi) = newcombe_independent(65, 161, 75, 161);
        assert!(lo < -0.1186 && hi > -0.0046, "{lo} {hi}");
    }

    /// Coverage of the paired interval on synthetic paired outcomes: 2,000 replications of
    /// n = 1,000 samples from a known joint distribution, for a small and a larger change.
    #[test]
    fn paired_interval_covers_95_percent() {
        // (P(both), P(only first), P(only second)); P(neither) is the rest.
        for (k, (p11, p10, p01)) in [(0.30, 0.01, 0.04), (0.20, 0.10, 0.05)]
            .into_iter()
            .enumerate()
        {
            let truth = p10 - p01;
            let (reps, n) = (2000u64, 1000u64);
            let mut covered = 0;
            let streams = polywear_core::sampling::Streams::new(77 + k as u64);
            for r in 0..reps {
                let mut t = [0u64; 4];
                let mut rng = streams.at(r, 0);
                for _ in 0..n {
                    let u: f64 = rand::RngExt::random(&mut rng);
                    let cell = if u < p11 {
                        0
                    } else if u < p11 + p10 {
                        1
                    } else if u < p11 + p10 + p01 {
                        2
                    } else {
                        3
                    };
                    t[cell] += 1;
                }
                let (lo, hi) = newcombe_paired(t[0], t[1], t[2], t[3]);
                if lo <= truth && truth <= hi {
                    covered += 1;
                }
            }
            let coverage = covered as f64 / reps as f64;
            assert!(
                (coverage - 0.95).abs() <= 0.015,
                "case {k}: coverage {coverage}"
            );
        }
    }

    #[test]
    fn mcnemar_exact_and_chi_square() {
        let (_, p, m) = mcnemar(0, 10);
        assert_eq!(m, "exact");
        assert!((p - 2.0 * 0.5f64.powi(10)).abs() < 1e-12);
        let (_, p, _) = mcnemar(5, 5);
        assert_eq!(p, 1.0);
        // No discordant pair: no test, and it says so.
        let (chi2, p, m) = mcnemar(0, 0);
        assert!(chi2.is_nan() && p.is_nan() && m == NO_TEST);
        assert_eq!(format_p(p), "n/a");
        assert_eq!(format_p(0.0), "< 1e-300");
        // Large samples: chi-square with continuity correction.
        let (chi2, p, m) = mcnemar(6000, 5500);
        assert_eq!(m, "chi2");
        assert!((chi2 - 499.0f64.powi(2) / 11500.0).abs() < 1e-9);
        assert!(p < 1e-5);
        // The exact test agrees with chi-square where both apply.
        let (chi2, p_exact, _) = mcnemar(250, 200);
        let p_chi = libm::erfc((chi2 / 2.0).sqrt());
        assert!((p_exact - p_chi).abs() < 0.005, "{p_exact} vs {p_chi}");
    }

    #[test]
    fn sobol_indices_of_the_ishigami_function() {
        use std::f64::consts::PI;
        let f =
            |x: [f64; 3]| x[0].sin() + 7.0 * x[1].sin().powi(2) + 0.1 * x[2].powi(4) * x[0].sin();
        let n = 20_000u64;
        let draw = |j: u64, d: u64| -PI + 2.0 * PI * polywear_core::sampling::uniform01(5, j, d);
        let a: Vec<[f64; 3]> = (0..n)
            .map(|j| [draw(j, 0), draw(j, 1), draw(j, 2)])
            .collect();
        let b: Vec<[f64; 3]> = (0..n)
            .map(|j| [draw(j, 3), draw(j, 4), draw(j, 5)])
            .collect();
        let fa: Vec<f64> = a.iter().map(|x| f(*x)).collect();
        let fb: Vec<f64> = b.iter().map(|x| f(*x)).collect();
        // Analytic values (Ishigami & Homma 1990, a = 7, b = 0.1).
        let want_s = [0.3139, 0.4424, 0.0];
        let want_st = [0.5576, 0.4424, 0.2437];
        for i in 0..3 {
            let fab: Vec<f64> = (0..n as usize)
                .map(|j| {
                    let mut x = a[j];
                    x[i] = b[j][i];
                    f(x)
                })
                .collect();
            let ((s, slo, shi), (st, stlo, sthi)) = sobol_with_bootstrap(&fa, &fb, &fab, 200, 9);
            assert!(
                slo <= want_s[i] && want_s[i] <= shi,
                "S{}: {s} [{slo}, {shi}] vs {}",
                i + 1,
                want_s[i]
            );
            assert!(
                stlo <= want_st[i] && want_st[i] <= sthi,
                "ST{}: {st} [{stlo}, {sthi}] vs {}",
                i + 1,
                want_st[i]
            );
            assert!(
                (shi - slo) < 0.1 && (sthi - stlo) < 0.1,
                "intervals too wide to mean anything"
            );
        }
    }
}
