//! The catalogue of bad and hostile inputs: each is refused before any work with exit 2 and a
//! message naming the field and its accepted range, or (for damaged output directories) handled
//! without losing or inventing a row. Each case is one that a plausible implementation gets
//! wrong.

use crate::common;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::parquet_rows::rows_in_dir;
use parquet::file::reader::{FileReader, SerializedFileReader};

/// Runs polywear with a time limit in seconds (see [`common::polywear_within`]).
fn run(args: &[&str], limit_s: u64) -> (i32, String, String) {
    common::polywear_within(Duration::from_secs(limit_s), args)
}

/// Asserts exit 2 with every needle in stderr, within a few seconds (refused before work).
fn refused(args: &[&str], needles: &[&str]) {
    let (code, _, stderr) = run(args, 20);
    assert_eq!(code, 2, "{args:?}: exit {code}: {stderr}");
    for n in needles {
        assert!(
            stderr.contains(n),
            "{args:?}: stderr lacks `{n}`:\n{stderr}"
        );
    }
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
}

/// `polywear explore STUDY --samples SAMPLES --threads 1 EXTRA --out OUT` in the background
/// (quiet, no closing report), for tests that watch or kill a run in progress.
fn spawn_explore(study: &Path, samples: &str, extra: &[&str], out: &Path) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_polywear"))
        .args(["explore", "--quiet", "--no-report", study.to_str().unwrap()])
        .args(["--samples", samples, "--threads", "1"])
        .args(extra)
        .args(["--out", out.to_str().unwrap()])
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

/// Polls `done` every 10 ms until it holds or 30 s have passed; returns the time waited.
fn wait_up_to_30s(mut done: impl FnMut() -> bool) -> Duration {
    let t0 = Instant::now();
    while !done() && t0.elapsed() < Duration::from_secs(30) {
        std::thread::sleep(Duration::from_millis(10));
    }
    t0.elapsed()
}

