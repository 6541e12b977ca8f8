//! What the tool says to its users: runs that remember (resume with the run's own settings, a
//! finished run named as such, a changed study shown as its lines, signals that stop cleanly,
//! progress lines in batch logs, one summary), verdicts in words, "did you mean" suggestions,
//! sweeps that say what they held fixed, readable maps and consistent refusals.

use crate::common;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::polywear;
use crate::parquet_rows::rows_in_dir;

fn tmp(name: &str) -> PathBuf {
    let d = common::fresh_dir(&format!("talk-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A small random study with small chunks (the one of tests/integration/explore.rs).
fn small_study(dir: &Path, g_sigma: &str) -> PathBuf {
    let path = dir.join(format!("small_{g_sigma}.toml"));
    std::fs::write(
        &path,
        format!(
            r#"name = "small"
seed = 11
samples = 600
chunk_size = 64
variants = ["paper"]
[params]
speed_kmh = {{ dist = "uniform", min = 60, max = 220 }}
toe_deg = {{ dist = "uniform", min = 0.05, max = 0.8 }}
load_n = {{ dist = "truncated_normal", mean = 4000, sd = 800, min = 2500, max = 6500 }}
pressure_kpa = {{ dist = "levels", levels = [200, 240, 280] }}
g_mod = {{ dist = "lognormal", median = 0.8645e6, sigma = {g_sigma} }}
"#
        ),
    )
    .unwrap();
    path
}

fn chunk_files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with("chunk-") && n.ends_with(".parquet"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

fn journal_files(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("_manifest.chunks.jsonl")).unwrap_or_default();
    let mut v: Vec<String> = text
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            v["file"].as_str().unwrap().to_string()
        })
        .collect();
    v.sort();
    v
}

/// Starts `explore` in the background with stderr to a file (so not a terminal), waits for
/// `chunks` chunk files (and a progress line when `--log-every` is given), sends `signal`;
/// returns (exit code, stderr).
fn stop_with(signal: i32, args: &[&str], out: &Path, chunks: usize) -> (i32, String) {
    let log = out.with_extension("stderr");
    let mut child = Command::new(env!("CARGO_BIN_EXE_polywear"))
        .arg("explore")
        .args(args)
        .args(["--out", out.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    let logging = args.contains(&"--log-every");
    let ready = || {
        chunk_files(out).len() >= chunks
            && (!logging
                || std::fs::read_to_string(&log)
                    .unwrap()
                    .contains("progress: "))
    };
    while !ready() && t0.elapsed() < Duration::from_secs(120) {
        std::thread::sleep(Duration::from_millis(5));
    }
    // SAFETY: kill(2) on the PID of our own child, which has not been waited for yet.
    unsafe {
        libc::kill(child.id() as i32, signal);
    }
    let t1 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(
            t1.elapsed() < Duration::from_secs(60),
            "did not stop after the signal"
        );
        std::thread::sleep(Duration::from_millis(10));
    };
    (
        status.code().unwrap_or(-1),
        std::fs::read_to_string(&log).unwrap(),
    )
}

#[test]
fn a_stopped_run_is_resumed_with_its_own_settings_and_equals_an_uninterrupted_one() {
    let base = tmp("resume");
    let study = small_study(&base, "0.05");
    let s = study.to_str().unwrap();
    let run = base.join("run");
    let (code, stderr) = stop_with(
        libc::SIGTERM,
        &[
            s,
            "--samples",
            "6000",
            "--threads",
            "1",
            "--log-every",
            "0.2",
        ],
        &run,
        3,
    );
    assert_eq!(code, 143, "{stderr}");
    // Batch log: progress lines with the rate and the time left.
    let progress = stderr
        .lines()
        .find(|l| l.starts_with("progress: "))
        .unwrap_or_else(|| panic!("no progress line: {stderr}"));
    assert!(
        progress.contains(" of 6000 samples") && progress.contains("samples/s, ETA "),
        "{progress}"
    );
    assert!(stderr.contains("stopped by SIGTERM: "), "{stderr}");
    // What is saved is exactly what the journal records: no chunk half-written or unrecorded.
    let files = chunk_files(&run);
    assert_eq!(files, journal_files(&run));
    assert!(files.len() >= 3 && files.len() < 94, "{files:?}");
    let saved = format!("{} of 6000 samples are saved", files.len() * 64);
    assert!(stderr.contains(&saved), "{saved}: {stderr}");
    let resume = stderr
        .lines()
        .find_map(|l| l.strip_prefix("resume with: "))
        .unwrap_or_else(|| panic!("no resume command: {stderr}"));
    let words: Vec<&str> = resume.split_whitespace().collect();
    assert_eq!(
        words[1..],
        [
            "explore",
            "--resume",
            "--out",
            run.to_str().unwrap(),
            "--threads",
            "1"
        ]
    );
    // Contradicting the run is refused with both values; the directory is untouched.
    let r = run.to_str().unwrap();
    for (flag, value, needle) in [
        ("--seed", "5", "--seed 5 contradicts the run's seed 11"),
        (
            "--samples",
            "7000",
            "--samples 7000 contradicts the run's 6000 samples",
        ),
        (
            "--shard",
            "1/2",
            "--shard 1/2 contradicts the run's shard 0/1",
        ),
    ] {
        let (code, _, stderr) = polywear(&["explore", "--resume", "--out", r, flag, value]);
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(needle), "{stderr}");
    }
    let changed = small_study(&base, "0.08");
    let (code, _, stderr) =
        polywear(&["explore", changed.to_str().unwrap(), "--resume", "--out", r]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("\n    - g_mod = { dist = \"lognormal\", median = 0.8645e6, sigma = 0.05 }\n    + g_mod = { dist = \"lognormal\", median = 0.8645e6, sigma = 0.08 }\n"),
        "{stderr}"
    );
    assert_eq!(
        stderr.matches("\n    ").count(),
        2,
        "only the changed lines: {stderr}"
    );
    assert_eq!(files, chunk_files(&run));
    // The printed command continues the run (repeating a recorded value is accepted).
    let (code, stdout, stderr) = polywear(&[&words[1..], &["--seed", "11"]].concat());
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains(&format!(
            "resume: {} of 6000 samples already saved",
            files.len() * 64
        )),
        "{stderr}"
    );
    // One summary, for the whole run, follower before driving.
    assert_eq!(stdout.matches("P(vibration)").count(), 1, "{stdout}");
    assert!(stdout.contains("6000 of 6000 samples present"), "{stdout}");
    let f = stdout
        .find("paper rear (follower):")
        .expect("follower line");
    let d = stdout.find("paper front (driving):").expect("driving line");
    assert!(f < d, "{stdout}");
    let whole = base.join("whole");
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        s,
        "--samples",
        "6000",
        "--out",
        whole.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(rows_in_dir(&[&run]), rows_in_dir(&[&whole]));
    // A finished run is named as finished, with the next step.
    let (code, _, stderr) = polywear(&["explore", s, "--out", r]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("holds a finished run")
            && stderr.contains(&format!("`polywear analyze {r}`"))
            && stderr.contains("another --out"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&base).ok();
}

#[test]
fn ctrl_c_stops_with_130_and_an_unfinished_run_says_how_far_it_got() {
    let base = tmp("sigint");
    let study = small_study(&base, "0.05");
    let run = base.join("run");
    let (code, stderr) = stop_with(
        libc::SIGINT,
        &[study.to_str().unwrap(), "--samples", "1e6"],
        &run,
        1,
    );
    assert_eq!(code, 130, "{stderr}");
    assert!(stderr.contains("stopped by SIGINT (Ctrl-C)"), "{stderr}");
    assert_eq!(chunk_files(&run), journal_files(&run));
    let r = run.to_str().unwrap();
    let (code, _, stderr) = polywear(&["explore", study.to_str().unwrap(), "--out", r]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("holds an unfinished run")
            && stderr.contains("of 1000000 samples saved")
            && stderr.contains(&format!("`polywear explore --resume --out {r}`")),
        "{stderr}"
    );
    std::fs::remove_dir_all(&base).ok();
}

#[test]
fn simulate_opens_with_a_verdict_in_words_per_wheel() {
    let (code, stdout, stderr) = polywear(&["simulate"]);
    assert_eq!(code, 0, "{stderr}");
    let lines: Vec<&str> = stdout.lines().collect();
    // The default point: both wheels on a limit cycle near 270 Hz, about 19 sides.
    assert!(
        lines[0].starts_with("rear (follower): vibrates (")
            && lines[0].contains(" mm/s, ")
            && lines[0].contains(" µm, ")
            && lines[0].contains(" Hz, ")
            && lines[0].ends_with("-gon)"),
        "{stdout}"
    );
    assert!(
        lines[1].starts_with("front (driving): vibrates ("),
        "{stdout}"
    );
    assert!(stdout.contains("amplitude v [mm/s]"), "{stdout}");
    assert!(!stdout.contains("e-"), "no exponents: {stdout}");
    let (_, stdout, _) = polywear(&["simulate", "--speed", "150", "--toe", "0.5"]);
    let first = stdout.lines().next().unwrap();
    let rate: f64 = first
        .strip_prefix("rear (follower): stable (decays at ")
        .and_then(|r| r.strip_suffix(" 1/s)"))
        .unwrap_or_else(|| panic!("{stdout}"))
        .parse()
        .unwrap();
    assert!(rate > 0.0, "{first}");
}

#[test]
fn help_shows_the_operating_defaults_from_the_parameter_table() {
    let (_, help, _) = polywear(&["simulate", "--help"]);
    for name in ["speed_kmh", "toe_deg", "load_n", "pressure_kpa"] {
        let s = polywear::params::spec(name).unwrap();
        let want = format!(
            "{} [default: {}]",
            s.range_text(),
            polywear_core::wording::plain(s.default, 6)
        );
        assert!(help.contains(&want), "{name}: {want}\n{help}");
    }
}

/// Asserts exit 2 and that stderr holds every needle.
fn refused(args: &[&str], needles: &[&str]) {
    let (code, _, stderr) = polywear(args);
    assert_eq!(code, 2, "{args:?}: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "{args:?}: lacks `{n}`:\n{stderr}");
    }
}

#[test]
fn misspelt_names_get_a_suggestion_wherever_they_are_typed() {
    let dir = tmp("suggest");
    let study = dir.join("typo.toml");
    std::fs::write(
        &study,
        "name = \"t\"\nsamples = 10\n[params]\nsped_kmh = { dist = \"uniform\", min = 60, max = 200 }\n",
    )
    .unwrap();
    refused(
        &[
            "explore",
            study.to_str().unwrap(),
            "--out",
            dir.join("o").to_str().unwrap(),
        ],
        &[
            "`params.sped_kmh`",
            "did you mean `speed_kmh`?",
            "accepted: speed_kmh, toe_deg",
        ],
    );
    let study2 = dir.join("typo2.toml");
    std::fs::write(&study2, "name = \"t\"\nsampels = 10\n").unwrap();
    refused(
        &[
            "explore",
            study2.to_str().unwrap(),
            "--out",
            dir.join("o").to_str().unwrap(),
        ],
        &["unknown key `sampels`; did you mean `samples`?"],
    );
    for (line, needle) in [
        (
            "design = \"sobel\"",
            "`design` = \"sobel\" is unknown; did you mean `sobol`?",
        ),
        (
            "[params]\nload_n = { dist = \"unifrom\", min = 1000, max = 2000 }",
            "did you mean `uniform`?",
        ),
        (
            "[params]\nload_n = { dist = \"normal\", mean = 4000, sdev = 800 }",
            "`params.load_n.sdev` is not a key of a normal distribution; did you mean `sd`?",
        ),
    ] {
        std::fs::write(&study2, format!("name = \"t\"\nsamples = 10\n{line}\n")).unwrap();
        refused(
            &[
                "explore",
                study2.to_str().unwrap(),
                "--out",
                dir.join("o").to_str().unwrap(),
            ],
            &[needle],
        );
    }
    refused(
        &["simulate", "--set", "gmod=0.9e6"],
        &["unknown parameter `gmod`; did you mean `g_mod`?"],
    );
    refused(
        &[
            "bifurcation",
            "--param",
            "spede_kmh",
            "--from",
            "50",
            "--to",
            "60",
        ],
        &["did you mean `speed_kmh`?"],
    );
    refused(
        &["analyze", dir.to_str().unwrap(), "--pair", "speed,toe_deg"],
        &["--pair `speed,toe_deg`", "did you mean `speed_kmh`?"],
    );
    let csv = dir.join("points.csv");
    std::fs::write(&csv, "speed_kmh,tow_deg\n100,0.3\n").unwrap();
    refused(
        &[
            "classify",
            csv.to_str().unwrap(),
            "--out",
            dir.join("v.csv").to_str().unwrap(),
        ],
        &["column `tow_deg`", "did you mean `toe_deg`?"],
    );
    // Nothing close: no suggestion, only the accepted names.
    let (_, _, stderr) = polywear(&["simulate", "--set", "wheelbase=2.7"]);
    assert!(!stderr.contains("did you mean"), "{stderr}");
    assert_eq!(
        polywear::params::suggest_name("pressure"),
        Some("pressure_kpa")
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_sweep_says_what_it_held_fixed_and_where_each_wheel_vibrates() {
    let dir = tmp("sweep");
    let prefix = dir.join("toe");
    let (code, stdout, stderr) = polywear(&[
        "bifurcation",
        "--param",
        "toe_deg",
        "--from",
        "0.05",
        "--to",
        "0.8",
        "--steps",
        "40",
        "--speed",
        "120",
        "--set",
        "g_mod=0.9e6",
        "--out",
        prefix.to_str().unwrap(),
        "--format",
        "svg",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let header = stdout.lines().next().unwrap();
    assert!(
        header.ends_with("at speed 120 km/h, load 4000 N, pressure 240 kPa, g_mod 900000 Pa"),
        "{header}"
    );
    // One plain line per wheel and window, with the bounds in degrees.
    let follower: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("follower vibrates for toe-in "))
        .collect();
    assert_eq!(follower.len(), 1, "{stdout}");
    let (a, b) = follower[0]
        .trim_start_matches("follower vibrates for toe-in ")
        .split_once("°–")
        .unwrap();
    let (a, b): (f64, f64) = (a.parse().unwrap(), b.trim_end_matches('°').parse().unwrap());
    assert!(0.05 < a && a < b && b < 0.8, "{a} {b}");
    assert!(
        stdout.contains("\ndriving vibrates for toe-in "),
        "{stdout}"
    );
    // The figure as SVG, its title naming the fixed point and a zero line in the eigenvalue panels.
    let svg = std::fs::read_to_string(prefix.with_extension("svg")).unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..100]);
    assert!(svg.contains("Toe-in sweep at speed 120 km/h, load 4000 N, pressure 240 kPa"));
    assert!(svg.contains("Zoomed on zero: follower vibrates for toe-in "));
    assert!(!prefix.with_extension("png").exists());
    // A sweep without a window says so.
    let (_, stdout, _) = polywear(&[
        "bifurcation",
        "--param",
        "speed_kmh",
        "--from",
        "150",
        "--to",
        "200",
        "--steps",
        "6",
        "--toe",
        "0.5",
        "--out",
        dir.join("fast").to_str().unwrap(),
    ]);
    assert!(
        stdout.contains("follower is stable over the whole sweep (speed 150–200 km/h)"),
        "{stdout}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn risk_maps_speak_plainly_and_can_be_svg() {
    let dir = tmp("maps");
    let study = dir.join("grid.toml");
    std::fs::write(
        &study,
        r#"name = "grid"
seed = 3
samples = 600
chunk_size = 300
[params]
speed_kmh = { dist = "levels", levels = [80, 120, 160] }
toe_deg = { dist = "levels", levels = [0.1, 0.3, 0.5] }
load_n = { dist = "uniform", min = 3000, max = 6000 }
pressure_kpa = { dist = "levels", levels = [200, 280] }
"#,
    )
    .unwrap();
    let run = dir.join("run");
    let r = run.to_str().unwrap();
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        study.to_str().unwrap(),
        "--out",
        r,
    ]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, stderr) = polywear(&["analyze", r, "--format", "svg", "--min-count", "5"]);
    assert_eq!(code, 0, "{stderr}");
    let f = stdout.find("sliding_share rear (follower):").unwrap();
    let d = stdout.find("sliding_share front (driving):").unwrap();
    assert!(f < d, "{stdout}");
    let report = run.join("_report");
    let map = std::fs::read_to_string(report.join("riskmap_speed_kmh_toe_deg_sliding_share.svg"))
        .unwrap();
    for words in [
        "Risk of tread vibration, rear (follower) wheel",
        "Risk of tread vibration, front (driving) wheel",
        "front (driving) minus rear (follower) (blue: front (driving) wheel less exposed)",
        "Speed [km/h]",
        "Toe-in [deg]",
        "Risk of vibration [%]",
        "Difference [percentage points]",
    ] {
        assert!(map.contains(words), "{words}");
    }
    assert!(!map.contains("P(limit cycle)"));
    // A 3 x 3 grid carries its percentages in the cells: nine numbers per wheel.
    let cell_texts = map.matches("text-anchor=\"middle\"").count();
    assert!(cell_texts >= 27, "{cell_texts}");
    let md = std::fs::read_to_string(report.join("report.md")).unwrap();
    assert!(
        md.contains("riskmap_speed_kmh_toe_deg_sliding_share.svg"),
        "{md}"
    );
    assert!(!report
        .join("riskmap_speed_kmh_toe_deg_sliding_share.png")
        .exists());
    // The severity table in engineering units and plain numbers, no exponents: amplitudes of
    // some tens of µm, energies of some µJ.
    let severity: Vec<&str> = md
        .lines()
        .filter(|l| l.starts_with("| sliding_share |") && l.contains(" [µ"))
        .collect();
    assert_eq!(severity.len(), 4, "{md}");
    for l in severity {
        assert!(!l.contains("e1") && !l.contains("e-"), "{l}");
        let mean: f64 = l.split('|').nth(5).unwrap().trim().parse().unwrap();
        assert!((0.1..1e4).contains(&mean), "{l}");
    }
    assert!(md.contains("| Polygon order (wear facets) |"), "{md}");
    let figure = std::fs::read_to_string(report.join("severity_sliding_share.svg")).unwrap();
    for words in [
        "Lateral displacement amplitude [µm]",
        "Vibration energy per cycle [µJ]",
    ] {
        assert!(figure.contains(words), "{words}");
    }
    assert!(!figure.contains("amp_y_m") && !figure.contains("energy_per_cycle_j"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn refusals_name_the_value_its_place_and_what_is_accepted() {
    let dir = tmp("consistent");
    let study = |body: &str| {
        let p = dir.join("s.toml");
        std::fs::write(
            &p,
            format!("name = \"x\"\nsamples = 10\n[params]\n{body}\n"),
        )
        .unwrap();
        p
    };
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    // The first offending level, by its place counted from 0, with its value; not the first
    // level nor the largest.
    let s = study("toe_deg = { dist = \"levels\", levels = [0.2, 0.4, -0.3, 0] }");
    refused(
        &["explore", s.to_str().unwrap(), "--out", o],
        &["`params.toe_deg.levels[2]`: parameter `toe_deg` = -0.3 is outside its accepted range (0, 10] deg"],
    );
    // No float noise: the largest value of a uniform is its max, not 59999.99999999999.
    let s = study("load_n = { dist = \"uniform\", min = 600, max = 60000 }");
    let (_, _, stderr) = polywear(&["explore", s.to_str().unwrap(), "--out", o]);
    assert!(
        stderr.contains("`load_n` = 60000 is outside its accepted range (0, 50000] N"),
        "{stderr}"
    );
    assert!(!stderr.contains("999999"), "{stderr}");
    // `analyze` names the folder it found empty, and says what it accepts.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    refused(
        &["analyze", empty.to_str().unwrap()],
        &[
            &format!("no Parquet files in {}", empty.display()),
            "accepted: an explore output directory",
        ],
    );
    // Every command creates a missing output folder.
    let series = dir.join("a/b/series.csv");
    let (code, _, stderr) = polywear(&["simulate", "--out", series.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(series.is_file());
    let prefix = dir.join("c/d/sweep");
    let (code, _, stderr) = polywear(&[
        "bifurcation",
        "--param",
        "speed_kmh",
        "--from",
        "80",
        "--to",
        "120",
        "--steps",
        "3",
        "--out",
        prefix.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(prefix.with_extension("png").is_file());
    // Refusals end with what is accepted.
    let full = dir.join("full");
    std::fs::create_dir_all(&full).unwrap();
    std::fs::write(full.join("notes.txt"), "x").unwrap();
    refused(
        &["explore", "--out", full.to_str().unwrap()],
        &["holds no polywear run; accepted: an empty or absent directory"],
    );
    refused(
        &["simulate", "--plot", dir.join("p.jpg").to_str().unwrap()],
        &["accepted: .png, .svg"],
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn flag_refusals_end_with_what_is_accepted() {
    refused(
        &["bifurcation", "--param", "speed_kmh", "--from", "80", "--to", "80"],
        &["--from and --to are both 80; accepted: two different values of speed_kmh in its range (0, 400] km/h"],
    );
    refused(
        &["simulate", "--kick", "-1"],
        &["accepted: a positive lateral velocity amplitude in m/s"],
    );
    refused(
        &["analyze", ".", "--pair", "load_n,load_n"],
        &["accepted: two different parameter names"],
    );
    refused(
        &["explore", "--log-every", "0"],
        &["--log-every `0` must be a number of seconds in [0.1, 86400]"],
    );
}

#[test]
fn the_papers_figures_can_be_svg_too() {
    let dir = tmp("reproduce-svg");
    let out = dir.join("paper");
    let (code, _, stderr) = polywear(&[
        "reproduce",
        "--out",
        out.to_str().unwrap(),
        "--steps",
        "21",
        "--paired-samples",
        "20",
        "--format",
        "svg",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    for fig in [
        "fig4_adhesion",
        "bifurcation_speed_kmh_sliding_share",
        "fig18_amplitude_vs_speed",
    ] {
        let svg = std::fs::read_to_string(out.join(format!("{fig}.svg"))).unwrap();
        assert!(svg.starts_with("<svg"), "{fig}");
        assert!(md.contains(&format!("![]({fig}.svg)")), "{fig}");
        assert!(!out.join(format!("{fig}.png")).exists());
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_time_history_as_svg_is_one_polyline_per_curve_not_one_per_segment() {
    let dir = tmp("simulate-svg");
    let svg_path = dir.join("point.svg");
    let (code, _, stderr) = polywear(&["simulate", "--plot", svg_path.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    assert!(svg.starts_with("<svg"));
    // Both wheels' time histories, phase portraits and spectra: a handful of curves, each an
    // unbroken polyline; drawn segment by segment they were tens of thousands of elements.
    let polylines = svg.matches("<polyline").count();
    assert!(
        polylines < 2_000,
        "{polylines} polylines, {} bytes",
        svg.len()
    );
    std::fs::remove_dir_all(&dir).ok();
}
