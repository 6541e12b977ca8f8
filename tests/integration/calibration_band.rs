//! The calibration band (MODEL.md#the-calibration-band): the shipped sets regenerate, each
//! set's rows in the band are the rows of a run made with that set's constants, bad band files
//! are refused before any work, and a study with a scenario reports the band beside the
//! sampling interval of the headline and of the scenario's effect.

use std::collections::HashMap;
use std::path::Path;

use super::common::{fresh_dir, polywear};
use super::parquet_rows::rows;
use parquet::record::Field;
use polywear::params::Params;
use polywear_core::wear::FittedConstants;
use polywear_study::calibration_band::evaluate::{set_column, BandPlan, BAND_FILE, RUN_SET};
use polywear_study::calibration_band::fit::{fit, FitOptions};
use polywear_study::calibration_band::CalibrationBand;
use polywear_study::field_facts::FieldFacts;

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

/// (sample_id, wheel) -> (distance, life, order) of the rows of a run's chunk.
fn answers(file: &Path) -> HashMap<(String, String), (f64, f64, f64)> {
    rows(file)
        .into_iter()
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

/// (sample_id, wheel) -> what the band holds for a run's row: the distance where the polygon
/// is visible before the tire is worn out, +inf where it is not, NaN where unknown, as float32.
fn visible_of_run(file: &Path) -> HashMap<(String, String), f32> {
    rows(file)
        .into_iter()
        .map(|r| {
            let km = match text(&r["wear_outcome"]).as_str() {
                "visible" => float(&r["distance_to_visible_km"]),
                "not_within_life" => f64::INFINITY,
                _ => f64::NAN,
            };
            ((text(&r["sample_id"]), text(&r["wheel"])), km as f32)
        })
        .collect()
}

/// (sample_id, wheel) -> the band's column of set `id`.
fn band_column(file: &Path, id: &str) -> HashMap<(String, String), f32> {
    let column = set_column(id);
    rows(file)
        .into_iter()
        .map(|r| {
            let km = match &r[&column] {
                Field::Float(x) => *x,
                other => panic!("{column} is not a float32: {other:?}"),
            };
            ((text(&r["sample_id"]), text(&r["wheel"])), km)
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

/// The band's column of a set is exactly what a run made with that set's constants
/// (`--params`) answers, and its `run` column the run's own rows: the band drives a set's legs
/// only where its plain answer has a polygon and shares the tread's ageing among the sets of
/// one carcass and belt share, where the run solves its one set afresh; any slip in how φ_s,
/// σ_V, k_d, c or μ_b enter shows.
#[test]
fn the_band_under_each_set_is_the_run_made_with_that_set() {
    let dir = fresh_dir("band-sets");
    let out = dir.join("run");
    explore_quietly(&out, "300", &["--band-samples", "300"]);
    let band_file = out.join(BAND_FILE);
    let chunk = out.join("chunk-0000000.parquet");
    let run_rows = answers(&chunk);
    let run_visible = visible_of_run(&chunk);
    let band_run = band_column(&band_file, RUN_SET);
    assert_eq!(run_visible.len(), 600);
    assert_eq!(band_run.len(), 600);
    let same32 = |a: f32, b: f32| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    for (k, a) in &run_visible {
        assert!(same32(*a, band_run[k]), "{k:?}: {a} vs {}", band_run[k]);
    }
    // Two sets far from each other: the first and the last of the file.
    let band = CalibrationBand::shipped();
    let others: Vec<_> = band.sets.iter().filter(|s| !s.nominal).collect();
    for set in [others[0], others[others.len() - 1]] {
        let params = dir.join(format!("{}.toml", set.id));
        std::fs::write(
            &params,
            format!(
                "[params]\nwear_share_straight = {}\nspeed_spread_kmh = {}\nwear_rate_driven_factor = {}\ncarcass_share = {}\nbelt_mass_share = {}\n",
                set.wear_share_straight,
                set.speed_spread_kmh,
                set.wear_rate_driven_factor,
                set.carcass_share,
                set.belt_mass_share
            ),
        )
        .unwrap();
        let other = dir.join(&set.id);
        explore_quietly(
            &other,
            "300",
            &[
                "--calibration-band",
                "off",
                "--params",
                params.to_str().unwrap(),
            ],
        );
        let own_chunk = other.join("chunk-0000000.parquet");
        let direct = visible_of_run(&own_chunk);
        let banded = band_column(&band_file, &set.id);
        for (k, a) in &direct {
            assert!(
                same32(*a, banded[k]),
                "set {} {k:?}: run {a} vs band {}",
                set.id,
                banded[k]
            );
        }
        // Most wheels have no polygon under any set: the tire's life moves instead, and the
        // order that got deepest with it; so the comparison above compares answers that move.
        let (mut moved, mut orders_moved) = (0, 0);
        for (k, a) in &answers(&own_chunk) {
            moved += usize::from(!same(a.1, run_rows[k].1));
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

/// The shipped sets are what the fit gives: a reduced design (every accepted point of the
/// shipped design table and every 64th of the rest, evaluated again on the same 2,000 samples)
/// reproduces the table's figures and verdicts at those points, the table's accepted points
/// give the shipped file's sets again, and the shipped defaults are the nominal set.
#[test]
fn the_calibrated_sets_regenerate_within_tolerance() {
    use polywear_study::calibration_band::fit::Fit;
    let facts = FieldFacts::shipped();
    let base = Params::default();
    let opts = FitOptions::shipped(&facts);
    let design = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/calibration_design.csv"
    ));
    let table = Fit::from_design(&opts, design).unwrap();
    assert_eq!(table.points.len() as u64, opts.points);
    let again = table
        .band(
            &FittedConstants::of(&base),
            &CalibrationBand::shipped().generated_by,
        )
        .unwrap();
    assert_eq!(again, CalibrationBand::shipped());
    assert!(again.nominal_is(&base), "{:?}", again.nominal());
    let only: Vec<u64> = table
        .points
        .iter()
        .filter(|g| g.accepted || g.index % 64 == 0)
        .map(|g| g.index)
        .collect();
    let reduced = FitOptions {
        only: Some(only.clone()),
        ..opts
    };
    let f = fit(&base, &facts, &reduced, &|_| {}).unwrap();
    assert_eq!(f.points.len(), only.len());
    let close = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a - b).abs() <= 1e-9 * b.abs();
    for g in &f.points {
        let t = table.points.iter().find(|t| t.index == g.index).unwrap();
        assert_eq!(g.accepted, t.accepted, "point {}", g.index);
        assert!(
            close(g.highway_median_km, t.highway_median_km)
                && close(g.fleet_median_km, t.fleet_median_km)
                && close(g.fleet_visible_share, t.fleet_visible_share)
                && close(g.sides_share, t.sides_share),
            "point {}: {g:?} against the table's {t:?}",
            g.index
        );
    }
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
    let good = polywear_study::calibration_band::SHIPPED;
    let first_line = |start: &str| good.lines().find(|l| l.starts_with(start)).unwrap();
    let cases = [
        ("empty.toml", String::new(), "empty file"),
        (
            "damaged.toml",
            good[..good.len() / 3].to_string() + "\n[[set]\n",
            "damaged.toml",
        ),
        (
            "range.toml",
            good.replacen(
                first_line("wear_share_straight = "),
                "wear_share_straight = 1.5",
                1,
            ),
            "`wear_share_straight` = 1.5: accepted (0, 1]",
        ),
        (
            "prior.toml",
            good.replacen(first_line("belt_mass_share = "), "belt_mass_share = 0.9", 1),
            "`belt_mass_share` = 0.9 is outside the file's range [0, 0.7]",
        ),
        (
            "missing.toml",
            good.replacen(&format!("{}\n", first_line("carcass_share = ")), "", 1),
            "missing field `carcass_share`",
        ),
        (
            "twice.toml",
            good.replacen(
                first_line("belt_mass_share = "),
                &format!("{0}\n{0}", first_line("belt_mass_share = ")),
                1,
            ),
            "duplicate key",
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
         \n[params]\n\
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
    let headline = line("rear (follower) within  40,000 km");
    assert!(
        headline.contains('[') && headline.contains("(calibration band "),
        "{headline}"
    );
    let effect = line("less_toe (sliding_share, wear_within_40000_km)");
    assert!(
        effect.contains("95% interval") && effect.contains("calibration band"),
        "{effect}"
    );
    let sets = CalibrationBand::shipped().sets.len();
    assert!(
        stdout.contains(&format!("calibration band: {sets} calibrated sets")),
        "{stdout}"
    );
    // The fitted wear constants do not move vibration: its effects carry no band.
    let vibration = line("less_toe (sliding_share, vibration)");
    assert!(!vibration.contains("calibration band"), "{vibration}");
    let paired = line("paired within  40,000 km");
    assert!(
        paired.contains(&format!("under all {sets} calibrated sets"))
            || paired.contains(&format!("behind under none of the {sets}"))
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
    use polywear_study::calibration_band::evaluate::BAND_DIGEST;
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
/// is the distance of a cycle run with that set's φ_s and k_d (σ_V does not enter a cycle; the
/// carcass and belt shares stay the run's): the profiles' sums read under the set against the
/// cycle run with it.
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
    // A set under which the cycle's polygons become visible, its constants inside the shipped
    // file's prior ranges. The cycle's steps are laid out at the run's carcass and belt shares,
    // which a set's do not replace (MODEL.md#the-calibration-band): the set keeps the run's.
    let defaults = Params::default();
    let (carcass, belt) = (
        defaults.carcass_share.to_string(),
        defaults.belt_mass_share.to_string(),
    );
    let (share, factor) = ("0.5", "2");
    let shipped = polywear_study::calibration_band::SHIPPED;
    let head = shipped.split("[[set]]").next().unwrap();
    let one = dir.join("one.toml");
    std::fs::write(
        &one,
        format!(
            "{head}[[set]]\nid = \"hi\"\nnominal = true\nwear_share_straight = {share}\n\
             speed_spread_kmh = 9.0\nwear_rate_driven_factor = {factor}\n\
             carcass_share = {carcass}\nbelt_mass_share = {belt}\n"
        ),
    )
    .unwrap();
    let banded = dir.join("banded");
    let (code, stdout, err) = polywear(&[
        "cycle",
        cycle,
        "--set",
        "toe_deg=0.45",
        "--calibration-band",
        one.to_str().unwrap(),
        "--out",
        banded.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("over 1 calibrated sets"), "{stdout}");
    let lo = distance(&banded, "distance_to_visible_km_band_low");
    assert_eq!(lo, distance(&banded, "distance_to_visible_km_band_high"));
    let direct = dir.join("direct");
    let mut args = vec!["cycle", cycle, "--set", "toe_deg=0.45"];
    let sets = [
        format!("wear_share_straight={share}"),
        format!("wear_rate_driven_factor={factor}"),
        format!("carcass_share={carcass}"),
        format!("belt_mass_share={belt}"),
    ];
    for s in &sets {
        args.extend(["--set", s]);
    }
    args.extend([
        "--calibration-band",
        "off",
        "--out",
        direct.to_str().unwrap(),
    ]);
    let (code, _, err) = polywear(&args);
    assert_eq!(code, 0, "{err}");
    let d = distance(&direct, "distance_to_visible_km");
    assert_eq!(d.len(), 2);
    assert!(d.iter().any(|a| a.is_finite()), "{d:?}");
    for (a, b) in d.iter().zip(&lo) {
        assert!(
            (a.is_infinite() && a == b) || (a.is_nan() && b.is_nan()) || ((a - b) / a).abs() < 1e-9,
            "{d:?} vs band {lo:?}"
        );
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
    let sets = CalibrationBand::shipped().sets.len();
    assert!(
        stdout.contains(&format!("over {sets} calibrated sets")),
        "{stdout}"
    );
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

/// `WheelGrowth::answers_on` keeps what depends on the tread's ageing and on the speed spread
/// once per group of sets: for the shipped sets each answer is `saturated_answer`'s bit for
/// bit, and that is the estimator's answer at a sample carrying the set's constants, on a
/// vibrating and a stable wheel of both positions; the answers move with the set, so the check
/// can fail.
#[test]
fn grouping_the_sets_changes_no_answer() {
    use polywear::classify::budget::Meter;
    use polywear::classify::ClassifierOptions;
    use polywear::evaluate::{self, PointProblem, WearStage};
    use polywear::model::Variant;
    use polywear_core::wear::{LifeAnswer, WheelGrowth};
    let band = CalibrationBand::shipped();
    let sets: Vec<FittedConstants> = band.sets.iter().map(|s| s.constants()).collect();
    let opts = ClassifierOptions::default();
    let variants = [Variant::SlidingShare];
    let base = Params::default();
    let stage =
        WearStage::for_run(&base, variants[0], Default::default(), &opts).expect("calibrates");
    let mut moved = 0;
    for (toe_deg, speed_kmh) in [(0.6, 120.0), (0.05, 100.0)] {
        let p = Params {
            toe_deg,
            speed_kmh,
            ..base
        };
        let point = evaluate::solve(&PointProblem::new(p, &variants, &opts));
        for w in &point.wheels {
            let g = WheelGrowth::new(&stage.problem(&p, w), &Meter::new(opts.budget)).unwrap();
            let grouped = g.answers_on(&sets);
            let single: Vec<LifeAnswer> = sets.iter().map(|c| g.saturated_answer(c)).collect();
            // Bit for bit, NaN orders included (NaN is not equal to itself): their debug texts.
            assert_eq!(
                format!("{grouped:?}"),
                format!("{single:?}"),
                "toe {toe_deg} {}",
                w.record.wheel
            );
            for (c, a) in sets.iter().zip(&grouped).step_by(5) {
                let q = c.applied_to(&p);
                let e = stage.problem(&q, w).solve(&Meter::new(opts.budget));
                assert_eq!(
                    e.distance_to_visible_km.to_bits(),
                    a.distance_to_visible_km.to_bits(),
                    "toe {toe_deg} {} {c:?}",
                    w.record.wheel
                );
                assert_eq!(
                    e.polygon_order_dominant.to_bits(),
                    a.polygon_order_wear.to_bits()
                );
            }
            let first = grouped[0].tread_life_km;
            moved += grouped
                .iter()
                .filter(|a| a.tread_life_km.to_bits() != first.to_bits())
                .count();
        }
    }
    assert!(
        moved > 20,
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
    let band = CalibrationBand::shipped();
    let others: Vec<&polywear_study::calibration_band::CalibratedSet> =
        band.sets.iter().filter(|s| !s.nominal).collect();
    let (first_set, second_set) = (others[0], others[others.len() - 1]);
    std::fs::write(
        &two,
        format!(
            "{head}[[set]]{}[[set]]{}",
            pick(&first_set.id),
            pick(&second_set.id).replace("nominal = false", "nominal = true")
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
    assert!(
        stdout.contains("rear (follower): calibration band"),
        "{stdout}"
    );
    let band = rows(&banded.join("wear_calibration_band.parquet"));
    assert_eq!(band.len(), 4);
    let mut differ = 0;
    let mut first = None;
    for set in [first_set, second_set] {
        let id = set.id.as_str();
        let (phi, sv, kd, cs, mu) = (
            set.wear_share_straight.to_string(),
            set.speed_spread_kmh.to_string(),
            set.wear_rate_driven_factor.to_string(),
            set.carcass_share.to_string(),
            set.belt_mass_share.to_string(),
        );
        let own = dir.join(id);
        wear(
            &own,
            &[
                "--calibration-band",
                "off",
                "--set",
                &format!("wear_share_straight={phi}"),
                "--speed-spread-kmh",
                &sv,
                "--set",
                &format!("wear_rate_driven_factor={kd}"),
                "--set",
                &format!("carcass_share={cs}"),
                "--set",
                &format!("belt_mass_share={mu}"),
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
        stderr.contains("(speed_spread_kmh = ") && stderr.contains("): the slowest leg drives at"),
        "{stderr}"
    );
    assert!(!slow.exists(), "work was done");
    wear(&banded, &["--calibration-band", "off"]);
    assert!(!banded.join("wear_calibration_band.parquet").exists());
    assert!(!banded.join("wear_calibration_band.csv").exists());
}
