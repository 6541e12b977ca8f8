//! The random streams and the quantile functions: uniformity and independence tests
//! that a weak generator fails (each is also run on a deliberately flawed stream, which it must
//! reject), pinned values so that a dependency update that changes the stream is caught, the
//! truncated-normal far tails, and `--resume` refusing a directory written with
//! another generator.

use crate::common;
use polywear::study::Study;
use polywear_core::sampling::design::{Coordinates, Design};
use polywear_core::sampling::distribution::{
    ln_normal_cdf, ln_normal_mass, normal_cdf, normal_quantile, normal_quantile_of_ln,
    truncated_normal_quantile, Distribution,
};
use polywear_core::sampling::{Streams, RNG_NAME};

const N: usize = 1_000_000;
const SEED: u64 = 2014;

/// Wilson–Hilferty bounds of a chi-square with `dof` degrees of freedom at ±z standard normal
/// deviates (z = 5: a false alarm once in 1.7 million runs on each side).
fn chi2_bounds(dof: f64, z: f64) -> (f64, f64) {
    let s = (2.0 / (9.0 * dof)).sqrt();
    let m = 1.0 - 2.0 / (9.0 * dof);
    (dof * (m - z * s).powi(3), dof * (m + z * s).powi(3))
}

/// Pearson's chi-square of values in [0, 1) over `bins` equal bins.
fn chi2_uniform(us: &[f64], bins: usize) -> f64 {
    let mut counts = vec![0u64; bins];
    for u in us {
        assert!((0.0..1.0).contains(u), "{u} outside [0, 1)");
        counts[(u * bins as f64) as usize] += 1;
    }
    let e = us.len() as f64 / bins as f64;
    counts.iter().map(|c| (*c as f64 - e).powi(2) / e).sum()
}

/// Chi-square of pairs over a `k`×`k` grid (independence and uniformity of the pair).
fn chi2_pairs(xs: &[f64], ys: &[f64], k: usize) -> f64 {
    let mut counts = vec![0u64; k * k];
    for (x, y) in xs.iter().zip(ys) {
        counts[(x * k as f64) as usize * k + (y * k as f64) as usize] += 1;
    }
    let e = xs.len() as f64 / (k * k) as f64;
    counts.iter().map(|c| (*c as f64 - e).powi(2) / e).sum()
}

/// Pearson correlation.
fn correlation(xs: &[f64], ys: &[f64]) -> f64 {
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (x, y) in xs.iter().zip(ys) {
        sxy += (x - mx) * (y - my);
        sxx += (x - mx).powi(2);
        syy += (y - my).powi(2);
    }
    sxy / (sxx * syy).sqrt()
}

fn uniform_ok(us: &[f64]) -> Result<(), String> {
    let (lo, hi) = chi2_bounds(999.0, 5.0);
    let c = chi2_uniform(us, 1000);
    if (lo..hi).contains(&c) {
        Ok(())
    } else {
        Err(format!(
            "chi-square {c:.1} over 1000 bins outside [{lo:.1}, {hi:.1}]"
        ))
    }
}

fn independent_ok(xs: &[f64], ys: &[f64]) -> Result<(), String> {
    // |r| ≤ 5/√n, and the 32×32 contingency chi-square inside its bounds.
    let r = correlation(xs, ys);
    let limit = 5.0 / (xs.len() as f64).sqrt();
    if r.abs() > limit {
        return Err(format!("correlation {r:.2e} beyond {limit:.1e}"));
    }
    let (lo, hi) = chi2_bounds(1023.0, 5.0);
    let c = chi2_pairs(xs, ys, 32);
    if !(lo..hi).contains(&c) {
        return Err(format!("pair chi-square {c:.1} outside [{lo:.1}, {hi:.1}]"));
    }
    Ok(())
}

