//! The calibration band (MODEL.md#the-calibration-band): the shipped sets regenerate, each
//! set's rows in the band are the rows of a run made with that set's constants, bad band files
//! are refused before any work, and a study with a scenario reports the band beside the
//! sampling interval of the headline and of the scenario's effect.

use std::collections::HashMap;
use std::path::Path;

use super::common::{fresh_dir, polywear};
use super::parquet_rows::rows;
use parquet::record::Field;
use polywear::calibration_band::evaluate::{BandPlan, BAND_FILE, RUN_SET};
use polywear::calibration_band::fit::{fit, FitOptions};
use polywear::calibration_band::CalibrationBand;
use polywear::field_facts::FieldFacts;
use polywear::params::Params;
use polywear::wear::FittedConstants;

fn text(f: &Field) -> String {
    match f {
        Field::Str(s) => s.clone(),
        other => other.to_string(),
    }
}

fn float(f: &Field) -> f64 {
    match f {
        Field::Double(x) => *x,
        other => panic!("not a double: {other:?}"),
    }
}

/// (sample_id, wheel) -> (distance, life, order) of the rows of `file` that pass `keep`.
fn answers(
    file: &Path,
    keep: &dyn Fn(&HashMap<String, Field>) -> bool,
) -> HashMap<(String, String), (f64, f64, f64)> {
    rows(file)
        .into_iter()
        .filter(|r| keep(r))
        .map(|r| {
            (
                (text(&r["sample_id"]), text(&r["wheel"])),
                (
                    float(&r["distance_to_visible_km"]),
                    float(&r["tread_life_km"]),
                    float(&r["polygon_order_wear"]),
                ),
            )
        })
        .collect()
}

/// Every row of a Parquet file as text, in order.
fn row_text(file: &Path) -> Vec<String> {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    let reader = SerializedFileReader::new(std::fs::File::open(file).unwrap()).unwrap();
    reader
        .get_row_iter(None)
        .unwrap()
        .map(|r| r.unwrap().to_string())
        .collect()
}

/// `polywear explore --quiet --no-report --samples N --out OUT` with `extra` flags on the
/// default study; panics unless it succeeds.
fn explore_quietly(out: &Path, samples: &str, extra: &[&str]) {
    let mut args = vec![
        "explore",
        "--quiet",
        "--no-report",
        "--samples",
        samples,
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, _, err) = polywear(&args);
    assert_eq!(code, 0, "{err}");
}

fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

/// The band's rows under a set are exactly the rows of a run made with that set's constants
/// (`--params`), and its `run` set the run's own rows: the band re-evaluates the closed loop in
/// closed form where the run solves it afresh, so any slip in how φ_s, σ_V or k_d enter shows.
/// On the new tire's level, where most wheels have a distance that the sets move.
#[test]
fn the_band_under_each_set_is_the_run_made_with_that_set() {
    band_sets_are_the_runs_made_with_them("band-sets", &["--wear-estimate", "new_tire"]);
}

/// The same over the tread's life (`--wear-estimate tread_life`): the band walks each wheel's
/// orders under every set from nodes shared per spread, where the run walks them afresh.
#[test]
fn over_the_tread_s_life_the_band_under_each_set_is_the_run_made_with_that_set() {
    band_sets_are_the_runs_made_with_them("band-sets-life", &["--wear-estimate", "tread_life"]);
}

/// The same with each speed's print saturated (`--wear-estimate tread_life_saturated`): the
/// band drives a set's legs only where its plain answer has a polygon, built once per spread,
/// where the run builds them afresh for its one set.
#[test]
fn saturated_the_band_under_each_set_is_the_run_made_with_that_set() {
    band_sets_are_the_runs_made_with_them(
        "band-sets-saturated",
        &["--wear-estimate", "tread_life_saturated"],
    );
}

