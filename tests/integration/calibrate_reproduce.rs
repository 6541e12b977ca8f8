//! Calibration recovers known parameters from targets polywear generated itself, and
//! `polywear reproduce` writes its report and a Table 3 that comes from the engine.

use crate::common::polywear;
use polywear::params::{ParamId, Params};
use polywear_study::calibrate::{calibrate, observe, parse_problem};

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
    // Placeholders inside each target's searched range (a value outside it is refused).
    let template = parse_problem(
        &TARGETS
            .replace("ONSET", "80")
            .replace("TOE", "0.5")
            .replace("PRESSURE", "300")
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
        let want = truth[*name];
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
    let (code, json0, _) = polywear(&["simulate", "--json", "--wheel", "follower"]);
    assert_eq!(code, 0);
    let v0: serde_json::Value = serde_json::from_str(json0.lines().next().unwrap()).unwrap();
    let k_default = v0["k_s"].as_f64().unwrap();
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
        let mut args = vec![
            "reproduce",
            "--steps",
            "41",
            "--paired-samples",
            "60",
            "--out",
            out.to_str().unwrap(),
        ];
        if let Some(p) = params {
            args.extend(["--params", p]);
        }
        let (code, _, stderr) = polywear(&args);
        assert_eq!(code, 0, "{stderr}");
        for f in [
            "fig4_adhesion.png",
            "bifurcation_speed_kmh_paper.png",
            "bifurcation_speed_kmh_sliding_share.png",
            "fig18_amplitude_vs_speed.png",
            "speed100_paper.png",
            "fig9_10_speed100.png",
            "bifurcation.parquet",
            "chart_speed_kmh_toe_deg.png",
            "chart_load_n_pressure_kpa.parquet",
        ] {
            assert!(out.join(f).exists(), "missing {f}");
        }
        std::fs::read_to_string(out.join("report.md")).unwrap()
    };
    std::fs::create_dir_all(&dir).unwrap();
    let r0 = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/params_r0.toml");
    let reference = run(Some(r0), "r0");
    // With the constants R0, the follower's toe window from the engine (MODEL.md#targets:
    // 0.214-0.409 deg) and the driving wheel's under `sliding_share`
    // (MODEL.md#the-default-sliding-share: 0.233-0.384).
    assert!(
        reference.contains("| toe_deg (swept 0.05–1) | 0.2x–0.41 | 0.x–0.35 | 0.2139–0.4088 deg | 0.2333–0.3835 deg |"),
        "{reference}"
    );
    let report = run(None, "default");
    // The whole story: three variants, both wheels, the paired comparison and why.
    for s in [
        "driving, `sliding_share`",
        "driving, `paper`",
        "driving, `combined`",
        "## Which wheel vibrates more often: the default study, paired",
        "| `sliding_share` | 60 |",
        "## Why the literal equations cannot carry the paper's conclusion",
        "fig18_amplitude_vs_speed.png",
        "## Stability charts: the boundary in two operating parameters at a time",
        "| [chart_speed_kmh_toe_deg](chart_speed_kmh_toe_deg.png) | 1, ending on the box | 1, closed (an island) | yes, entirely |",
    ] {
        assert!(report.contains(s), "missing `{s}` in\n{report}");
    }
    // Change the tire: Table 3 changes with it.
    let params = dir.join("soft.toml");
    std::fs::write(&params, "[params]\ng_mod = 0.75e6\n").unwrap();
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

const TWO_WHEELS: &str = r#"
fit = ["g_mod"]
[choices]
phi = [0.90, 0.92, 0.94, 0.98]
[[target]]
name = "driving toe end"
kind = "hopf"
wheel = "driving"
variant = "sliding_share"
param = "toe_deg"
from = 0.3
to = 1.0
value = DTOE
[[target]]
name = "follower toe end"
kind = "hopf"
param = "toe_deg"
from = 0.3
to = 1.0
value = FTOE
"#;

#[test]
fn calibration_of_both_wheels_picks_the_lost_digit_reading() {
    // The truth: phi at one of its readings, G 4% up; targets of both wheels generated by polywear.
    let truth = Params {
        phi: 0.92,
        g_mod: Params::default().g_mod * 1.04,
        ..Params::default()
    };
    let template = parse_problem(&TWO_WHEELS.replace("DTOE", "1").replace("FTOE", "1")).unwrap();
    assert_eq!(template.targets[0].wheel, polywear::model::Wheel::Driving);
    assert_eq!(
        template.choices,
        vec![(ParamId::Phi, vec![0.90, 0.92, 0.94, 0.98])]
    );
    let v: Vec<f64> = template
        .targets
        .iter()
        .map(|t| observe(t, &truth))
        .collect();
    let problem = parse_problem(
        &TWO_WHEELS
            .replace("DTOE", &v[0].to_string())
            .replace("FTOE", &v[1].to_string()),
    )
    .unwrap();
    let fit = calibrate(&problem);
    assert_eq!(fit.combinations, 4);
    assert_eq!(fit.chosen, vec![(ParamId::Phi, 0.92)]);
    assert!(
        (fit.params.g_mod / truth.g_mod - 1.0).abs() < 1e-4,
        "{}",
        fit.params.g_mod
    );
    assert!(fit
        .targets
        .iter()
        .all(|t| t.met() && t.shortfall().is_none()));
    // The parameter file carries the chosen reading.
    let file = polywear_study::calibrate::parameter_file(&fit, "test").unwrap();
    let back = polywear::study::apply_param_file(&Params::default(), &file).unwrap();
    assert_eq!(back.phi, 0.92);
}

