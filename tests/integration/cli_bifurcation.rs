//! `polywear bifurcation`: Hopf points of the speed sweep at the constants R0
//! (MODEL.md#r0-and-the-shipped-defaults) (≈ 93–224 km/h for the follower), the Parquet table and
//! the PNG, and bad input.

use crate::common;
use crate::common::polywear;

#[test]
fn speed_sweep_finds_both_hopf_points_and_writes_files() {
    let dir = std::env::temp_dir().join(format!("polywear-bif-{}", std::process::id()));
    let prefix = dir.join("speed");
    let (code, stdout, stderr) = polywear(&[
        "bifurcation",
        "--param",
        "speed_kmh",
        "--from",
        "40",
        "--to",
        "260",
        "--steps",
        "45",
        "--params",
        concat!(env!("CARGO_MANIFEST_DIR"), "/studies/params_r0.toml"),
        "--out",
        prefix.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let hopf: Vec<f64> = stdout
        .lines()
        .filter(|l| l.contains("Hopf point"))
        .map(|l| {
            l.split('=')
                .nth(1)
                .unwrap()
                .split_whitespace()
                .next()
                .unwrap()
                .parse()
                .unwrap()
        })
        .collect();
    assert_eq!(hopf.len(), 4, "{stdout}");
    // Follower first: onset near 93 km/h, end near 224 km/h.
    assert!(
        (hopf[0] - 93.23).abs() < 0.1 && (hopf[1] - 223.55).abs() < 0.1,
        "{hopf:?}"
    );
    // Each located Hopf point is a root of Re λ to 1e-6 relative: check with simulate --json.
    for (i, wheel) in [(0, "follower"), (1, "follower")] {
        for (dx, sign) in [(-1e-3, -1.0f64), (1e-3, 1.0)] {
            let x = hopf[i] + dx;
            let (_, out, _) = polywear(&[
                "simulate",
                "--json",
                "--wheel",
                wheel,
                "--speed",
                &x.to_string(),
                "--duration",
                "0.01",
                "--params",
                concat!(env!("CARGO_MANIFEST_DIR"), "/studies/params_r0.toml"),
            ]);
            let v: serde_json::Value = serde_json::from_str(out.lines().next().unwrap()).unwrap();
            let re = v["eig_re_max"].as_f64().unwrap();
            let expect = if i == 0 { sign } else { -sign };
            assert_eq!(re.signum(), expect, "Re λ at {x} = {re}");
        }
    }
    assert!(prefix.with_extension("png").exists());
    // The table reads back in pandas (skipped, and said so, where pandas is missing).
    if common::python_has(&["pandas", "pyarrow"]) {
        let py = r#"
import sys, json, pandas as pd, pyarrow.parquet as pq
df = pd.read_parquet(sys.argv[1])
assert len(df) == 90 and set(df.wheel) == {"follower", "driving"}
f = df[df.wheel == "follower"]
assert ((f.eig_re_max > 0) == (f["class"] == "limit_cycle")).all()
md = pq.read_metadata(sys.argv[1]).metadata
assert md[b"sweep_param"] == b"speed_kmh" and len(json.loads(md[b"hopf_points"])) == 4
"#;
        common::python(py, &[prefix.with_extension("parquet").to_str().unwrap()]);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_sweeps_exit_2() {
    for (args, needle) in [
        (
            vec!["bifurcation", "--param", "nope", "--from", "1", "--to", "2"],
            "unknown parameter `nope`",
        ),
        (
            vec![
                "bifurcation",
                "--param",
                "toe_deg",
                "--from",
                "0",
                "--to",
                "1",
            ],
            "toe_deg",
        ),
        (
            vec![
                "bifurcation",
                "--param",
                "speed_kmh",
                "--from",
                "50",
                "--to",
                "500",
            ],
            "(0, 400]",
        ),
        (
            vec![
                "bifurcation",
                "--param",
                "speed_kmh",
                "--from",
                "50",
                "--to",
                "60",
                "--steps",
                "1",
            ],
            "--steps",
        ),
    ] {
        let (code, _, stderr) = polywear(&args);
        assert_eq!(code, 2, "{args:?}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
    }
}
