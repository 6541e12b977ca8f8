//! `polywear optimize`: its files (the optimum is the best setting of the surface, with its
//! interval), and every refusal before any work.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::common::{self, polywear};
use crate::parquet_rows::rows;

const STUDY: &str = "studies/toe_and_pressure.toml";

fn tmp(name: &str) -> PathBuf {
    let d = common::fresh_dir(&format!("optimize-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn csv(path: &Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

fn number(f: &parquet::record::Field) -> f64 {
    match f {
        parquet::record::Field::Double(x) => *x,
        parquet::record::Field::Long(x) => *x as f64,
        other => panic!("not a number: {other:?}"),
    }
}

#[test]
fn the_optimum_is_the_surfaces_best_setting_with_its_interval() {
    let dir = tmp("files");
    let out = dir.join("out");
    let (code, stdout, stderr) = polywear(&[
        "optimize",
        STUDY,
        "--vary",
        "toe_deg=0.05..0.40",
        "--vary",
        "pressure_kpa=200..300",
        "--objective",
        "vibration",
        "--wheel",
        "follower",
        "--samples",
        "150",
        "--grid",
        "3",
        "--levels",
        "2",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("optimum: toe_deg = "), "{stdout}");
    assert!(stdout.contains("how flat:"), "{stdout}");
    let optimum = csv(&out.join("optimum.csv"));
    assert_eq!(optimum.len(), 1);
    let o = &optimum[0];
    let mut keys: Vec<&str> = o.keys().map(String::as_str).collect();
    keys.sort();
    assert_eq!(
        keys,
        [
            "objective",
            "objective_high",
            "objective_low",
            "pressure_kpa",
            "toe_deg"
        ]
    );
    let get = |k: &str| o[k].parse::<f64>().unwrap();
    assert!(get("objective_low") <= get("objective") && get("objective") <= get("objective_high"));
    // The optimum is the smallest objective of the surface, and its own paired difference is 0.
    let surface = rows(&out.join("surface.parquet"));
    assert!(surface.len() >= 9, "{}", surface.len());
    let best = surface
        .iter()
        .min_by(|a, b| number(&a["objective"]).total_cmp(&number(&b["objective"])))
        .unwrap();
    assert_eq!(number(&best["objective"]), get("objective"));
    assert_eq!(number(&best["toe_deg"]), get("toe_deg"));
    assert_eq!(number(&best["pressure_kpa"]), get("pressure_kpa"));
    assert_eq!(number(&best["difference_vs_best"]), 0.0);
    assert_eq!(number(&best["within_best_interval"]), 1.0);
    for f in ["surface.png", "report.md", "optimum.parquet"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("What a setting means"), "{report}");
}

#[test]
fn one_parameter_the_edge_is_said_and_a_fixed_parameter_is_set() {
    let dir = tmp("edge");
    let run = |name: &str, study: &str, vary: &str| {
        let out = dir.join(name);
        let (code, stdout, stderr) = polywear(&[
            "optimize",
            study,
            "--vary",
            vary,
            "--objective",
            "vibration",
            "--samples",
            "100",
            "--grid",
            "5",
            "--levels",
            "1",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{stderr}");
        (
            stdout,
            std::fs::read_to_string(out.join("report.md")).unwrap(),
        )
    };
    // Less toe-in vibrates less over this box: the lowest end is the optimum, and it says so.
    let (stdout, report) = run("toe", STUDY, "toe_deg=0.05..0.40");
    assert!(stdout.contains("optimum: toe_deg = 0.05:"), "{stdout}");
    assert!(stdout.contains("lower edge of toe_deg"), "{stdout}");
    assert!(
        report.contains("toe_deg: the centre of its distribution (now 0.25)"),
        "{report}"
    );
    // The study fixes load: a setting is its value.
    let study = dir.join("fixed_load.toml");
    let text = std::fs::read_to_string(STUDY).unwrap().replace(
        "load_n       = { dist = \"truncated_normal\", mean = 4000, sd = 600, min = 2500, max = 6500 }",
        "load_n = 4000",
    );
    std::fs::write(&study, text).unwrap();
    let (_, report) = run("load", study.to_str().unwrap(), "load_n=3000..5000");
    assert!(
        report.contains("load_n: the value every sample takes"),
        "{report}"
    );
}

/// Where the objective takes one value over the whole box (no workshop toe-in of 0.05–0.15°
/// gives a polygon within 40,000 km on these samples), the summary says the box is flat and
/// names no edge to widen, and the band's flat sets are told apart from those whose objective
/// moves; where it moves (up to 0.40°, where the follower's polygons begin), the edge is named.
#[test]
fn a_flat_objective_names_no_edge_and_a_moving_one_names_its_edge() {
    let dir = tmp("level");
    std::fs::create_dir_all(&dir).unwrap();
    let run = |name: &str, toe: &str| {
        let out = dir.join(name);
        let (code, stdout, stderr) = polywear(&[
            "optimize",
            STUDY,
            "--vary",
            toe,
            "--objective",
            "wear",
            "--wheel",
            "follower",
            "--samples",
            "200",
            "--grid",
            "5",
            "--levels",
            "0",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{stderr}");
        stdout
    };
    let stdout = run("moves", "toe_deg=0.05..0.40");
    assert!(
        !stdout.contains("at every setting of the box") && stdout.contains("edge of toe_deg"),
        "{stdout}"
    );
    // Flat under the run's constants; under the band's sets flat or not, depending on the set:
    // the sets where it moves are named apart from those where it is flat.
    let stdout = run("flat", "toe_deg=0.05..0.15");
    assert!(
        stdout.contains("the objective is 0.0% at every setting of the box")
            && !stdout.contains("widen the box")
            && (stdout
                .contains("under every calibrated set the objective is flat over the box too")
                || stdout
                    .contains("under every calibrated set whose objective moves over the box (")),
        "{stdout}"
    );
}

#[test]
fn bad_optimize_input_is_refused_before_any_work() {
    let dir = tmp("refused");
    let wear = polywear_study::optimize::evaluate::wear_available();
    let mut cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        (
            vec!["--vary", "toe_deg=0.40..0.05"],
            vec![
                "--vary `toe_deg=0.40..0.05`",
                "the box is empty",
                "toe_deg=0.05..0.4",
            ],
        ),
        (
            vec!["--vary", "toe=0.05..0.40"],
            vec!["unknown parameter `toe`", "did you mean `toe_deg`"],
        ),
        (
            vec!["--vary", "toe_deg=0.01..0.40"],
            vec![
                "--vary toe_deg=0.01..0.4",
                "(0, 10]",
                "of this run's 100 samples",
                "centre",
            ],
        ),
        (
            vec!["--vary", "c_s=-1..5"],
            vec![
                "--vary c_s=-1..5",
                "outside the accepted range",
                "[0, 1000000]",
            ],
        ),
        (
            vec!["--vary", "toe_deg=0.05..0.4", "--objective", "wer"],
            vec![
                "unknown objective `wer`",
                "did you mean `wear`",
                "weighted sum",
            ],
        ),
        (
            vec![
                "--vary",
                "toe_deg=0.05..0.4",
                "--objective",
                "1e308*wear+1e308*vibration",
            ],
            vec!["--objective", "weights adding up to at most 1e100"],
        ),
        (
            vec!["--vary", "toe_deg=0.05..0.4", "--wheel", "worse"],
            vec!["unknown wheel `worse`", "worst"],
        ),
        (
            vec!["--vary", "toe_deg=0.05..0.4", "--vary", "toe_deg=0.1..0.2"],
            vec!["names toe_deg twice"],
        ),
        (
            vec![
                "--vary",
                "toe_deg=0.05..0.4",
                "--constraint",
                "pressure_kpa>=230",
            ],
            vec!["--constraint `pressure_kpa>=230`", "not varied"],
        ),
        (
            vec![
                "--vary",
                "toe_deg=0.05..0.4",
                "--constraint",
                "vibration<=2",
            ],
            vec!["--constraint `vibration<=2`", "[0, 1]"],
        ),
        (
            vec![
                "--vary",
                "toe_deg=0.05..0.4",
                "--constraint",
                "toe_deg>=0.5",
            ],
            vec!["--constraint `toe_deg>=0.5`", "empty box"],
        ),
        (
            vec!["--vary", "toe_deg=0.05..0.4", "--samples", "0"],
            vec!["--samples `0`"],
        ),
    ];
    if !wear {
        cases.push((
            vec!["--vary", "toe_deg=0.05..0.4"],
            vec![
                "--objective wear",
                "distance_to_visible_km",
                "--objective vibration",
            ],
        ));
    }
    for (k, (flags, words)) in cases.iter().enumerate() {
        let out = dir.join(format!("out{k}"));
        let mut args = vec!["optimize", STUDY];
        if !flags.contains(&"--samples") {
            args.extend(["--samples", "100"]);
        }
        args.extend(flags.iter().copied());
        // Every case but the refusal of wear minimises vibration.
        let wear_case = words.contains(&"distance_to_visible_km");
        if !flags.contains(&"--objective") && !wear_case {
            args.extend(["--objective", "vibration"]);
        }
        args.extend(["--quiet", "--out", out.to_str().unwrap()]);
        let (code, _, stderr) = polywear(&args);
        assert_eq!(code, 2, "{flags:?}: {stderr}");
        for w in words {
            assert!(stderr.contains(w), "{flags:?}: `{w}` not in {stderr}");
        }
        assert!(!out.exists(), "{flags:?}: work started");
    }
}

/// Every setting the search can evaluate goes through the checks of a direct input: a count of
/// wheels takes whole values only (no 3.75 wheels), a box that breaks a cross-parameter rule is
/// refused before any work naming the rule, and a box whose settings move a drawn parameter's
/// samples out of their plausible range is refused with the setting that does.
#[test]
fn optimize_settings_are_checked_like_direct_inputs() {
    let dir = tmp("settings");
    let out = dir.join("wheels");
    let (code, _, stderr) = polywear(&[
        "optimize",
        STUDY,
        "--samples",
        "10",
        "--vary",
        "n_wheels=2..9",
        "--objective",
        "vibration",
        "--grid",
        "3",
        "--levels",
        "1",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let wheels: Vec<f64> = rows(&out.join("surface.parquet"))
        .iter()
        .map(|r| number(&r["n_wheels"]))
        .collect();
    assert!(wheels.len() >= 5, "{wheels:?}");
    assert!(wheels.iter().all(|w| w.fract() == 0.0), "{wheels:?}");
    let mut distinct = wheels.clone();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    assert_eq!(
        distinct.len(),
        wheels.len(),
        "each setting once: {wheels:?}"
    );
    let refused: [(&str, &[&str]); 4] = [
        (
            "mu_s=0.5..0.95",
            &[
                "--vary mu_s=0.5..0.95",
                "mu_m down to 0.76",
                "accepted: mu_s at most mu_m",
            ],
        ),
        (
            "n_driven=1..8",
            &[
                "--vary n_driven=1..8",
                "n_wheels down to 4",
                "accepted: n_driven at most n_wheels",
            ],
        ),
        (
            "n_wheels=2.5..9",
            &["--vary n_wheels=2.5..9", "(whole number)"],
        ),
        (
            "toe_deg=0.3..0.98",
            &[
                "--vary toe_deg=0.3..0.98",
                "the setting toe_deg = ",
                "implausible",
            ],
        ),
    ];
    for (k, (vary, words)) in refused.iter().enumerate() {
        let out = dir.join(format!("out{k}"));
        let (code, _, stderr) = polywear(&[
            "optimize",
            STUDY,
            "--samples",
            "10",
            "--vary",
            vary,
            "--objective",
            "vibration",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{vary}: {stderr}");
        for w in *words {
            assert!(stderr.contains(w), "{vary}: `{w}` not in {stderr}");
        }
        assert!(!out.exists(), "{vary}: work started");
    }
}

/// `optimize --out` is resolved before any work: a path through a file or a link to nothing is
/// refused at once in the words `wear` and `explore` use.
#[test]
fn optimize_checks_its_folder_before_any_work() {
    let dir = tmp("out");
    let file = dir.join("afile");
    std::fs::write(&file, "x").unwrap();
    let through = file.join("sub");
    let mut outs = vec![(through, "is a file")];
    #[cfg(unix)]
    {
        let dangling = dir.join("dangling");
        std::os::unix::fs::symlink(dir.join("nowhere"), &dangling).unwrap();
        outs.push((dangling, "symbolic link to nothing"));
    }
    for (out, said) in outs {
        let (code, _, stderr) = crate::common::polywear_within(
            std::time::Duration::from_secs(20),
            &[
                "optimize",
                STUDY,
                "--samples",
                "2000",
                "--vary",
                "toe_deg=0.05..0.4",
                "--objective",
                "vibration",
                "--quiet",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        assert_eq!(code, 2, "{stderr}");
        assert!(
            stderr.contains("--out") && stderr.contains(said),
            "{stderr}"
        );
    }
}

/// No feasible setting is an answer, not an error: a NaN optimum, the words saying so, and the
/// files written (over one parameter the curve shows every setting), exit 0.
#[test]
fn no_feasible_setting_ends_normally_with_a_nan_optimum() {
    let dir = tmp("infeasible");
    {
        let out = dir.join("out");
        let mut args = vec![
            "optimize",
            STUDY,
            "--samples",
            "30",
            "--vary",
            "toe_deg=0.2..0.4",
        ];
        args.extend([
            "--objective",
            "vibration",
            "--constraint",
            "vibration<=0",
            "--grid",
            "3",
            "--levels",
            "0",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        let (code, stdout, stderr) = polywear(&args);
        assert_eq!(code, 0, "{stderr}");
        assert!(stdout.contains("no setting of the 3"), "{stdout}");
        let optimum = csv(&out.join("optimum.csv"));
        assert!(optimum[0]["objective"] == "NaN", "{optimum:?}");
        assert!(out.join("report.md").is_file() && out.join("surface.png").is_file());
    }
}

/// Ctrl-C during the search ends optimize with 130 and a word on what is (not) saved, where it
/// used to end it in silence.
#[test]
fn ctrl_c_during_the_search_says_what_is_left() {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};
    let dir = tmp("sigint");
    let out = dir.join("out");
    let child = Command::new(env!("CARGO_BIN_EXE_polywear"))
        .args([
            "optimize",
            STUDY,
            "--samples",
            "200000",
            "--vary",
            "toe_deg=0.05..0.4",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The folder is made, and the handler set, before the search starts.
    let t0 = Instant::now();
    while !out.exists() && t0.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(5));
    }
    std::thread::sleep(Duration::from_millis(300));
    // SAFETY: kill(2) on the PID of our own child, which has not been waited for yet.
    unsafe {
        libc::kill(child.id() as i32, libc::SIGINT);
    }
    let done = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert_eq!(done.status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("optimize: stopped by SIGINT (Ctrl-C)")
            && stderr.contains("its files are written only at its end"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The calibration band (MODEL.md#the-calibration-band) in `optimize`: the run's own surface is
/// the one without a band, row for row; under a set, the optimum and the objective at the
/// run's optimum are those of a run made with that set's constants in `--params`; a band where
/// nothing weighs wear, or over a varied constant of the sets, is refused when asked for. Over
/// a box where the sets move the objective (at 0.40° the follower's polygons begin).
#[test]
fn the_optimum_under_each_calibrated_set_is_the_run_made_with_that_set() {
    let dir = tmp("band");
    std::fs::create_dir_all(&dir).unwrap();
    let study = STUDY.to_string();
    let run = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "optimize",
            study.as_str(),
            "--vary",
            "toe_deg=0.05..0.40",
            "--objective",
            "wear",
            "--wheel",
            "follower",
            "--samples",
            "300",
            "--grid",
            "5",
            "--levels",
            "0",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, stdout, stderr) = polywear(&args);
        assert_eq!(code, 0, "{stderr}");
        (out, stdout)
    };
    let (banded, stdout) = run("banded", &[]);
    assert!(stdout.contains("; calibration band "), "{stdout}");
    let sets = rows(&banded.join("calibration_band.parquet"));
    assert!(
        stdout.contains(&format!(
            "under each of the {} calibrated sets (data/calibration_band.toml)",
            sets.len()
        )),
        "{stdout}"
    );
    let (off, stdout_off) = run("off", &["--calibration-band", "off"]);
    assert!(!stdout_off.contains("calibration band"), "{stdout_off}");
    assert!(!off.join("calibration_band.parquet").exists());
    let surface = |d: &Path| -> Vec<(f64, f64)> {
        rows(&d.join("surface.parquet"))
            .iter()
            .map(|r| (number(&r["toe_deg"]), number(&r["objective"])))
            .collect()
    };
    assert_eq!(surface(&banded), surface(&off));
    let run_optimum = number(&rows(&banded.join("optimum.parquet"))[0]["toe_deg"]);
    let text = |f: &parquet::record::Field| match f {
        parquet::record::Field::Str(s) => s.clone(),
        other => other.to_string(),
    };
    let mut moved = 0;
    for set in [&sets[0], &sets[sets.len() - 1]] {
        let params = dir.join(format!("{}.toml", text(&set["set"])));
        std::fs::write(
            &params,
            format!(
                "[params]\nwear_share_straight = {}\nspeed_spread_kmh = {}\nwear_rate_driven_factor = {}\ncarcass_share = {}\nbelt_mass_share = {}\n",
                number(&set["wear_share_straight"]),
                number(&set["speed_spread_kmh"]),
                number(&set["wear_rate_driven_factor"]),
                number(&set["carcass_share"]),
                number(&set["belt_mass_share"])
            ),
        )
        .unwrap();
        let (with, _) = run(
            &text(&set["set"]),
            &[
                "--calibration-band",
                "off",
                "--params",
                params.to_str().unwrap(),
            ],
        );
        let best = &rows(&with.join("optimum.parquet"))[0];
        assert_eq!(number(&best["toe_deg"]), number(&set["toe_deg"]));
        assert_eq!(number(&best["objective"]), number(&set["objective"]));
        let at_run = surface(&with)
            .into_iter()
            .find(|(toe, _)| *toe == run_optimum)
            .unwrap()
            .1;
        assert_eq!(at_run, number(&set["objective_at_run_optimum"]));
        if surface(&with) != surface(&off) {
            moved += 1;
        }
    }
    assert_eq!(moved, 2, "a set's constants moved no objective");
    // Refused when asked for where it cannot apply; the default band is then left out.
    let shipped = "data/calibration_band.toml";
    for (extra, says) in [
        (
            vec!["--objective", "vibration", "--calibration-band", shipped],
            "neither the objective nor a constraint weighs wear",
        ),
        (
            vec![
                "--vary",
                "wear_share_straight=0.1..0.2",
                "--calibration-band",
                shipped,
            ],
            "--vary wear_share_straight varies a constant the calibrated sets fix",
        ),
    ] {
        let out = dir.join("refused");
        let mut args = vec!["optimize", STUDY, "--samples", "20", "--quiet"];
        if extra[0] != "--vary" {
            args.extend(["--vary", "toe_deg=0.05..0.40"]);
        }
        args.extend(extra.iter().copied());
        args.extend(["--out", out.to_str().unwrap()]);
        let (code, _, stderr) = polywear(&args);
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(says), "{stderr}");
        assert!(!out.exists(), "work was done: {}", out.display());
    }
}

/// optimize's band on a subsample (`--band-samples`, a control variate): the run's own surface
/// is the full run's, row for row; the band file records the subsample; under nearly every set
/// the objective at the set's optimum is the full band's within the subsample's interval; and
/// a subsample no smaller than the run is the full band, bit for bit. Over toe-in of 0.40–0.70°,
/// where the sets move the objective.
#[test]
fn the_band_on_a_subsample_is_the_full_band_within_its_interval() {
    let dir = tmp("band-subsample");
    let study = STUDY.to_string();
    let run = |name: &str, band_samples: &str| {
        let out = dir.join(name);
        let (code, _, stderr) = polywear(&[
            "optimize",
            study.as_str(),
            "--vary",
            "toe_deg=0.40..0.70",
            "--objective",
            "wear",
            "--wheel",
            "follower",
            "--samples",
            "400",
            "--grid",
            "5",
            "--levels",
            "0",
            "--band-samples",
            band_samples,
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{stderr}");
        out
    };
    let full = run("full", "400");
    let sub = run("sub", "150");
    let same = run("same", "1000");
    assert_eq!(
        rows(&full.join("surface.parquet")),
        rows(&sub.join("surface.parquet"))
    );
    assert_eq!(
        rows(&full.join("calibration_band.parquet")),
        rows(&same.join("calibration_band.parquet"))
    );
    let footer =
        String::from_utf8_lossy(&std::fs::read(sub.join("calibration_band.parquet")).unwrap())
            .into_owned();
    assert!(
        footer.contains("\"samples\":150"),
        "the subsample is not recorded"
    );
    let (a, b) = (
        rows(&full.join("calibration_band.parquet")),
        rows(&sub.join("calibration_band.parquet")),
    );
    let sets = a.len();
    let mut outside = 0;
    let mut moved = 0;
    for (x, y) in a.iter().zip(&b) {
        let (want, got) = (number(&x["objective"]), number(&y["objective"]));
        let (low, high) = (number(&y["objective_low"]), number(&y["objective_high"]));
        assert!(low <= got && got <= high, "{got} outside [{low}, {high}]");
        if !(low..=high).contains(&want) {
            outside += 1;
        }
        if got != want {
            moved += 1;
        }
    }
    assert!(
        outside * 10 <= sets,
        "{outside} of {sets} sets outside the subsample's interval"
    );
    assert!(moved > 0, "the subsample changed nothing: it was not used");
}