#[test]
fn draws_are_uniform_over_a_million_samples() {
    let s = Streams::new(SEED);
    for axis in [0u64, 7] {
        let us: Vec<f64> = (0..N as u64).map(|i| s.uniform01(i, axis)).collect();
        uniform_ok(&us).unwrap_or_else(|e| panic!("axis {axis}: {e}"));
    }
    // Within one axis's stream, consecutive draws (as a rejection sampler takes them).
    let mut rng = s.at(12345, 2);
    let us: Vec<f64> = (0..N)
        .map(|_| rand::RngExt::random::<f64>(&mut rng))
        .collect();
    uniform_ok(&us).unwrap();
    // The test has power: a stream with a mild bias (u^1.03) is rejected.
    let biased: Vec<f64> = (0..N as u64)
        .map(|i| s.uniform01(i, 0).powf(1.03))
        .collect();
    assert!(uniform_ok(&biased).is_err(), "a biased stream passed");
}

#[test]
fn neighbouring_samples_and_axes_are_independent() {
    let s = Streams::new(SEED);
    let axis = |a: u64| -> Vec<f64> { (0..N as u64 + 1).map(|i| s.uniform01(i, a)).collect() };
    let a0 = axis(0);
    // Neighbouring sample indices, one axis.
    independent_ok(&a0[..N], &a0[1..]).unwrap_or_else(|e| panic!("neighbours: {e}"));
    // Axes of one sample, every pair of the first 8 (the default study draws 8).
    let axes: Vec<Vec<f64>> = std::iter::once(a0.clone())
        .chain((1..8).map(axis))
        .collect();
    for i in 0..8 {
        for j in i + 1..8 {
            independent_ok(&axes[i][..N], &axes[j][..N])
                .unwrap_or_else(|e| panic!("axes {i} and {j}: {e}"));
        }
    }
    // Neighbouring seeds.
    let other = Streams::new(SEED + 1);
    let b0: Vec<f64> = (0..N as u64).map(|i| other.uniform01(i, 0)).collect();
    independent_ok(&a0[..N], &b0).unwrap_or_else(|e| panic!("seeds: {e}"));
    // The tests have power: a weakly dependent neighbour (a 5% share of the previous value),
    // and a non-linear dependence with no correlation at all (|2x - 1| vs x), are rejected.
    let mixed: Vec<f64> = a0
        .windows(2)
        .map(|w| (0.95 * w[1] + 0.05 * w[0]).min(0.999_999))
        .collect();
    assert!(independent_ok(&a0[..N - 1], &mixed[..N - 1]).is_err());
    let folded: Vec<f64> = a0[..N].iter().map(|x| (2.0 * x - 1.0).abs()).collect();
    assert!(correlation(&a0[..N], &folded).abs() < 5e-3);
    assert!(independent_ok(&a0[..N], &folded).is_err());
}

#[test]
fn random_design_draws_follow_their_distributions() {
    // Probability integral transform: F(draw) must be uniform for each distribution drawn
    // directly with rand_distr (or by inverse CDF for the truncated normal).
    type Cdf = Box<dyn Fn(f64) -> f64>;
    let cases: Vec<(Distribution, Cdf)> = vec![
        (
            Distribution::Normal {
                mean: 4000.0,
                sd: 500.0,
            },
            Box::new(|x| normal_cdf((x - 4000.0) / 500.0)),
        ),
        (
            Distribution::LogNormal {
                median: 0.8645e6,
                sigma: 0.05,
            },
            Box::new(|x: f64| normal_cdf((x / 0.8645e6).ln() / 0.05)),
        ),
        (
            Distribution::Uniform {
                min: 60.0,
                max: 200.0,
                count: None,
            },
            Box::new(|x| (x - 60.0) / 140.0),
        ),
        (
            Distribution::TruncatedNormal {
                mean: 115.0,
                sd: 25.0,
                min: 60.0,
                max: 200.0,
            },
            Box::new(|x| {
                let (a, b) = (normal_cdf(-55.0 / 25.0), normal_cdf(85.0 / 25.0));
                (normal_cdf((x - 115.0) / 25.0) - a) / (b - a)
            }),
        ),
    ];
    let coords = Coordinates::new(Design::Random, SEED, N as u64, 1);
    for (d, cdf) in &cases {
        let us: Vec<f64> = (0..N as u64 / 4)
            .map(|i| cdf(coords.value(i, 0, d)).min(1.0 - 1e-12))
            .collect();
        uniform_ok(&us).unwrap_or_else(|e| panic!("{d:?}: {e}"));
    }
    // Levels: each equally likely.
    let d = Distribution::Levels(vec![1.0, 2.0, 3.0, 4.0, 5.0]);
    let mut counts = [0u64; 5];
    for i in 0..N as u64 / 4 {
        counts[coords.value(i, 0, &d) as usize - 1] += 1;
    }
    let e = N as f64 / 20.0;
    let c: f64 = counts.iter().map(|k| (*k as f64 - e).powi(2) / e).sum();
    assert!(c < chi2_bounds(4.0, 5.0).1, "levels {counts:?}");
}

