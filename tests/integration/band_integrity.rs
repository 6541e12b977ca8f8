//! The calibration band holds to the guarantees (docs/book/src/reference/guarantees.md): its
//! samples are the run's own (fleet rows and scenarios included), its sets stay inside their
//! parameters' ranges under every scenario, its file and digest are read only when they are the
//! regular files explore wrote and of the same run (every recorded setting, the wear level
//! among them), and a band stopped before it is finished is never taken for one.

use std::os::unix::fs::symlink;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::common::{fresh_dir, polywear, polywear_within, Mount};
use polywear::params::Params;
use polywear::study::Study;
use polywear_study::calibration_band::evaluate::{BandPlan, BAND_DIGEST, BAND_FILE};
use polywear_study::calibration_band::CalibrationBand;

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// The band of `study_text` (a study file's text, its fleet file beside it in `dir`) on its
/// first `n` samples, every wheel's speed and answers under the shipped sets.
fn band_of(dir: &Path, study_text: &str, n: u64) -> Vec<(f64, Vec<String>)> {
    let study = Study::parse_at(study_text, Params::default(), dir).unwrap();
    let stage = polywear::evaluate::WearStage::for_run(
        &study.base,
        study.variants[0],
        Default::default(),
        &Default::default(),
    )
    .unwrap();
    let band = CalibrationBand::shipped();
    let plan = BandPlan {
        study: &study,
        seed: 5,
        samples: n,
        band_samples: n,
        stage: &stage,
        band: &band,
        band_source: "shipped".into(),
    };
    plan.evaluate(&|_| {})
        .iter()
        .flat_map(|s| &s.wheels)
        .map(|w| {
            let answers = w
                .answers
                .iter()
                .map(|a| format!("{:?}", a.distance_to_visible_km))
                .collect();
            (w.speed_kmh, answers)
        })
        .collect()
}

/// A fleet file's row is part of a band sample, as it is of the run's: every band row was
/// evaluated at the default point (100 km/h, 0.3°) instead, and a one-row fleet at 115 km/h and
/// 0.62° gave a band of 0.0–0.0% where the same point as fixed values gave 0.0–100.0%.
#[test]
fn the_band_draws_a_fleet_row_as_the_run_does() {
    let dir = fresh_dir("band-fleet");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("fleet.csv"), "speed_kmh,toe_deg\n115,0.62\n").unwrap();
    let drawn = "[params]\nload_n = { dist = \"uniform\", min = 3000, max = 5000 }\n";
    let fleet = band_of(
        &dir,
        &format!("name = \"f\"\n[operating_points]\nfile = \"fleet.csv\"\n{drawn}"),
        6,
    );
    let fixed = band_of(
        &dir,
        &format!("name = \"f\"\n{drawn}speed_kmh = 115\ntoe_deg = 0.62\n"),
        6,
    );
    assert!(fleet.iter().all(|(v, _)| *v == 115.0), "{fleet:?}");
    assert_eq!(fleet, fixed);
    std::fs::remove_dir_all(&dir).ok();
}

/// The run's own constants are the band's set `run`: a file's set of that id merged with them.
#[test]
fn a_set_may_not_take_the_run_s_own_id() {
    let shipped = CalibrationBand::shipped().to_toml();
    let first_id = shipped.lines().find(|l| l.starts_with("id = ")).unwrap();
    let text = shipped.replacen(first_id, "id = \"run\"", 1);
    let e = CalibrationBand::parse(&text, "c.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("c.toml: set 1 (`run`): `id` = `run` is reserved"),
        "{e}"
    );
}

/// What a band file says of itself is quoted in the report and the summary: one plain line,
/// bounded; and a refusal names the line and the set.
#[test]
fn a_band_file_s_words_are_one_line_and_its_refusals_name_line_and_set() {
    let shipped = CalibrationBand::shipped().to_toml();
    for (method, needle) in [
        (
            "\"a\\n# heading\"",
            "`method` holds the control character '\\n'",
        ),
        ("\"<script>\\u0007\"", "control character"),
        (
            &format!("\"{}\"", "m".repeat(20_000)),
            "holds 20000 characters",
        ),
    ] {
        let text = shipped.replacen(
            &shipped
                .lines()
                .find(|l| l.starts_with("method = "))
                .unwrap()
                .to_string(),
            &format!("method = {method}"),
            1,
        );
        let e = CalibrationBand::parse(&text, "c.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(needle) && e.contains("one line of printable text"),
            "{e}"
        );
    }
    let second_set_factor = shipped
        .lines()
        .filter(|l| l.starts_with("wear_rate_driven_factor = "))
        .nth(1)
        .unwrap();
    let text = shipped.replacen(second_set_factor, "wear_rate_driven_factor = \"x\"", 1);
    let e = CalibrationBand::parse(&text, "c.toml")
        .unwrap_err()
        .to_string();
    let line = text
        .lines()
        .position(|l| l.contains("\"x\""))
        .map(|k| k + 1)
        .unwrap();
    assert!(e.contains(&format!("line {line} (set 2)")), "{e}");
}

