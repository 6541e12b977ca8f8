//! What-if scenarios: the baseline's rows are those of the study without scenarios, bit for
//! bit; a scenario is the same draw with its changes, so a change that changes nothing differs
//! by exactly zero and a `set` equals a separate run with that value; threads, shards and resume
//! give the same rows; pairing narrows the interval of a small change; every refusal.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::common::{self, polywear};
use crate::parquet_rows::rows;

fn tmp(name: &str) -> PathBuf {
    let d = common::fresh_dir(&format!("scenarios-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `study` as `dir/name.toml` and explores it into `dir/name`; returns the output.
fn explore(dir: &Path, name: &str, study: &str, extra: &[&str]) -> PathBuf {
    common::explore_study(dir, name, study, &[&["--no-report"], extra].concat())
}

/// Two variants, three chunks, a drawn structure parameter that is not an operating axis.
const BASE: &str = r#"name = "base"
seed = 11
samples = 240
chunk_size = 100
variants = ["sliding_share", "paper"]
[params]
speed_kmh = { dist = "uniform", min = 60, max = 250 }
toe_deg = { dist = "uniform", min = 0.1, max = 0.5 }
g_mod = { dist = "lognormal", median = 0.8557e6, sigma = 0.05 }
pressure_kpa = 240
"#;

const SCENARIOS: &str = r#"
[scenarios.toe_in]
toe_deg = { shift = -0.05 }
g_mod = { scale = 1.1 }

[scenarios."+20 kPa"]
pressure_kpa = { set = 260 }

[scenarios.nothing]
toe_deg = { scale = 1 }
"#;

/// Every row of the chunk files in `dir`, in file and row order: (column, value as text), the
/// text of a float exact (shortest round trip).
fn table(dir: &Path) -> Vec<Vec<(String, String)>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension().is_some_and(|e| e == "parquet")
                && !p.file_name().unwrap().to_string_lossy().starts_with('_')
        })
        .collect();
    files.sort();
    let mut out = Vec::new();
    for f in files {
        let reader =
            parquet::file::reader::SerializedFileReader::new(std::fs::File::open(&f).unwrap())
                .unwrap();
        for row in parquet::file::reader::FileReader::get_row_iter(&reader, None).unwrap() {
            out.push(
                row.unwrap()
                    .get_column_iter()
                    .map(|(k, v)| (k.clone(), v.to_string()))
                    .collect(),
            );
        }
    }
    out
}

fn value<'a>(row: &'a [(String, String)], column: &str) -> &'a str {
    &row.iter().find(|(k, _)| k == column).unwrap().1
}

/// The rows of scenario `name` (quoted as the Parquet text writes it), without the column.
fn of_scenario(rows: &[Vec<(String, String)>], name: &str) -> Vec<Vec<(String, String)>> {
    rows.iter()
        .filter(|r| value(r, "scenario") == format!("{name:?}"))
        .map(|r| r.iter().filter(|(k, _)| k != "scenario").cloned().collect())
        .collect()
}