#[test]
fn pinned_values_reproduce_across_builds() {
    // The stream is part of the output's contract (`rng` metadata): a dependency update that
    // changes it must fail here, not silently change rows.
    let s = Streams::new(SEED);
    assert_eq!(
        [s.bits(0, 0), s.bits(1, 0), s.bits(0, 1), s.bits(999_999, 7)],
        PINNED_BITS
    );
    // A fixed copy of the default study, so that the shipped defaults can move.
    let study = Study::parse(PINNED_STUDY).unwrap();
    let sampler = study.sampler(study.seed, study.samples);
    let (_, values) = sampler.sample(12_345);
    // The bits are exact; the values pass through the platform's ln and exp, hence 1e-12.
    for (v, pinned) in values.iter().zip(PINNED_SAMPLE_12345) {
        assert!(((v - pinned) / pinned).abs() < 1e-12, "{values:?}");
    }
    assert!(RNG_NAME.starts_with("ChaCha12Rng"));
}

const PINNED_BITS: [u64; 4] = [
    1872743519639272642,
    8575124341919020688,
    7088150796675597632,
    13181290650984201415,
];
/// Sample 12,345 of the default study (speed, toe, load, pressure, tread height, rho, g_mod,
/// c_brush).
/// The default study's axes and structure uncertainty, frozen (the medians of `g_mod` and
/// `c_brush` are R0, MODEL.md#r0-and-the-shipped-defaults).
const PINNED_STUDY: &str = r#"
name = "highway_fleet"
seed = 2014
samples = 100000
design = "random"
[params]
speed_kmh    = { dist = "truncated_normal", mean = 115, sd = 25, min = 60, max = 200 }
toe_deg      = { dist = "truncated_normal", mean = 0.25, sd = 0.12, min = 0.02, max = 0.8 }
load_n       = { dist = "truncated_normal", mean = 4000, sd = 600, min = 2500, max = 6500 }
pressure_kpa = { dist = "truncated_normal", mean = 240, sd = 20, min = 180, max = 320 }
g_mod        = { dist = "lognormal", median = 0.8645e6, sigma = 0.05 }
c_brush      = { dist = "lognormal", median = 3.6e7, sigma = 0.05 }
tread_height = { dist = "truncated_normal", mean = 0.015, sd = 0.0005, min = 0.0135, max = 0.0165 }
rho          = { dist = "truncated_normal", mean = 1250, sd = 25, min = 1175, max = 1325 }
"#;

const PINNED_SAMPLE_12345: [f64; 8] = [
    130.40256116222704,
    0.1152590008999837,
    4041.363576968214,
    233.8407982998501,
    0.014724913029328584,
    1274.5726563437124,
    844998.335451863,
    34950607.87933827,
];

