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
        .filter(|p| {
            p.extension().is_some_and(|e| e == "parquet")
                && !p.file_name().unwrap().to_string_lossy().starts_with('_')
        })
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

/// A fresh folder `name` holding [`STUDY`] as `s.toml`: (folder, study).
fn with_study(name: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = fresh_dir(name);
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("s.toml");
    std::fs::write(&study, STUDY).unwrap();
    (dir, study)
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
                // NaN only where no order rises above its seed (so none is visible).
                let n = float(&ra["polygon_order_dominant"]);
                assert!(
                    (n >= 1.0 && n.fract() == 0.0) || (n.is_nan() && d.is_infinite()),
                    "{n} {d}"
                );
                assert_eq!(
                    float(&ra["wear_calibration_share"]),
                    polywear::params::Params::default().wear_share_straight
                );
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

mod along_a_cycle {
    use crate::common::{fresh_dir, polywear};
    use polywear::classify::ClassifierOptions;
    use polywear::evaluate::{self, PointProblem, WearStage};
    use polywear::model::Variant;
    use polywear::params::Params;
    use polywear_core::wear::estimator::tread_life_km;
    use polywear_core::wear::{FittedConstants, WearSettings};
    use polywear_study::cycle::wear::step_life;
    use polywear_study::cycle::{classify_cycle, ClassifiedCycle, DriveCycle};

    /// `c` classified with the wear stage `stage` on one thread and on two.
    fn on_one_and_two_threads(
        c: &DriveCycle,
        p: &Params,
        opts: &ClassifierOptions,
        stage: &WearStage,
    ) -> (ClassifiedCycle, ClassifiedCycle) {
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| classify_cycle(c, p, Variant::SlidingShare, opts, Some(stage)))
        };
        (on(1), on(2))
    }

    fn cycle(name: &str, text: &str) -> DriveCycle {
        let dir = fresh_dir(name);
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("c.csv");
        std::fs::write(&path, text).unwrap();
        DriveCycle::read(&path).unwrap()
    }

    /// A cycle held at one speed is explore's answer at that point without a speed spread: the
    /// same order, the
    /// distance within 1% (the cycle's profile is read on a grid of the worn depth, the
    /// sample's on nodes of x), the same tread life; at points where a polygon becomes visible
    /// and where none does. Its sums do not depend on the number of threads.
    #[test]
    fn a_cycle_held_at_one_speed_over_the_tread_s_life_is_the_sample_s_answer() {
        let opts = ClassifierOptions::default();
        let (mut visible, mut none) = (0, 0);
        for (speed_kmh, toe_deg) in [(120.0, 0.45), (110.0, 0.6)] {
            let p = Params {
                speed_kmh,
                toe_deg,
                wear_share_straight: 0.28,
                speed_spread_kmh: 0.0,
                ..Params::default()
            };
            let stage =
                WearStage::for_run(&p, Variant::SlidingShare, WearSettings::default(), &opts)
                    .unwrap();
            let c = cycle(
                &format!("wear-cycle-life-{speed_kmh}"),
                &format!("time_s,speed_kmh\n0,{speed_kmh}\n600,{speed_kmh}\n1200,{speed_kmh}\n"),
            );
            let classified = classify_cycle(&c, &p, Variant::SlidingShare, &opts, Some(&stage));
            let point = evaluate::solve(
                &PointProblem::new(p, &[Variant::SlidingShare], &opts).with_wear(Some(&stage)),
            );
            for w in 0..2 {
                let here = format!("{speed_kmh} km/h {toe_deg} deg wheel {w}");
                let life = classified.life[w].as_ref().expect("the life level");
                let got = life.wear(&p, &FittedConstants::of(&p));
                let e = point.wheels[w].wear.as_ref().unwrap();
                assert_eq!(got.dominant_order, e.polygon_order_dominant, "{here}");
                let (a, b) = (got.distance_to_visible_km, e.distance_to_visible_km);
                assert!(a == b || (a - b).abs() <= 0.01 * b, "{here}: {a} vs {b} km");
                let tread_life = tread_life_km(&p, e.tread_wear_mm_per_1000km);
                assert!(
                    (got.tread_life_km - tread_life).abs() <= 1e-9 * tread_life,
                    "{here}: {} vs {tread_life} km",
                    got.tread_life_km
                );
                let (x, y) = (got.peak_share_of_visible, e.peak_share_of_visible);
                assert!((x - y).abs() <= 0.02 * y, "{here}: peak {x} vs {y}");
                if b.is_finite() {
                    visible += 1;
                } else {
                    none += 1;
                }
            }
        }
        assert!(visible >= 1 && none >= 1, "{visible} visible, {none} none");
        // The same sums on one thread and on two (blocks summed in their order).
        let p = Params {
            wear_share_straight: 0.28,
            ..Params::default()
        };
        let stage =
            WearStage::for_run(&p, Variant::SlidingShare, WearSettings::default(), &opts).unwrap();
        let c = DriveCycle::read(std::path::Path::new("data/cycles/hwfet.csv")).unwrap();
        let (one, two) = on_one_and_two_threads(&c, &p, &opts, &stage);
        assert!(one.life[0].as_ref().unwrap().known_km > 16.0);
        // Bit for bit (the records' NaNs are not equal to themselves): their debug texts.
        assert!(
            format!("{:?}", one.life) == format!("{:?}", two.life),
            "the profiles' sums differ with the thread count"
        );
        assert!(format!("{:?}", one.steps) == format!("{:?}", two.steps));
    }

    /// With each speed's print saturated (`tread_life_saturated`), a cycle's steps saturate on
    /// their own: its answer is `answer_saturated_per_step` over every moving step's own profile
    /// (its speed bins of 0.1 km/h hold one speed each here, and a repeated step the same
    /// profile twice), at least 10% later than the summed profile's where the print saturates
    /// (φ_s = 1, 0.45°: the follower 51% later, the driving wheel 5%); and its sums do not
    /// depend on the number of threads.
    #[test]
    fn a_saturated_cycle_is_its_steps_each_saturated_on_its_own() {
        use polywear_core::wear::estimator::{answer_saturated_per_step, SLIDING_MODULATION_MAX};
        use polywear_core::wear::LifeProfile;
        let opts = ClassifierOptions::default();
        let p = Params {
            toe_deg: 0.45,
            wear_share_straight: 1.0,
            ..Params::default()
        };
        let stage =
            WearStage::for_run(&p, Variant::SlidingShare, WearSettings::default(), &opts).unwrap();
        let speeds = [
            88.0, 90.5, 93.0, 93.0, 95.5, 98.0, 101.0, 104.0, 104.0, 108.0,
        ];
        let mut text = String::from("time_s,speed_kmh\n");
        for (i, v) in speeds.iter().enumerate() {
            text.push_str(&format!("{},{v}\n", 60 * i));
        }
        text.push_str(&format!("{},0\n", 60 * speeds.len()));
        let c = cycle("wear-cycle-saturated", &text);
        let (one, two) = on_one_and_two_threads(&c, &p, &opts, &stage);
        assert!(format!("{:?}", one.life) == format!("{:?}", two.life));
        let km = c.step_km();
        let mut slowed = 0;
        for w in 0..2 {
            let life = one.life[w].as_ref().expect("the life level");
            let got = life.wear(&p, &FittedConstants::of(&p));
            // Every moving step on its own, its profile from a point solved at its speed.
            let profiles: Vec<(f64, LifeProfile)> = (0..c.len())
                .filter(|&i| !c.standstill(i) && km[i] > 0.0)
                .map(|i| {
                    let q = c.step_params(&p, i);
                    let s = evaluate::solve(&PointProblem::new(q, &[Variant::SlidingShare], &opts));
                    let life = step_life(&q, &s.wheels[w], &stage, &opts).unwrap();
                    (km[i], life)
                })
                .collect();
            let steps: Vec<(f64, &LifeProfile)> = profiles.iter().map(|(a, pr)| (*a, pr)).collect();
            let c0 = FittedConstants::of(&p);
            let want = answer_saturated_per_step(&steps, &c0, &p, SLIDING_MODULATION_MAX);
            let summed = answer_saturated_per_step(&steps, &c0, &p, f64::INFINITY);
            let here = format!("wheel {w}: {got:?} against {want:?}");
            assert_eq!(got.dominant_order, want.polygon_order_wear, "{here}");
            let (a, b) = (got.distance_to_visible_km, want.distance_to_visible_km);
            assert!(a.is_finite() && (a - b).abs() <= 1e-9 * b, "{here}");
            if a > 1.1 * summed.distance_to_visible_km {
                slowed += 1;
            }
        }
        assert!(slowed >= 1, "the print saturates on no wheel");
    }

    /// `cycle` gives each wheel's distance over the tread's life in words and in its summary,
    /// with the tire's life and how near the deepest order came; `--no-wear` leaves them out.
    #[test]
    fn cycle_says_the_lifetime_distance_and_no_wear_leaves_it_out() {
        let dir = fresh_dir("wear-cycle-cli");
        let out = dir.join("with");
        let (code, stdout, stderr) = polywear(&[
            "cycle",
            "data/cycles/hwfet.csv",
            "--set",
            "wear_share_straight=1",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{stderr}");
        // Both wheels' lines give the one answer over the tread's life, with the tire's life.
        assert_eq!(
            stdout
                .matches("driving this cycle all its life, its tread wearing: a ")
                .count(),
            2,
            "{stdout}"
        );
        assert!(
            stdout.contains("-sided polygon becomes visible after")
                && stdout.contains("(the tire is worn out at "),
            "{stdout}"
        );
        let summary = std::fs::read_to_string(out.join("cycle_summary.csv")).unwrap();
        let lines: Vec<Vec<&str>> = summary.lines().map(|l| l.split(',').collect()).collect();
        let at = |name: &str| {
            lines[0]
                .iter()
                .position(|h| *h == name)
                .unwrap_or_else(|| panic!("no {name} in {summary}"))
        };
        for row in &lines[1..] {
            // The wear's order under explore's name, and under its old one for one version.
            assert_eq!(
                row[at("polygon_order_wear")],
                row[at("wear_dominant_order")]
            );
            // The distance, the tread's life and how near the deepest order came.
            for name in [
                "distance_to_visible_km",
                "tread_life_km",
                "wear_peak_share_of_visible",
            ] {
                let x: f64 = row[at(name)].parse().unwrap_or(f64::NAN);
                assert!(x.is_finite(), "{name} in {summary}");
            }
        }
        let out = dir.join("without");
        let (code, stdout, _) = polywear(&[
            "cycle",
            "data/cycles/hwfet.csv",
            "--no-wear",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0);
        assert!(!stdout.contains("all its life"), "{stdout}");
        let summary = std::fs::read_to_string(out.join("cycle_summary.csv")).unwrap();
        assert!(!summary.contains("distance_to_visible_km"), "{summary}");
    }
}

/// Every row of every chunk file of `dir`.
fn all_rows(dir: &std::path::Path) -> Vec<std::collections::HashMap<String, Field>> {
    crate::parquet_rows::chunk_rows(dir)
}

/// Samples where only the follower, and only the driving wheel, has a visible polygon within
/// `km`, before its tire is worn out (each sample's two rows are written together, follower
/// first).
fn discordant(rows: &[std::collections::HashMap<String, Field>], km: f64) -> (u64, u64) {
    let (mut f, mut d) = (0, 0);
    for pair in rows.chunks(2) {
        assert_eq!(text(&pair[0]["wheel"]), "follower");
        let within = |r: &std::collections::HashMap<String, Field>| {
            let d = float(&r["distance_to_visible_km"]);
            d <= km && d <= float(&r["tread_life_km"])
        };
        match (within(&pair[0]), within(&pair[1])) {
            (true, false) => f += 1,
            (false, true) => d += 1,
            _ => {}
        }
    }
    (f, d)
}

/// The built-in study's one wear answer (MODEL.md#the-driving-wheels-slip-power): with the
/// driving wheel's slip power and its position's faster even wear, the follower gets a visible
/// polygon more often than the driving wheel at 25,000, 40,000 and 60,000 km, by a clear
/// majority of the discordant samples (on 4,000 samples: 163, 249 and 250 only-follower
/// samples against none); on the lateral-only reading the driving wheel leads at 60,000 km (22
/// against 7), as it did before the slip power was counted. The follower's rows are the same
/// under both.
#[test]
fn the_follower_wears_polygonal_more_often_than_the_driving_wheel() {
    let dir = fresh_dir("wear-explore-field");
    let study = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/default.toml");
    let (with, without) = (dir.join("with"), dir.join("without"));
    let n = ["--samples", "4000", "--calibration-band", "off"];
    assert_eq!(explore(&study, &with, &n).0, 0);
    let lateral = [n[0], n[1], n[2], n[3], "--wear-power", "lateral_only"];
    assert_eq!(explore(&study, &without, &lateral).0, 0);
    let (a, b) = (all_rows(&with), all_rows(&without));
    for km in [25_000.0, 40_000.0, 60_000.0] {
        let (f, d) = discordant(&a, km);
        assert!(f > 4 * d, "{km} km: only follower {f}, only driving {d}");
    }
    let (f, d) = discordant(&b, 60_000.0);
    assert!(
        d > f,
        "lateral only, 60,000 km: only follower {f}, only driving {d}"
    );
    for (x, y) in a
        .iter()
        .zip(&b)
        .filter(|(x, _)| text(&x["wheel"]) == "follower")
    {
        let (dx, dy) = (
            float(&x["distance_to_visible_km"]),
            float(&y["distance_to_visible_km"]),
        );
        assert!(dx == dy || (dx.is_nan() && dy.is_nan()), "{dx} vs {dy}");
    }
}

/// One wear answer per sample (MODEL.md#one-wear-answer): the run records it, its peaks say
/// how near the others came, and the retired levels are refused before any work, as a flag, a
/// study key or a resume's flag, naming what replaced them; a run written on a retired level
/// (tests/data/retired_level_run, 4 samples written by polywear 0.5.0 at 40a1633 with
/// `--wear-estimate new_tire`) is refused by `analyze` and `--resume`.
#[test]
fn one_wear_answer_is_recorded_and_the_retired_levels_are_refused() {
    let dir = fresh_dir("wear-explore-level");
    std::fs::create_dir_all(&dir).unwrap();
    // Highway points with much toe-in, where the follower gets polygons.
    let study = dir.join("s.toml");
    std::fs::write(
        &study,
        "name = \"w\"\nsamples = 24\nchunk_size = 12\n[params]\nspeed_kmh = { dist = \"uniform\", min = 100, max = 130 }\ntoe_deg = { dist = \"uniform\", min = 0.4, max = 0.6 }\n",
    )
    .unwrap();
    let life = dir.join("life");
    let (code, stderr) = explore(&study, &life, &[]);
    assert_eq!(code, 0, "{stderr}");
    let manifest = std::fs::read_to_string(life.join("_manifest.json")).unwrap();
    assert!(
        manifest.contains("\"wear_estimate\": \"tread_life_saturated\""),
        "{manifest}"
    );
    // How near the deepest order came: in (0, 1], 1 exactly where a polygon is visible before
    // the tire is worn out.
    let peaks: Vec<(f64, String)> = rows(&first_chunk(&life))
        .iter()
        .map(|r| {
            (
                float(&r["wear_peak_share_of_visible"]),
                text(&r["wear_outcome"]),
            )
        })
        .collect();
    assert!(
        peaks
            .iter()
            .filter(|(_, o)| o != "unknown")
            .all(|(p, o)| *p > 0.0 && *p <= 1.0 && (*p == 1.0) == (o == "visible")),
        "{peaks:?}"
    );
    let retired = |stderr: &str, level: &str| {
        assert!(
            stderr.contains(&format!("the wear answer `{level}` was retired"))
                && stderr.contains("tread_life_saturated"),
            "{stderr}"
        );
    };
    for level in ["new_tire", "tread_life"] {
        let out = dir.join(level);
        let (code, stderr) = explore(&study, &out, &["--wear-estimate", level]);
        assert_eq!(code, 2, "{stderr}");
        retired(&stderr, level);
        assert!(!out.exists(), "nothing written before the refusal");
        let keyed = dir.join(format!("{level}.toml"));
        std::fs::write(&keyed, format!("wear_estimate = \"{level}\"\n{STUDY}")).unwrap();
        let (code, stderr) = explore(&keyed, &out, &[]);
        assert_eq!(code, 2, "{stderr}");
        retired(&stderr, level);
        assert!(stderr.contains("wear_estimate"), "{stderr}");
        assert!(!out.exists(), "nothing written before the refusal");
    }
    let o = life.to_str().unwrap();
    let (code, _, stderr) = polywear(&[
        "explore",
        "--resume",
        "--out",
        o,
        "--quiet",
        "--wear-estimate",
        "new_tire",
    ]);
    assert_eq!(code, 2, "{stderr}");
    retired(&stderr, "new_tire");
    let (code, _, stderr) =
        polywear(&["explore", "--resume", "--out", o, "--quiet", "--no-report"]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stderr) = explore(&study, &dir.join("typo"), &["--wear-estimate", "tread"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("tread_life_saturated"), "{stderr}");
    assert!(!dir.join("typo").exists());
    let off = dir.join("off.toml");
    std::fs::write(
        &off,
        format!("wear = false\nwear_estimate = \"tread_life_saturated\"\n{STUDY}"),
    )
    .unwrap();
    let (code, stderr) = explore(&off, &dir.join("off"), &[]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("`wear_estimate` is set but `wear = false`"),
        "{stderr}"
    );
    // A run written on a retired level: refused by analyze and by resume, nothing written.
    let old = dir.join("old");
    std::fs::create_dir_all(&old).unwrap();
    let fixture =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/retired_level_run");
    for f in std::fs::read_dir(&fixture).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(&f, old.join(f.file_name().unwrap())).unwrap();
    }
    let report = dir.join("old-report");
    let (code, _, stderr) = polywear(&[
        "analyze",
        old.to_str().unwrap(),
        "--out",
        report.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("`wear.wear_estimate` = \"new_tire\"") && stderr.contains("was retired"),
        "{stderr}"
    );
    assert!(!report.exists());
    let (code, _, stderr) = polywear(&[
        "explore",
        "--resume",
        "--out",
        old.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("`wear.wear_estimate` = \"new_tire\"") && stderr.contains("was retired"),
        "{stderr}"
    );
    // The summary and the report give the one answer, over the tread's life.
    let reported = dir.join("reported");
    let (code, stdout, stderr) = polywear(&[
        "explore",
        study.to_str().unwrap(),
        "--quiet",
        "--out",
        reported.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("over the tread's life at each sample's operating point")
            && !stdout.contains("new tire"),
        "{stdout}"
    );
    let report = std::fs::read_to_string(reported.join("_report/report.md")).unwrap();
    assert!(
        report.contains("These distances are over the tread's life"),
        "{report}"
    );
    // How near the others came: the wheels whose peak reached the visible depth are those
    // visible in the rows, per wheel.
    assert!(report.contains("### How near the others came"), "{report}");
    let table = std::fs::read_to_string(reported.join("_report/wear_near_misses.csv")).unwrap();
    let mut lines = table.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let all = all_rows(&reported);
    let mut seen = 0;
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let wheel = cells[at("wheel")];
        let visible = all
            .iter()
            .filter(|r| text(&r["wheel"]) == wheel && text(&r["wear_outcome"]) == "visible")
            .count();
        let known = all
            .iter()
            .filter(|r| {
                text(&r["wheel"]) == wheel && float(&r["wear_peak_share_of_visible"]).is_finite()
            })
            .count();
        assert_eq!(cells[at("reached_visible")], visible.to_string(), "{table}");
        assert_eq!(cells[at("wheels_with_peak")], known.to_string(), "{table}");
        let half: u64 = cells[at("reached_50pct")].parse().unwrap();
        assert!(half >= visible as u64, "{table}");
        seen += 1;
    }
    assert_eq!(seen, 2, "{table}");
}

/// The slip power's inputs are refused before any work, naming the key and its range.
#[test]
fn bad_driven_factors_and_wear_powers_are_refused() {
    let (code, _, stderr) = polywear(&["simulate", "--set", "wear_rate_driven_factor=0"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("`wear_rate_driven_factor` = 0 is outside its accepted range (0, 10]"),
        "{stderr}"
    );
    let (code, _, stderr) = polywear(&["simulate", "--set", "wear_rate_driven_factor=-1.5"]);
    assert_eq!(code, 2, "{stderr}");
    let dir = fresh_dir("wear-explore-power");
    let (code, _, stderr) = polywear(&[
        "wear",
        "--wear-power",
        "lateral",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("did you mean `lateral_only`?"), "{stderr}");
    assert!(!dir.exists(), "nothing written before the refusal");
    std::fs::create_dir_all(&dir).unwrap();
    let off = dir.join("off.toml");
    std::fs::write(
        &off,
        format!("wear = false\nwear_power = \"lateral_only\"\n{STUDY}"),
    )
    .unwrap();
    let (code, stderr) = explore(&off, &dir.join("out"), &[]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("`wear_power` is set but `wear = false`"),
        "{stderr}"
    );
}

/// `--quiet` silences the progress and the chatter, not the answer, and a finished run leaves
/// no `_lock` behind (a killed one leaves it, and the next run takes it over).
#[test]
fn quiet_still_prints_the_answer_and_a_finished_run_leaves_no_lock() {
    let (dir, study) = with_study("wear-explore-quiet");
    let out = dir.join("out");
    let (code, stdout, stderr) = polywear(&[
        "explore",
        study.to_str().unwrap(),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("P(vibration) over classified rows"),
        "{stdout}"
    );
    assert!(
        stdout.contains("P(visible polygonal wear within X km, before the tire is worn out)"),
        "{stdout}"
    );
    assert!(!stdout.contains("samples evaluated in"), "{stdout}");
    assert!(!stderr.contains("progress"), "{stderr}");
    assert!(!out.join("_lock").exists());
    assert!(out.join("_manifest.chunks.jsonl").exists());
    // A killed run's lock file (the kernel dropped its lock) is taken over by the next run.
    std::fs::write(out.join("_lock"), "99999\n").unwrap();
    let (code, _, stderr) = polywear(&[
        "explore",
        "--resume",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(!out.join("_lock").exists());
}

/// Over the tread's life a wheel whose every order levels from its seed has no wear order: its
/// order and growth are NaN and its distance +inf. The report counts it as never growing, not
/// as unknown: `wear_severity.csv`'s growth rows hold those wheels at `pos_inf`, and as unknown
/// only the rows without a figure.
#[test]
fn a_wheel_whose_every_order_levels_has_no_order_and_never_grows() {
    let (dir, study) = with_study("wear-explore-levels");
    let out = dir.join("run");
    let (code, stderr) = explore(&study, &out, &["--calibration-band", "off"]);
    assert_eq!(code, 0, "{stderr}");
    let mut chunks: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_str()
                .unwrap()
                .starts_with("chunk-")
        })
        .collect();
    chunks.sort();
    let (mut levelling, mut unknown) = (0, 0);
    for r in chunks.iter().flat_map(|c| rows(c)) {
        let (order, growth) = (
            float(&r["polygon_order_wear"]),
            float(&r["growth_rate_per_1000km"]),
        );
        let distance = float(&r["distance_to_visible_km"]);
        if order.is_nan() && distance.is_infinite() {
            assert!(growth.is_nan() && text(&r["wear_reason"]).is_empty());
            levelling += 1;
        } else if growth.is_nan() {
            unknown += 1;
        }
    }
    assert!(
        levelling >= 5,
        "{levelling} wheels whose every order levels"
    );
    let report = dir.join("report");
    let (code, _, stderr) = polywear(&[
        "analyze",
        out.to_str().unwrap(),
        "--out",
        report.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let table = std::fs::read_to_string(report.join("wear_severity.csv")).unwrap();
    let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (mut never, mut unknown_rows) = (0, 0);
    for line in table.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f[at("quantity")] == "growth_rate_per_1000km" {
            never += f[at("pos_inf")].parse::<usize>().unwrap();
            unknown_rows += f[at("unknown")].parse::<usize>().unwrap();
        }
    }
    assert_eq!((never, unknown_rows), (levelling, unknown), "{table}");
}