/// A scenario's change is made to every set's constants: one that takes a set outside its
/// parameter's range is refused before any work, naming the scenario's key, the set and the
/// range (`scale = 5` took a set at φ_s = 0.23 to 1.15, outside (0, 1], without a word; with
/// today's sets `scale = 3` keeps the run's φ_s in range and takes the largest sets' out).
#[test]
fn a_scenario_that_takes_a_set_out_of_range_is_refused_before_any_work() {
    let dir = fresh_dir("band-scenario");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("s.toml");
    let out = dir.join("run");
    for (change, needles) in [
        (
            "wear_share_straight = { scale = 3 }",
            &[
                "scenarios.x.wear_share_straight",
                "wear_share_straight scaled by 3 takes",
                "outside the accepted range (0, 1]",
            ][..],
        ),
        (
            "speed_spread_kmh = { shift = 92 }",
            &[
                "scenarios.x.speed_spread_kmh",
                "shifted by +92 km/h takes",
                "sets outside the accepted range [0, 100]",
            ][..],
        ),
    ] {
        std::fs::write(
            &study,
            format!("name = \"s\"\nsamples = 10\n[params]\nspeed_kmh = {{ dist = \"uniform\", min = 80, max = 140 }}\n[scenarios.x]\n{change}\n"),
        )
        .unwrap();
        let (code, _, stderr) = polywear(&["explore", "-q", &s(&study), "--out", &s(&out)]);
        assert_eq!(code, 2, "{stderr}");
        for n in needles {
            assert!(stderr.contains(n), "lacks `{n}`: {stderr}");
        }
        assert!(!out.exists(), "wrote {} before refusing", out.display());
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A small run with its band in `dir/run`, and the same samples' band under another wear zone
/// in `dir/other`.
fn small_runs(dir: &Path) -> (PathBuf, PathBuf) {
    let (run, other) = (dir.join("run"), dir.join("other"));
    for (out, zone) in [(&run, None), (&other, Some("whole_patch"))] {
        let mut args = vec![
            "explore",
            "-q",
            "--no-report",
            "--samples",
            "200",
            "--band-samples",
            "100",
            "--out",
        ];
        let o = s(out);
        args.push(&o);
        if let Some(zone) = zone {
            args.extend(["--wear-zone", zone]);
        }
        let (code, _, stderr) = polywear(&args);
        assert_eq!(code, 0, "{stderr}");
    }
    (run, other)
}

/// analyze reads the band and its digest only as the regular files explore wrote: a FIFO
/// planted as the digest hung it for ever, a link to /dev/zero was read into memory (2.1 GB),
/// a damaged digest was reported as missing, and a FIFO or folder as the band was skipped with
/// exit 0. Each is refused at once, exit 2, with the way back; a band of another wear zone of
/// the same study, seed and samples is refused naming the setting.
#[test]
fn analyze_refuses_a_band_that_is_not_the_run_s_own_regular_files() {
    let dir = fresh_dir("band-files");
    std::fs::create_dir_all(&dir).unwrap();
    let (run, other) = small_runs(&dir);
    let (digest, band) = (run.join(BAND_DIGEST), run.join(BAND_FILE));
    let (good_digest, good_band) = (dir.join("digest"), dir.join("band"));
    std::fs::copy(&digest, &good_digest).unwrap();
    std::fs::copy(&band, &good_band).unwrap();
    let fifo = |p: &Path| {
        let c = std::ffi::CString::new(s(p)).unwrap();
        // SAFETY: mkfifo on a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    };
    let report = dir.join("report");
    let refused = |what: &str, needles: &[&str]| {
        let (code, _, stderr) = polywear_within(
            Duration::from_secs(60),
            &["analyze", &s(&run), "--out", &s(&report)],
        );
        assert_eq!(code, 2, "{what}: {stderr}");
        for n in needles {
            assert!(stderr.contains(n), "{what}: lacks `{n}`: {stderr}");
        }
    };
    std::fs::remove_file(&digest).unwrap();
    fifo(&digest);
    refused("a FIFO digest", &["is a FIFO", "explore --resume --out"]);
    std::fs::remove_file(&digest).unwrap();
    symlink("/dev/zero", &digest).unwrap();
    refused("a link to /dev/zero", &["is a symbolic link"]);
    std::fs::remove_file(&digest).unwrap();
    std::fs::write(&digest, "{\"bytes\": 12,").unwrap();
    refused("a damaged digest", &["is damaged"]);
    std::fs::copy(&good_digest, &digest).unwrap();
    std::fs::remove_file(&band).unwrap();
    std::fs::create_dir(&band).unwrap();
    refused("a folder as the band", &["is a directory"]);
    std::fs::remove_dir(&band).unwrap();
    fifo(&band);
    refused("a FIFO as the band", &["is a FIFO"]);
    std::fs::remove_file(&band).unwrap();
    std::fs::copy(other.join(BAND_FILE), &band).unwrap();
    std::fs::copy(other.join(BAND_DIGEST), &digest).unwrap();
    refused(
        "another zone's band",
        &[
            "belongs to another run",
            "`wear.wear_zone` is `whole_patch`, the rows' `trailing`",
        ],
    );
    std::fs::copy(&good_band, &band).unwrap();
    std::fs::copy(&good_digest, &digest).unwrap();
    let (code, _, stderr) = polywear(&["analyze", &s(&run), "--out", &s(&report)]);
    assert_eq!(code, 0, "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A band stopped before it is finished says so: SIGTERM during the band's pass ended the
/// program at once with no word (exit 143), and analyze then reported the run as one without a
/// band. Now the run says what is saved and how to finish, analyze refuses the run until the
/// band is whole, and `--resume` writes it.
#[test]
fn a_band_stopped_midway_is_finished_by_resume_and_never_taken_for_done() {
    let dir = fresh_dir("band-stopped");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("run");
    let study = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/excess_toe.toml");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_polywear"))
        .args([
            "explore",
            study,
            "-q",
            "--no-report",
            "--samples",
            "1000",
            "--band-samples",
            "1000",
            "--out",
            &s(&out),
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // The band's pass starts once the journal holds the run's one chunk.
    let journal = out.join("_manifest.chunks.jsonl");
    let start = std::time::Instant::now();
    while !std::fs::read_to_string(&journal).is_ok_and(|t| t.lines().count() >= 1) {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no chunk written"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let pending = std::fs::read_to_string(out.join(BAND_DIGEST)).unwrap();
    assert!(pending.contains("\"pending\""), "{pending}");
    // SAFETY: kill(2) on the child's pid.
    unsafe {
        libc::kill(child.id() as i32, libc::SIGTERM);
    }
    let end = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&end.stderr);
    assert_eq!(end.status.code(), Some(143), "{stderr}");
    // (A signal between the chunk and the band's first sample stops the run as a run: either
    // way the band is left pending and the run says how to go on.)
    assert!(
        stderr.contains("stopped by SIGTERM")
            && stderr.contains(&format!("explore --resume --out {}", out.display())),
        "{stderr}"
    );
    let (code, _, stderr) = polywear(&["analyze", &s(&out), "--out", &s(&dir.join("r"))]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("is not finished") && stderr.contains("explore --resume --out"),
        "{stderr}"
    );
    let (code, _, stderr) = polywear(&[
        "explore",
        "--resume",
        "-q",
        "--no-report",
        "--out",
        &s(&out),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, stderr) = polywear(&["analyze", &s(&out), "--out", &s(&dir.join("r"))]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("calibration band 0"), "{stdout}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A full disk during the band's pass said no more than the error: it now says that every
/// sample's rows are saved and gives the command that finishes the band.
#[test]
fn a_full_disk_during_the_band_says_how_to_finish_it() {
    let dir = fresh_dir("band-full-disk");
    // The run's chunk (about 114 KB) and manifests fit, its band (about 23 KB) does not.
    let Some(_m) = Mount::tmpfs(&dir, "128k", false) else {
        return;
    };
    let out = dir.join("run");
    let (code, _, stderr) = polywear(&[
        "explore",
        "-q",
        "--no-report",
        "--samples",
        "300",
        "--band-samples",
        "300",
        "--out",
        &s(&out),
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("the disk is full")
            && stderr.contains("every sample's rows are saved")
            && stderr.contains(&format!("explore --resume --out {}", out.display())),
        "{stderr}"
    );
}
