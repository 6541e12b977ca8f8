//! Calibration recovers known parameters from targets polywear generated itself, and
//! `polywear reproduce` writes its report and a Table 3 that comes from the engine.

mod common;

use common::polywear;
use polywear::calibrate::{calibrate, observe, parse_problem};
use polywear::params::Params;

const TARGETS: &str = r#"
fit = ["g_mod", "v_s"]
[[target]]
name = "onset"
kind = "hopf"
param = "speed_kmh"
from = 40
to = 150
value = ONSET
[[target]]
name = "toe end"
kind = "hopf"
param = "toe_deg"
from = 0.3
to = 1.0
value = TOE
[[target]]
name = "pressure"
kind = "hopf"
param = "pressure_kpa"
from = 150
to = 450
value = PRESSURE
[[target]]
name = "frequency"
kind = "frequency"
at = { speed_kmh = 100 }
value = FREQ
"#;

#[test]
fn calibration_recovers_known_parameters() {
    // The truth: g_mod 3% up, v_s 10% down.
    let truth = Params {
        g_mod: 0.8645e6 * 1.03,
        v_s: 0.126 * 0.9,
        ..Params::default()
    };
    // Generate the targets with polywear itself at the truth.
    let template = parse_problem(
        &TARGETS
            .replace("ONSET", "1")
            .replace("TOE", "1")
            .replace("PRESSURE", "1")
            .replace("FREQ", "1"),
    )
    .unwrap();
    let values: Vec<f64> = template
        .targets
        .iter()
        .map(|t| observe(t, &truth))
        .collect();
    assert!(values.iter().all(|v| v.is_finite()), "{values:?}");
    let text = TARGETS
        .replace("ONSET", &values[0].to_string())
        .replace("TOE", &values[1].to_string())
        .replace("PRESSURE", &values[2].to_string())
        .replace("FREQ", &values[3].to_string());
    let problem = parse_problem(&text).unwrap();
    // Starting from the defaults, the fit finds the truth again.
    let fit = calibrate(&problem);
    for (name, start, got) in &fit.fitted {
        let want = truth.get(name).unwrap();
        assert!(
            ((got - want) / want).abs() < 1e-4,
            "{name}: fitted {got}, truth {want}, start {start}"
        );
    }
    assert!(fit.cost < 1e-12, "{}", fit.cost);
}

#[test]
fn calibrate_command_writes_a_params_file_that_simulate_reads() {
    let dir = std::env::temp_dir().join(format!("polywear-cal-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let targets = dir.join("t.toml");
    std::fs::write(
        &targets,
        TARGETS
            .replace("ONSET", "90")
            .replace("TOE", "0.42")
            .replace("PRESSURE", "345")
            .replace("FREQ", "272"),
    )
    .unwrap();
    let out = dir.join("fitted.toml");
    let (code, stdout, stderr) = polywear(&[
        "calibrate",
        targets.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("sensitivity"), "{stdout}");
    let (code, json, stderr) = polywear(&[
        "simulate",
        "--json",
        "--wheel",
        "follower",
        "--params",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let fitted = polywear::study::apply_param_file(
        &Params::default(),
        &std::fs::read_to_string(&out).unwrap(),
    )
    .unwrap();
    assert_ne!(fitted.g_mod, Params::default().g_mod);
    let v: serde_json::Value = serde_json::from_str(json.lines().next().unwrap()).unwrap();
    // K_s is proportional to G: the simulated point used the fitted G.
    let k_default = 1562132.448;
    assert!(
        (v["k_s"].as_f64().unwrap() / k_default - fitted.g_mod / Params::default().g_mod).abs()
            < 1e-6
    );
    // Bad targets exit 2.
    std::fs::write(
        &targets,
        "[[target]]\nkind = \"hopf\"\nparam = \"speed_kmh\"\nfrom = 150\nto = 40\nvalue = 80\n",
    )
    .unwrap();
    let (code, _, stderr) = polywear(&[
        "calibrate",
        targets.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("from = 150 must be below to = 40"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn reproduce_writes_the_report_with_table_3_from_the_engine() {
    let dir = std::env::temp_dir().join(format!("polywear-repro-{}", std::process::id()));
    let run = |params: Option<&str>, out: &str| -> String {
        let out = dir.join(out);
        let mut args = vec!["reproduce", "--steps", "41", "--out", out.to_str().unwrap()];
        if let Some(p) = params {
            args.extend(["--params", p]);
        }
        let (code, _, stderr) = polywear(&args);
        assert_eq!(code, 0, "{stderr}");
        for f in [
            "fig4_adhesion.png",
            "bifurcation_speed_kmh_paper.png",
            "fig9_10_speed100.png",
            "bifurcation.parquet",
        ] {
            assert!(out.join(f).exists(), "missing {f}");
        }
        std::fs::read_to_string(out.join("report.md")).unwrap()
    };
    std::fs::create_dir_all(&dir).unwrap();
    let report = run(None, "default");
    // The follower's toe window from the engine (MODEL.md reference: 0.21-0.41 deg).
    assert!(
        report.contains("| toe_deg (swept 0.05–1) | 0.2139–0.4088 deg |"),
        "{report}"
    );
    // Change the tire: Table 3 changes with it.
    let params = dir.join("soft.toml");
    std::fs::write(&params, "[params]\ng_mod = 0.8e6\n").unwrap();
    let soft = run(Some(params.to_str().unwrap()), "soft");
    let row = |r: &str| {
        r.lines()
            .find(|l| l.starts_with("| toe_deg"))
            .unwrap()
            .to_string()
    };
    assert_ne!(row(&report), row(&soft));
    std::fs::remove_dir_all(&dir).ok();
}