#[test]
fn a_target_that_cannot_be_met_is_named() {
    // No Hopf point of the follower's speed in 40-50 km/h: the fit says so.
    let problem = parse_problem(
        "fit = [\"g_mod\"]\n[[target]]\nname = \"impossible\"\nkind = \"hopf\"\nparam = \"speed_kmh\"\nfrom = 40\nto = 50\nvalue = 45\n",
    )
    .unwrap();
    let fit = calibrate(&problem);
    let s = fit.targets[0].shortfall().unwrap();
    assert!(
        s.contains("impossible") && s.contains("cannot be met"),
        "{s}"
    );
}

#[test]
fn amplitude_ratio_observes_the_driving_wheels_smaller_cycle() {
    let problem = parse_problem(
        "fit = [\"g_mod\"]\n[[target]]\nkind = \"amplitude_ratio\"\nwheel = \"driving\"\nat = { speed_kmh = 100 }\nvalue = 0.5\n",
    )
    .unwrap();
    let t = &problem.targets[0];
    let share = observe(t, &Params::default());
    assert!(share > 0.3 && share < 0.95, "{share}");
    let mut paper = t.clone();
    paper.variant = polywear::model::Variant::Paper;
    let lit = observe(&paper, &Params::default());
    assert!(
        lit > 1.0,
        "the literal equations give the driving wheel the larger cycle: {lit}"
    );
}

#[test]
fn bad_targets_files_are_refused_with_the_key() {
    let base = "[[target]]\nkind = \"frequency\"\nvalue = 270\n";
    let hopf =
        "[[target]]\nkind = \"hopf\"\nparam = \"speed_kmh\"\nfrom = 40\nto = 150\nvalue = VALUE\n";
    for (text, needle) in [
        (format!("fit = [\"g_mod\", \"g_mod\"]\n{base}"), "names `g_mod` twice"),
        (format!("{base}colour = 3\n"), "unknown key `target[0].colour`"),
        (format!("bogus = 1\n{base}"), "unknown key `bogus`"),
        (format!("[choices]\nphi = [0.9, -1]\n{base}"), "choices.phi[1]"),
        (format!("fit = [\"phi\"]\n[choices]\nphi = [0.9]\n{base}"), "both in `fit`"),
        (format!("{base}tolerance = 0\n"), "target[0].tolerance"),
        (format!("{base}wheel = \"front\"\n"), "target[0].wheel"),
        (
            "[[target]]\nkind = \"amplitude_ratio\"\nwheel = \"driving\"\nrelative_to = \"driving\"\nvalue = 1\n".to_string(),
            "relative_to",
        ),
        // Targets that can never be met, and fits that cannot move what they name.
        (hopf.replace("VALUE", "-80"), "`target[0].value`: parameter `speed_kmh` = -80"),
        (hopf.replace("VALUE", "200"), "outside the searched range [from, to] = [40, 150]"),
        (format!("{base}weight = 0\n"), "`target[0].weight` = 0 is outside"),
        (format!("fit = [\"speed_kmh\"]\n{}", hopf.replace("VALUE", "80")), "`speed_kmh` is set by `target[0]`"),
        (format!("fit = [\"n_wheels\"]\n{base}"), "`n_wheels` is a whole number"),
        (base.replace("270", "-270"), "a frequency is positive"),
    ] {
        let e = parse_problem(&text).unwrap_err().to_string();
        assert!(e.contains(needle), "`{needle}` not in `{e}` for\n{text}");
    }
}

#[test]
fn a_diverged_fit_writes_no_parameter_file() {
    let problem =
        parse_problem("fit = [\"g_mod\"]\n[[target]]\nkind = \"frequency\"\nvalue = 270\n")
            .unwrap();
    let mut fit = calibrate(&problem);
    fit.params.g_mod = f64::NAN;
    let e = polywear_study::calibrate::parameter_file(&fit, "x")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("g_mod") && e.contains("no parameter file"),
        "{e}"
    );
    fit.params = Params::default();
    fit.cost = f64::NAN;
    assert!(polywear_study::calibrate::parameter_file(&fit, "x").is_err());
}

#[test]
fn a_fit_with_a_target_not_met_writes_no_file_unless_asked() {
    let dir = crate::common::fresh_dir("cal-unmet");
    std::fs::create_dir_all(&dir).unwrap();
    let targets = dir.join("t.toml");
    // No Hopf point of the follower's speed in 40-50 km/h.
    std::fs::write(
        &targets,
        "fit = [\"g_mod\"]\n[[target]]\nname = \"impossible\"\nkind = \"hopf\"\nparam = \"speed_kmh\"\nfrom = 40\nto = 50\nvalue = 45\n",
    )
    .unwrap();
    let out = dir.join("fit.toml");
    let args = [
        "calibrate",
        targets.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    let (code, _, stderr) = polywear(&args);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("impossible")
            && stderr.contains("no parameter file is written")
            && stderr.contains("--write-anyway"),
        "{stderr}"
    );
    assert!(
        !out.exists(),
        "a fit that does not stand wrote {}",
        out.display()
    );
    let mut anyway = args.to_vec();
    anyway.push("--write-anyway");
    let (code, _, stderr) = polywear(&anyway);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        out.exists() && stderr.contains("written nonetheless"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
