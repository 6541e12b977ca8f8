//! Dumps polywear's quantile functions at 10,000 probabilities (1e-12 to 1 - 1e-12) for every
//! distribution of the shipped studies and a set of hard cases (far tails, truncation beyond
//! where Φ underflows), one JSON object per line, for `tests/data/quantiles_vs_scipy.py` to
//! check against SciPy's `ppf`. Run from `.ci/run`:
//!
//! ```sh
//! cargo run --release --example dump_quantiles > target/quantiles.jsonl
//! python3 tests/data/quantiles_vs_scipy.py target/quantiles.jsonl
//! ```

use std::io::Write;

use polywear::study::Study;
use polywear_core::sampling::distribution::Distribution;

/// 10,000 probabilities: 3,000 log-spaced from 1e-12 to ½, their complements, and 4,000 evenly
/// spaced midpoints.
fn probabilities() -> Vec<f64> {
    let mut p = Vec::with_capacity(10_000);
    let (lo, hi) = (-12.0f64, 0.5f64.log10());
    for k in 0..3000 {
        let x = 10f64.powf(lo + (hi - lo) * k as f64 / 2999.0);
        p.push(if k == 0 { 1e-12 } else { x });
    }
    for k in 0..3000 {
        p.push(1.0 - p[k]);
    }
    for k in 0..4000 {
        p.push((k as f64 + 0.5) / 4000.0);
    }
    p.sort_by(f64::total_cmp);
    p
}

fn spec(d: &Distribution) -> serde_json::Value {
    match d {
        Distribution::Uniform { min, max, .. } => {
            serde_json::json!({"dist": "uniform", "min": min, "max": max})
        }
        Distribution::Normal { mean, sd } => {
            serde_json::json!({"dist": "normal", "mean": mean, "sd": sd})
        }
        Distribution::TruncatedNormal { mean, sd, min, max } => serde_json::json!({
            "dist": "truncated_normal", "mean": mean, "sd": sd, "min": min, "max": max
        }),
        Distribution::LogNormal { median, sigma } => {
            serde_json::json!({"dist": "lognormal", "median": median, "sigma": sigma})
        }
        Distribution::Levels(l) => serde_json::json!({"dist": "levels", "levels": l}),
    }
}

fn main() {
    let mut cases: Vec<(String, Distribution)> = Vec::new();
    let studies = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let mut files: Vec<_> = std::fs::read_dir(&studies)
        .expect("studies/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    files.sort();
    for f in files {
        let Ok(study) = Study::parse(&std::fs::read_to_string(&f).expect("study file")) else {
            continue; // not a study (e.g. calibration targets)
        };
        let stem = f.file_stem().unwrap().to_string_lossy().to_string();
        for d in &study.drawn {
            cases.push((format!("{stem}.{}", d.param), d.dist.clone()));
        }
    }
    let tn = |mean, sd, min, max| Distribution::TruncatedNormal { mean, sd, min, max };
    cases.extend([
        (
            "standard_normal".into(),
            Distribution::Normal { mean: 0.0, sd: 1.0 },
        ),
        (
            "normal_load".into(),
            Distribution::Normal {
                mean: 4000.0,
                sd: 500.0,
            },
        ),
        (
            "lognormal_wide".into(),
            Distribution::LogNormal {
                median: 1.0,
                sigma: 2.0,
            },
        ),
        (
            "uniform".into(),
            Distribution::Uniform {
                min: 2.0,
                max: 5.0,
                count: None,
            },
        ),
        ("tn_far_upper_tail".into(), tn(240.0, 8.0, 312.0, 400.0)),
        ("tn_lower_tail".into(), tn(240.0, 8.0, 100.0, 168.0)),
        ("tn_symmetric".into(), tn(0.0, 1.0, -1.0, 1.0)),
        ("tn_one_sided_upper".into(), tn(0.0, 1.0, -0.5, 30.0)),
        ("tn_narrow_left".into(), tn(0.0, 1.0, -3.0, -2.9)),
        ("tn_beyond_underflow_upper".into(), tn(0.0, 1.0, 40.0, 45.0)),
        (
            "tn_beyond_underflow_lower".into(),
            tn(0.0, 1.0, -45.0, -40.0),
        ),
        ("tn_wide_upper_tail".into(), tn(0.0, 1.0, 8.0, 1000.0)),
        (
            "levels".into(),
            Distribution::Levels(vec![200.0, 240.0, 280.0, 320.0, 360.0]),
        ),
    ]);
    let p = probabilities();
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    for (name, d) in &cases {
        let x: Vec<f64> = p.iter().map(|u| d.quantile(*u)).collect();
        let mut obj = spec(d);
        obj["case"] = name.as_str().into();
        obj["p"] = serde_json::json!(p);
        obj["x"] = serde_json::json!(x);
        writeln!(out, "{obj}").expect("stdout");
    }
}