#[test]
fn the_baseline_is_the_plain_run_bit_for_bit_and_scenarios_change_their_draws_only() {
    let dir = tmp("baseline");
    let plain = explore(&dir, "plain", BASE, &[]);
    let with = explore(&dir, "with", &format!("{BASE}{SCENARIOS}"), &[]);
    let (plain_rows, with_rows) = (table(&plain), table(&with));
    assert_eq!(plain_rows.len(), 240 * 4);
    assert_eq!(with_rows.len(), 240 * 4 * 4);
    assert!(plain_rows[0].iter().all(|(k, _)| k != "scenario"));
    // Compared whole, but not printed whole: a mismatch would print thousands of rows.
    assert!(of_scenario(&with_rows, "baseline") == plain_rows);
    // A scenario that changes nothing gives the baseline's rows.
    assert!(of_scenario(&with_rows, "nothing") == plain_rows);
    // The same draws with the changes: toe-in and g_mod moved, speed kept.
    let toe_in = of_scenario(&with_rows, "toe_in");
    for (b, s) in plain_rows.iter().zip(&toe_in) {
        let num = |r: &[(String, String)], c: &str| value(r, c).parse::<f64>().unwrap();
        assert_eq!(value(b, "sample_id"), value(s, "sample_id"));
        assert_eq!(num(b, "speed_kmh"), num(s, "speed_kmh"));
        assert_eq!(num(s, "toe_deg"), num(b, "toe_deg") - 0.05);
        assert_eq!(num(s, "g_mod"), num(b, "g_mod") * 1.1);
    }
    // The footers say what the scenarios are; the plain run's say nothing of them.
    let footer = |dir: &Path| -> BTreeMap<String, String> {
        let reader = parquet::file::reader::SerializedFileReader::new(
            std::fs::File::open(dir.join("chunk-0000000.parquet")).unwrap(),
        )
        .unwrap();
        parquet::file::reader::FileReader::metadata(&reader)
            .file_metadata()
            .key_value_metadata()
            .unwrap()
            .iter()
            .map(|kv| (kv.key.clone(), kv.value.clone().unwrap_or_default()))
            .collect()
    };
    assert!(!footer(&plain).contains_key("scenarios"));
    let scenarios = &footer(&with)["scenarios"];
    assert!(
        scenarios.contains(r#""toe_deg":{"shift":-0.05}"#),
        "{scenarios}"
    );
}

#[test]
fn threads_shards_and_resume_give_the_same_rows_with_scenarios() {
    let dir = tmp("shards");
    let study = format!("{BASE}{SCENARIOS}");
    let whole = table(&explore(&dir, "whole", &study, &["--threads", "2"]));
    assert!(table(&explore(&dir, "one", &study, &["--threads", "1"])) == whole);
    let s0 = explore(&dir, "s0", &study, &["--shard", "0/2"]);
    let s1 = explore(&dir, "s1", &study, &["--shard", "1/2"]);
    let mut sharded = table(&s0);
    sharded.extend(table(&s1));
    let key = |r: &Vec<(String, String)>| value(r, "sample_id").parse::<i64>().unwrap();
    sharded.sort_by_key(key);
    let mut sorted = whole.clone();
    sorted.sort_by_key(key);
    assert!(sharded == sorted);
    // A lost chunk is redone on resume, with the same rows.
    let resumed = dir.join("one");
    std::fs::remove_file(resumed.join("chunk-0000001.parquet")).unwrap();
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        "--resume",
        "--out",
        resumed.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(table(&resumed) == whole);
}

/// The scenarios table of an analysis: (scenario, wheel, outcome) → row.
fn effects(report: &Path) -> BTreeMap<(String, String, String), BTreeMap<String, String>> {
    let text = std::fs::read_to_string(report.join("scenarios.csv")).unwrap();
    let mut lines = text.lines();
    let header = fields(lines.next().unwrap());
    lines
        .map(|l| {
            let m: BTreeMap<String, String> = header.iter().cloned().zip(fields(l)).collect();
            let key = (
                m["scenario"].clone(),
                m["wheel"].clone(),
                m["outcome"].clone(),
            );
            (key, m)
        })
        .collect()
}

/// The fields of one CSV line (RFC 4180 quoting: the changes of a scenario hold commas).
fn fields(line: &str) -> Vec<String> {
    let (mut out, mut field, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut field)),
            (c, _) => field.push(c),
        }
    }
    out.push(field);
    out
}

fn analyze(dir: &Path, extra: &[&str]) -> PathBuf {
    let out = dir.join("_report");
    let mut args = vec![
        "analyze",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, stdout, stderr) = polywear(&args);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("What the changes do"), "{stdout}");
    out
}

