//! Measured operating points (`[operating_points]` in a study): rows drawn in proportion to
//! their weights (chi-square), zero-weight rows never drawn, the structure still drawn per
//! sample, every bad file refused before any work naming file, row and column, the manifest's
//! hash refusing a resume over a changed file, and the same rows whatever the threads.

use crate::common;
use std::path::{Path, PathBuf};

use crate::common::polywear;
use crate::parquet_rows::rows_in_dir;
use polywear::params::Params;
use polywear::study::{Study, StudyError};

fn dir(name: &str) -> PathBuf {
    let d = common::fresh_dir(&format!("op-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A study drawing the structure (g_mod, rho) and taking the operating point from `points`.
fn study_text(op: &str, design: &str) -> String {
    format!(
        r#"name = "fleet"
seed = 5
samples = 300
chunk_size = 64
design = "{design}"
[operating_points]
{op}
[params]
g_mod = {{ dist = "lognormal", median = 0.8645e6, sigma = 0.05 }}
rho = {{ dist = "uniform", min = 1200, max = 1300 }}
"#
    )
}

const WEIGHTED: &str = "speed_kmh,load_n,pressure_kpa,hours\n\
                        80,3500,220,10\n\
                        100,4000,240,0\n\
                        120,4500,250,30\n\
                        140,5000,260,5\n\
                        160,4200,230,0\n\
                        110,3800,245,55\n";

fn parse(d: &Path, points: &str, op: &str) -> Result<Study, StudyError> {
    std::fs::write(d.join("points.csv"), points).unwrap();
    Study::parse_at(&study_text(op, "random"), Params::default(), d)
}

#[test]
fn rows_are_drawn_in_proportion_to_their_weights() {
    let d = dir("chi2");
    let study = parse(&d, WEIGHTED, "file = \"points.csv\"\nweight = \"hours\"").unwrap();
    let n = 100_000u64;
    let sampler = study.sampler(study.seed, n);
    let mut counts = [0u64; 6];
    for i in 0..n {
        let (p, values, row) = sampler.sample_with_row(i);
        let row = row.expect("a row per sample");
        counts[row] += 1;
        // The row's columns set the parameters, all three together (correlations kept).
        let op = study.operating_points.as_ref().unwrap();
        assert_eq!(
            [p.speed_kmh, p.load_n, p.pressure_kpa],
            [op.values[row][0], op.values[row][1], op.values[row][2]]
        );
        assert_eq!(&values[2..], &op.values[row][..]);
    }
    assert_eq!(counts[1], 0, "zero-weight row drawn");
    assert_eq!(counts[4], 0, "zero-weight row drawn");
    let weights = [10.0, 0.0, 30.0, 5.0, 0.0, 55.0];
    let total: f64 = weights.iter().sum();
    let mut chi2 = 0.0;
    for (c, w) in counts.iter().zip(weights) {
        if w > 0.0 {
            let e = n as f64 * w / total;
            chi2 += (*c as f64 - e).powi(2) / e;
        }
    }
    // 4 positive rows: 3 degrees of freedom; the 0.999 quantile of chi-square(3) is 16.27.
    assert!(chi2 < 16.27, "chi-square {chi2} for counts {counts:?}");
    // And the test can fail: uniform weights are far from these counts.
    let uniform: f64 = counts
        .iter()
        .zip(weights)
        .filter(|(_, w)| *w > 0.0)
        .map(|(c, _)| (*c as f64 - n as f64 / 4.0).powi(2) / (n as f64 / 4.0))
        .sum();
    assert!(uniform > 1000.0, "{uniform}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn without_a_weight_column_rows_are_equally_likely() {
    let d = dir("uniform");
    let study = parse(
        &d,
        "speed_kmh,load_n\n90,3500\n120,4000\n150,4500\n",
        "file = \"points.csv\"",
    )
    .unwrap();
    let n = 30_000u64;
    let sampler = study.sampler(study.seed, n);
    let mut counts = [0u64; 3];
    for i in 0..n {
        counts[sampler.sample_with_row(i).2.unwrap()] += 1;
    }
    let e = n as f64 / 3.0;
    let chi2: f64 = counts.iter().map(|c| (*c as f64 - e).powi(2) / e).sum();
    // 2 degrees of freedom: the 0.999 quantile is 13.82.
    assert!(chi2 < 13.82, "{counts:?}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn the_structure_is_still_drawn_per_sample_and_unchanged_by_the_file() {
    let d = dir("structure");
    let with = parse(&d, WEIGHTED, "file = \"points.csv\"\nweight = \"hours\"").unwrap();
    let without = Study::parse(
        r#"seed = 5
[params]
g_mod = { dist = "lognormal", median = 0.8645e6, sigma = 0.05 }
rho = { dist = "uniform", min = 1200, max = 1300 }
"#,
    )
    .unwrap();
    let (a, b) = (with.sampler(5, 2000), without.sampler(5, 2000));
    let mut g_of_row: Vec<Vec<f64>> = vec![Vec::new(); 6];
    for i in 0..2000 {
        let (p, _, row) = a.sample_with_row(i);
        let (q, _) = b.sample(i);
        // The structure draws use their own axes: the row draw does not shift them.
        assert_eq!((p.g_mod, p.rho), (q.g_mod, q.rho), "sample {i}");
        g_of_row[row.unwrap()].push(p.g_mod);
    }
    // Samples that drew the same row still have their own structure.
    let most = g_of_row.iter().max_by_key(|v| v.len()).unwrap();
    let mut distinct = most.clone();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    assert!(most.len() > 500 && distinct.len() == most.len());
    let mean_log: f64 = most.iter().map(|g| (g / 0.8645e6).ln()).sum::<f64>() / most.len() as f64;
    assert!(mean_log.abs() < 0.01, "{mean_log}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn bad_files_are_refused_naming_file_row_and_column() {
    let d = dir("refusals");
    let w = "file = \"points.csv\"\nweight = \"hours\"";
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "speed_kmh,vin,hours\n100,7,1\n",
            w,
            &["points.csv", "column `vin`", "polywear params"],
        ),
        (
            "speed_kmh,presure_kpa,hours\n100,240,1\n",
            w,
            &["column `presure_kpa`", "did you mean `pressure_kpa`?"],
        ),
        (
            "speed_kmh,load_n,speed_kmh,hours\n1,2,3,4\n",
            w,
            &["points.csv", "`speed_kmh` appears twice"],
        ),
        (
            "speed_kmh,load_n,hours\n100,4000,1\n120,NaN,2\n",
            w,
            &["points.csv", "row 2 (line 3), column `load_n`", "NaN"],
        ),
        (
            "speed_kmh,load_n,hours\n100,inf,1\n",
            w,
            &["points.csv", "row 1 (line 2), column `load_n`", "finite"],
        ),
        (
            "speed_kmh,load_n,hours\n100,4000,1\n100,-5,1\n",
            w,
            &[
                "points.csv",
                "row 2 (line 3), column `load_n`",
                "(0, 50000]",
            ],
        ),
        (
            "speed_kmh,load_n,hours\n100,4000,1\n110,4000,-2\n",
            w,
            &["points.csv", "row 2 (line 3), column `hours`", "negative"],
        ),
        (
            "speed_kmh,load_n,hours\n100,4000,0\n110,4000,0\n",
            w,
            &["points.csv", "column `hours`", "every weight is zero"],
        ),
        ("", w, &["points.csv", "empty file"]),
        ("speed_kmh,load_n,hours\n", w, &["points.csv", "no rows"]),
        (
            "speed_kmh,load_n\n100,4000\n",
            w,
            &["points.csv", "no column `hours`"],
        ),
        (
            "speed_kmh,g_mod,hours\n100,0.9e6,1\n",
            w,
            &["points.csv", "column `g_mod`", "drawn in [params]"],
        ),
        (
            "speed_kmh,mu_s,hours\n100,0.9,1\n",
            w,
            &["points.csv", "row 1 (line 2)", "mu_s"],
        ),
    ];
    for (points, op, needles) in cases {
        let e = parse(&d, points, op).unwrap_err().to_string();
        for n in *needles {
            assert!(e.contains(n), "{points:?}: `{n}` not in: {e}");
        }
    }
    // A parameter fixed in [params] and given by the file.
    std::fs::write(d.join("points.csv"), "speed_kmh,toe_deg\n100,0.3\n").unwrap();
    let text = study_text("file = \"points.csv\"", "random")
        .replace("[params]\n", "[params]\ntoe_deg = 0.2\n");
    let e = Study::parse_at(&text, Params::default(), &d)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("column `toe_deg`") && e.contains("fixed in [params]"),
        "{e}"
    );
    // Designs other than random are refused with the reason.
    let grid = "design = \"grid\"\n[operating_points]\nfile = \"points.csv\"\n[params]\ng_mod = { dist = \"levels\", levels = [0.8e6, 0.9e6] }\n";
    for (design, text) in [
        ("lhs", study_text("file = \"points.csv\"", "lhs")),
        ("sobol", study_text("file = \"points.csv\"", "sobol")),
        ("saltelli", study_text("file = \"points.csv\"", "saltelli")),
        ("grid", grid.to_string()),
    ] {
        let e = Study::parse_at(&text, Params::default(), &d)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(design) && e.contains("design = \"random\""),
            "{e}"
        );
    }
    // A missing file and an unknown key of the section.
    let e = Study::parse_at(
        &study_text("file = \"nope.csv\"", "random"),
        Params::default(),
        &d,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("nope.csv") && e.contains("cannot read"), "{e}");
    let e = Study::parse_at(
        &study_text("file = \"points.csv\"\nweights = \"h\"", "random"),
        Params::default(),
        &d,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("operating_points.weights"), "{e}");
    std::fs::remove_dir_all(&d).ok();
}

/// Writes the weighted points and a study beside them; returns the study's path.
fn study_file(d: &Path) -> PathBuf {
    std::fs::write(d.join("points.csv"), WEIGHTED).unwrap();
    let s = d.join("fleet.toml");
    std::fs::write(
        &s,
        study_text("file = \"points.csv\"\nweight = \"hours\"", "random"),
    )
    .unwrap();
    s
}

#[test]
fn explore_refuses_bad_files_with_exit_2_before_any_work() {
    let d = dir("cli-refusal");
    let s = study_file(&d);
    std::fs::write(
        d.join("points.csv"),
        "speed_kmh,load_n,hours\n100,4000,1\n120,NaN,2\n",
    )
    .unwrap();
    let out = d.join("run");
    let (code, _, err) = polywear(&[
        "explore",
        "--quiet",
        s.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("points.csv, row 2 (line 3), column `load_n`"),
        "{err}"
    );
    assert!(!out.exists(), "work started");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn same_rows_whatever_threads_and_the_file_is_found_beside_the_study() {
    let d = dir("repro");
    let s = study_file(&d);
    let (one, two) = (d.join("t1"), d.join("t2"));
    // Run from another folder: the relative `file` is resolved against the study's folder.
    let run = |threads: &str, out: &Path| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_polywear"))
            .current_dir(std::env::temp_dir())
            .args([
                "explore",
                "--quiet",
                "--no-report",
                "--samples",
                "300",
                "--threads",
                threads,
            ])
            .args([s.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    run("1", &one);
    run("2", &two);
    let rows = rows_in_dir(&[&one]);
    assert_eq!(rows.len(), 300 * 2);
    assert_eq!(rows, rows_in_dir(&[&two]));
    // Zero-weight rows (2 and 5, counted from 1) are never drawn; the drawn row is recorded.
    assert!(rows
        .iter()
        .all(|r| !r.contains("operating_point_row: 2,") && !r.contains("operating_point_row: 5,")));
    assert!(rows.iter().any(|r| r.contains("operating_point_row: 6,")));
    // The manifest records the file's hash.
    let manifest = std::fs::read_to_string(one.join("_manifest.json")).unwrap();
    let m: serde_json::Value = serde_json::from_str(&manifest).unwrap();
    let bytes = std::fs::read(d.join("points.csv")).unwrap();
    assert_eq!(
        m["operating_points"]["hash"],
        polywear_study::table_input::bytes_hash(&bytes)
    );
    assert_eq!(m["operating_points"]["weight"], "hours");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn resume_refuses_a_changed_file() {
    let d = dir("resume");
    let s = study_file(&d);
    let out = d.join("run");
    let args = [
        "explore",
        "--quiet",
        "--no-report",
        "--samples",
        "128",
        s.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    let (code, _, err) = polywear(&args);
    assert_eq!(code, 0, "{err}");
    let resume = [&args[..], &["--resume"]].concat();
    let (code, _, err) = polywear(&resume);
    assert_eq!(code, 0, "the same file resumes: {err}");
    std::fs::write(
        d.join("points.csv"),
        WEIGHTED.replace("110,3800,245,55", "110,3800,245,56"),
    )
    .unwrap();
    let (code, _, err) = polywear(&resume);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("operating-point file changed"), "{err}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn the_shipped_fleet_study_parses_beside_its_file() {
    let studies = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let text = std::fs::read_to_string(studies.join("fleet_telematics.toml")).unwrap();
    let s = Study::parse_at(&text, Params::default(), &studies).unwrap();
    let op = s.operating_points.as_ref().unwrap();
    assert_eq!(op.names, ["speed_kmh", "load_n", "pressure_kpa", "toe_deg"]);
    assert!(op.weights.contains(&0.0), "a zero-hours bin");
    let hours: f64 = op.weights.iter().sum();
    for (i, w) in op.weights.iter().enumerate() {
        assert!((op.probability(i) - w / hours).abs() < 1e-12);
    }
}

#[test]
fn a_parquet_file_is_read_like_the_csv_and_refused_like_it() {
    use polywear_study::parquet_out::{write_table, Column};
    let d = dir("parquet");
    let speeds = vec![80.0, 120.0, 160.0];
    let write = |name: &str, loads: Vec<f64>| {
        let cols = vec![
            Column::f64("speed_kmh", "km/h", speeds.clone()),
            Column::i64("hours", "h", vec![2, 0, 6]),
            Column::f64("load_n", "N", loads),
        ];
        write_table(&d.join(name), &cols, &[]).unwrap();
    };
    write("points.parquet", vec![3500.0, 4000.0, 4500.0]);
    let op = "file = \"points.parquet\"\nweight = \"hours\"";
    let s = Study::parse_at(&study_text(op, "random"), Params::default(), &d).unwrap();
    let o = s.operating_points.as_ref().unwrap();
    assert_eq!(o.names, ["speed_kmh", "load_n"]);
    assert_eq!(o.values[2], [160.0, 4500.0]);
    assert_eq!(o.weights, [2.0, 0.0, 6.0]);
    assert_eq!(o.probability(1), 0.0);
    assert!((o.probability(2) - 0.75).abs() < 1e-12);
    write("points.parquet", vec![3500.0, f64::NAN, 4500.0]);
    let e = Study::parse_at(&study_text(op, "random"), Params::default(), &d)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("points.parquet, row 2, column `load_n`") && e.contains("NaN"),
        "{e}"
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn the_analysis_finds_a_relative_file_again_from_another_working_directory() {
    // Explore run from the study's own folder with relative paths; the analysis (here, in the
    // test's working directory) re-reads the study and must find the file it names.
    let d = dir("relative");
    study_file(&d);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_polywear"))
        .current_dir(&d)
        .args([
            "explore",
            "fleet.toml",
            "--quiet",
            "--no-report",
            "--samples",
            "50",
        ])
        .args(["--out", "run"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let info = polywear::analysis::inputs::check_inputs(&[d.join("run")]).unwrap();
    let study = info.study.expect("the study re-read beside its file");
    assert!(study.operating_points.is_some());
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn the_analysis_bins_a_files_column_by_its_values_that_can_be_drawn() {
    let d = dir("levels");
    let s = study_file(&d);
    let out = d.join("run");
    let (code, _, err) = polywear(&[
        "explore",
        "--quiet",
        s.to_str().unwrap(),
        "--samples",
        "400",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(out.join("_report/conditional.csv")).unwrap();
    let mut mids: Vec<String> = csv
        .lines()
        .filter(|l| l.starts_with("sliding_share,follower,speed_kmh,"))
        .map(|l| l.split(',').nth(5).unwrap().to_string())
        .collect();
    mids.dedup();
    // The speeds of the rows of positive weight; 100 and 160 km/h have 0 hours.
    assert_eq!(mids, ["80", "110", "120", "140"], "{csv}");
    std::fs::remove_dir_all(&d).ok();
}

/// Weights near the largest float are drawn in their proportion, not through an overflowed
/// total (two rows of 1e308 were drawn 487:13), and analyze's fleet table gives each its share;
/// a `km` weight computed from hours × speed that is not finite is refused naming the row.
#[test]
fn huge_weights_are_drawn_and_shared_without_overflow() {
    let d = dir("huge");
    let points = "speed_kmh,load_n,hours\n90,3500,1e308\n120,4000,1e308\n";
    let study = parse(&d, points, "file = \"points.csv\"\nweight = \"hours\"").unwrap();
    let op = study.operating_points.as_ref().unwrap();
    assert_eq!((op.probability(0), op.probability(1)), (0.5, 0.5));
    let n = 10_000u64;
    let sampler = study.sampler(study.seed, n);
    let first = (0..n)
        .filter(|&i| sampler.sample_with_row(i).2 == Some(0))
        .count() as f64;
    // Binomial(10000, 1/2): sd 50; 4.5 sd either side.
    assert!((first - 5000.0).abs() < 225.0, "{first} of {n}");
    // The fleet table's weight shares.
    let toml = d.join("huge.toml");
    std::fs::write(
        &toml,
        study_text("file = \"points.csv\"\nweight = \"hours\"", "random")
            .replace("samples = 300", "samples = 40"),
    )
    .unwrap();
    let out = d.join("run");
    let (code, _, stderr) = polywear(&[
        "explore",
        toml.to_str().unwrap(),
        "--quiet",
        "--no-report",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let report = d.join("report");
    let (code, stdout, stderr) = polywear(&[
        "analyze",
        out.to_str().unwrap(),
        "--out",
        report.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let fleet = std::fs::read_to_string(report.join("fleet_rows.csv")).expect(&stdout);
    let header: Vec<&str> = fleet.lines().next().unwrap().split(',').collect();
    let j = header.iter().position(|c| *c == "weight_share").unwrap();
    for line in fleet.lines().skip(1) {
        let share: f64 = line.split(',').nth(j).unwrap().parse().unwrap();
        assert!((share - 0.5).abs() < 1e-12, "{fleet}");
    }
    // hours 1e307 at 120 km/h: a km weight of 1.2e309.
    let e = parse(
        &d,
        "speed_kmh,load_n,hours\n90,3500,1\n120,4000,1e307\n",
        "file = \"points.csv\"\nweight = \"km\"",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains(
            "weight `km` computed as hours × speed_kmh = 1e307 × 120 is not a finite number"
        ) && e.contains("accepted: hours × speed_kmh below 1.8e308"),
        "{e}"
    );
    std::fs::remove_dir_all(&d).ok();
}
