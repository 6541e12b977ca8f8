//! The per-wheel work budget: a wheel that needs more RHS evaluations or wall time
//! than allowed becomes a `failed` row with reason `budget exceeded (...)`; the limits are set
//! in the study file or on the command line and checked before any work; and no input makes a
//! command hang (the eigenvalue iteration at toe-in 1e-200° is bounded too).

use crate::{common, parquet_rows};
use std::time::Duration;

use crate::common::{polywear, polywear_within};
use polywear::classify::budget::Meter;
use polywear::classify::{classify, Class, ClassifierOptions, WheelBudget};
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::params::Params;

#[test]
fn tiny_toe_in_does_not_hang() {
    for toe in ["1e-200", "1e-300", "5e-324", "1e-12"] {
        let (code, stdout, stderr) = polywear_within(
            Duration::from_secs(30),
            &["simulate", "--toe", toe, "--json"],
        );
        assert!(code == 0 || code == 2, "--toe {toe}: exit {code}: {stderr}");
        if code == 0 {
            for line in stdout.lines() {
                let v: serde_json::Value = serde_json::from_str(line).unwrap();
                let class = v["class"].as_str().unwrap();
                assert!(
                    class != "failed" || !v["reason"].as_str().unwrap().is_empty(),
                    "--toe {toe}: a failed row needs a reason: {line}"
                );
            }
        }
    }
}

fn default_cycle_model() -> WheelModel {
    // The default point lies between the Hopf points: both wheels vibrate.
    WheelModel::build(&Params::default(), Wheel::Follower, Variant::Paper).unwrap()
}

#[test]
fn a_wheel_over_its_evaluation_budget_is_failed_with_the_reason() {
    let m = default_cycle_model();
    let rot = WheelModel::rotation_hz(&Params::default());
    let free = classify(&m.ode, rot, &ClassifierOptions::default());
    assert_eq!(free.class, Class::LimitCycle);
    let budget = WheelBudget {
        max_rhs_evals: free.rhs_evals / 2,
        ..WheelBudget::default()
    };
    let v = classify(
        &m.ode,
        rot,
        &ClassifierOptions {
            budget,
            ..ClassifierOptions::default()
        },
    );
    assert_eq!(v.class, Class::Failed, "{v:?}");
    assert!(
        v.reason.starts_with("budget exceeded (max_rhs_evals"),
        "{}",
        v.reason
    );
    // The work stops at the limit (slack: one DOP853 step and its start, 16 evaluations).
    assert!(v.rhs_evals <= budget.max_rhs_evals + 16, "{v:?}");
    // A budget just above what the wheel needs changes nothing.
    let enough = ClassifierOptions {
        budget: WheelBudget {
            max_rhs_evals: free.rhs_evals + 100,
            ..WheelBudget::default()
        },
        ..ClassifierOptions::default()
    };
    assert_eq!(classify(&m.ode, rot, &enough), free);
}

#[test]
fn the_wall_time_budget_stops_the_work() {
    // Not exceeded before its time: an hour's budget (a short one could run out on a loaded
    // machine between two lines of this test).
    let roomy = Meter::new(WheelBudget {
        max_wheel_seconds: 3600.0,
        ..WheelBudget::default()
    });
    assert!(roomy.exceeded().is_none() && !roomy.out_of_time());
    // Exceeded after it: the sleep guarantees the elapsed time, whatever the load.
    let meter = Meter::new(WheelBudget {
        max_wheel_seconds: 1e-3,
        ..WheelBudget::default()
    });
    std::thread::sleep(Duration::from_millis(5));
    assert!(meter.out_of_time());
    let reason = meter.exceeded().unwrap();
    assert!(
        reason.starts_with("budget exceeded (max_wheel_seconds = 0.001 s"),
        "{reason}"
    );
}