fn tmp(name: &str) -> PathBuf {
    let d = common::fresh_dir(&format!("bad-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A small study (chunks of 16 samples) with `extra` params lines, written to `dir/NAME.toml`.
fn study(dir: &Path, name: &str, extra: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(
        &path,
        format!(
            r#"name = "{name}"
seed = 3
samples = 64
chunk_size = 16
[params]
speed_kmh = {{ dist = "uniform", min = 60, max = 200 }}
toe_deg = {{ dist = "uniform", min = 0.05, max = 0.6 }}
{extra}
"#
        ),
    )
    .unwrap();
    path
}

fn explore_ok(args: &[&str]) -> String {
    let (code, _, stderr) = run(
        &[&["explore", "--quiet", "--no-report"], args].concat(),
        120,
    );
    assert_eq!(code, 0, "{args:?}: {stderr}");
    stderr
}

fn footer(path: &Path) -> Vec<(String, String)> {
    let r = SerializedFileReader::new(std::fs::File::open(path).unwrap()).unwrap();
    r.metadata()
        .file_metadata()
        .key_value_metadata()
        .unwrap()
        .iter()
        .map(|kv| (kv.key.clone(), kv.value.clone().unwrap_or_default()))
        .collect()
}

fn get<'a>(meta: &'a [(String, String)], key: &str) -> Option<&'a str> {
    meta.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

#[test]
fn negative_and_absurd_integer_flags_name_their_range() {
    let cases: &[(&[&str], &[&str])] = &[
        (&["explore", "--samples", "-5"], &["--samples", "[1, 2^40]"]),
        (
            &["explore", "--seed", "-1"],
            &["--seed", "[0, 4398046510080]"],
        ),
        (&["explore", "--seed", "1.5"], &["--seed", "whole number"]),
        (&["explore", "--threads", "-2"], &["--threads", "[1, 1024]"]),
        (&["explore", "--threads", "0"], &["--threads", "[1, 1024]"]),
        (
            &["explore", "--samples", "10", "--threads", "100000"],
            &["--threads", "[1, 1024]"],
        ),
        (
            &["classify", "x.csv", "--out", "y.csv", "--threads", "100000"],
            &["--threads", "[1, 1024]"],
        ),
        (
            &[
                "bifurcation",
                "--param",
                "speed_kmh",
                "--from",
                "60",
                "--to",
                "90",
                "--threads",
                "5000",
            ],
            &["--threads", "[1, 1024]"],
        ),
        (
            &["reproduce", "--threads", "-1"],
            &["--threads", "[1, 1024]"],
        ),
        (
            &["validate", "--threads", "2048"],
            &["--threads", "[1, 1024]"],
        ),
        (
            &["analyze", "somewhere", "--bins", "-3"],
            &["--bins", "[2, 200]"],
        ),
        (
            &["analyze", "somewhere", "--map-bins", "-1"],
            &["--map-bins", "[2, 200]"],
        ),
        (
            &["analyze", "somewhere", "--min-count", "-7"],
            &["--min-count", "[1, 1000000000]"],
        ),
        (
            &["analyze", "somewhere", "--bootstrap", "-10"],
            &["--bootstrap", "[10, 100000]"],
        ),
        (
            &[
                "bifurcation",
                "--param",
                "speed_kmh",
                "--from",
                "60",
                "--to",
                "90",
                "--steps",
                "-4",
            ],
            &["--steps", "[2, 100000]"],
        ),
        (&["reproduce", "--steps", "-11"], &["--steps", "[11, 2001]"]),
        (
            &["validate", "--points", "-1"],
            &["--points", "[1, 100000]"],
        ),
        (
            &["validate", "--seed", "-1"],
            &["--seed", "[0, 4398046510080]"],
        ),
        // A count the design cannot address: the study's check, named by the flag that gave it.
        (
            &[
                "explore",
                "studies/wide_structure.toml",
                "--samples",
                "4294967297",
            ],
            &[
                "--samples 4294967297",
                "sobol design supports at most 2^32 samples",
            ],
        ),
    ];
    for (args, needles) in cases {
        refused(args, needles);
    }
}

#[test]
fn levels_are_checked_element_by_element() {
    let dir = tmp("levels");
    for (levels, needle) in [
        (
            "[200, nan, -5, 300]",
            "`params.pressure_kpa.levels[1]` = NaN must be finite",
        ),
        ("[200, -5, 300]", "`params.pressure_kpa.levels[1]`"),
        ("[200, 240, 1e9, 300]", "`params.pressure_kpa.levels[2]`"),
        ("[200, inf]", "`params.pressure_kpa.levels[1]`"),
    ] {
        let s = study(
            &dir,
            "lv",
            &format!("pressure_kpa = {{ dist = \"levels\", levels = {levels} }}"),
        );
        let out = dir.join("out");
        refused(
            &[
                "explore",
                s.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            &[needle],
        );
        assert!(!out.exists(), "{levels}: output created before the check");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn resume_of_a_different_study_with_multibyte_text_does_not_panic() {
    let dir = tmp("short");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    // The old study's JSON text has a two-byte character across byte 60.
    let manifest = serde_json::json!({
        "polywear_version": env!("CARGO_PKG_VERSION"),
        "rng": polywear_core::sampling::RNG_NAME,
        "study": format!("# {}", "é".repeat(100)),
        "params": serde_json::to_value(polywear::params::Params::default()).unwrap(),
        "seed": 1, "samples": 64, "chunk_size": 64, "shard": "0/1",
    });
    std::fs::write(out.join("_manifest.json"), manifest.to_string()).unwrap();
    let s = study(&dir, "other", "");
    refused(
        &[
            "explore",
            s.to_str().unwrap(),
            "--resume",
            "--out",
            out.to_str().unwrap(),
        ],
        &["differs from the run's study", "- # éé", "+ "],
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn classify_and_simulate_check_their_output_before_any_work() {
    let dir = tmp("outdir");
    let csv = dir.join("points.csv");
    std::fs::write(&csv, "speed_kmh,toe_deg\n100,0.3\n150,0.4\n").unwrap();
    // A missing folder is created, as every command does with its output paths.
    let missing = dir.join("no/such/dir/out.csv");
    let m = missing.to_str().unwrap();
    let (code, _, stderr) = common::polywear(&["classify", csv.to_str().unwrap(), "--out", m]);
    assert_eq!(code, 0, "{stderr}");
    assert!(missing.is_file());
    let png = dir.join("other/dir/plot.png");
    let (code, _, stderr) = common::polywear(&["simulate", "--plot", png.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(png.is_file());
    // An existing directory is not a file name.
    let d = dir.join("a_dir.csv");
    std::fs::create_dir_all(&d).unwrap();
    refused(
        &[
            "classify",
            csv.to_str().unwrap(),
            "--out",
            d.to_str().unwrap(),
        ],
        &["--out", "is a directory"],
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn duplicate_csv_header_columns_are_refused() {
    let dir = tmp("dupcsv");
    let csv = dir.join("points.csv");
    std::fs::write(&csv, "speed_kmh,toe_deg,speed_kmh\n100,0.3,150\n").unwrap();
    let out = dir.join("out.csv");
    refused(
        &[
            "classify",
            csv.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &["`speed_kmh` appears twice"],
    );
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn failed_rows_carry_nan_not_zero_and_metadata_is_json() {
    let dir = tmp("failed");
    // A pressure of 2.3 kPa leaves no contact patch: those samples are failed rows.
    let s = study(
        &dir,
        "fails",
        "pressure_kpa = { dist = \"levels\", levels = [240, 2.3] }",
    );
    let out = dir.join("out");
    explore_ok(&[
        s.to_str().unwrap(),
        "--accept-implausible",
        "--out",
        out.to_str().unwrap(),
    ]);
    let chunk = out.join("chunk-0000000.parquet");
    let r = SerializedFileReader::new(std::fs::File::open(&chunk).unwrap()).unwrap();
    let mut failed = 0;
    for row in r.get_row_iter(None).unwrap() {
        let row = row.unwrap();
        let mut class = String::new();
        let mut values = Vec::new();
        for (name, field) in row.get_column_iter() {
            let text = field.to_string();
            if name == "class" {
                class = text.trim_matches('"').to_string();
            } else if [
                "amp_y_m",
                "amp_v_mps",
                "freq_hz",
                "polygon_order",
                "energy_per_cycle_j",
            ]
            .contains(&name.as_str())
            {
                values.push((name.clone(), text));
            }
        }
        if class == "failed" {
            failed += 1;
            for (name, v) in values {
                assert!(v.contains("NaN") || v == "null", "failed row: {name} = {v}");
            }
        }
    }
    assert!(failed > 0, "the study should give failed rows");
    // `drawn` is real JSON, one object per drawn parameter in study-file terms.
    let meta = footer(&chunk);
    let drawn: serde_json::Value = serde_json::from_str(get(&meta, "drawn").unwrap()).unwrap();
    let speed = drawn
        .as_array()
        .unwrap()
        .iter()
        .find(|d| d["name"] == "speed_kmh")
        .expect("speed_kmh in drawn");
    assert_eq!(speed["dist"], "uniform");
    assert_eq!(speed["min"], 60.0);
    assert_eq!(speed["max"], 200.0);
    // The study text once, in the manifest; each chunk carries its hash.
    let text = std::fs::read_to_string(&s).unwrap();
    assert!(
        get(&meta, "study").is_none(),
        "study text copied into a chunk footer"
    );
    assert_eq!(
        get(&meta, "study_hash"),
        Some(polywear::study::text_hash(&text).as_str())
    );
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("_manifest.json")).unwrap())
            .unwrap();
    assert_eq!(manifest["study"], text.as_str());
    // The JSON of `simulate` gives null for what a failed point does not have.
    let (code, stdout, stderr) = run(
        &[
            "simulate", "--json", "--set", "mu_m=0.3", "--set", "mu_s=0.2",
        ],
        60,
    );
    assert_eq!(code, 0, "{stderr}");
    for line in stdout.lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        if v["class"] == "failed" {
            assert!(v["amp_y_m"].is_null(), "{line}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Writes a finished 4-chunk run into `dir/NAME` and returns (out dir, its rows).
fn finished_run(dir: &Path, s: &Path, name: &str) -> (PathBuf, Vec<String>) {
    let out = dir.join(name);
    explore_ok(&[s.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let rows = rows_in_dir(&[&out]);
    assert_eq!(rows.len(), 64 * 2);
    (out, rows)
}

#[test]
fn resume_verifies_every_kept_chunk_and_redoes_bad_ones() {
    let dir = tmp("verify");
    let s = study(&dir, "v", "");
    let sa = s.to_str().unwrap();
    let (reference, rows) = finished_run(&dir, &s, "reference");

    // Truncated to 500 bytes (disk full, a node lost mid-copy).
    let (out, _) = finished_run(&dir, &s, "truncated");
    let f = out.join("chunk-0000002.parquet");
    let bytes = std::fs::read(&f).unwrap();
    std::fs::write(&f, &bytes[..500]).unwrap();
    let stderr = explore_ok(&[sa, "--resume", "--out", out.to_str().unwrap()]);
    assert!(
        stderr.contains("chunk-0000002.parquet") && stderr.contains("truncated"),
        "{stderr}"
    );
    assert_eq!(rows_in_dir(&[&out]), rows);

    // Two chunk files swapped.
    let (out, _) = finished_run(&dir, &s, "swapped");
    let (a, b) = (
        out.join("chunk-0000001.parquet"),
        out.join("chunk-0000003.parquet"),
    );
    let tmpf = out.join("x");
    std::fs::rename(&a, &tmpf).unwrap();
    std::fs::rename(&b, &a).unwrap();
    std::fs::rename(&tmpf, &b).unwrap();
    let stderr = explore_ok(&[sa, "--resume", "--out", out.to_str().unwrap()]);
    for c in ["chunk-0000001.parquet", "chunk-0000003.parquet"] {
        assert!(stderr.contains(c), "{c}: {stderr}");
    }
    assert_eq!(rows_in_dir(&[&out]), rows);

    // A foreign chunk (another seed's) under a kept name; one byte flipped in another.
    let (out, _) = finished_run(&dir, &s, "foreign");
    let other = dir.join("other");
    explore_ok(&[sa, "--seed", "99", "--out", other.to_str().unwrap()]);
    std::fs::copy(
        other.join("chunk-0000000.parquet"),
        out.join("chunk-0000000.parquet"),
    )
    .unwrap();
    let f = out.join("chunk-0000003.parquet");
    let mut bytes = std::fs::read(&f).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x40;
    std::fs::write(&f, &bytes).unwrap();
    let stderr = explore_ok(&[sa, "--resume", "--out", out.to_str().unwrap()]);
    assert!(stderr.contains("chunk-0000000.parquet"), "{stderr}");
    assert!(
        stderr.contains("chunk-0000003.parquet") && stderr.contains("CRC-32"),
        "{stderr}"
    );
    assert_eq!(rows_in_dir(&[&out]), rows);

    // A chunk file deleted: redone. A chunk file of no chunk of this run: refused.
    std::fs::remove_file(out.join("chunk-0000001.parquet")).unwrap();
    let stderr = explore_ok(&[sa, "--resume", "--out", out.to_str().unwrap()]);
    assert!(
        stderr.contains("chunk-0000001.parquet") && stderr.contains("missing"),
        "{stderr}"
    );
    assert_eq!(rows_in_dir(&[&out]), rows);
    std::fs::copy(
        out.join("chunk-0000001.parquet"),
        out.join("chunk-0000009.parquet"),
    )
    .unwrap();
    refused(
        &["explore", sa, "--resume", "--out", out.to_str().unwrap()],
        &["chunk-0000009.parquet", "not a chunk of this run"],
    );

    // A resume of a finished run changes nothing.
    explore_ok(&[sa, "--resume", "--out", reference.to_str().unwrap()]);
    assert_eq!(rows_in_dir(&[&reference]), rows);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn leftovers_of_a_run_killed_before_its_manifest_do_not_block_the_directory() {
    let dir = tmp("leftover");
    let s = study(&dir, "l", "");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("_lock"), "12345\n").unwrap();
    std::fs::write(out.join("_manifest.json.partial"), "").unwrap();
    explore_ok(&[s.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(rows_in_dir(&[&out]).len(), 128);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_second_run_on_the_same_out_is_refused_with_the_holders_pid() {
    let dir = tmp("lock");
    let s = study(&dir, "lk", "");
    let out = dir.join("out");
    let mut first = spawn_explore(&s, "1e9", &[], &out);
    let pid = first.id().to_string();
    wait_up_to_30s(|| out.join("_manifest.json").exists());
    for extra in [&["--resume"][..], &[]] {
        refused(
            &[
                &[
                    "explore",
                    s.to_str().unwrap(),
                    "--samples",
                    "1e9",
                    "--out",
                    out.to_str().unwrap(),
                ],
                extra,
            ]
            .concat(),
            &["in use", &format!("PID {pid}")],
        );
    }
    first.kill().unwrap();
    first.wait().unwrap();
    // The kernel dropped the lock with the process: the next run gets past the lock (and is
    // then told that its sample count contradicts the run's).
    refused(
        &[
            "explore",
            s.to_str().unwrap(),
            "--samples",
            "1e8",
            "--resume",
            "--out",
            out.to_str().unwrap(),
        ],
        &["--samples 100000000 contradicts the run's 1000000000 samples"],
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn startup_is_not_quadratic_in_the_chunk_count() {
    // 1e10 samples in chunks of 16: 625 million chunks. The first chunk must come at once.
    let dir = tmp("startup");
    let s = study(&dir, "big", "");
    let out = dir.join("out");
    let mut child = spawn_explore(&s, "1e10", &[], &out);
    let took = wait_up_to_30s(|| out.join("chunk-0000000.parquet").exists());
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        out.join("chunk-0000000.parquet").exists(),
        "no chunk after {took:?}"
    );
    // Resuming it is as quick: verification is linear in the files present.
    let mut child = spawn_explore(&s, "1e10", &["--resume"], &out);
    let next = |o: &Path| {
        std::fs::read_dir(o)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .starts_with("chunk-")
            })
            .count()
    };
    let before = next(&out);
    let took = wait_up_to_30s(|| next(&out) > before);
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(next(&out) > before, "resume wrote nothing in {took:?}");
    std::fs::remove_dir_all(&dir).ok();
}
