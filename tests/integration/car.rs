//! The car around the pair (MODEL.md#the-car-axles-and-drivetrain): each axle's own toe-in
//! reaches its wheel's rows, which name the axle; the drivetrain puts the driving wheel on the
//! front or rear axle; naming each axle the shared value changes no row; and every refusal,
//! before any work, with exit 2, naming the key and its range.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use parquet::record::Field;

use crate::common::{self, polywear};
use crate::parquet_rows::{chunk_rows, rows_in_dir};

fn tmp(name: &str) -> PathBuf {
    let d = common::fresh_dir(&format!("car-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn explore(dir: &Path, name: &str, study: &str, extra: &[&str]) -> PathBuf {
    common::explore_study(dir, name, study, extra)
}

fn text(row: &HashMap<String, Field>, key: &str) -> String {
    match &row[key] {
        Field::Str(s) => s.clone(),
        other => panic!("{key} is {other:?}"),
    }
}

fn number(row: &HashMap<String, Field>, key: &str) -> f64 {
    match &row[key] {
        Field::Double(x) => *x,
        other => panic!("{key} is {other:?}"),
    }
}

/// The engineer's study: the rear axle toed in more than the front.
const AXLES: &str = r#"name = "axles"
seed = 5
samples = 16
wear = false
[params]
speed_kmh = { dist = "uniform", min = 80, max = 140 }
toe_rear_deg = { dist = "uniform", min = 0.2, max = 0.6 }
toe_front_deg = { dist = "uniform", min = 0.05, max = 0.2 }
"#;

/// Each wheel's row carries its axle and that axle's toe-in, under `fwd` (the default) and
/// `rwd`; the report names the wheels by axle.
#[test]
fn each_axles_toe_reaches_its_wheels_rows_under_either_drivetrain() {
    let dir = tmp("axles");
    for (name, extra, driven) in [
        ("fwd", &[][..], "front"),
        ("rwd", &["--drivetrain", "rwd"][..], "rear"),
    ] {
        let out = explore(&dir, name, AXLES, extra);
        let rows = chunk_rows(&out);
        assert_eq!(rows.len(), 32, "{name}: 16 samples, both wheels");
        for r in &rows {
            let (axle, wheel, toe) = (text(r, "axle"), text(r, "wheel"), number(r, "toe_deg"));
            let expected_axle = if wheel == "driving" {
                driven
            } else if driven == "front" {
                "rear"
            } else {
                "front"
            };
            assert_eq!(axle, expected_axle, "{name}: the {wheel} wheel");
            let (lo, hi) = if axle == "front" {
                (0.05, 0.2)
            } else {
                (0.2, 0.6)
            };
            assert!((lo..=hi).contains(&toe), "{name}: {axle} toe {toe}");
        }
        let report = std::fs::read_to_string(out.join("_report/report.md")).unwrap();
        let follower = if driven == "front" {
            "rear (follower)"
        } else {
            "front (follower)"
        };
        let driving = if driven == "front" {
            "front (driving)"
        } else {
            "rear (driving)"
        };
        assert!(
            report.contains(follower) && report.contains(driving),
            "{name}: {report}"
        );
    }
}

/// Naming each axle the shared value is the paper's pair: every row equals the run without
/// per-axle keys, key by key (the rows of a study without them are today's).
#[test]
fn naming_each_axle_the_shared_value_changes_no_row() {
    let dir = tmp("same");
    let shared = "name = \"same\"\nseed = 3\nsamples = 12\nwear = false\n[params]\n\
        speed_kmh = { dist = \"uniform\", min = 80, max = 160 }\n\
        load_n = { dist = \"uniform\", min = 3000, max = 5000 }\n";
    let a = explore(
        &dir,
        "shared",
        &format!("{shared}toe_deg = 0.35\n"),
        &["--no-report"],
    );
    let per_axle = format!("{shared}toe_front_deg = 0.35\ntoe_rear_deg = 0.35\n");
    let b = explore(&dir, "per_axle", &per_axle, &["--no-report"]);
    // As text, so that a NaN cell equals a NaN cell.
    let (ra, rb) = (rows_in_dir(&[&a]), rows_in_dir(&[&b]));
    assert_eq!(ra.len(), 24);
    let differ = ra.iter().zip(&rb).filter(|(x, y)| x != y).count();
    assert_eq!(differ, 0, "{differ} of {} rows differ", ra.len());
}

fn refused(args: &[&str], names: &[&str]) {
    let (code, _, stderr) = polywear(args);
    assert_eq!(code, 2, "{args:?}: {stderr}");
    for n in names {
        assert!(stderr.contains(n), "{args:?} should name {n}: {stderr}");
    }
}

/// Every bad car input is refused before any work, with exit 2, naming the key and its range.
#[test]
fn bad_car_inputs_are_refused_naming_the_key_and_its_range() {
    let dir = tmp("bad");
    refused(
        &["simulate", "--drivetrain", "4wd"],
        &["--drivetrain", "fwd", "rwd"],
    );
    refused(
        &["explore", "--drivetrain", "awd", "--samples", "4"],
        &["--drivetrain", "fwd"],
    );
    refused(
        &["simulate", "--set", "toe_rear_deg=12"],
        &["toe_rear_deg", "(0, 10]"],
    );
    refused(
        &["simulate", "--set", "toe_front_deg=0"],
        &["toe_front_deg", "(0, 10]"],
    );
    refused(
        &["simulate", "--set", "toe_rear_deg=3"],
        &["toe_rear_deg", "implausible", "(0, 1]"],
    );
    refused(
        &["simulate", "--toe", "0.3", "--set", "toe_rear_deg=0.4"],
        &["`toe_deg`", "`toe_rear_deg`"],
    );
    refused(
        &[
            "simulate",
            "--set",
            "load_n=4000",
            "--set",
            "load_front_n=4500",
        ],
        &["`load_n`", "`load_front_n`"],
    );
    let study = |name: &str, body: &str| -> PathBuf {
        let p = dir.join(format!("{name}.toml"));
        std::fs::write(&p, format!("name = \"{name}\"\nsamples = 4\n{body}")).unwrap();
        p
    };
    let both = study(
        "both",
        "[params]\ntoe_deg = 0.3\ntoe_rear_deg = { dist = \"uniform\", min = 0.2, max = 0.6 }\n",
    );
    refused(
        &["explore", both.to_str().unwrap()],
        &["`toe_deg`", "`toe_rear_deg`"],
    );
    let bad_key = study(
        "bad_key",
        "drivetrain = \"4wd\"\n[params]\nspeed_kmh = { dist = \"uniform\", min = 80, max = 120 }\n",
    );
    refused(
        &["explore", bad_key.to_str().unwrap()],
        &["drivetrain", "fwd", "rwd"],
    );
    let scenario = study(
        "scenario",
        "[params]\ntoe_rear_deg = { dist = \"uniform\", min = 0.2, max = 0.6 }\n\
         [scenarios.less]\ntoe_deg = { shift = -0.1 }\n",
    );
    refused(
        &["explore", scenario.to_str().unwrap()],
        &["scenarios.less.toe_deg", "per axle"],
    );
    let rear = study(
        "rear",
        "[params]\ntoe_rear_deg = { dist = \"uniform\", min = 0.2, max = 0.6 }\n",
    );
    let out = dir.join("optimum");
    refused(
        &[
            "optimize",
            rear.to_str().unwrap(),
            "--vary",
            "toe_deg=0.1..0.3",
            "--out",
            out.to_str().unwrap(),
        ],
        &["--vary toe_deg", "per axle", "toe_rear_deg"],
    );
}