/// The body of the three tests above, the runs made with the flags `level`.
fn band_sets_are_the_runs_made_with_them(name: &str, level: &[&str]) {
    let dir = fresh_dir(name);
    let out = dir.join("run");
    explore_quietly(&out, "300", &[&["--band-samples", "300"], level].concat());
    let band_file = out.join(BAND_FILE);
    let chunk = out.join("chunk-0000000.parquet");
    let run_rows = answers(&chunk, &|_| true);
    let band_run = answers(&band_file, &|r| text(&r["set"]) == RUN_SET);
    assert_eq!(run_rows.len(), 600);
    assert_eq!(band_run.len(), 600);
    for (k, a) in &run_rows {
        let b = band_run[k];
        assert!(
            same(a.0, b.0) && same(a.1, b.1) && same(a.2, b.2),
            "{k:?}: {a:?} vs {b:?}"
        );
    }
    // Two sets far from the nominal: the ridge's low-spread end and its high-spread end, with
    // the driven axle's rate at either end of its range.
    let band = CalibrationBand::shipped();
    for set in [band.sets.first().unwrap(), band.sets.last().unwrap()] {
        assert!(!set.nominal);
        let params = dir.join(format!("{}.toml", set.id));
        std::fs::write(
            &params,
            format!(
                "[params]\nwear_share_straight = {}\nspeed_spread_kmh = {}\nwear_rate_driven_factor = {}\n",
                set.wear_share_straight, set.speed_spread_kmh, set.wear_rate_driven_factor
            ),
        )
        .unwrap();
        let other = dir.join(&set.id);
        explore_quietly(
            &other,
            "300",
            &[
                &[
                    "--calibration-band",
                    "off",
                    "--params",
                    params.to_str().unwrap(),
                ],
                level,
            ]
            .concat(),
        );
        let direct = answers(&other.join("chunk-0000000.parquet"), &|_| true);
        let banded = answers(&band_file, &|r| text(&r["set"]) == set.id);
        let (mut moved, mut orders_moved) = (0, 0);
        for (k, a) in &direct {
            let b = banded[k];
            assert!(
                same(a.0, b.0) && same(a.1, b.1) && same(a.2, b.2),
                "set {} {k:?}: run {a:?} vs band {b:?}",
                set.id
            );
            // Over the tread's life most wheels have no polygon under any set: the tire's life
            // moves instead, and the order that got deepest with it.
            moved += usize::from(if level.contains(&"new_tire") {
                !same(a.0, run_rows[k].0)
            } else {
                !same(a.1, run_rows[k].1)
            });
            orders_moved += usize::from(!same(a.2, run_rows[k].2));
        }
        assert!(moved > 100, "set {} moved only {moved} answers", set.id);
        assert!(
            orders_moved > 10,
            "set {} moved only {orders_moved} orders",
            set.id
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The shipped sets are what the history matching gives today: the same accepted grid points
/// but for at most two at the edge of a target, every target met by every shipped set, and
/// the shipped defaults among them.
#[test]
fn the_calibrated_sets_regenerate_within_tolerance() {
    let facts = FieldFacts::shipped();
    let base = Params::default();
    let f = fit(&base, &facts, &FitOptions::shipped(2000, &facts)).unwrap();
    let again = f
        .band(&FittedConstants::of(&base), "test")
        .expect("the shipped defaults are accepted");
    let shipped = CalibrationBand::shipped();
    let key = |c: FittedConstants| c.values().map(|x| (x * 1000.0).round() as i64);
    let a: std::collections::BTreeSet<_> = again.sets.iter().map(|s| key(s.constants())).collect();
    let b: std::collections::BTreeSet<_> =
        shipped.sets.iter().map(|s| key(s.constants())).collect();
    let differ = a.symmetric_difference(&b).count();
    assert!(
        differ <= 2,
        "{differ} sets differ: {:?}",
        a.symmetric_difference(&b).collect::<Vec<_>>()
    );
    assert!(shipped.nominal_is(&base));
    for (x, y) in again.ranges().iter().zip(shipped.ranges()) {
        assert!(
            (x.1 - y.1).abs() <= 0.011 && (x.2 - y.2).abs() <= 1.01,
            "{x:?} vs {y:?}"
        );
    }
    // Every accepted point meets the targets as the facts state them; a rejected neighbour
    // exists on each side of the ridge, so the grid is not what bounds the band in φ_s.
    let highway = facts.get("highway_follower_distance").unwrap();
    for g in f.accepted() {
        assert!(highway.holds_for(g.highway_median_km), "{g:?}");
    }
    let shares: Vec<f64> = f
        .accepted()
        .map(|g| g.constants.wear_share_straight)
        .collect();
    let (lo, hi) = (
        shares.iter().copied().fold(f64::INFINITY, f64::min),
        shares.iter().copied().fold(0.0, f64::max),
    );
    let opts = FitOptions::shipped(2000, &facts);
    assert!(
        lo > opts.shares[0] && hi < *opts.shares.last().unwrap(),
        "{lo}..{hi}"
    );
}

/// A band file that is empty, damaged or holds a constant outside its range is refused before
/// any work (exit 2, nothing written), naming the file, the key and the range; `off` gives the
/// nominal answer alone and says so; a band without the wear stage is refused.
#[test]
fn a_bad_band_file_is_refused_before_any_work_and_off_says_so() {
    let dir = fresh_dir("band-bad");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let good = polywear::calibration_band::SHIPPED;
    let cases = [
        ("empty.toml", String::new(), "empty file"),
        (
            "damaged.toml",
            good[..good.len() / 3].to_string() + "\n[[set]\n",
            "damaged.toml",
        ),
        (
            "range.toml",
            good.replacen("wear_share_straight = 0.05", "wear_share_straight = 1.5", 1),
            "`wear_share_straight` = 1.5: accepted (0, 1]",
        ),
    ];
    for (name, body, says) in cases {
        let file = dir.join(name);
        std::fs::write(&file, body).unwrap();
        let (code, _, err) = polywear(&[
            "explore",
            "--samples",
            "50",
            "--out",
            o,
            "--calibration-band",
            file.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(err.contains(name) && err.contains(says), "{name}: {err}");
        assert!(!out.exists(), "{name}: the run started");
    }
    let (code, _, err) = polywear(&[
        "explore",
        "--samples",
        "50",
        "--no-wear",
        "--out",
        o,
        "--calibration-band",
        dir.join("range.toml").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no wear stage"), "{err}");
    let (code, stdout, err) = polywear(&[
        "explore",
        "--samples",
        "50",
        "--out",
        o,
        "--calibration-band",
        "off",
        "--format",
        "svg",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("calibration band: off"), "{err}");
    assert!(
        stdout.contains("no calibration band in this run"),
        "{stdout}"
    );
    assert!(!out.join(BAND_FILE).exists());
    let report = std::fs::read_to_string(out.join("_report/report.md")).unwrap();
    assert!(
        report.contains("No calibration band in this run"),
        "{report}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// In a study with a scenario the printed summary and report.md give the calibration band
/// beside the sampling interval of the headline within 40,000 km and of the scenario's effect,
/// and name a wheel as more exposed only with the sign across the band.
#[test]
fn a_scenario_study_reports_the_band_beside_each_interval() {
    let dir = fresh_dir("band-scenario");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("toe.toml");
    std::fs::write(
        &study,
        "name = \"toe_band\"\nseed = 7\nsamples = 400\ndesign = \"random\"\n\
         wear_estimate = \"new_tire\"\n\n[params]\n\
         speed_kmh = { dist = \"uniform\", min = 90, max = 140 }\n\
         toe_deg = { dist = \"uniform\", min = 0.3, max = 0.6 }\n\n\
         [scenarios.less_toe]\ntoe_deg = { shift = -0.2 }\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (code, stdout, err) = polywear(&[
        "explore",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--band-samples",
        "200",
        "--format",
        "svg",
    ]);
    assert_eq!(code, 0, "{err}");
    let line = |what: &str| {
        stdout
            .lines()
            .find(|l| l.contains(what))
            .unwrap_or_else(|| panic!("no line with {what}: {stdout}"))
            .to_string()
    };
    let headline = line("follower within  40,000 km");
    assert!(
        headline.contains('[') && headline.contains("(calibration band "),
        "{headline}"
    );
    let effect = line("less_toe (sliding_share, wear_within_40000_km)");
    assert!(
        effect.contains("95% interval") && effect.contains("calibration band"),
        "{effect}"
    );
    assert!(
        stdout.contains("calibration band: 96 calibrated sets"),
        "{stdout}"
    );
    // The fitted wear constants do not move vibration: its effects carry no band.
    let vibration = line("less_toe (sliding_share, vibration)");
    assert!(!vibration.contains("calibration band"), "{vibration}");
    let paired = line("paired within  40,000 km");
    assert!(
        paired.contains("under all 96 calibrated sets")
            || paired.contains("behind under none of the 96")
            || paired.contains("no wheel is named"),
        "{paired}"
    );
    let report = std::fs::read_to_string(out.join("_report/report.md")).unwrap();
    assert!(report.contains("### The calibration band"), "{report}");
    assert!(report.contains("; calibration band "), "headline: {report}");
    assert!(report.contains("`less_toe`, follower"), "{report}");
    // analyze reads the same band back from the directory.
    let again_dir = dir.join("again");
    let (code, again, err) = polywear(&[
        "analyze",
        out.to_str().unwrap(),
        "--out",
        again_dir.to_str().unwrap(),
        "--format",
        "svg",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(again.contains(&headline), "{again}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The band's rows do not depend on the thread count.
#[test]
fn the_band_is_the_same_whatever_the_threads() {
    let study =
        polywear::study::Study::parse_with_base(polywear::study::DEFAULT_STUDY, Params::default())
            .unwrap();
    let stage = polywear::evaluate::WearStage::for_run(
        &study.base,
        polywear::model::Variant::SlidingShare,
        Default::default(),
        &Default::default(),
    )
    .unwrap();
    let band = CalibrationBand::shipped();
    let plan = BandPlan {
        study: &study,
        seed: 11,
        samples: 5000,
        band_samples: 40,
        stage: &stage,
        band: &band,
        band_source: "shipped".into(),
    };
    let indices = plan.indices();
    assert_eq!(indices.len(), 40);
    assert!(indices.windows(2).all(|w| w[0] < w[1]) && *indices.last().unwrap() < 5000);
    assert!(
        *indices.last().unwrap() > 2500,
        "the subsample spans the run: {indices:?}"
    );
    let at = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| plan.evaluate(&|_| {}))
    };
    // Compared as printed (Rust prints every float so that it reads back to the same bits),
    // so that a NaN order, a wheel whose every order levels, equals itself.
    assert_eq!(format!("{:?}", at(1)), format!("{:?}", at(2)));
}

/// A band file changed after the run, or left without its digest by a run killed while writing
/// it, is refused by `analyze` with the way back, and `--resume` writes it again.
#[test]
fn a_changed_band_is_refused_and_resume_writes_it_again() {
    use polywear::calibration_band::evaluate::BAND_DIGEST;
    let dir = fresh_dir("band-changed");
    let out = dir.join("run");
    let o = out.to_str().unwrap();
    explore_quietly(&out, "60", &[]);
    let band = out.join(BAND_FILE);
    let good = std::fs::read(&band).unwrap();
    let good_rows = row_text(&band);
    let mut bytes = good.clone();
    let at = bytes.len() / 2;
    bytes[at] ^= 0x10;
    std::fs::write(&band, &bytes).unwrap();
    let report = dir.join("report");
    let analyze = || {
        polywear(&[
            "analyze",
            o,
            "--out",
            report.to_str().unwrap(),
            "--format",
            "svg",
        ])
    };
    let (code, _, err) = analyze();
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("differ from those recorded") && err.contains("explore --resume"),
        "{err}"
    );
    std::fs::write(&band, &good).unwrap();
    std::fs::remove_file(out.join(BAND_DIGEST)).unwrap();
    let (code, _, err) = analyze();
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no _calibration_band.digest.json"), "{err}");
    let (code, _, err) = polywear(&["explore", "--quiet", "--no-report", "--resume", "--out", o]);
    assert_eq!(code, 0, "{err}");
    // The same rows again (the footer records the resuming command).
    assert!(
        row_text(&band) == good_rows,
        "the band's rows changed on resume"
    );
    let (code, stdout, err) = analyze();
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("(calibration band "), "{stdout}");
    // The band's file named as an input is not taken for rows.
    let (code, _, err) = polywear(&["analyze", band.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("not an explore output"), "{err}");
    // A resume asked for no band leaves none behind.
    let (code, _, err) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        "--resume",
        "--out",
        o,
        "--calibration-band",
        "off",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!band.exists() && !out.join(BAND_DIGEST).exists());
    let (code, stdout, err) = analyze();
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("no calibration band in this run"),
        "{stdout}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `cycle` gives its distance to a visible polygon a calibration band, and the band under a set
/// is the distance of a cycle run with that set's φ_s and k_d (σ_V does not enter a cycle):
/// the closed form β_n(φ_s, k_d) = φ_s β_n(1) − (1 − φ_s) λ_other(k_d) against the loop solved
/// at those constants, as the new tire; over the tread's life, the profiles' sums read under the
/// set against the cycle run with it.
#[test]
fn a_cycle_s_distance_carries_its_band_and_each_set_is_the_cycle_run_with_it() {
    let dir = fresh_dir("band-cycle");
    std::fs::create_dir_all(&dir).unwrap();
    let cycle = concat!(env!("CARGO_MANIFEST_DIR"), "/data/cycles/hwfet.csv");
    let distance = |out: &Path, column: &str| -> Vec<f64> {
        let text = std::fs::read_to_string(out.join("cycle_summary.csv")).unwrap();
        let mut lines = text.lines();
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        let k = head.iter().position(|h| *h == column).expect(column);
        lines
            .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
            .collect()
    };
    // On both levels, at a set under which the cycle's polygons become visible on that level.
    let mut direct = dir.join("direct-new_tire");
    for (level, share) in [("new_tire", "0.2"), ("tread_life", "0.5")] {
        let one = dir.join(format!("one-{level}.toml"));
        std::fs::write(
            &one,
            format!(
                "method = \"m\"\ngenerated_by = \"g\"\n\n[[set]]\nid = \"hi\"\nnominal = true\n\
                 wear_share_straight = {share}\nspeed_spread_kmh = 9.0\nwear_rate_driven_factor = 2.0\n"
            ),
        )
        .unwrap();
        let banded = dir.join(format!("banded-{level}"));
        let (code, stdout, err) = polywear(&[
            "cycle",
            cycle,
            "--set",
            "toe_deg=0.45",
            "--wear-estimate",
            level,
            "--calibration-band",
            one.to_str().unwrap(),
            "--out",
            banded.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(stdout.contains("over 1 calibrated sets"), "{stdout}");
        let lo = distance(&banded, "distance_to_visible_km_band_low");
        assert_eq!(lo, distance(&banded, "distance_to_visible_km_band_high"));
        direct = dir.join(format!("direct-{level}"));
        let (code, _, err) = polywear(&[
            "cycle",
            cycle,
            "--set",
            "toe_deg=0.45",
            "--set",
            &format!("wear_share_straight={share}"),
            "--set",
            "wear_rate_driven_factor=2",
            "--wear-estimate",
            level,
            "--calibration-band",
            "off",
            "--out",
            direct.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        let d = distance(&direct, "distance_to_visible_km");
        assert_eq!(d.len(), 2);
        for (a, b) in d.iter().zip(&lo) {
            assert!(
                a.is_finite() && ((a - b) / a).abs() < 1e-9,
                "{level}: {d:?} vs band {lo:?}"
            );
        }
    }
    // The default band, and `off` without its columns; a bad file before any work.
    let (code, stdout, _) = polywear(&[
        "cycle",
        cycle,
        "--set",
        "toe_deg=0.45",
        "--quiet",
        "--out",
        dir.join("default").to_str().unwrap(),
    ]);
    assert_eq!(code, 0);
    assert!(stdout.contains("over 96 calibrated sets"), "{stdout}");
    let off = std::fs::read_to_string(direct.join("cycle_summary.csv")).unwrap();
    assert!(!off.contains("band_low"));
    std::fs::write(dir.join("bad.toml"), "").unwrap();
    let late = dir.join("late");
    let (code, _, err) = polywear(&[
        "cycle",
        cycle,
        "--calibration-band",
        dir.join("bad.toml").to_str().unwrap(),
        "--out",
        late.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("bad.toml: empty file") && !late.exists(),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `WheelGrowth::answers_with` keeps what depends on the speed spread once per spread: for the
/// shipped sets (many sets on few spreads) each answer is `answer_with`'s bit for bit, and that
/// is the estimator's answer at a sample carrying the set's constants, on a vibrating and a
/// stable wheel of both positions; the answers move with the set, so the check can fail.
#[test]
fn grouping_the_sets_by_their_spread_changes_no_answer() {
    use polywear::classify::budget::Meter;
    use polywear::classify::ClassifierOptions;
    use polywear::evaluate::{self, PointProblem, WearStage};
    use polywear::model::Variant;
    use polywear::wear::{WearAnswer, WheelGrowth};
    let band = CalibrationBand::shipped();
    let sets: Vec<FittedConstants> = band.sets.iter().map(|s| s.constants()).collect();
    let opts = ClassifierOptions::default();
    let variants = [Variant::SlidingShare];
    let base = Params::default();
    // `answers_with` is the new tire's level: the estimator is asked on that level.
    let settings = polywear::wear::WearSettings {
        estimate: polywear::wear::EstimateLevel::NewTire,
        ..Default::default()
    };
    let stage = WearStage::for_run(&base, variants[0], settings, &opts).expect("calibrates");
    let mut moved = 0;
    for toe_deg in [0.45, 0.05] {
        let p = Params { toe_deg, ..base };
        let point = evaluate::solve(&PointProblem::new(p, &variants, &opts));
        for w in &point.wheels {
            let g = WheelGrowth::new(&stage.inputs(&p, w), &Meter::new(opts.budget)).unwrap();
            let grouped = g.answers_with(&sets);
            let single: Vec<WearAnswer> = sets.iter().map(|c| g.answer_with(c)).collect();
            assert_eq!(grouped, single, "toe {toe_deg} {}", w.record.wheel);
            for (c, a) in sets.iter().zip(&grouped).step_by(7) {
                let q = c.applied_to(&p);
                let e = polywear::wear::estimate(&stage.inputs(&q, w), &Meter::new(opts.budget));
                assert_eq!(
                    e.distance_to_visible_km.to_bits(),
                    a.distance_to_visible_km.to_bits(),
                    "toe {toe_deg} {} {c:?}",
                    w.record.wheel
                );
                assert_eq!(e.polygon_order_dominant, a.polygon_order_wear);
            }
            let first = grouped[0].distance_to_visible_km;
            moved += grouped
                .iter()
                .filter(|a| a.distance_to_visible_km.to_bits() != first.to_bits())
                .count();
        }
    }
    assert!(
        moved > 100,
        "only {moved} answers differ from the first set's"
    );
}

/// `wear`'s verdict under the calibrated sets: each set's row is the loop run with that set's
/// constants (`--set`, `--speed-spread-kmh`), wheel by wheel; `--band-sets all` runs every set;
/// a bad `--band-sets` is refused before any work; `off` leaves no band of an earlier run.
#[test]
fn wear_s_verdict_under_each_set_is_the_loop_run_with_it() {
    let dir = fresh_dir("band-wear");
    std::fs::create_dir_all(&dir).unwrap();
    let shipped = std::fs::read_to_string("data/calibration_band.toml").unwrap();
    let head = shipped.split("[[set]]").next().unwrap();
    let pick = |id: &str| {
        shipped
            .split("[[set]]")
            .find(|s| s.contains(&format!("id = \"{id}\"")))
            .unwrap()
            .to_string()
    };
    let two = dir.join("two.toml");
    std::fs::write(
        &two,
        format!(
            "{head}[[set]]{}[[set]]{}",
            pick("phi0.230_sv10_kd2"),
            pick("phi0.050_sv2_kd1.5").replace("nominal = false", "nominal = true")
        ),
    )
    .unwrap();
    let wear = |out: &Path, extra: &[&str]| {
        let mut args = vec!["wear", "--quiet", "--distance-km", "20000"];
        args.extend_from_slice(extra);
        args.extend(["--out", out.to_str().unwrap()]);
        let (code, stdout, stderr) = polywear(&args);
        assert_eq!(code, 0, "{stderr}");
        stdout
    };
    let banded = dir.join("banded");
    let stdout = wear(
        &banded,
        &[
            "--calibration-band",
            two.to_str().unwrap(),
            "--band-sets",
            "all",
        ],
    );
    assert!(
        stdout.contains("the loop run again under 2 of the 2 calibrated sets"),
        "{stdout}"
    );
    assert!(stdout.contains("follower: calibration band"), "{stdout}");
    let band = rows(&banded.join("wear_calibration_band.parquet"));
    assert_eq!(band.len(), 4);
    let mut differ = 0;
    let mut first = None;
    for (id, phi, sv, kd) in [
        ("phi0.230_sv10_kd2", "0.23", "10", "2"),
        ("phi0.050_sv2_kd1.5", "0.05", "2", "1.5"),
    ] {
        let own = dir.join(id);
        wear(
            &own,
            &[
                "--calibration-band",
                "off",
                "--set",
                &format!("wear_share_straight={phi}"),
                "--speed-spread-kmh",
                sv,
                "--set",
                &format!("wear_rate_driven_factor={kd}"),
            ],
        );
        assert!(!own.join("wear_calibration_band.parquet").exists());
        for r in rows(&own.join("wear_summary.parquet")) {
            let b = band
                .iter()
                .find(|b| text(&b["set"]) == id && text(&b["wheel"]) == text(&r["wheel"]))
                .unwrap();
            let kind = match text(&r["run_end"]).as_str() {
                "distance" => "none".to_string(),
                other => other.to_string(),
            };
            assert_eq!(text(&b["verdict"]), kind, "{id}");
            let (x, y) = (
                float(&b["distance_to_visible_km"]),
                float(&r["distance_to_visible_km"]),
            );
            assert_eq!(x.to_bits(), y.to_bits(), "{id} {}", text(&r["wheel"]));
            if text(&r["wheel"]) == "follower" {
                differ += usize::from(first.is_some_and(|f: f64| f.to_bits() != y.to_bits()));
                first = Some(y);
            }
        }
    }
    assert_eq!(
        differ, 1,
        "the two sets gave the follower the same distance"
    );
    // A bad choice, or a set whose spread drives a leg the point's own does not, is refused
    // before any work; `off` removes an earlier run's band.
    let (code, _, stderr) = polywear(&["wear", "--band-sets", "some", "--out", "x"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("accepted: ends"), "{stderr}");
    let slow = dir.join("slow");
    let (code, _, stderr) = polywear(&["wear", "--speed", "12", "--out", slow.to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("set `phi0.180_sv10_kd1.5` (speed_spread_kmh = 10): a leg drives at"),
        "{stderr}"
    );
    assert!(!slow.exists(), "work was done");
    wear(&banded, &["--calibration-band", "off"]);
    assert!(!banded.join("wear_calibration_band.parquet").exists());
    assert!(!banded.join("wear_calibration_band.csv").exists());
}
