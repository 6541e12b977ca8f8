//! What polywear says is true and said once (docs/book/src/reference/guarantees.md): a count
//! written as a number is a count, a value that would not be used is refused, a flag that
//! overrides a study's setting says so, a run's own constants are not called fitted, no
//! distance is extrapolated past the tire's life, no advice sends a user round in a circle, and
//! no number runs to hundreds of digits.

use std::path::Path;

use crate::common::{fresh_dir, polywear};

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// `--band-samples 2e4` was refused as "must be a whole number in [100, 1000000]", which it is.
#[test]
fn a_count_written_as_a_number_is_a_count() {
    let dir = fresh_dir("count-2e4");
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        "--samples",
        "3e2",
        "--band-samples",
        "2e2",
        "--seed",
        "1e1",
        "--out",
        &s(&dir),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let (code, _, stderr) = polywear(&["explore", "--band-samples", "2.5e1", "--out", &s(&dir)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("--band-samples `2.5e1` must be a whole number in [100, 1000000]"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A value given where nothing uses it is refused, not silently dropped: `--band-samples` with
/// the band off (explore and optimize), and a setting given to `--set` says what it is.
#[test]
fn a_value_nothing_uses_is_refused_and_a_setting_is_named_as_one() {
    let dir = fresh_dir("unused-values");
    let out = s(&dir.join("run"));
    for args in [
        vec![
            "explore",
            "--calibration-band",
            "off",
            "--band-samples",
            "500",
            "--out",
            &out,
        ],
        vec![
            "explore",
            "--no-wear",
            "--band-samples",
            "500",
            "--out",
            &out,
        ],
    ] {
        let (code, _, stderr) = polywear(&args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(
            stderr.contains("--band-samples 500") && stderr.contains("leave it out"),
            "{stderr}"
        );
    }
    let study = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/toe_and_pressure.toml");
    let (code, _, stderr) = polywear(&[
        "optimize",
        study,
        "--vary",
        "toe_deg=-0.05..0.05",
        "--calibration-band",
        "off",
        "--band-samples",
        "500",
        "--out",
        &out,
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("--band-samples 500"), "{stderr}");
    let (code, _, stderr) = polywear(&["wear", "--set", "wear_zone=trailing"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("`wear_zone` is a setting, not a parameter")
            && stderr.contains("--wear-zone trailing")
            && stderr.contains("whole_patch"),
        "{stderr}"
    );
    assert!(!dir.join("run").exists());
}

/// A flag that replaces a study's work limit says so in one line ("no silent override"); a run's own φ_s (1, from --params) is not called fitted, and the band's
/// replacing it is said.
#[test]
fn an_override_and_a_run_s_own_constants_are_said() {
    let dir = fresh_dir("overrides");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("s.toml");
    std::fs::write(
        &study,
        "name = \"o\"\nsamples = 20\nmax_rhs_evals = 1e7\n[params]\nspeed_kmh = { dist = \"uniform\", min = 80, max = 140 }\n",
    )
    .unwrap();
    let (code, _, stderr) = polywear(&[
        "explore",
        &s(&study),
        "--max-rhs-evals",
        "2e7",
        "--calibration-band",
        "off",
        "--no-report",
        "--out",
        &s(&dir.join("a")),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("--max-rhs-evals 20000000 overrides")
            && stderr.contains("max_rhs_evals = 10000000"),
        "{stderr}"
    );
    let params = dir.join("p.toml");
    std::fs::write(&params, "[params]\nwear_share_straight = 1\n").unwrap();
    let (code, stdout, stderr) = polywear(&[
        "explore",
        &s(&study),
        "--params",
        &s(&params),
        "--band-samples",
        "100",
        "--out",
        &s(&dir.join("b")),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("the run's own wear_share_straight = 1 is not the fitted constants'"),
        "{stderr}"
    );
    let headline = stdout
        .lines()
        .find(|l| l.starts_with("P(visible polygonal wear"))
        .unwrap();
    assert!(
        headline.contains("not the fitted constants") && !headline.contains("fitted to the field"),
        "{headline}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `wear --distance-km 500` extrapolated a growing order to 424,000 km past the tire's
/// 53,333 km: the verdict now says the tire wears out first, in the wheel's own clause.
#[test]
fn no_distance_is_extrapolated_past_the_tire_s_life() {
    let dir = fresh_dir("no-extrapolation");
    let (code, stdout, stderr) = polywear(&[
        "wear",
        "--distance-km",
        "500",
        "--calibration-band",
        "off",
        "--out",
        &s(&dir),
    ]);
    assert_eq!(code, 0, "{stderr}");
    // A wheel whose polygon would come only after the tire is worn out says so in its own
    // clause; no clause gives a distance past the tire's life alone.
    let verdict = stdout.lines().nth(1).unwrap();
    let clauses: Vec<&str> = verdict.split("; ").collect();
    assert!(
        verdict.contains("the tire is worn out at about")
            && clauses
                .iter()
                .filter(|c| c.contains("would be visible only after about"))
                .all(|c| c.contains("the tire is worn out at about")),
        "{verdict}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Resuming a run of another polywear version said "continue it with `--resume --out DIR`
/// alone", which said the same again: it now names the version that can finish it.
#[test]
fn another_version_s_run_is_not_sent_round_in_a_circle() {
    let dir = fresh_dir("other-version");
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        "--calibration-band",
        "off",
        "--samples",
        "20",
        "--out",
        &s(&dir),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let manifest = dir.join("_manifest.json");
    let text = std::fs::read_to_string(&manifest).unwrap();
    let here = format!("\"polywear_version\": \"{}\"", env!("CARGO_PKG_VERSION"));
    assert!(text.contains(&here), "{text}");
    std::fs::write(
        &manifest,
        text.replace(&here, "\"polywear_version\": \"0.0.9\""),
    )
    .unwrap();
    let (code, _, stderr) = polywear(&["explore", "--resume", "--out", &s(&dir)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("written by polywear 0.0.9")
            && stderr.contains("finish it with polywear 0.0.9")
            && !stderr.contains("--resume --out"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A number in a refusal or a data file never runs to hundreds of digits (`1e300` was written
/// out as 301 of them).
#[test]
fn no_number_runs_to_hundreds_of_digits() {
    let dir = fresh_dir("long-numbers");
    std::fs::create_dir_all(&dir).unwrap();
    let band = dir.join("band.toml");
    let shipped = polywear_study::calibration_band::CalibrationBand::shipped().to_toml();
    // The first set's φ_s line, whatever the fit put there.
    let line = shipped
        .lines()
        .find(|l| l.starts_with("wear_share_straight = "))
        .unwrap();
    std::fs::write(
        &band,
        shipped.replacen(line, "wear_share_straight = 1e300", 1),
    )
    .unwrap();
    let (code, _, stderr) = polywear(&[
        "explore",
        "--calibration-band",
        &s(&band),
        "--out",
        &s(&dir.join("run")),
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("`wear_share_straight` = 1e300"), "{stderr}");
    assert!(stderr.len() < 400, "{stderr}");
}
