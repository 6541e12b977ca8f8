//! `polywear analyze`: a risk map whose answer is known, report files, and bad input.

mod common;

use std::path::PathBuf;

use common::polywear;
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::record::Field;

fn tmp(name: &str) -> PathBuf {
    let d = common::fresh_dir(&format!("analyze-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn risk_map_of_a_one_axis_grid_is_the_bifurcation_diagram() {
    let dir = tmp("grid");
    let study = dir.join("speed_only.toml");
    // Only speed varies; toe is a single level, so the map speed × toe is one row of cells.
    std::fs::write(
        &study,
        r#"name = "speed_only"
design = "grid"
variants = ["paper"]
[params]
speed_kmh = { dist = "levels", levels = [60, 80, 90, 100, 150, 200, 220, 230, 250] }
toe_deg = { dist = "levels", levels = [0.3] }
# MODEL.md's reference constants R0 (studies/params_r0.toml), whose Hopf points are known.
g_mod = 0.8645e6
c_brush = 3.6e7
alpha2 = 4.0e-8
v_s = 0.126
phi = 0.94
c_s = 18
"#,
    )
    .unwrap();
    let out = dir.join("run");
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, stderr) = polywear(&["analyze", out.to_str().unwrap(), "--min-count", "1"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("note: risk map load_n × pressure_kpa skipped"),
        "{stdout}"
    );
    let table = out.join("_report/riskmap_speed_kmh_toe_deg.parquet");
    let reader = SerializedFileReader::new(std::fs::File::open(&table).unwrap()).unwrap();
    let mut seen = 0;
    for row in reader.get_row_iter(None).unwrap() {
        let row = row.unwrap();
        let get = |name: &str| {
            row.get_column_iter()
                .find(|(n, _)| n.as_str() == name)
                .unwrap()
                .1
                .clone()
        };
        let (Field::Str(variant), Field::Str(wheel), Field::Double(speed), Field::Double(p)) =
            (get("variant"), get("wheel"), get("speed_kmh_lo"), get("p"))
        else {
            panic!("unexpected types in {row}");
        };
        assert_eq!(variant, "paper");
        // Hopf points at R0 (`paper`): 93.23 and 223.55 km/h (follower), 93.02 and 225.52 (driving).
        let (lo, hi) = if wheel == "follower" {
            (93.23, 223.55)
        } else {
            (93.02, 225.52)
        };
        let expect = if speed > lo && speed < hi { 1.0 } else { 0.0 };
        assert_eq!(p, expect, "{wheel} at {speed} km/h");
        seen += 1;
    }
    assert_eq!(seen, 2 * 9);
    for f in [
        "report.md",
        "occurrence.csv",
        "paired.csv",
        "conditional.parquet",
        "severity.csv",
        "riskmap_speed_kmh_toe_deg_paper.png",
        "conditional_paper.png",
        "severity_paper.png",
    ] {
        assert!(out.join("_report").join(f).exists(), "missing {f}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn saltelli_run_gives_sobol_indices_in_the_report() {
    let dir = tmp("saltelli");
    let study = dir.join("sobol.toml");
    std::fs::write(
        &study,
        r#"name = "sens"
design = "saltelli"
samples = 128
chunk_size = 256
[params]
speed_kmh = { dist = "uniform", min = 60, max = 250 }
toe_deg = { dist = "uniform", min = 0.1, max = 0.5 }
rho = { dist = "uniform", min = 1240, max = 1260 }
"#,
    )
    .unwrap();
    let out = dir.join("run");
    let (code, stdout, stderr) = polywear(&[
        "explore",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("640 samples evaluated"),
        "128 base samples x (3 + 2): {stdout}"
    );
    let csv = std::fs::read_to_string(out.join("_report/sensitivity.csv")).unwrap();
    let total = |wheel: &str, param: &str| -> f64 {
        let line = csv
            .lines()
            .find(|l| l.starts_with(&format!("sliding_share,{wheel},limit_cycle,{param},")))
            .unwrap_or_else(|| panic!("no row for {param} in\n{csv}"));
        line.split(',').nth(8).unwrap().parse().unwrap()
    };
    // Speed decides the Hopf window; a 1% spread of the tread density barely matters.
    assert!(total("follower", "speed_kmh") > 0.3, "{csv}");
    assert!(total("follower", "rho") < 0.05, "{csv}");
    assert!(std::fs::read_to_string(out.join("_report/report.md"))
        .unwrap()
        .contains("Sobol indices"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn analyze_bad_input_exits_2() {
    let dir = tmp("bad");
    for (args, needle) in [
        (
            vec!["analyze", "/nonexistent/polywear"],
            "no such file or directory",
        ),
        (vec!["analyze", dir.to_str().unwrap()], "no Parquet files"),
        (
            vec!["analyze", dir.to_str().unwrap(), "--bins", "1"],
            "--bins",
        ),
        (
            vec!["analyze", dir.to_str().unwrap(), "--pair", "speed_kmh"],
            "X,Y",
        ),
        (
            vec!["analyze", dir.to_str().unwrap(), "--pair", "speed_kmh,nope"],
            "nope",
        ),
    ] {
        let (code, _, stderr) = polywear(&args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
