//! `polywear analyze`: a risk map whose answer is known, report files, and bad input.

use crate::{common, parquet_rows};
use std::path::PathBuf;

use crate::common::polywear;
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
# The reference constants R0 (studies/params_r0.toml), whose Hopf points are known.
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
            .find(|l| l.starts_with(&format!("sliding_share,{wheel},vibration,{param},")))
            .unwrap_or_else(|| panic!("no row for {param} in\n{csv}"));
        line.split(',').nth(8).unwrap().parse().unwrap()
    };
    // Speed decides the Hopf window; a 1% spread of the tread density barely matters.
    assert!(total("follower", "speed_kmh") > 0.3, "{csv}");
    assert!(total("follower", "rho") < 0.05, "{csv}");
    // The first-order indices from the same rows rank them alike, and rho's is noise.
    let (head, rows) = csv_table(&out.join("_report/first_order.csv"));
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let first = |param: &str| -> (f64, f64, f64) {
        let r = rows
            .iter()
            .find(|r| r[1] == "follower" && r[col("param")] == param)
            .unwrap();
        let v = |c: &str| r[col(c)].parse::<f64>().unwrap();
        (v("first_order"), v("first_order_conf"), v("noise"))
    };
    let (speed, speed_conf, _) = first("speed_kmh");
    let (rho, rho_conf, noise) = first("rho");
    assert!(
        speed - speed_conf > noise,
        "{speed} ± {speed_conf} vs noise {noise}"
    );
    assert!(
        rho - rho_conf < noise,
        "{rho} ± {rho_conf} vs noise {noise}"
    );
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

/// Writes `study` into `dir` and runs `explore --quiet --no-report` on it; panics on failure.
fn explore_study(dir: &std::path::Path, name: &str, study: &str, extra: &[&str]) -> PathBuf {
    crate::common::explore_study(dir, name, study, &[&["--no-report"], extra].concat())
}

/// A cheap study: 3 chunks of 100 samples, both variants.
const SMALL: &str = r#"name = "small"
seed = 5
samples = 300
chunk_size = 100
variants = ["paper", "combined"]
[params]
speed_kmh = { dist = "uniform", min = 60, max = 250 }
toe_deg = { dist = "uniform", min = 0.1, max = 0.5 }
"#;

