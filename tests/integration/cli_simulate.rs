//! `polywear simulate` end to end: JSON columns, bad input (exit 2 before any work), files.

use crate::common::polywear;

#[test]
fn json_has_exactly_the_reference_columns_first() {
    let (code, stdout, _) = polywear(&["simulate", "--json"]);
    assert_eq!(code, 0);
    let header = include_str!("../data/points.csv").lines().next().unwrap();
    let want: Vec<&str> = header.split(',').collect();
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 2, "one object per wheel");
    for (line, wheel) in lines.iter().zip(["follower", "driving"]) {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        // Key order as printed (serde_json's map would sort them).
        let keys: Vec<&str> = line
            .trim_matches(|c| c == '{' || c == '}')
            .split(',')
            .filter_map(|kv| kv.split_once("\":").map(|(k, _)| k.trim_start_matches('"')))
            .collect();
        assert_eq!(&keys[..want.len()], &want[..]);
        assert_eq!(v["wheel"], wheel);
        assert_eq!(v["class"], "limit_cycle");
    }
}

#[test]
fn bad_inputs_exit_2_naming_field_value_and_range() {
    let cases: &[(&[&str], &[&str])] = &[
        (&["simulate", "--toe", "0"], &["toe_deg", "0", "(0, 10]"]),
        (
            &["simulate", "--speed", "-5"],
            &["speed_kmh", "-5", "(0, 400]"],
        ),
        (&["simulate", "--load", "nan"], &["load_n", "NaN"]),
        (&["simulate", "--pressure", "inf"], &["pressure_kpa", "inf"]),
        (
            &["simulate", "--set", "bogus=3"],
            &["unknown parameter `bogus`"],
        ),
        (&["simulate", "--set", "g_mod"], &["NAME=VALUE"]),
        (
            &["simulate", "--set", "g_mod=abc"],
            &["g_mod", "not a number"],
        ),
        (
            &["simulate", "--set", "rho=-1"],
            &["rho", "-1", "(0, 20000]"],
        ),
        (&["simulate", "--set", "mu_s=0.9"], &["mu_s", "mu_m"]),
        (&["simulate", "--speed"], &["--speed"]),
        (&["simulate", "--wheel", "left"], &["left"]),
        (&["simulate", "--variant", "lugre"], &["lugre"]),
        (
            &["simulate", "--duration", "0"],
            &["--duration", "(0, 600]"],
        ),
        (&["simulate", "--out", "x.txt"], &["--out", ".txt"]),
        (&["simulate", "--plot", "x.jpg"], &["--plot", ".jpg"]),
        (&["simulate", "--kick", "-1"], &["--kick"]),
        (&["simulate", "--frobnicate"], &["--frobnicate"]),
    ];
    for (args, needles) in cases {
        let (code, stdout, stderr) = polywear(args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stdout.is_empty(), "{args:?} printed results: {stdout}");
        for n in *needles {
            assert!(stderr.contains(n), "{args:?}: stderr lacks `{n}`: {stderr}");
        }
    }
}

#[test]
fn writes_time_series_and_plot() {
    let dir = std::env::temp_dir().join(format!("polywear-sim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("ts.csv");
    let png = dir.join("p.png");
    let (code, _, stderr) = polywear(&[
        "simulate",
        "--duration",
        "0.2",
        "--out",
        csv.to_str().unwrap(),
        "--plot",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "wheel,t_s,z_m,y_m,v_mps");
    // 0.2 s at 20 kHz plus the start, for two wheels.
    assert_eq!(lines.count(), 2 * 4001);
    let png_bytes = std::fs::read(&png).unwrap();
    assert_eq!(&png_bytes[1..4], b"PNG");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn no_traction_is_a_row_not_a_crash() {
    let (code, stdout, _) = polywear(&[
        "simulate",
        "--json",
        "--speed",
        "300",
        "--load",
        "500",
        "--set",
        "area=50",
        "--set",
        "c_d=5",
        "--set",
        "n_driven=1",
    ]);
    assert_eq!(code, 0);
    let driving: serde_json::Value = serde_json::from_str(stdout.lines().nth(1).unwrap()).unwrap();
    assert_eq!(driving["class"], "no_traction");
    assert!(driving["reason"]
        .as_str()
        .unwrap()
        .contains("adhesion limit"));
}