#[test]
fn simulate_and_classify_take_the_budget_flags() {
    let (code, stdout, stderr) = polywear(&[
        "simulate",
        "--json",
        "--max-rhs-evals",
        "100",
        "--wheel",
        "follower",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.lines().next().unwrap()).unwrap();
    assert_eq!(v["class"], "failed", "{stdout}");
    assert!(v["reason"]
        .as_str()
        .unwrap()
        .starts_with("budget exceeded (max_rhs_evals = 100;"));

    let dir = common::fresh_dir("budget-classify");
    std::fs::create_dir_all(&dir).unwrap();
    let points = dir.join("points.csv");
    std::fs::write(&points, "speed_kmh,toe_deg\n100,0.3\n40,0.3\n").unwrap();
    let out = dir.join("out.csv");
    let (code, _, stderr) = polywear(&[
        "classify",
        points.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--max-rhs-evals",
        "1e2",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("budget exceeded (max_rhs_evals = 100;"),
        "{text}"
    );
}

#[test]
fn bad_budgets_exit_2_naming_the_flag_or_key() {
    for (args, want) in [
        (vec!["simulate", "--max-rhs-evals", "-5"], "--max-rhs-evals"),
        (
            vec!["simulate", "--max-rhs-evals", "1500.5"],
            "--max-rhs-evals",
        ),
        (vec!["simulate", "--max-rhs-evals", "10"], "[100,"),
        (
            vec!["simulate", "--max-wheel-seconds", "nan"],
            "--max-wheel-seconds",
        ),
        (
            vec!["simulate", "--max-wheel-seconds", "0"],
            "--max-wheel-seconds",
        ),
        (
            vec![
                "classify",
                "x.csv",
                "--out",
                "y.csv",
                "--max-wheel-seconds",
                "-1",
            ],
            "--max-wheel-seconds",
        ),
        (
            vec!["bifurcation", "--max-rhs-evals", "inf"],
            "--max-rhs-evals",
        ),
        (
            vec!["explore", "--max-wheel-seconds", "1e9"],
            "--max-wheel-seconds",
        ),
        (vec!["validate", "--max-rhs-evals", "0"], "--max-rhs-evals"),
    ] {
        let (code, _, stderr) = polywear(&args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(want), "{args:?}: {stderr}");
    }
    let dir = common::fresh_dir("budget-study");
    std::fs::create_dir_all(&dir).unwrap();
    for (line, want) in [
        ("max_rhs_evals = 5", "`max_rhs_evals`"),
        ("max_rhs_evals = \"many\"", "`max_rhs_evals`"),
        ("max_wheel_seconds = -1.0", "`max_wheel_seconds`"),
    ] {
        let study = dir.join("s.toml");
        std::fs::write(
            &study,
            format!(
                "{line}\n[params]\nspeed_kmh = {{ dist = \"uniform\", min = 60, max = 200 }}\n"
            ),
        )
        .unwrap();
        let out = dir.join("out");
        let (code, _, stderr) = polywear(&[
            "explore",
            study.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{line}: {stderr}");
        assert!(stderr.contains(want), "{line}: {stderr}");
        assert!(!out.exists(), "{line}: refused before any work");
    }
}

#[test]
fn explore_records_budget_failures_as_rows() {
    let dir = common::fresh_dir("budget-explore");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("s.toml");
    std::fs::write(
        &study,
        "name = \"tight\"\nsamples = 40\nchunk_size = 16\nmax_rhs_evals = 200\n[params]\nspeed_kmh = { dist = \"uniform\", min = 60, max = 220 }\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (code, _, stderr) = polywear(&[
        "explore",
        study.to_str().unwrap(),
        "--quiet",
        "--no-report",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let rows = parquet_rows::rows_in_dir(&[&out]);
    assert_eq!(rows.len(), 80, "every sample and wheel is a row");
    let text = format!("{rows:?}");
    assert!(
        text.contains("budget exceeded (max_rhs_evals = 200;"),
        "{text}"
    );
}
