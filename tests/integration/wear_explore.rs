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

mod along_a_cycle {
    use crate::common::{fresh_dir, polywear};
    use polywear::classify::ClassifierOptions;
    use polywear::cycle::wear::{cycle_wear, step_growth};
    use polywear::cycle::{classify_cycle, ClassifiedCycle, DriveCycle};
    use polywear::evaluate::{self, PointProblem, WearStage};
    use polywear::model::Variant;
    use polywear::params::Params;
    use polywear::wear::estimator::tread_life_km;
    use polywear::wear::{EstimateLevel, FittedConstants, WearSettings};

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

    /// The worst case (φ_s = 1, no spread) at the paper's constants, where the follower grows.
    fn worst() -> Params {
        Params {
            wear_share_straight: 1.0,
            speed_spread_kmh: 0.0,
            ..Params::r0()
        }
    }

    #[test]
    fn a_cycle_held_at_one_speed_is_the_per_sample_estimate_without_spread() {
        let opts = ClassifierOptions::default();
        let p = worst();
        // A cycle answers as the new tire does (MODEL.md#along-a-drive-cycle): compared on
        // that level.
        let settings = WearSettings {
            estimate: polywear::wear::EstimateLevel::NewTire,
            ..WearSettings::default()
        };
        let stage = WearStage::for_run(&p, Variant::SlidingShare, settings, &opts).unwrap();
        let c = cycle(
            "wear-cycle-held",
            "time_s,speed_kmh\n0,100\n600,100\n1200,100\n",
        );
        let steps = classify_cycle(&c, &p, Variant::SlidingShare, &opts, Some(&stage)).steps;
        let point = evaluate::solve(
            &PointProblem::new(p, &[Variant::SlidingShare], &opts).with_wear(Some(&stage)),
        );
        for w in 0..2 {
            let lifetime = cycle_wear(&c, &steps, w, &p);
            let e = point.wheels[w].wear.as_ref().unwrap();
            assert_eq!(
                lifetime.dominant_order, e.polygon_order_dominant,
                "wheel {w}"
            );
            let (a, b) = (lifetime.growth_rate_per_1000km, e.growth_rate_per_1000km);
            assert!(
                (a - b).abs() <= 1e-9 * b.abs().max(1.0),
                "wheel {w}: {a} vs {b}"
            );
            // The cycle's mean of three equal steps may round differently: the same tolerance.
            let (a, b) = (lifetime.distance_to_visible_km, e.distance_to_visible_km);
            assert!((a - b).abs() <= 1e-9 * b.abs(), "wheel {w}: {a} vs {b} km");
            assert!(
                lifetime.distance_to_visible_km.is_finite(),
                "the worst case grows"
            );
            assert_eq!(lifetime.unknown_distance_share, 0.0);
        }
    }

    #[test]
    fn a_lifetime_weighs_each_speed_by_the_distance_driven_at_it() {
        let opts = ClassifierOptions::default();
        let p = worst();
        let stage =
            WearStage::for_run(&p, Variant::SlidingShare, WearSettings::default(), &opts).unwrap();
        // 2 s at 50 km/h and 1 s at 100 km/h cover the same distance; the standstill covers none.
        let c = cycle(
            "wear-cycle-two",
            "time_s,speed_kmh\n0,50\n2,100\n3,0\n4,0\n",
        );
        let steps = classify_cycle(&c, &p, Variant::SlidingShare, &opts, Some(&stage)).steps;
        let at = |v: f64| {
            let q = Params { speed_kmh: v, ..p };
            let s = evaluate::solve(&PointProblem::new(q, &[Variant::SlidingShare], &opts));
            [0, 1].map(|w| step_growth(&q, &s.wheels[w], &stage, &opts).orders_per_1000km)
        };
        let (slow, fast) = (at(50.0), at(100.0));
        for w in 0..2 {
            let mean: Vec<f64> = slow[w]
                .iter()
                .zip(&fast[w])
                .map(|(a, b)| 0.5 * (a + b))
                .collect();
            let (k, best) = mean
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .unwrap();
            let lifetime = cycle_wear(&c, &steps, w, &p);
            assert_eq!(lifetime.dominant_order, k as f64 + 1.0, "wheel {w}");
            assert!(
                (lifetime.growth_rate_per_1000km - best).abs() < 1e-12,
                "wheel {w}"
            );
        }
    }