#[test]
fn a_set_equals_a_separate_run_and_nothing_differs_by_exactly_zero() {
    let dir = tmp("separate");
    let one_variant = BASE.replace(r#"["sliding_share", "paper"]"#, r#"["sliding_share"]"#);
    let with = explore(&dir, "with", &format!("{one_variant}{SCENARIOS}"), &[]);
    let at_260 = explore(
        &dir,
        "at260",
        &one_variant.replace("pressure_kpa = 240", "pressure_kpa = 260"),
        &[],
    );
    // The scenario's rows are the separate run's rows.
    assert!(of_scenario(&table(&with), "+20 kPa") == table(&at_260));
    let report = analyze(&with, &[]);
    let e = effects(&report);
    let separate =
        std::fs::read_to_string(analyze_plain(&dir, &at_260).join("occurrence.csv")).unwrap();
    let base = std::fs::read_to_string(report.join("occurrence.csv")).unwrap();
    for wheel in ["follower", "driving"] {
        let p = |occurrence: &str| -> f64 {
            let header: Vec<&str> = occurrence.lines().next().unwrap().split(',').collect();
            let col = header.iter().position(|h| *h == "p").unwrap();
            let w = header.iter().position(|h| *h == "wheel").unwrap();
            occurrence
                .lines()
                .skip(1)
                .map(|l| l.split(',').collect::<Vec<_>>())
                .find(|f| f[w] == wheel)
                .unwrap()[col]
                .parse()
                .unwrap()
        };
        let row = &e[&("+20 kPa".to_string(), wheel.to_string(), "vibration".into())];
        let num = |k: &str| row[k].parse::<f64>().unwrap();
        assert_eq!(num("p_scenario"), p(&separate), "{wheel}");
        assert_eq!(num("p_baseline"), p(&base), "{wheel}");
        let difference = num("difference");
        assert!(
            (difference - (p(&separate) - p(&base))).abs() < 1e-15,
            "{wheel}: {difference} vs {} - {}",
            p(&separate),
            p(&base)
        );
        let none = &e[&("nothing".to_string(), wheel.to_string(), "vibration".into())];
        assert_eq!(none["difference"], "0", "{none:?}");
        assert_eq!(
            (&*none["only_baseline"], &*none["only_scenario"]),
            ("0", "0")
        );
    }
    let page = std::fs::read_to_string(report.join("report.md")).unwrap();
    assert!(page.contains("## What the changes do"), "{page}");
    assert!(page.contains("(no sample changes)"), "{page}");
    // Without `compare_to` nothing names a reference: the table keeps its columns.
    assert!(
        !page.contains("against `") && !page.contains("compare_to"),
        "{page}"
    );
    assert!(e.values().all(|row| !row.contains_key("reference")));
    assert!(report.join("scenarios.png").is_file());
}

fn analyze_plain(dir: &Path, run: &Path) -> PathBuf {
    let out = dir.join("plain_report");
    let (code, _, stderr) = polywear(&[
        "analyze",
        run.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    out
}

/// Toe-in −0.02° on the shipped study: the paired interval is at least three times narrower
/// than two separate runs of the same size would give (pairing cancels the samples' spread).
#[test]
fn pairing_narrows_a_small_changes_interval_at_least_threefold() {
    let dir = tmp("narrow");
    let shipped = std::fs::read_to_string("studies/toe_and_pressure.toml").unwrap();
    let study = shipped.split("\n[scenarios.").next().unwrap().to_string()
        + "\n[scenarios.small]\ntoe_deg = { shift = -0.02 }\n";
    let run = explore(&dir, "run", &study, &["--samples", "3000"]);
    let e = effects(&analyze(&run, &[]));
    let f = &e[&("small".to_string(), "follower".into(), "vibration".into())];
    let num = |k: &str| f[k].parse::<f64>().unwrap();
    let ratio = (num("unpaired_high") - num("unpaired_low"))
        / (num("difference_high") - num("difference_low"));
    assert!(
        ratio >= 3.0,
        "paired interval only {ratio:.2} times narrower: {f:?}"
    );
}

/// `compare_to` end to end: explore a small study whose scenario names another as its
/// reference, then analyze the chunk files alone (the study file removed). Each effect against
/// the reference is the paired count of the two scenarios' rows; the footers, the table, the
/// report and the printed summary name the reference.
#[test]
fn a_scenario_is_compared_with_the_scenario_it_names() {
    let dir = tmp("compare-to");
    let one_variant = BASE
        .replace(r#"["sliding_share", "paper"]"#, r#"["sliding_share"]"#)
        .replace("samples = 240", "samples = 40");
    let study = format!(
        "{one_variant}\n[scenarios.toe_in]\ntoe_deg = {{ shift = -0.05 }}\n\
         [scenarios.toe_in_soft]\ncompare_to = \"toe_in\"\ntoe_deg = {{ shift = -0.05 }}\n\
         g_mod = {{ scale = 0.8 }}\n"
    );
    let run = explore(&dir, "run", &study, &[]);
    std::fs::remove_file(dir.join("run.toml")).unwrap();
    let rows = table(&run);
    // (scenario, wheel, sample) → outcome code: 1 vibrates, 0 stable, None no verdict.
    let mut code = BTreeMap::new();
    for r in &rows {
        let class = value(r, "class").trim_matches('"');
        let c = match class {
            "limit_cycle" | "bistable" => Some(1),
            "stable" => Some(0),
            _ => None,
        };
        let key = (
            value(r, "scenario").trim_matches('"').to_string(),
            value(r, "wheel").trim_matches('"').to_string(),
            value(r, "sample_id").to_string(),
        );
        code.insert(key, c);
    }
    let out = dir.join("_report");
    let (status, stdout, stderr) = polywear(&[
        "analyze",
        run.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(status, 0, "{stderr}");
    let e = effects(&out);
    let mut compared = 0;
    for wheel in ["follower", "driving"] {
        let row = &e[&(
            "toe_in_soft".to_string(),
            wheel.to_string(),
            "vibration".into(),
        )];
        assert_eq!(row["reference"], "toe_in", "{row:?}");
        let base_row = &e[&("toe_in".to_string(), wheel.to_string(), "vibration".into())];
        assert_eq!(base_row["reference"], "baseline", "{base_row:?}");
        // The paired counts of toe_in_soft's rows against toe_in's, sample by sample.
        let mut t = [[0u64; 2]; 2];
        for sample in 0..40 {
            let get = |s: &str| code[&(s.to_string(), wheel.to_string(), sample.to_string())];
            if let (Some(r), Some(s)) = (get("toe_in"), get("toe_in_soft")) {
                t[r][s] += 1;
            }
        }
        let n = |k: &str| row[k].parse::<u64>().unwrap();
        assert_eq!(
            (
                n("both"),
                n("only_baseline"),
                n("only_scenario"),
                n("neither")
            ),
            (t[1][1], t[1][0], t[0][1], t[0][0]),
            "{wheel}: {row:?}"
        );
        let pairs = (t[0][0] + t[0][1] + t[1][0] + t[1][1]) as f64;
        let direct = (t[0][1] as f64 - t[1][0] as f64) / pairs;
        let difference = row["difference"].parse::<f64>().unwrap();
        assert!((difference - direct).abs() < 1e-15, "{wheel}: {row:?}");
        compared += t[0][1] + t[1][0];
    }
    // Softer rubber changes some verdicts: the comparison is not of two equal blocks.
    assert!(compared > 0, "{e:?}");
    // The reference travels in the footers, so the analysis above needed no study file.
    let footer = std::fs::read(run.join("chunk-0000000.parquet")).unwrap();
    let footer = String::from_utf8_lossy(&footer);
    assert!(footer.contains(r#""compare_to":"toe_in""#));
    let page = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        page.contains("**toe_in_soft** (toe_deg shifted by -0.05 deg, g_mod scaled by 0.8), against **toe_in** (toe_deg shifted by -0.05 deg):"),
        "{page}"
    );
    assert!(page.contains("against `toe_in`"), "{page}");
    let against: Vec<&str> = stdout
        .lines()
        .filter(|l| l.trim_start().starts_with("toe_in_soft ("))
        .collect();
    assert_eq!(against.len(), 4, "{stdout}");
    assert!(
        against.iter().all(|l| l.contains("against `toe_in`")),
        "{stdout}"
    );
    assert!(
        stdout
            .lines()
            .filter(|l| l.trim_start().starts_with("toe_in ("))
            .all(|l| !l.contains("against `")),
        "{stdout}"
    );
}

/// A scenario study that must be refused: (what is changed, words the message must hold).
const REFUSED: [(&str, &[&str]); 15] = [
    (
        "[scenarios.a]\ntoe_mm = { shift = -1 }\n",
        &["scenarios.a.toe_mm.shift", "`toe_deg = { shift = -0.1504 }` at the 381 mm rim"],
    ),
    (
        "[scenarios.a]\ntoe_mm = { set = 1 }\ntoe_deg = { shift = -0.1 }\n",
        &["changes the toe-in twice"],
    ),
    (
        "[scenarios.a]\ntoe_deg = { shift = -0.01 }\n[scenarios.\"a \"]\nload_n = { set = 3000 }\n",
        &["scenario `a ` is used twice", "differ only in the spaces"],
    ),
    (
        "[scenarios.a]\ntoe = { shift = -0.1 }\n",
        &["scenarios.a.toe", "did you mean `toe_deg`"],
    ),
    (
        "[scenarios.a]\ntoe_deg = { shift = -0.2 }\n",
        &[
            "scenarios.a.toe_deg",
            "(0, 10]",
            "of this run's 50 samples",
            "[0.1, 0.5] become [-0.1, 0.3]",
        ],
    ),
    (
        "[scenarios.a]\ntoe_deg = { shift = -0.1 }\n[scenarios.a]\nload_n = { set = 3000 }\n",
        &["scenario `a` is used twice", "line 13"],
    ),
    ("[scenarios.a]\n", &["`scenarios.a` changes nothing"]),
    (
        "[scenarios.Baseline]\ntoe_deg = { shift = 0.1 }\n",
        &["`Baseline` is used twice", "the study without changes"],
    ),
    (
        "[scenarios.a]\ntoe_deg = { shift = 0.1, scale = 2 }\n",
        &[
            "scenarios.a.toe_deg",
            "exactly one of set, shift, scale, cap",
            "shift, scale",
        ],
    ),
    (
        "[scenarios.a]\ntoe_deg = { shfit = 0.1 }\n",
        &["scenarios.a.toe_deg.shfit", "shift"],
    ),
    (
        "[scenarios.a]\ntoe_deg = { scale = -1 }\n",
        &["scenarios.a.toe_deg.scale", "must be positive"],
    ),
    (
        "[scenarios.a]\npressure_kpa = { set = 5000 }\n",
        &["scenarios.a.pressure_kpa.set", "(0, 2000]"],
    ),
    (
        "[scenarios.toe_a]\ntoe_deg = { shift = -0.01 }\n[scenarios.toe_b]\ntoe_deg = { shift = -0.02 }\ncompare_to = \"toe_c\"\n",
        &[
            ".toml: `scenarios.toe_b.compare_to` = \"toe_c\" names no scenario of this study",
            "did you mean `toe_a`?",
            "accepted: \"baseline\", \"toe_a\"",
        ],
    ),
    (
        "[scenarios.toe_a]\ntoe_deg = { shift = -0.01 }\ncompare_to = \"toe_a\"\n",
        &[
            "`scenarios.toe_a.compare_to` = \"toe_a\" compares the scenario with itself",
            "accepted: \"baseline\"",
        ],
    ),
    (
        "[scenarios.a]\ng_mod = { scale = 1e5 }\n",
        &[
            "scenarios.a.g_mod",
            "(0, 10000000000]",
            "of this run's 50 samples",
        ],
    ),
];

#[test]
fn bad_scenarios_are_refused_before_any_work_naming_the_key_and_range() {
    let dir = tmp("refused");
    let base = BASE.replace("samples = 240", "samples = 50");
    for (k, (scenarios, words)) in REFUSED.iter().enumerate() {
        refused_before_work(
            &dir,
            &format!("bad{k}"),
            &format!("{base}{scenarios}"),
            words,
        );
    }
}

/// Explores the study `text` (written as `dir/NAME.toml`) and checks that it is refused before
/// any work: exit 2, every one of `words` in the message, and no output folder.
fn refused_before_work(dir: &Path, name: &str, text: &str, words: &[&str]) {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let out = dir.join(format!("{name}_out"));
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{text}: {stderr}");
    for w in words {
        assert!(stderr.contains(w), "{text}: `{w}` not in {stderr}");
    }
    assert!(!out.exists(), "{text}: work started");
}

/// A scenario's changed values go through the plausibility and cross-parameter checks every
/// direct input gets: refused before any work, naming the scenario's key and what is accepted
/// (they ran, and every scenario row failed).
#[test]
fn scenario_values_are_checked_like_direct_inputs() {
    let dir = tmp("rules");
    let base = BASE.replace("samples = 240", "samples = 50");
    let cases: [(&str, &[&str]); 6] = [
        (
            "pressure_kpa = { scale = 0.01 }",
            &[
                "`scenarios.a.pressure_kpa.scale`",
                "2.4 kPa is implausible",
                "plausible [50, 1000] kPa",
            ],
        ),
        (
            "pressure_kpa = { set = 2.4 }",
            &["`scenarios.a.pressure_kpa.set`", "plausible [50, 1000] kPa"],
        ),
        (
            "load_n = { cap = 400 }",
            &["`scenarios.a.load_n.cap`", "plausible [500, 50000] N"],
        ),
        (
            "mu_s = { set = 0.9 }",
            &[
                "`scenarios.a.mu_s` = { set = 0.9 }",
                "mu_m down to 0.76",
                "accepted: mu_s at most mu_m",
            ],
        ),
        (
            "n_driven = { set = 6 }",
            &[
                "`scenarios.a.n_driven` = { set = 6 }",
                "n_wheels down to 4",
                "accepted: n_driven at most n_wheels",
            ],
        ),
        (
            "visible_depth_mm = { set = 5 }",
            &[
                "`scenarios.a.visible_depth_mm`",
                "accepted: visible_depth_mm at most limit_depth_mm",
            ],
        ),
    ];
    for (k, (change, words)) in cases.iter().enumerate() {
        let text = format!("{base}[scenarios.a]\n{change}\n");
        refused_before_work(&dir, &format!("rule{k}"), &text, words);
    }
    // An implausible change that is meant runs with --accept-implausible.
    let path = dir.join("meant.toml");
    std::fs::write(
        &path,
        format!("{base}[scenarios.a]\nload_n = {{ cap = 400 }}\n"),
    )
    .unwrap();
    let out = dir.join("meant");
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        "--accept-implausible",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
}

#[test]
fn the_shipped_scenario_study_is_checked_against_its_own_samples() {
    // Its toe-in is drawn within [0.21, 0.29]: toe-in -0.15° keeps every sample in range.
    let dir = tmp("shipped");
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        "studies/toe_and_pressure.toml",
        "--samples",
        "20",
        "--out",
        dir.join("run").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let rows = rows(&dir.join("run/chunk-0000000.parquet"));
    assert_eq!(rows.len(), 20 * 2 * 4);
}