#[test]
fn truncated_normal_far_in_a_tail_stays_near_its_bound() {
    // { mean = 240, sd = 8, min = 312, max = 400 }: a quantile computed on the wrong side of the
    // median gives 400 for every row. The interval starts 9 sd above the mean, so the values pile up just above 312: the density
    // falls by e^-9 per sd there, mean ≈ 312 + 8/9.
    let d = Distribution::TruncatedNormal {
        mean: 240.0,
        sd: 8.0,
        min: 312.0,
        max: 400.0,
    };
    let median = d.quantile(0.5);
    // Exponential approximation of the tail: median ≈ 312 + 8·ln 2/(9 + 1/9).
    assert!(
        (median - (312.0 + 8.0 * 2f64.ln() / (9.0 + 1.0 / 9.0))).abs() < 0.01,
        "{median}"
    );
    assert!(d.quantile(0.0) == 312.0 && d.quantile(1e-12) >= 312.0);
    // 0.999 quantile ≈ 312 + (8/9)·ln 1000.
    let q999 = d.quantile(0.999);
    assert!((317.0..319.0).contains(&q999), "{q999}");
    let (m, v) = d.moments();
    assert!(
        (m - 312.87).abs() < 0.02 && v > 0.0 && v < 1.0,
        "moments {m} {v}"
    );
    // The same in the lower tail, mirrored.
    let lower = Distribution::TruncatedNormal {
        mean: 240.0,
        sd: 8.0,
        min: 100.0,
        max: 168.0,
    };
    assert!((lower.quantile(0.5) - (480.0 - median)).abs() < 1e-9);
    // Beyond where Φ itself underflows (40 sd): still near the bound, still monotone.
    let extreme = Distribution::TruncatedNormal {
        mean: 0.0,
        sd: 1.0,
        min: 40.0,
        max: 45.0,
    };
    let xs: Vec<f64> = (1..1000)
        .map(|k| extreme.quantile(k as f64 / 1000.0))
        .collect();
    assert!(xs.windows(2).all(|w| w[0] <= w[1]) && xs[0] > 40.0 && xs[998] < 40.3);

    // Through a study, in every design: all 400 rows just above 312, none at 400.
    for design in ["random", "lhs", "sobol"] {
        let study = Study::parse(&format!(
            "design = \"{design}\"\nsamples = 400\n[params]\npressure_kpa = {{ dist = \"truncated_normal\", mean = 240, sd = 8, min = 312, max = 400 }}"
        ))
        .unwrap();
        let sampler = study.sampler(study.seed, 400);
        let xs: Vec<f64> = (0..400).map(|i| sampler.sample(i).1[0]).collect();
        let mean = xs.iter().sum::<f64>() / 400.0;
        assert!(
            xs.iter().all(|x| (312.0..325.0).contains(x)),
            "{design}: {:?}",
            xs.iter().cloned().fold(f64::NAN, f64::max)
        );
        assert!((mean - 312.87).abs() < 0.15, "{design}: mean {mean}");
    }
}

#[test]
fn truncated_normal_quantile_inverts_its_cdf_everywhere() {
    // Intervals in the body, in either tail, beyond Φ's underflow, narrow and wide: the
    // quantile stays inside [a, b], never decreases, and its CDF gives back u.
    for a in [-60.0, -40.0, -9.0, -3.0, -0.5, 0.0, 0.5, 3.0, 9.0, 40.0] {
        for width in [1e-3, 0.1, 1.0, 5.0, 100.0] {
            let b: f64 = a + width;
            let ln_mass = ln_normal_mass(a, b);
            assert!(ln_mass.is_finite(), "[{a}, {b}]");
            let mut last = f64::NEG_INFINITY;
            for k in 0..=2000 {
                let u = k as f64 / 2000.0;
                let x = truncated_normal_quantile(a, b, u);
                assert!(
                    x >= a && x <= b && x >= last,
                    "[{a}, {b}] u {u}: {x} after {last}"
                );
                last = x;
                let cdf = if x > a {
                    (ln_normal_mass(a, x) - ln_mass).exp()
                } else {
                    0.0
                };
                assert!(
                    (cdf - u).abs() < 1e-9,
                    "[{a}, {b}] u {u}: x {x}, F(x) {cdf}"
                );
            }
        }
    }
}

