//! What a tire engineer meets on a first try: toe-in in the units of an alignment sheet (mm at
//! the rim, total toe) converted and recorded beside the angle, a per-wheel angle typed as one
//! of those refused with the reading named, outcomes in words, names that say their unit and
//! which order they are, and optimize's words.

use std::path::PathBuf;

use crate::common::{fresh_dir, polywear};

fn tmp(name: &str) -> PathBuf {
    let d = fresh_dir(&format!("engineer-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The first JSON row of `simulate --json` with `args`.
fn first_row(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["simulate", "--wheel", "follower", "--json"];
    all.extend_from_slice(args);
    let (code, out, err) = polywear(&all);
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_str(out.lines().next().unwrap()).unwrap()
}

#[test]
fn a_toe_typed_as_mm_or_total_toe_is_refused_as_a_per_wheel_angle_and_converted_when_said_so() {
    // `--toe 2` is neither a service nor a misaligned wheel's angle: refused, naming both
    // likely readings and the inputs that take them, before any work (exit 2).
    let d = tmp("toe");
    let out = d.join("wear_out");
    let (code, stdout, err) = polywear(&["wear", "--toe", "2", "--out", out.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(stdout.is_empty() && !out.exists(), "{stdout}");
    for words in [
        "`toe_deg` = 2 deg is implausible for a road tire (plausible (0, 1] deg)",
        "2 mm at a 15-inch (381 mm) rim = 0.3008 deg (toe_mm, --toe-mm)?",
        "2 deg total toe (both wheels) = 1 deg (toe_total_deg, --toe-total)?",
        "--accept-implausible",
    ] {
        assert!(err.contains(words), "{words}: {err}");
    }
    for cmd in ["simulate", "wear"] {
        let (code, _, err) = polywear(&[cmd, "--toe", "2"]);
        assert_eq!(code, 2, "{cmd}: {err}");
    }
    // Said to be meant, it runs.
    let row = first_row(&["--toe", "2", "--accept-implausible"]);
    assert_eq!(row["toe_deg"], 2.0);
    // The default study's upper toe bound, and the paper's sweep end, stay plausible.
    assert_eq!(first_row(&["--toe", "0.8"])["toe_deg"], 0.8);
    assert_eq!(first_row(&["--toe", "1"])["toe_deg"], 1.0);

    // In mm at the rim: toe_deg = atan(mm / D_rim), D_rim = rim_diameter_mm (381 mm default).
    let row = first_row(&["--toe-mm", "2"]);
    let deg = |mm: f64, rim: f64| (mm / rim).atan().to_degrees();
    assert!(
        (row["toe_deg"].as_f64().unwrap() - deg(2.0, 381.0)).abs() < 1e-13,
        "{row}"
    );
    assert!(
        (row["toe_mm"].as_f64().unwrap() - 2.0).abs() < 1e-12,
        "{row}"
    );
    let total = row["toe_total_deg"].as_f64().unwrap();
    assert!((total - 2.0 * deg(2.0, 381.0)).abs() < 1e-13, "{row}");
    let row = first_row(&["--toe-mm", "2", "--set", "rim_diameter_mm=406.4"]);
    assert!(
        (row["toe_deg"].as_f64().unwrap() - deg(2.0, 406.4)).abs() < 1e-13,
        "{row}"
    );
    let row = first_row(&["--set", "toe_mm=1.5"]);
    assert!(
        (row["toe_deg"].as_f64().unwrap() - deg(1.5, 381.0)).abs() < 1e-13,
        "{row}"
    );
    // As total toe: half per wheel; every row carries the three forms.
    let row = first_row(&["--toe-total", "0.5"]);
    assert_eq!(row["toe_deg"], 0.25);
    assert_eq!(row["toe_total_deg"], 0.5);
    let row = first_row(&[]);
    assert!((row["toe_mm"].as_f64().unwrap() - 381.0 * 0.3f64.to_radians().tan()).abs() < 1e-12);

    // A converted toe outside the plausible angle is refused in the words typed.
    let (code, _, err) = polywear(&["simulate", "--toe-mm", "30"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--toe-mm 30 (30 mm at the 381 mm rim (rim_diameter_mm) = 4.502 deg per wheel): implausible"),
        "{err}"
    );
    // Two ways of one toe are refused as given twice, or by clap as conflicting (exit 2).
    for args in [
        &["simulate", "--toe", "0.2", "--toe-mm", "1"][..],
        &["simulate", "--toe-total", "0.4", "--set", "toe_mm=1"][..],
    ] {
        let (code, _, err) = polywear(args);
        assert_eq!(code, 2, "{args:?}: {err}");
    }
    // The cycle's --set takes the same names.
    let cycle = d.join("cycle.csv");
    std::fs::write(&cycle, "time_s,speed_kmh\n0,100\n1,100\n").unwrap();
    let (code, _, err) = polywear(&[
        "cycle",
        cycle.to_str().unwrap(),
        "--set",
        "toe_mm=30",
        "--out",
        d.join("c").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--set toe_mm=30 (30 mm at the 381 mm rim"),
        "{err}"
    );
    assert!(!d.join("c").exists());
    // A parameter file takes them too, at its own rim, and refuses in the words written.
    let params = d.join("p.toml");
    std::fs::write(&params, "[params]\ntoe_mm = 2\nrim_diameter_mm = 406.4\n").unwrap();
    let row = first_row(&["--params", params.to_str().unwrap()]);
    assert!(
        (row["toe_deg"].as_f64().unwrap() - deg(2.0, 406.4)).abs() < 1e-13,
        "{row}"
    );
    std::fs::write(&params, "[params]\ntoe_total_deg = 0.5\n").unwrap();
    assert_eq!(
        first_row(&["--params", params.to_str().unwrap()])["toe_deg"],
        0.25
    );
    for (text, words) in [
        (
            "[params]\ntoe_mm = 30\n",
            "`params.toe_mm = 30 mm at the 381 mm rim (rim_diameter_mm) = 4.502 deg per wheel`: implausible",
        ),
        (
            "[params]\ntoe_deg = 0.2\ntoe_mm = 1\n",
            "`params.toe_mm` and `params.toe_deg` both give the toe-in",
        ),
    ] {
        std::fs::write(&params, text).unwrap();
        let (code, _, err) = polywear(&["simulate", "--params", params.to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(words), "{words}: {err}");
    }
}

#[test]
fn a_study_takes_the_toe_as_total_toe_or_in_mm_at_its_rim() {
    let study = |params: &str| {
        polywear::study::Study::parse(&format!(
            "name = \"t\"\nsamples = 4\n[params]\nspeed_kmh = {{ dist = \"uniform\", min = 80, max = 120 }}\n{params}\n"
        ))
    };
    use polywear::params::ParamId;
    use polywear_core::sampling::distribution::Distribution;
    let s = study("toe_total_deg = { dist = \"uniform\", min = 0.2, max = 0.6 }").unwrap();
    let toe = s.drawn.iter().find(|d| d.param == ParamId::ToeDeg).unwrap();
    assert_eq!(
        toe.dist,
        Distribution::Uniform {
            min: 0.1,
            max: 0.3,
            count: None
        }
    );
    let s =
        study("rim_diameter_mm = 406.4\ntoe_mm = { dist = \"levels\", levels = [1, 2] }").unwrap();
    let toe = s.drawn.iter().find(|d| d.param == ParamId::ToeDeg).unwrap();
    let Distribution::Levels(l) = &toe.dist else {
        panic!("{:?}", toe.dist)
    };
    assert!((l[1] - (2.0f64 / 406.4).atan().to_degrees()).abs() < 1e-15);
    let s = study("toe_mm = 1.5").unwrap();
    assert!((s.base.toe_deg - (1.5f64 / 381.0).atan().to_degrees()).abs() < 1e-15);
    assert!(s.fixed.contains(&ParamId::ToeDeg));
    for (params, words) in [
        (
            "toe_mm = { dist = \"uniform\", min = 0.5, max = 2 }",
            "only a number or `levels` convert",
        ),
        (
            "toe_mm = 1\ntoe_deg = 0.2",
            "both give the toe-in; give one",
        ),
        (
            "toe_total_deg = { dist = \"uniform\", min = 0, max = 0.6 }",
            "params.toe_deg",
        ),
    ] {
        let e = study(params).unwrap_err().to_string();
        assert!(e.contains(words), "{params}: {e}");
    }
}

/// A small wear study drawing the tread height, run into `dir`.
fn wear_run(dir: &std::path::Path) -> PathBuf {
    let study = dir.join("t3.toml");
    std::fs::write(
        &study,
        // Highway points with much toe-in: the outcome test needs both words.
        "name = \"t3\"\nseed = 3\nsamples = 24\nwear = true\n[params]\n\
         speed_kmh = { dist = \"uniform\", min = 80, max = 160 }\n\
         toe_deg = { dist = \"uniform\", min = 0.1, max = 0.6 }\n\
         tread_height = { dist = \"uniform\", min = 0.012, max = 0.016 }\n",
    )
    .unwrap();
    let out = dir.join("run");
    let (code, _, err) = polywear(&[
        "explore",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    out
}

fn chunk_files(dir: &std::path::Path) -> Vec<PathBuf> {
    crate::parquet_rows::chunk_files(&[dir])
}

#[test]
fn the_rows_say_the_wear_outcome_in_words_and_renamed_columns_keep_their_old_names_a_version() {
    use parquet::record::Field;
    let d = tmp("outcome");
    let run = wear_run(&d);
    let f64_of = |f: &Field| match f {
        Field::Double(x) => *x,
        other => panic!("{other:?}"),
    };
    let str_of = |f: &Field| match f {
        Field::Str(s) => s.clone(),
        other => panic!("{other:?}"),
    };
    let defaults = polywear::params::Params::default();
    let mut seen = std::collections::BTreeSet::new();
    for file in chunk_files(&run) {
        for r in crate::parquet_rows::rows(&file) {
            let distance = f64_of(&r["distance_to_visible_km"]);
            let even = f64_of(&r["wear_even_mm_per_1000km"]);
            let life = f64_of(&r["tread_life_km"]);
            // The shipped usable tread (8 mm new, worn out at 1.6 mm) over the position's whole
            // even wear: w' and the rest of the position's wear, (1 - phi_s) w'_pos, with
            // w'_pos = 0.12 mm/1000 km, times k_d on the driving wheel.
            let share = f64_of(&r["wear_share_straight"]);
            let position = match str_of(&r["wheel"]).as_str() {
                "driving" => defaults.wear_rate_driven_factor * 0.12,
                _ => 0.12,
            };
            let whole = even + (1.0 - share) * position;
            if !distance.is_nan() {
                assert!(
                    (life - (8.0 - 1.6) / whole * 1000.0).abs() <= 1e-9 * life,
                    "{life} against {}",
                    (8.0 - 1.6) / whole * 1000.0
                );
            }
            let outcome = str_of(&r["wear_outcome"]);
            let expected = if distance.is_nan() {
                assert!(!str_of(&r["wear_reason"]).is_empty());
                "unknown"
            } else if distance <= life {
                "visible"
            } else {
                "not_within_life"
            };
            assert_eq!(outcome, expected, "{distance} {life}");
            seen.insert(outcome);
            // New names beside the old ones, equal (NaN equal to NaN).
            for (old, new) in [
                ("polygon_order_dominant", "polygon_order_wear"),
                ("wear_calibration_share", "wear_share_straight"),
                ("tread_height", "tread_height_m"),
            ] {
                let (a, b) = (f64_of(&r[old]), f64_of(&r[new]));
                assert!(a == b || (a.is_nan() && b.is_nan()), "{old} {a} {new} {b}");
            }
            assert_eq!(
                f64_of(&r["wear_share_straight"]),
                defaults.wear_share_straight
            );
        }
        let map = crate::parquet_rows::footer_json(&file, "deprecated");
        assert_eq!(map["polygon_order_dominant"], "polygon_order_wear");
        assert_eq!(map["wear_calibration_share"], "wear_share_straight");
        assert_eq!(map["tread_height"], "tread_height_m");
    }
    assert!(
        seen.contains("visible") && seen.contains("not_within_life"),
        "{seen:?}"
    );
    // Both outcome words, and unknown, from one rule.
    use polywear::records::WearOutcome;
    assert_eq!(WearOutcome::of(f64::NAN, 5e4), WearOutcome::Unknown);
    assert_eq!(
        WearOutcome::of(f64::INFINITY, 5e4).as_str(),
        "not_within_life"
    );
    assert_eq!(WearOutcome::of(4e4, 5e4).as_str(), "visible");

    // This version's rows read without a deprecation line; rows written before the rename
    // (only the old names) read the same, with one.
    let (code, fresh, err) = polywear(&["analyze", run.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(!fresh.contains("deprecated"), "{fresh}");
    if !crate::common::python_has(&["pyarrow"]) {
        return;
    }
    let drop_new = "import sys, pyarrow.parquet as pq\n\
        for f in sys.argv[1:]:\n    t = pq.read_table(f)\n    \
        t = t.drop_columns(['polygon_order_wear', 'wear_share_straight'])\n    \
        pq.write_table(t, f)\n";
    // Copied apart from the run's manifest, which records each chunk's size.
    let old_run = d.join("old");
    std::fs::create_dir_all(&old_run).unwrap();
    let mut files = Vec::new();
    for f in chunk_files(&run) {
        let to = old_run.join(f.file_name().unwrap());
        std::fs::copy(&f, &to).unwrap();
        files.push(to.display().to_string());
    }
    // The run's calibration band goes with its rows (it holds no renamed column).
    for name in [
        polywear_study::calibration_band::evaluate::BAND_FILE,
        polywear_study::calibration_band::evaluate::BAND_DIGEST,
    ] {
        std::fs::copy(run.join(name), old_run.join(name)).unwrap();
    }
    let args: Vec<&str> = files.iter().map(String::as_str).collect();
    crate::common::python(drop_new, &args);
    let (code, old, err) = polywear(&["analyze", old_run.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    for name in [
        "polygon_order_dominant` is read as `polygon_order_wear",
        "wear_calibration_share` is read as `wear_share_straight",
    ] {
        assert!(
            old.contains(&format!("note: deprecated: column `{name}`")),
            "{old}"
        );
    }
    let answer = |s: &str| -> Vec<String> {
        s.lines()
            .filter(|l| !l.contains("deprecated") && !l.contains("report:"))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(answer(&old), answer(&fresh));
}

#[test]
fn optimize_says_did_you_mean_the_next_box_and_its_figure_in_percent() {
    let (code, _, err) = polywear(&[
        "optimize",
        "--objective",
        "waer",
        "--vary",
        "toe_deg=0.05..0.4",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("unknown objective `waer`; did you mean `wear`?"),
        "{err}"
    );
    // A negative weight reaches the objective's own words, not clap's "unexpected argument".
    let (code, _, err) = polywear(&[
        "optimize",
        "--objective",
        "-1*vibration",
        "--vary",
        "toe_deg=0.05..0.4",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("the weight must be a positive number"),
        "{err}"
    );
    let d = tmp("optimize");
    let study = "studies/toe_and_pressure.toml";
    let run = |name: &str, vary: &[&str]| {
        let out = d.join(name);
        let mut args = vec!["optimize", study];
        for v in vary {
            args.extend(["--vary", v]);
        }
        args.extend([
            "--objective",
            "vibration",
            "--samples",
            "100",
            "--grid",
            "3",
            "--levels",
            "1",
            "--format",
            "svg",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        let (code, stdout, err) = polywear(&args);
        assert_eq!(code, 0, "{err}");
        (stdout, out)
    };
    // Less toe-in vibrates less: the optimum is the box's lower edge, and the next box to try is
    // said as a --vary that runs.
    let (stdout, _) = run("edge", &["toe_deg=0.05..0.40"]);
    let said = "next step: widen the box there, `--vary ";
    let at = stdout.find(said).unwrap_or_else(|| panic!("{stdout}")) + said.len();
    let next = &stdout[at..at + stdout[at..].find('`').unwrap()];
    let (lo, hi) = next
        .trim_start_matches("toe_deg=")
        .split_once("..")
        .unwrap();
    let (lo, hi): (f64, f64) = (lo.parse().unwrap(), hi.parse().unwrap());
    assert!(lo < 0.05 && lo > 0.0 && hi == 0.4, "{next}");
    let (again, _) = run("next", &[next]);
    assert!(again.contains("optimum: toe_deg = "), "{again}");
    // The surface's colour bar is in %, as the text says.
    let (_, out) = run("map", &["toe_deg=0.05..0.40", "pressure_kpa=200..300"]);
    let svg = std::fs::read_to_string(out.join("surface.svg")).unwrap();
    let texts: Vec<String> = crate::common::svg::texts(&svg)
        .into_iter()
        .map(|t| t.text)
        .collect();
    assert!(
        texts.iter().any(|t| t == "vibration (worst wheel) [%]"),
        "{texts:?}"
    );
    let ticks: Vec<f64> = texts.iter().filter_map(|t| t.parse().ok()).collect();
    assert!(
        ticks
            .iter()
            .any(|&t| (10.0..=100.0).contains(&t) && t.fract() == 0.0),
        "{ticks:?}"
    );
    // The book says which objective answers which question.
    let page = std::fs::read_to_string("docs/book/src/reference/optimize.md").unwrap();
    assert!(page.contains("**Which objective answers which question.**"));
}

#[test]
fn the_wear_figure_gives_every_legend_entry_its_own_colour() {
    let d = tmp("wear-figure");
    let out = d.join("w");
    let (code, _, err) = polywear(&["wear", "--format", "svg", "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let svg = std::fs::read_to_string(out.join("wear.svg")).unwrap();
    let texts: Vec<String> = crate::common::svg::texts(&svg)
        .into_iter()
        .map(|t| t.text)
        .collect();
    // One wheel's legend: its distances and its orders (the visible depth is black).
    let per_wheel = texts
        .iter()
        .filter(|t| {
            t.ends_with(" km") && t.chars().next().unwrap().is_ascii_digit()
                || t.starts_with("order ")
        })
        .count()
        / 2;
    assert!(per_wheel >= 6, "{texts:?}");
    let mut colours = std::collections::BTreeSet::new();
    let mut rest = svg.as_str();
    while let Some(i) = rest.find("<polyline ") {
        let tag = &rest[i..i + rest[i..].find('>').unwrap()];
        if let Some(j) = tag.find("stroke=\"#") {
            colours.insert(tag[j + 9..j + 15].to_string());
        }
        rest = &rest[i + 1..];
    }
    colours.remove("000000");
    assert_eq!(colours.len(), per_wheel, "{colours:?}");
    assert!(texts.iter().any(|t| t == "visible depth"));
}

#[test]
fn the_report_ranks_the_parameters_for_the_wear_outcome_and_never_calls_vibration_the_cause() {
    let d = tmp("report");
    let run = wear_run(&d);
    let report = std::fs::read_to_string(run.join("_report/report.md")).unwrap();
    let drivers = &report[report.find("## Which parameters drive it?").unwrap()..];
    let wear = drivers
        .find("### The wear outcome")
        .expect("a wear section");
    let vibration = drivers.find("### Vibration").expect("a vibration section");
    assert!(wear < vibration, "{drivers}");
    let table = &drivers[wear..vibration];
    assert!(table.contains("visible within 40,000 km"), "{table}");
    // Toe-in drives the wear outcome of this run; every drawn parameter has a row per wheel.
    for p in ["Toe-in", "Speed", "Tread height h"] {
        assert_eq!(
            table.matches(&format!("| {p} |")).count(),
            2,
            "{p}: {table}"
        );
    }
    let (_, help, _) = polywear(&["--help"]);
    for text in [&report, &help] {
        assert!(!text.contains("the cause of polygonal wear"), "{text}");
    }
    assert!(
        help.contains("the mechanism the wear model builds on"),
        "{help}"
    );
}