#[test]
fn inputs_that_do_not_belong_together_are_refused_naming_files_and_key() {
    let dir = tmp("mixed");
    let a = explore_study(&dir, "a", SMALL, &[]);
    let seed = explore_study(&dir, "seed", SMALL, &["--seed", "6"]);
    let samples = explore_study(&dir, "samples", SMALL, &["--samples", "200"]);
    let variant = explore_study(
        &dir,
        "variant",
        &SMALL.replace(r#"["paper", "combined"]"#, r#"["paper"]"#),
        &[],
    );
    let study = explore_study(&dir, "study", &SMALL.replace("max = 250", "max = 240"), &[]);
    let a0 = a.join("chunk-0000000.parquet");
    for (other, key) in [
        (&seed, "`seed`"),
        (&samples, "`samples`"),
        (&variant, "`variant`"),
        (&study, "`study_hash`"),
    ] {
        let report = dir.join("report");
        let (code, _, stderr) = polywear(&[
            "analyze",
            a.to_str().unwrap(),
            other.to_str().unwrap(),
            "--out",
            report.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{key}: {stderr}");
        assert!(stderr.contains(key), "{key}: {stderr}");
        assert!(stderr.contains(a0.to_str().unwrap()), "{key}: {stderr}");
        assert!(stderr.contains(other.to_str().unwrap()), "{key}: {stderr}");
        assert!(!report.exists(), "refused before any work");
    }
    // The same directory twice: duplicate rows, not double counts.
    let (code, _, stderr) = polywear(&["analyze", a.to_str().unwrap(), a.to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("duplicate (sample_id, variant, wheel)"),
        "{stderr}"
    );
    assert!(stderr.contains(a0.to_str().unwrap()), "{stderr}");
    // Overlapping shards: shard 0/2 and shard 0/3 both hold chunk 0.
    let s02 = explore_study(&dir, "s02", SMALL, &["--shard", "0/2"]);
    let s03 = explore_study(&dir, "s03", SMALL, &["--shard", "0/3"]);
    let (code, _, stderr) = polywear(&["analyze", s02.to_str().unwrap(), s03.to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("duplicate (sample_id, variant, wheel)"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Shards that differ in a parameter value or a stage setting recorded in their footers (a
/// `--params` file, the wear zone) are refused naming the first differing key and both values,
/// not merged into one answer.
#[test]
fn shards_with_other_parameters_or_stage_settings_are_refused_naming_the_key() {
    let dir = tmp("differ");
    let s0 = explore_study(&dir, "s0", SMALL, &["--shard", "0/3"]);
    let params = dir.join("p.toml");
    std::fs::write(&params, "[params]\nwear_share_straight = 1\n").unwrap();
    let p = params.to_str().unwrap();
    let with_params = explore_study(&dir, "s1p", SMALL, &["--shard", "1/3", "--params", p]);
    let zone = explore_study(
        &dir,
        "s1z",
        SMALL,
        &["--shard", "1/3", "--wear-zone", "whole_patch"],
    );
    let same = explore_study(&dir, "s1", SMALL, &["--shard", "1/3"]);
    let nominal = format!(
        "({} vs 1.0)",
        polywear::params::Params::default().wear_share_straight
    );
    for (other, words) in [
        (&with_params, ["`params.wear_share_straight`", &nominal]),
        (&zone, ["`wear.wear_zone`", "(trailing vs whole_patch)"]),
    ] {
        let report = dir.join("report");
        let (code, _, stderr) = polywear(&[
            "analyze",
            s0.to_str().unwrap(),
            other.to_str().unwrap(),
            "--out",
            report.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{words:?}: {stderr}");
        for w in words {
            assert!(stderr.contains(w), "`{w}` not in {stderr}");
        }
        assert!(!report.exists(), "refused before any work");
    }
    // Shards of one run still merge.
    let (code, _, stderr) = polywear(&[
        "analyze",
        s0.to_str().unwrap(),
        same.to_str().unwrap(),
        "--out",
        dir.join("ok").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// (samples, vibrating, no_traction, failed) of a variant and wheel in occurrence.csv.
fn occurrence_row(csv: &str, variant: &str, wheel: &str) -> (u64, u64, u64, u64) {
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let line = csv
        .lines()
        .find(|l| l.starts_with(&format!("{variant},{wheel},")))
        .unwrap_or_else(|| panic!("no {variant} {wheel} row in\n{csv}"));
    let cells: Vec<&str> = line.split(',').collect();
    let get = |name: &str| -> u64 {
        let i = header.iter().position(|h| *h == name).unwrap();
        cells[i].parse().unwrap()
    };
    (
        get("samples"),
        get("vibrating"),
        get("no_traction"),
        get("failed"),
    )
}

#[test]
fn missing_chunks_are_reported_and_the_rest_analysed() {
    let dir = tmp("missing");
    let run = explore_study(&dir, "run", SMALL, &[]);
    std::fs::remove_file(run.join("chunk-0000001.parquet")).unwrap();
    let (code, stdout, stderr) = polywear(&["analyze", run.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("200 of 300 samples present"), "{stdout}");
    let md = std::fs::read_to_string(run.join("_report/report.md")).unwrap();
    assert!(md.contains("200 of 300 samples present"), "{md}");
    assert!(md.contains("100 samples are missing"), "{md}");
    let csv = std::fs::read_to_string(run.join("_report/occurrence.csv")).unwrap();
    assert_eq!(occurrence_row(&csv, "paper", "follower").0, 200);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn failed_rows_are_counted_apart_and_an_all_failed_study_says_so() {
    let dir = tmp("failed");
    // A pressure of 2.3 kPa leaves no contact patch: those samples' rows are `failed`.
    let half = explore_study(
        &dir,
        "half",
        &format!("accept_implausible = true\n{SMALL}pressure_kpa = {{ dist = \"levels\", levels = [240, 2.3] }}\n"),
        &[],
    );
    let (code, _, stderr) = polywear(&["analyze", half.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    let csv = std::fs::read_to_string(half.join("_report/occurrence.csv")).unwrap();
    let rows = parquet_rows::rows_in_dir(&[&half]);
    let failed = rows
        .iter()
        .filter(|r| {
            r.contains("variant: \"paper\"")
                && r.contains("wheel: \"follower\"")
                && r.contains("class: \"failed\"")
        })
        .count() as u64;
    let vibrating = rows
        .iter()
        .filter(|r| {
            r.contains("variant: \"paper\"")
                && r.contains("wheel: \"follower\"")
                && (r.contains("class: \"limit_cycle\"") || r.contains("class: \"bistable\""))
        })
        .count() as u64;
    assert!(failed > 100 && failed < 200, "about half: {failed}");
    let (samples, vib, _, f) = occurrence_row(&csv, "paper", "follower");
    assert_eq!(f, failed, "{csv}");
    assert_eq!(
        samples,
        300 - failed,
        "probabilities over classified rows: {csv}"
    );
    assert_eq!(vib, vibrating, "{csv}");
    // Every sample fails: no probability, exit non-zero, the report says so.
    let all = explore_study(
        &dir,
        "all",
        &format!("accept_implausible = true\n{SMALL}pressure_kpa = {{ dist = \"levels\", levels = [2.2, 2.3] }}\n"),
        &[],
    );
    let (code, _, stderr) = polywear(&["analyze", all.to_str().unwrap()]);
    assert_ne!(code, 0);
    assert!(stderr.contains("no row has a verdict"), "{stderr}");
    let md = std::fs::read_to_string(all.join("_report/report.md")).unwrap();
    assert!(md.contains("No row has a verdict"), "{md}");
    assert!(
        !md.contains("| 0.00% |"),
        "no 0% for an all-failed study:\n{md}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn an_empty_shard_succeeds_and_all_shards_give_the_single_machine_answer() {
    let dir = tmp("shards");
    let study = dir.join("small.toml");
    std::fs::write(&study, SMALL).unwrap();
    let single = explore_study(&dir, "single", SMALL, &[]);
    let mut shards = Vec::new();
    for k in 0..4 {
        // 3 chunks for 4 shards: shard 3 owns none.
        let out = dir.join(format!("shard-{k}"));
        let (code, stdout, stderr) = polywear(&[
            "explore",
            study.to_str().unwrap(),
            "--shard",
            &format!("{k}/4"),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "shard {k}: {stderr}");
        if k == 3 {
            assert!(stdout.contains("holds no rows"), "{stdout}");
            assert!(out.join("_manifest.json").exists());
            let md = std::fs::read_to_string(out.join("_report/report.md")).unwrap();
            assert!(md.contains("This shard holds no rows"), "{md}");
        }
        shards.push(out);
    }
    let report = dir.join("all_report");
    let mut args = vec!["analyze".to_string()];
    args.extend(shards.iter().map(|s| s.to_str().unwrap().to_string()));
    args.extend(["--out".into(), report.to_str().unwrap().into()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, stdout, stderr) = polywear(&args);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("300 of 300 samples present"), "{stdout}");
    let (code, _, stderr) = polywear(&["analyze", single.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    for table in [
        "occurrence.csv",
        "paired.csv",
        "conditional.csv",
        "severity.csv",
    ] {
        assert_eq!(
            std::fs::read_to_string(report.join(table)).unwrap(),
            std::fs::read_to_string(single.join("_report").join(table)).unwrap(),
            "{table}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn robustness_to_the_lost_digits_compares_wheels_per_decoding() {
    let dir = tmp("decoding");
    // Provisional decoding study: two decoded constants over alternative readings, with the
    // operating axes drawn; the combined variant makes the driving wheel less exposed.
    let run = explore_study(
        &dir,
        "decoding",
        r#"name = "decoding_provisional"
seed = 3
samples = 1200
chunk_size = 400
variants = ["paper", "combined"]
[params]
speed_kmh = { dist = "uniform", min = 60, max = 250 }
toe_deg = { dist = "uniform", min = 0.1, max = 0.5 }
xi = { dist = "levels", levels = [0.67, 0.61] }
phi = { dist = "levels", levels = [0.94, 0.9, 0.98] }
"#,
        &[],
    );
    let (code, stdout, stderr) = polywear(&["analyze", run.to_str().unwrap(), "--min-count", "50"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("lost digits"), "{stdout}");
    let md = std::fs::read_to_string(run.join("_report/report.md")).unwrap();
    assert!(md.contains("## Robustness to the lost digits"), "{md}");
    let csv = std::fs::read_to_string(run.join("_report/robustness.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // 2 x 3 decodings per variant.
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 2 * 6, "{csv}");
    // The same counts from the rows themselves.
    let all = parquet_rows::rows_in_dir(&[&run]);
    for r in &rows {
        let (variant, xi, phi) = (r[col("variant")], r[col("xi")], r[col("phi")]);
        for wheel in ["follower", "driving"] {
            let of = |class: &str| {
                all.iter()
                    .filter(|x| {
                        x.contains(&format!("variant: \"{variant}\""))
                            && x.contains(&format!("wheel: \"{wheel}\""))
                            && x.contains(&format!("xi: {xi},"))
                            && x.contains(&format!("phi: {phi},"))
                            && x.contains(&format!("class: \"{class}\""))
                    })
                    .count()
            };
            let vib = of("limit_cycle") + of("bistable");
            let n = vib + of("stable");
            assert_eq!(r[col(&format!("{wheel}_samples"))], n.to_string(), "{r:?}");
            assert_eq!(
                r[col(&format!("{wheel}_vibrating"))],
                vib.to_string(),
                "{r:?}"
            );
        }
    }
    // The share for the combined variant: the driving wheel is less exposed in every decoding.
    let combined: Vec<&Vec<&str>> = rows.iter().filter(|r| r[0] == "combined").collect();
    let less = combined
        .iter()
        .filter(|r| r[col("driving_less_exposed")] == "yes")
        .count();
    assert_eq!(less, 6, "{csv}");
    assert!(
        md.contains(
            "**combined**: the driving wheel is less exposed than the follower in 6 of 6 decodings"
        ),
        "{md}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn tables_are_csv_with_quoting_and_parquet_copies() {
    let dir = tmp("tables");
    let run = explore_study(&dir, "run", SMALL, &[]);
    let (code, _, stderr) = polywear(&["analyze", run.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    for stem in [
        "occurrence",
        "paired",
        "conditional",
        "severity",
        "riskmap_speed_kmh_toe_deg",
    ] {
        let csv = run.join("_report").join(format!("{stem}.csv"));
        let pq = run.join("_report").join(format!("{stem}.parquet"));
        let text = std::fs::read_to_string(&csv).unwrap();
        let reader = SerializedFileReader::new(std::fs::File::open(&pq).unwrap()).unwrap();
        let n = reader.metadata().file_metadata().num_rows() as usize;
        assert_eq!(
            text.lines().count(),
            n + 1,
            "{stem}: CSV and Parquet hold the same rows"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_grid_axis_of_one_level_is_labelled_with_the_value_sampled() {
    // A uniform grid axis with count = 1 samples the middle of its range; the analysis labels
    // the level with that value, never with `min`.
    let dir = tmp("grid-one-level");
    let study = dir.join("one_level.toml");
    std::fs::write(
        &study,
        r#"name = "one_level"
design = "grid"
[params]
speed_kmh = { dist = "uniform", min = 80, max = 160, count = 3 }
toe_deg = { dist = "uniform", min = 0.2, max = 0.4, count = 1 }
"#,
    )
    .unwrap();
    let out = dir.join("run");
    let (code, _, stderr) = polywear(&[
        "explore",
        study.to_str().unwrap(),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let rows = parquet_rows::rows(&out.join("_report/conditional.parquet"));
    let toe_mids: Vec<f64> = rows
        .iter()
        .filter(|r| r["axis"] == Field::Str("toe_deg".into()))
        .map(|r| match r["bin_mid"] {
            Field::Double(x) => x,
            ref other => panic!("bin_mid {other:?}"),
        })
        .collect();
    assert!(!toe_mids.is_empty(), "no toe_deg rows");
    for mid in toe_mids {
        assert!(
            (mid - 0.3).abs() < 1e-12,
            "toe level labelled {mid}, sampled 0.3"
        );
    }
    // Every sample really was drawn at toe 0.3.
    for r in parquet_rows::rows(&out.join("chunk-0000000.parquet")) {
        let Field::Double(toe) = r["toe_deg"] else {
            panic!("toe_deg {:?}", r["toe_deg"])
        };
        assert!((toe - 0.3).abs() < 1e-12, "sampled toe {toe}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_analysis_reads_the_runs_parameter_values_back_for_its_nominal_tire() {
    // A run made with `--params`: the study the analysis re-reads (for the nominal tire whose
    // Hopf curves overlay the risk maps) stands on the run's values, not on the defaults.
    let dir = tmp("params-back");
    let study = dir.join("small.toml");
    std::fs::write(
        &study,
        "name = \"small\"\nsamples = 64\n[params]\nspeed_kmh = { dist = \"uniform\", min = 80, max = 160 }\n",
    )
    .unwrap();
    let out = dir.join("run");
    let (code, _, stderr) = polywear(&[
        "explore",
        study.to_str().unwrap(),
        "--params",
        concat!(env!("CARGO_MANIFEST_DIR"), "/studies/params_r0.toml"),
        "--quiet",
        "--no-report",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let info = polywear::analysis::inputs::check_inputs(&[out]).unwrap();
    let base = info.study.unwrap().base;
    let r0 = polywear::params::Params::r0();
    assert_eq!(
        (base.g_mod, base.c_brush, base.alpha2),
        (r0.g_mod, r0.c_brush, r0.alpha2)
    );
    assert_ne!(base.g_mod, polywear::params::Params::default().g_mod);
    std::fs::remove_dir_all(&dir).ok();
}

/// The CSV table `file` as its header and rows of fields.
fn csv_table(file: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(file).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (head, rows)
}

#[test]
fn rows_without_a_verdict_lead_the_summary_and_the_report_with_their_reasons() {
    let dir = tmp("failures");
    let out = dir.join("run");
    // A work budget too small for most limit cycles: those wheels are `failed`.
    let (code, _, stderr) = polywear(&[
        "explore",
        "--samples",
        "300",
        "--max-rhs-evals",
        "300",
        "--quiet",
        "--no-report",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, stderr) = polywear(&["analyze", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.starts_with("WARNING: "), "{stdout}");
    let warning = stdout.lines().next().unwrap();
    assert!(warning.contains(" of 600 rows ("), "{warning}");
    assert!(
        stdout.contains(" failed: budget exceeded (max_rhs_evals = …; … RHS evaluations spent)"),
        "{stdout}"
    );
    // No discordant pair is left to test: the p-value says so.
    assert!(
        stdout.contains("McNemar p = n/a (no discordant pairs)"),
        "{stdout}"
    );
    let report = out.join("_report");
    let md = std::fs::read_to_string(report.join("report.md")).unwrap();
    let no_verdict = md.find("have no verdict").expect("the warning");
    assert!(no_verdict < md.find("P(vibration)").unwrap(), "{md}");
    assert!(md.contains("| n/a (no discordant pairs) |"), "{md}");
    // The reasons' table counts every failed row once.
    let (head, rows) = csv_table(&report.join("failures.csv"));
    assert_eq!(head[..2], ["class", "rows"]);
    let counted: u64 = rows.iter().map(|r| r[1].parse::<u64>().unwrap()).sum();
    let (_, occurrence) = csv_table(&report.join("occurrence.csv"));
    let failed: u64 = occurrence
        .iter()
        .map(|r| r[11].parse::<u64>().unwrap())
        .sum();
    assert!(failed > 6, "more than 1% of 600 rows: {failed}");
    assert_eq!(counted, failed);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_fleet_report_answers_per_operating_point() {
    let dir = tmp("fleet");
    let out = dir.join("run");
    let study = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/fleet_telematics.toml");
    let (code, stdout, stderr) = polywear(&[
        "explore",
        study,
        "--samples",
        "4000",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(!stdout.contains("WARNING"), "{stdout}");
    assert!(
        stdout.contains(
            "P(vibration) over classified rows, weighted by hours driven at each operating point (column `hours`)"
        ),
        "{stdout}"
    );
    let report = out.join("_report");
    let (head, rows) = csv_table(&report.join("fleet_rows.csv"));
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let num = |r: &Vec<String>, name: &str| r[col(name)].parse::<f64>().unwrap();
    assert!(rows.len() >= 20, "{} rows", rows.len());
    // Sorted by the share of the fleet's risk; the shares of each wheel add up to 1.
    let shares: Vec<f64> = rows.iter().map(|r| num(r, "risk_share")).collect();
    assert!(shares.windows(2).all(|w| w[0] >= w[1]), "{shares:?}");
    for share in ["risk_share", "follower_risk_share", "driving_risk_share"] {
        let sum: f64 = rows.iter().map(|r| num(r, share)).sum();
        assert!((sum - 1.0).abs() < 1e-9, "{share}: {sum}");
    }
    // The rows' P, weighted by the samples that drew them, is the headline P; weighted by the
    // hours, the same within the sampling noise.
    let (_, occurrence) = csv_table(&report.join("occurrence.csv"));
    let headline = |wheel: &str| -> f64 {
        let r = occurrence.iter().find(|r| r[1] == wheel).unwrap();
        r[4].parse().unwrap()
    };
    for wheel in ["follower", "driving"] {
        let n: f64 = rows
            .iter()
            .map(|r| num(r, &format!("{wheel}_samples")))
            .sum();
        let by_samples: f64 = rows
            .iter()
            .map(|r| num(r, &format!("{wheel}_samples")) / n * num(r, &format!("{wheel}_p")))
            .sum();
        assert!((by_samples - headline(wheel)).abs() < 1e-12, "{wheel}");
        let by_hours: f64 = rows
            .iter()
            .map(|r| num(r, "weight_share") * num(r, &format!("{wheel}_p")))
            .sum();
        assert!(
            (by_hours - headline(wheel)).abs() < 0.03,
            "{wheel}: {by_hours}"
        );
    }
    // The per-row table comes before the maps, and the mostly empty maps are not drawn.
    let md = std::fs::read_to_string(report.join("report.md")).unwrap();
    let table = md
        .find("## Which operating points carry the risk?")
        .unwrap();
    assert!(table < md.find("## Where does the risk live?").unwrap());
    assert!(md.contains("carry half of the fleet's risk"), "{md}");
    assert!(
        md.contains("Risk map speed × toe-in (sliding_share) not drawn"),
        "{md}"
    );
    assert!(!report
        .join("riskmap_speed_kmh_toe_deg_sliding_share.png")
        .exists());
    assert!(report.join("riskmap_speed_kmh_toe_deg.csv").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// A chunk whose wear columns were edited after the run (a negative distance, +inf growth, NaN
/// distances on rows with a verdict and no `wear_reason`) is refused naming the file, the column
/// and what is accepted, instead of being counted.
#[test]
fn edited_wear_values_are_refused_naming_file_column_and_range() {
    if !crate::common::python_has(&["pyarrow"]) {
        return;
    }
    let dir = tmp("wearvalues");
    let run = explore_study(
        &dir,
        "run",
        &SMALL.replace("samples = 300", "samples = 100"),
        &[],
    );
    let chunk = run.join("chunk-0000000.parquet");
    let edit = r#"
import sys, math, pyarrow as pa, pyarrow.parquet as pq
src, dst, how = sys.argv[1], sys.argv[2], sys.argv[3]
t = pq.read_table(src)
col = "growth_rate_per_1000km" if how == "inf" else "distance_to_visible_km"
v = t.column(col).to_pylist()
cls = t.column("class").to_pylist()
if how == "negative":
    v[0] = -5000.0
elif how == "inf":
    v[0] = math.inf
else:
    reason = t.column("wear_reason").to_pylist()
    i = next(i for i, c in enumerate(cls) if c in ("stable", "limit_cycle", "bistable"))
    v[i] = math.nan
    reason[i] = ""
    t = t.set_column(t.schema.get_field_index("wear_reason"), "wear_reason", pa.array(reason, pa.string()))
t = t.set_column(t.schema.get_field_index(col), col, pa.array(v, pa.float64()))
pq.write_table(t, dst)
"#;
    for (how, words) in [
        (
            "negative",
            ["`distance_to_visible_km`", "values below 0", "[0, inf] km"],
        ),
        ("inf", ["`growth_rate_per_1000km`", "+inf", "a finite rate"]),
        (
            "nan",
            [
                "`distance_to_visible_km`",
                "NaN on rows with a verdict and no `wear_reason`",
                "accepted: a distance",
            ],
        ),
    ] {
        let edited = dir.join(format!("{how}.parquet"));
        crate::common::python(
            edit,
            &[chunk.to_str().unwrap(), edited.to_str().unwrap(), how],
        );
        let report = dir.join(format!("report-{how}"));
        let (code, _, stderr) = polywear(&[
            "analyze",
            edited.to_str().unwrap(),
            "--out",
            report.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{how}: {stderr}");
        assert!(stderr.contains(edited.to_str().unwrap()), "{stderr}");
        for w in words {
            assert!(stderr.contains(w), "{how}: `{w}` not in {stderr}");
        }
    }
    // The unedited chunk, given as a file, is analysed.
    let (code, _, stderr) = polywear(&[
        "analyze",
        chunk.to_str().unwrap(),
        "--out",
        dir.join("ok").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}