#[test]
fn normal_quantiles_hold_their_accuracy_in_both_tails() {
    // Reference values (mpmath, 50 digits).
    for (p, x) in [
        (1e-12, -7.034_483_825_301_132),
        (1e-300, -37.047_096_299_361_2),
        (0.975, 1.959_963_984_540_054),
        (0.5 + 1e-12, 2.506_572_823_701_860_5e-12),
    ] {
        let q = normal_quantile(p);
        assert!(((q - x) / x).abs() < 1e-14, "p {p}: {q} vs {x}");
    }
    // 1 - 1e-12 is the exact mirror of its own complement.
    let p = 1.0 - 1e-12;
    assert_eq!(normal_quantile(p), -normal_quantile(1.0 - p));
    // ln Φ and its inverse, far beyond f64's smallest probability.
    for y in [-1e-12, -0.1, -0.69, -1.0, -50.0, -699.0, -701.0, -1e4, -1e6] {
        let x = normal_quantile_of_ln(y);
        assert!(
            ((ln_normal_cdf(x) - y) / y).abs() < 1e-13,
            "ln p {y}: x {x}"
        );
    }
    assert!((ln_normal_cdf(-40.0) - (-804.608_442_013_753_8)).abs() < 1e-10);
}

#[test]
fn resume_refuses_a_directory_of_another_generator() {
    let dir = common::fresh_dir("sampling-rng-resume");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("s.toml");
    std::fs::write(
        &study,
        "name = \"tiny\"\nsamples = 8\nchunk_size = 4\n[params]\nspeed_kmh = { dist = \"uniform\", min = 60, max = 200 }\n",
    )
    .unwrap();
    let out = dir.join("out");
    let args = |resume: bool| {
        let mut a = vec![
            "explore".to_string(),
            "--quiet".into(),
            study.to_str().unwrap().into(),
            "--out".into(),
            out.to_str().unwrap().into(),
        ];
        if resume {
            a.push("--resume".into());
        }
        a
    };
    let run = |resume: bool| {
        let a = args(resume);
        common::polywear(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let (code, _, stderr) = run(false);
    assert_eq!(code, 0, "{stderr}");
    // The generator is recorded in the manifest and in every chunk's metadata.
    let manifest_path = out.join("_manifest.json");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&manifest_path).unwrap()).unwrap();
    assert_eq!(manifest["rng"], RNG_NAME);
    let chunk = std::fs::read(out.join("chunk-0000000.parquet")).unwrap();
    let needle = RNG_NAME.as_bytes();
    assert!(
        chunk.windows(needle.len()).any(|w| w == needle),
        "rng not in the chunk metadata"
    );
    // Same generator: resumes (nothing left to do).
    let (code, _, stderr) = run(true);
    assert_eq!(code, 0, "{stderr}");
    // Another generator, or none recorded: refused before any work.
    for old in [
        serde_json::json!("SplitMix64 counter hash"),
        serde_json::Value::Null,
    ] {
        let mut m = manifest.clone();
        match &old {
            serde_json::Value::Null => {
                m.as_object_mut().unwrap().remove("rng");
            }
            v => m["rng"] = v.clone(),
        }
        std::fs::write(&manifest_path, serde_json::to_string(&m).unwrap()).unwrap();
        std::fs::remove_file(out.join("chunk-0000001.parquet")).unwrap_or(());
        let (code, _, stderr) = run(true);
        assert_eq!(code, 2, "{old}: {stderr}");
        assert!(stderr.contains("random generator"), "{stderr}");
        assert!(!out.join("chunk-0000001.parquet").exists(), "work was done");
    }
    std::fs::remove_dir_all(&dir).ok();
}
