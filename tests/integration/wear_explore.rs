//! The wear stage in explore: on by default, its columns after the record columns, `--no-wear`
//! leaving exactly the vibration columns, the study's `wear`/`wear_zone` keys, and a resumed run
//! keeping the stage it started with.

use crate::common::{fresh_dir, polywear};
use crate::parquet_rows::rows;
use parquet::record::Field;
use polywear::records::{RECORD_COLUMNS, WEAR_COLUMNS};

fn first_chunk(dir: &std::path::Path) -> std::path::PathBuf {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "parquet"))
        .collect();
    files.sort();
    files.remove(0)
}

fn float(f: &Field) -> f64 {
    match f {
        Field::Double(x) => *x,
        Field::Null => f64::NAN,
        other => panic!("not a float: {other:?}"),
    }
}

fn text(f: &Field) -> String {
    match f {
        Field::Str(s) => s.clone(),
        other => panic!("not a string: {other:?}"),
    }
}

fn explore(study: &std::path::Path, out: &std::path::Path, extra: &[&str]) -> (i32, String) {
    let mut args = vec![
        "explore",
        study.to_str().unwrap(),
        "--quiet",
        "--no-report",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, _, stderr) = polywear(&args);
    (code, stderr)
}

const STUDY: &str = "name = \"w\"\nsamples = 24\nchunk_size = 12\n[params]\nspeed_kmh = { dist = \"uniform\", min = 20, max = 160 }\ntoe_deg = { dist = \"uniform\", min = 0.05, max = 0.6 }\n";

#[test]
fn explore_writes_the_wear_columns_and_no_wear_leaves_exactly_the_vibration_columns() {
    let dir = fresh_dir("wear-explore-columns");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("s.toml");
    std::fs::write(&study, STUDY).unwrap();
    let (with, without) = (dir.join("with"), dir.join("without"));
    assert_eq!(explore(&study, &with, &[]).0, 0);
    assert_eq!(explore(&study, &without, &["--no-wear"]).0, 0);
    let a = rows(&first_chunk(&with));
    let b = rows(&first_chunk(&without));
    assert_eq!(a.len(), b.len());
    for name in WEAR_COLUMNS.iter().map(|c| c.name) {
        assert!(a[0].contains_key(name), "{name} with the stage");
        assert!(!b[0].contains_key(name), "{name} without it");
    }
    let mut vibrating_growth = 0;
    for (ra, rb) in a.iter().zip(&b) {
        // The vibration columns are the same with and without the stage.
        for c in RECORD_COLUMNS {
            assert_eq!(
                format!("{:?}", ra[c.name]),
                format!("{:?}", rb[c.name]),
                "{}",
                c.name
            );
        }
        let class = text(&ra["class"]);
        let d = float(&ra["distance_to_visible_km"]);
        let reason = text(&ra["wear_reason"]);
        match class.as_str() {
            // A standstill wheel runs no distance: NaN with its reason, never a 0.
            "standstill" => assert!(d.is_nan() && !reason.is_empty(), "{class} {d} {reason}"),
            "stable" | "limit_cycle" | "bistable" => {
                assert!(d > 0.0 && reason.is_empty(), "{class} {d} {reason}");
                let n = float(&ra["polygon_order_dominant"]);
                assert!(n >= 1.0 && n.fract() == 0.0, "{n}");
                assert_eq!(float(&ra["wear_calibration_share"]), 0.12);
                if class != "stable" {
                    vibrating_growth += 1;
                    assert!(matches!(ra["wear_rhs_evals"], Field::Long(k) if k > 0 && k <= 1000));
                } else {
                    assert!(matches!(ra["wear_rhs_evals"], Field::Long(0)));
                }
            }
            _ => assert!(d.is_nan() && !reason.is_empty(), "{class} {d} {reason}"),
        }
    }
    assert!(vibrating_growth > 0, "some wheels vibrate in this study");
    let manifest = std::fs::read_to_string(with.join("_manifest.json")).unwrap();
    assert!(
        manifest.contains("\"wear_zone\": \"trailing\"")
            || manifest.contains("\"wear_zone\":\"trailing\""),
        "{manifest}"
    );
    assert!(manifest.contains("gamma_m3_per_j"), "{manifest}");
    let manifest = std::fs::read_to_string(without.join("_manifest.json")).unwrap();
    assert!(!manifest.contains("wear_zone"), "{manifest}");
}

#[test]
fn the_study_sets_the_wear_stage_and_a_resume_keeps_it() {
    let dir = fresh_dir("wear-explore-study");
    std::fs::create_dir_all(&dir).unwrap();
    let off = dir.join("off.toml");
    std::fs::write(&off, format!("wear = false\n{STUDY}")).unwrap();
    let out = dir.join("off");
    assert_eq!(explore(&off, &out, &[]).0, 0);
    assert!(!rows(&first_chunk(&out))[0].contains_key("distance_to_visible_km"));
    // wear = false and a zone contradict each other.
    let both = dir.join("both.toml");
    std::fs::write(
        &both,
        format!("wear = false\nwear_zone = \"whole_patch\"\n{STUDY}"),
    )
    .unwrap();
    let (code, stderr) = explore(&both, &dir.join("both"), &[]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("`wear_zone` is set but `wear = false`"),
        "{stderr}"
    );
    let (code, stderr) = explore(&off, &dir.join("zone"), &["--wear-zone", "whole_patch"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("--wear-zone whole_patch: the study sets `wear = false`"),
        "{stderr}"
    );
    let (code, stderr) = explore(&off, &dir.join("typo"), &["--wear-zone", "trialing"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("did you mean `trailing`"), "{stderr}");
    // A zone from the study reaches the manifest; a resume keeps it, and refuses --no-wear.
    let zoned = dir.join("zoned.toml");
    std::fs::write(&zoned, format!("wear_zone = \"whole_patch\"\n{STUDY}")).unwrap();
    let out = dir.join("zoned");
    assert_eq!(explore(&zoned, &out, &[]).0, 0);
    let manifest = std::fs::read_to_string(out.join("_manifest.json")).unwrap();
    assert!(manifest.contains("whole_patch"), "{manifest}");
    let o = out.to_str().unwrap();
    let (code, _, stderr) = polywear(&["explore", "--resume", "--out", o, "--quiet", "--no-wear"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--no-wear contradicts the run"), "{stderr}");
    let (code, _, stderr) =
        polywear(&["explore", "--resume", "--out", o, "--quiet", "--no-report"]);
    assert_eq!(code, 0, "{stderr}");
}