    /// Over the tread's life (`tread_life`) a cycle held at one speed is explore's answer
    /// over the tread's life at that point without a speed spread: the same order, the
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
            let settings = WearSettings {
                estimate: EstimateLevel::TreadLife,
                ..WearSettings::default()
            };
            let stage = WearStage::for_run(&p, Variant::SlidingShare, settings, &opts).unwrap();
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
    /// (φ_s = 1, 0.45°: 22% and 16%); and its sums do not depend on the number of threads.
    #[test]
    fn a_saturated_cycle_is_its_steps_each_saturated_on_its_own() {
        use polywear::wear::estimator::{answer_saturated_per_step, SLIDING_MODULATION_MAX};
        use polywear::wear::LifeProfile;
        let opts = ClassifierOptions::default();
        let p = Params {
            toe_deg: 0.45,
            wear_share_straight: 1.0,
            ..Params::default()
        };
        let settings = WearSettings {
            estimate: EstimateLevel::TreadLifeSaturated,
            ..WearSettings::default()
        };
        let stage = WearStage::for_run(&p, Variant::SlidingShare, settings, &opts).unwrap();
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
                    let life = step_growth(&q, &s.wheels[w], &stage, &opts).life.unwrap();
                    (km[i], life)
                })
                .collect();
            let steps: Vec<(f64, &LifeProfile)> = profiles.iter().map(|(a, pr)| (*a, pr)).collect();
            let c0 = FittedConstants::of(&p);
            let want = answer_saturated_per_step(&steps, &c0, &p, SLIDING_MODULATION_MAX).answer;
            let summed = answer_saturated_per_step(&steps, &c0, &p, f64::INFINITY).answer;
            let here = format!("wheel {w}: {got:?} against {want:?}");
            assert_eq!(got.dominant_order, want.polygon_order_wear, "{here}");
            let (a, b) = (got.distance_to_visible_km, want.distance_to_visible_km);
            assert!(a.is_finite() && (a - b).abs() <= 1e-9 * b, "{here}");
            if a > 1.1 * summed.distance_to_visible_km {
                slowed += 1;
            }
        }
        assert_eq!(slowed, 2, "the print saturates on both wheels");
    }

    #[test]
    fn cycle_says_the_lifetime_distance_and_no_wear_leaves_it_out() {
        let dir = fresh_dir("wear-cycle-cli");
        let out = dir.join("with");
        let (code, stdout, stderr) = polywear(&[
            "cycle",
            "data/cycles/hwfet.csv",
            "--set",
            "wear_share_straight=1",
            "--wear-estimate",
            "new_tire",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{stderr}");
        assert_eq!(
            stdout
                .matches("driving this cycle all its life, as the new tire: a ")
                .count(),
            2,
            "{stdout}"
        );
        assert!(
            stdout.contains("-sided polygon becomes visible after"),
            "{stdout}"
        );
        let summary = std::fs::read_to_string(out.join("cycle_summary.csv")).unwrap();
        assert!(
            summary
                .lines()
                .next()
                .unwrap()
                .contains("distance_to_visible_km"),
            "{summary}"
        );
        // The wear's order under explore's name, and under its old one for one version.
        let lines: Vec<Vec<&str>> = summary.lines().map(|l| l.split(',').collect()).collect();
        let at = |name: &str| lines[0].iter().position(|h| *h == name).unwrap();
        for row in &lines[1..] {
            assert_eq!(
                row[at("polygon_order_wear")],
                row[at("wear_dominant_order")]
            );
        }
        // The default level, over the tread's life: both wheels' lines say it, and the
        // summary has the tread's life and how near the deepest order came; on the new tire's
        // level those are NaN.
        let life = dir.join("life");
        let (code, stdout, stderr) = polywear(&[
            "cycle",
            "data/cycles/hwfet.csv",
            "--set",
            "wear_share_straight=0.28",
            "--out",
            life.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{stderr}");
        assert_eq!(
            stdout
                .matches("driving this cycle all its life, its tread wearing: ")
                .count(),
            2,
            "{stdout}"
        );
        assert!(stdout.contains("worn out at"), "{stdout}");
        for (dir, finite) in [(&life, true), (&out, false)] {
            let summary = std::fs::read_to_string(dir.join("cycle_summary.csv")).unwrap();
            let lines: Vec<Vec<&str>> = summary.lines().map(|l| l.split(',').collect()).collect();
            let at = |name: &str| lines[0].iter().position(|h| *h == name).unwrap();
            for row in &lines[1..] {
                for name in ["tread_life_km", "wear_peak_share_of_visible"] {
                    let x: f64 = row[at(name)].parse().unwrap_or(f64::NAN);
                    assert_eq!(x.is_finite(), finite, "{name} in {summary}");
                }
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
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension().is_some_and(|e| e == "parquet")
                && !p.file_name().unwrap().to_string_lossy().starts_with('_')
        })
        .collect();
    files.sort();
    files.iter().flat_map(|f| rows(f)).collect()
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

/// The built-in study's answer on the new tire's level (MODEL.md#the-driving-wheels-slip-power):
/// with the driving wheel's slip power and its position's faster even wear, the follower gets a
/// visible polygon more often than the driving wheel at 25,000, 40,000 and 60,000 km, by a clear
/// majority of the discordant samples; on the lateral-only reading the driving wheel leads at
/// 60,000 km, as it did before the slip power was counted. The follower's rows are the same
/// under both. (Over the tread's life, the shipped level, too few wheels of 6,000 samples have
/// a polygon to show the lateral-only reversal; its sign is held by
/// `wear_loop::over_the_tread_s_life_the_follower_is_more_exposed`.)
#[test]
fn the_follower_wears_polygonal_more_often_than_the_driving_wheel() {
    let dir = fresh_dir("wear-explore-field");
    let study = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/default.toml");
    let (with, without) = (dir.join("with"), dir.join("without"));
    let n = ["--samples", "6000", "--wear-estimate", "new_tire"];
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

/// The saturated level (`--wear-estimate tread_life_saturated`,
/// MODEL.md#the-forced-response-saturates) is recorded, keeps every row of the answer over the
/// tread's life that has no polygon (the saturated one is never earlier, so the plain answer
/// screens), and moves the polygons later or out: at φ_s = 0.28 on highway points, some by a
/// tenth or more, none earlier by more than the legs' quadrature of the spread (5%).
#[test]
fn the_saturated_level_keeps_the_rows_without_a_polygon_and_delays_the_rest() {
    let dir = fresh_dir("wear-explore-saturated");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("s.toml");
    std::fs::write(
        &study,
        "name = \"w\"\nsamples = 48\nchunk_size = 48\n[params]\nwear_share_straight = 0.28\nspeed_spread_kmh = 5\nspeed_kmh = { dist = \"uniform\", min = 100, max = 130 }\ntoe_deg = { dist = \"uniform\", min = 0.4, max = 0.6 }\n",
    )
    .unwrap();
    let (life, saturated) = (dir.join("life"), dir.join("saturated"));
    let (code, stderr) = explore(&study, &life, &["--wear-estimate", "tread_life"]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stderr) = explore(
        &study,
        &saturated,
        &["--wear-estimate", "tread_life_saturated"],
    );
    assert_eq!(code, 0, "{stderr}");
    let manifest = std::fs::read_to_string(saturated.join("_manifest.json")).unwrap();
    assert!(
        manifest.contains("\"wear_estimate\": \"tread_life_saturated\""),
        "{manifest}"
    );
    let answers = |out: &std::path::Path| -> Vec<(f64, f64, f64)> {
        rows(&first_chunk(out))
            .iter()
            .map(|r| {
                (
                    float(&r["distance_to_visible_km"]),
                    float(&r["polygon_order_wear"]),
                    float(&r["wear_peak_share_of_visible"]),
                )
            })
            .collect()
    };
    let (plain, bounded) = (answers(&life), answers(&saturated));
    assert_eq!(plain.len(), bounded.len());
    let (mut with_polygon, mut later) = (0, 0);
    for (i, (a, b)) in plain.iter().zip(&bounded).enumerate() {
        if a.0.is_finite() {
            with_polygon += 1;
            assert!(
                b.0.is_infinite() || b.0 >= 0.95 * a.0,
                "row {i}: {b:?} against {a:?}"
            );
            if b.0 > 1.1 * a.0 {
                later += 1;
            }
        } else {
            assert!(
                (a.0 == b.0 || (a.0.is_nan() && b.0.is_nan()))
                    && (a.1 == b.1 || (a.1.is_nan() && b.1.is_nan())),
                "row {i}: {b:?} against {a:?}"
            );
        }
    }
    assert!(
        with_polygon >= 5 && later >= 2,
        "{with_polygon} polygons, {later} later"
    );
}

/// The answer's level is a setting (`--wear-estimate`, the study's `wear_estimate`; over the
/// tread's life by default): the run records it, its rows differ from the new tire's, a resume
/// keeps it and refuses the other, and a misspelt or contradicted one is refused before any
/// work.
#[test]
fn the_estimate_level_is_recorded_kept_on_resume_and_refused_when_wrong() {
    let dir = fresh_dir("wear-explore-level");
    std::fs::create_dir_all(&dir).unwrap();
    // Highway points at a share and spread where the follower gets polygons on both levels.
    let study = dir.join("s.toml");
    std::fs::write(
        &study,
        "name = \"w\"\nsamples = 24\nchunk_size = 12\n[params]\nwear_share_straight = 0.28\nspeed_spread_kmh = 10\nspeed_kmh = { dist = \"uniform\", min = 100, max = 130 }\ntoe_deg = { dist = \"uniform\", min = 0.4, max = 0.6 }\n",
    )
    .unwrap();
    let (new_tire, life) = (dir.join("new"), dir.join("life"));
    assert_eq!(
        explore(&study, &new_tire, &["--wear-estimate", "new_tire"]).0,
        0
    );
    let (code, stderr) = explore(&study, &life, &[]);
    assert_eq!(code, 0, "{stderr}");
    let manifest = std::fs::read_to_string(life.join("_manifest.json")).unwrap();
    assert!(
        manifest.contains("\"wear_estimate\": \"tread_life_saturated\""),
        "{manifest}"
    );
    let manifest = std::fs::read_to_string(new_tire.join("_manifest.json")).unwrap();
    assert!(
        manifest.contains("\"wear_estimate\": \"new_tire\""),
        "{manifest}"
    );
    let distances = |out: &std::path::Path| -> Vec<f64> {
        rows(&first_chunk(out))
            .iter()
            .map(|r| float(&r["distance_to_visible_km"]))
            .collect()
    };
    let (a, b) = (distances(&new_tire), distances(&life));
    assert_eq!(a.len(), b.len());
    // How near the deepest order came, over the tread's life only: in (0, 1], 1 exactly where
    // a polygon is visible before the tire is worn out; NaN on the new tire's level.
    let peaks = |out: &std::path::Path| -> Vec<(f64, String)> {
        rows(&first_chunk(out))
            .iter()
            .map(|r| {
                (
                    float(&r["wear_peak_share_of_visible"]),
                    text(&r["wear_outcome"]),
                )
            })
            .collect()
    };
    assert!(peaks(&new_tire).iter().all(|(p, _)| p.is_nan()));
    let life_peaks = peaks(&life);
    assert!(
        life_peaks
            .iter()
            .filter(|(_, o)| o != "unknown")
            .all(|(p, o)| *p > 0.0 && *p <= 1.0 && (*p == 1.0) == (o == "visible")),
        "{life_peaks:?}"
    );
    assert!(
        a.iter().zip(&b).any(|(x, y)| x != y),
        "the same distances on both levels"
    );
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
    assert_eq!(code, 2);
    assert!(
        stderr.contains("--wear-estimate new_tire contradicts the run")
            && stderr.contains("--wear-estimate tread_life_saturated"),
        "{stderr}"
    );
    let (code, _, stderr) =
        polywear(&["explore", "--resume", "--out", o, "--quiet", "--no-report"]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stderr) = explore(&study, &dir.join("typo"), &["--wear-estimate", "tread"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("did you mean `tread_life`"), "{stderr}");
    assert!(
        !dir.join("typo").exists(),
        "nothing written before the refusal"
    );
    let off = dir.join("off.toml");
    std::fs::write(
        &off,
        format!("wear = false\nwear_estimate = \"tread_life\"\n{STUDY}"),
    )
    .unwrap();
    let (code, stderr) = explore(&off, &dir.join("off"), &[]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("`wear_estimate` is set but `wear = false`"),
        "{stderr}"
    );
    // The summary and the report say which level they show.
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
            && stdout.contains("km/h, as the run gives them, not the fitted constants: wear_share_straight = 0.28 where the fit has 0.12")
            && stdout.contains("fitted on the new tire's answers, not on this run's"),
        "{stdout}"
    );
    let report = std::fs::read_to_string(reported.join("_report/report.md")).unwrap();
    assert!(
        report.contains("These distances are over the tread's life"),
        "{report}"
    );
    // How near the others came: the wheels whose peak reached the visible depth are those
    // visible in the rows, per wheel; the new tire's level has no such section.
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
    let analysed = dir.join("new_analysed");
    let (code, _, stderr) = polywear(&[
        "analyze",
        new_tire.to_str().unwrap(),
        "--out",
        analysed.to_str().unwrap(),
        "--format",
        "svg",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let report = std::fs::read_to_string(analysed.join("report.md")).unwrap();
    assert!(!report.contains("How near the others came"), "{report}");
    assert!(!analysed.join("wear_near_misses.csv").exists());
    // The study's key reaches the manifest as the flag does.
    let keyed = dir.join("keyed.toml");
    std::fs::write(&keyed, format!("wear_estimate = \"new_tire\"\n{STUDY}")).unwrap();
    let out = dir.join("keyed");
    assert_eq!(explore(&keyed, &out, &[]).0, 0);
    let manifest = std::fs::read_to_string(out.join("_manifest.json")).unwrap();
    assert!(
        manifest.contains("\"wear_estimate\": \"new_tire\""),
        "{manifest}"
    );
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
