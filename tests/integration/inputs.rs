//! Inputs a newcomer gets right: a value outside its plausible range (a likely unit mix-up) is
//! refused at every place it can enter, before any work, with the conversion that lands in
//! range, and runs with `--accept-implausible`; a parameter set in two places is refused or, where
//! the precedence is documented, the run says which value won; the shipped inputs are all
//! plausible.

use std::path::{Path, PathBuf};

use crate::common::{self, polywear};
use polywear::params::{ParamId, Params};
use polywear::study::Study;

fn dir(name: &str) -> PathBuf {
    let d = common::fresh_dir(&format!("inputs-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(d: &Path, name: &str, text: &str) -> String {
    let p = d.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// Asserts exit 2, every needle in stderr, and that `out` (if given) was not created.
fn refused(args: &[&str], needles: &[&str], out: Option<&Path>) -> String {
    let (code, _, stderr) = polywear(args);
    assert_eq!(code, 2, "{args:?}: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "{args:?}: lacks `{n}`:\n{stderr}");
    }
    if let Some(out) = out {
        assert!(
            !out.exists(),
            "{args:?}: work started ({} exists)",
            out.display()
        );
    }
    stderr
}

fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// The shipped fleet with its pressures in bar (224 kPa → 2.24).
fn fleet_in_bar() -> String {
    let text = std::fs::read_to_string(shipped("studies/fleet_telematics.csv")).unwrap();
    let mut out = String::new();
    for (i, line) in text.lines().enumerate() {
        let mut cells: Vec<String> = line.split(',').map(str::to_string).collect();
        if i > 0 {
            cells[2] = format!("{}", cells[2].parse::<f64>().unwrap() / 100.0);
        }
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    out
}

const BAR: &str = "2.4 bar = 240 kPa?";

#[test]
fn the_shipped_studies_cycles_and_reference_data_are_plausible() {
    for f in [
        "default.toml",
        "decoding.toml",
        "fleet_telematics.toml",
        "grid_4axes.toml",
        "wide_structure.toml",
    ] {
        let path = shipped(&format!("studies/{f}"));
        let text = std::fs::read_to_string(&path).unwrap();
        let s = Study::parse_at(&text, Params::default(), path.parent().unwrap()).unwrap();
        s.check_plausible().unwrap_or_else(|e| panic!("{f}: {e}"));
        // And the check can fail: the same study with its pressure in bar.
        let bar = text
            .lines()
            .map(|l| {
                if l.starts_with("pressure_kpa") {
                    "pressure_kpa = 2.4"
                } else {
                    l
                }
            })
            .collect::<Vec<_>>()
            .join("\n");
        if bar != text && !text.contains("[operating_points]") {
            let s = Study::parse_at(&bar, Params::default(), path.parent().unwrap()).unwrap();
            let e = s.check_plausible().unwrap_err().to_string();
            assert!(
                e.contains("`params.pressure_kpa`") && e.contains(BAR),
                "{f}: {e}"
            );
        }
    }
    let r0 = std::fs::read_to_string(shipped("studies/params_r0.toml")).unwrap();
    let (p, _) = polywear::study::read_param_file(&Params::default(), &r0).unwrap();
    p.check_plausible().unwrap();
    let targets = std::fs::read_to_string(shipped("studies/paper_targets.toml")).unwrap();
    let problem = polywear_study::calibrate::parse_problem(&targets).unwrap();
    problem.start.check_plausible().unwrap();
    for c in ["hwfet", "udds", "us06", "wltc_class3b"] {
        let cycle =
            polywear_study::cycle::DriveCycle::read(&shipped(&format!("data/cycles/{c}.csv")))
                .unwrap();
        cycle.check_plausible().unwrap();
    }
    for f in ["points.csv", "points_sliding_share.csv"] {
        let t = polywear_study::table_input::NumericTable::read_with_text(
            &shipped(&format!("tests/data/{f}")),
            &|c| ["wheel", "variant", "class"].contains(&c),
        )
        .unwrap();
        for id in ParamId::ALL {
            let Some(j) = t.column(id.name()) else {
                continue;
            };
            for row in &t.rows {
                id.spec()
                    .check_plausible(row[j])
                    .unwrap_or_else(|e| panic!("{f}: {e}"));
            }
        }
    }
}

#[test]
fn an_implausible_flag_set_or_parameter_file_is_refused_before_any_work() {
    let d = dir("flags");
    let bar = write(&d, "bar.toml", "[params]\npressure_kpa = 2.4\n");
    let plot = d.join("plot.png");
    let p = plot.to_str().unwrap();
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["simulate", "--pressure", "2.4", "--plot", p],
            &["--pressure 2.4", BAR],
        ),
        (
            &["simulate", "--set", "pressure_kpa=2.4", "--plot", p],
            &["--set pressure_kpa=2.4", BAR],
        ),
        (
            &["simulate", "--params", &bar, "--plot", p],
            &["--params", "bar.toml", "`params.pressure_kpa`", BAR],
        ),
        (
            &["simulate", "--load", "400", "--plot", p],
            &["--load 400", "400 kg carry 3923 N?"],
        ),
        (
            &["simulate", "--set", "rho=1.25", "--plot", p],
            &["1.25 g/cm^3 = 1250 kg/m^3?"],
        ),
        (
            &["simulate", "--toe", "6", "--plot", p],
            &[
                "--toe 6",
                "plausible (0, 1] deg",
                "6 arc minutes = 0.1 deg?",
            ],
        ),
        (
            &["reproduce", "--params", &bar, "--out", p],
            &["--params", "`params.pressure_kpa`", BAR],
        ),
        (
            &[
                "bifurcation",
                "--param",
                "pressure_kpa",
                "--from",
                "1.5",
                "--to",
                "3.5",
                "--out",
                p,
            ],
            &["--from", "1.5 bar = 150 kPa?"],
        ),
        (
            &[
                "chart",
                "--x",
                "speed_kmh",
                "--x-from",
                "60",
                "--x-to",
                "200",
                "--y",
                "pressure_kpa",
                "--y-from",
                "150",
                "--y-to",
                "3.5",
                "--out",
                p,
            ],
            &["--y-to", "3.5 bar = 350 kPa?"],
        ),
    ];
    for (args, needles) in cases {
        refused(args, needles, Some(&plot));
        assert!(
            !d.join("plot.parquet").exists() && !d.join("plot").exists(),
            "{args:?}"
        );
    }
    // A value out of the accepted range names the mix-up too.
    refused(
        &["simulate", "--set", "tread_height=8"],
        &["(0, 0.2] m; 8 mm = 0.008 m?"],
        None,
    );
    // --accept-implausible runs it: the pressure in bar gives no contact patch, said per wheel.
    let (code, stdout, stderr) =
        polywear(&["simulate", "--pressure", "2.4", "--accept-implausible"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("contact patch undefined"), "{stdout}");
    let (code, _, stderr) = polywear(&["simulate", "--params", &bar, "--accept-implausible"]);
    assert_eq!(code, 0, "{stderr}");
    // Plausible values pass without a word.
    let (code, _, stderr) = polywear(&["simulate", "--pressure", "240", "--load", "4000"]);
    assert_eq!((code, stderr.as_str()), (0, ""), "{stderr}");
    // calibrate's starting values are parameters too.
    let targets = write(
        &d,
        "targets.toml",
        "[params]\ng_mod = 0.8557\n[[target]]\nkind = \"hopf\"\nparam = \"speed_kmh\"\nfrom = 40\nto = 150\nvalue = 80\n",
    );
    refused(
        &["calibrate", &targets, "--out", p],
        &["targets.toml", "`params.g_mod`", "0.8557 MPa = 855700 Pa?"],
        Some(&plot),
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn an_implausible_study_value_bound_or_fleet_cell_is_refused_before_any_work() {
    let d = dir("study");
    let out = d.join("out");
    let o = out.to_str().unwrap();
    let cases: &[(&str, &str, &[&str])] = &[
        ("fixed", "pressure_kpa = 2.4", &["`params.pressure_kpa`", BAR]),
        (
            "uniform",
            "pressure_kpa = { dist = \"uniform\", min = 1.8, max = 3.2 }",
            &["`params.pressure_kpa.min`", "1.8 bar = 180 kPa?"],
        ),
        (
            "truncated",
            "pressure_kpa = { dist = \"truncated_normal\", mean = 240, sd = 20, min = 180, max = 1500 }",
            &["`params.pressure_kpa.max`", "1500 mbar = 150 kPa?"],
        ),
        (
            "mean_outside",
            "load_n = { dist = \"truncated_normal\", mean = 400, sd = 50, min = 600, max = 6000 }",
            &[],
        ),
        (
            "lognormal",
            "pressure_kpa = { dist = \"lognormal\", median = 2.4, sigma = 0.05 }",
            &["`params.pressure_kpa.median`", BAR],
        ),
        (
            "levels",
            "toe_deg = { dist = \"levels\", levels = [0.2, 6, 0.3] }",
            &["`params.toe_deg.levels[1]`", "6 arc minutes = 0.1 deg?"],
        ),
    ];
    for (name, line, needles) in cases {
        // The study's [params] with the case's line added before the structure.
        let path = write(
            &d,
            &format!("{name}.toml"),
            &format!(
                "name = \"{name}\"\nsamples = 40\nchunk_size = 20\n[params]\n{line}\ng_mod = {{ dist = \"lognormal\", median = 0.8557e6, sigma = 0.05 }}\n"
            ),
        );
        if needles.is_empty() {
            // A truncated normal whose mean is implausible but whose bounds are not draws only
            // plausible values: accepted.
            let (code, _, stderr) =
                polywear(&["explore", &path, "--quiet", "--no-report", "--out", o]);
            assert_eq!(code, 0, "{name}: {stderr}");
            std::fs::remove_dir_all(&out).unwrap();
            continue;
        }
        let mut all = vec![format!("{name}.toml")];
        all.extend(needles.iter().map(|n| n.to_string()));
        let all: Vec<&str> = all.iter().map(String::as_str).collect();
        refused(&["explore", &path, "--out", o], &all, Some(&out));
        // Both ways of saying the value is meant run it.
        let (code, _, stderr) = polywear(&[
            "explore",
            &path,
            "--accept-implausible",
            "--quiet",
            "--no-report",
            "--out",
            o,
        ]);
        assert_eq!(code, 0, "{name}: {stderr}");
        std::fs::remove_dir_all(&out).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let meant = write(
            &d,
            &format!("{name}_meant.toml"),
            &format!("accept_implausible = true\n{text}"),
        );
        let (code, _, stderr) =
            polywear(&["explore", &meant, "--quiet", "--no-report", "--out", o]);
        assert_eq!(code, 0, "{name}: {stderr}");
        std::fs::remove_dir_all(&out).unwrap();
    }
    // The fleet in bar: refused up front, where 0.5.0 ran every sample and then found no verdict.
    write(&d, "bar.csv", &fleet_in_bar());
    let study = std::fs::read_to_string(shipped("studies/fleet_telematics.toml"))
        .unwrap()
        .replace("fleet_telematics.csv", "bar.csv");
    let s = write(&d, "fleet_bar.toml", &study);
    refused(
        &["explore", &s, "--out", o],
        &[
            "fleet_bar.toml: [operating_points]: ",
            "bar.csv, row 1 (line 2), column `pressure_kpa`",
            "2.24 bar = 224 kPa?",
        ],
        Some(&out),
    );
    // The same file as Parquet, and as classify's points.
    use polywear_study::parquet_out::{write_table, Column};
    let t = polywear_study::table_input::NumericTable::read(&d.join("bar.csv")).unwrap();
    let cols: Vec<Column> = t
        .columns
        .iter()
        .enumerate()
        .map(|(j, c)| Column::f64(c.as_str(), "", t.rows.iter().map(|r| r[j]).collect()))
        .collect();
    write_table(&d.join("bar.parquet"), &cols, &[]).unwrap();
    let s = write(
        &d,
        "fleet_pq.toml",
        &study.replace("bar.csv", "bar.parquet"),
    );
    refused(
        &["explore", &s, "--out", o],
        &[
            "bar.parquet, row 1, column `pressure_kpa`",
            "2.24 bar = 224 kPa?",
        ],
        Some(&out),
    );
    let csv = d.join("classified.csv");
    let bar_csv = d.join("bar.csv");
    refused(
        &[
            "classify",
            bar_csv.to_str().unwrap(),
            "--weight",
            "hours",
            "--out",
            csv.to_str().unwrap(),
        ],
        &[
            "bar.csv, row 1 (line 2), column `pressure_kpa`",
            "2.24 bar = 224 kPa?",
        ],
        Some(&csv),
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn an_implausible_cycle_column_set_or_study_is_refused_before_any_work() {
    let d = dir("cycle");
    let out = d.join("out");
    let o = out.to_str().unwrap();
    let c = write(
        &d,
        "c.csv",
        "time_s,speed_kmh,pressure_kpa\n0,0,2.4\n1,50,2.4\n2,80,2.4\n",
    );
    refused(
        &["cycle", &c, "--out", o],
        &["c.csv, row 1 (line 2), column `pressure_kpa`", BAR],
        Some(&out),
    );
    let plain = write(&d, "p.csv", "time_s,speed_kmh\n0,0\n1,50\n2,80\n");
    refused(
        &["cycle", &plain, "--set", "pressure_kpa=2.4", "--out", o],
        &["--set pressure_kpa=2.4", BAR],
        Some(&out),
    );
    write(&d, "bar.csv", &fleet_in_bar());
    let study = std::fs::read_to_string(shipped("studies/fleet_telematics.toml"))
        .unwrap()
        .replace("fleet_telematics.csv", "bar.csv");
    let s = write(&d, "fleet_bar.toml", &study);
    refused(
        &[
            "cycle",
            &plain,
            "--study",
            &s,
            "--structure-samples",
            "4",
            "--out",
            o,
        ],
        &[
            "--study",
            "fleet_bar.toml",
            "bar.csv, row 1 (line 2)",
            "2.24 bar = 224 kPa?",
        ],
        Some(&out),
    );
    let (code, _, stderr) = polywear(&["cycle", &c, "--accept-implausible", "--quiet", "--out", o]);
    assert_eq!(code, 0, "{stderr}");
    std::fs::remove_dir_all(&d).ok();
}

/// The first JSON object `simulate --json` prints (the follower).
fn follower_json(args: &[&str]) -> (serde_json::Value, String) {
    let mut all = vec![
        "simulate",
        "--json",
        "--wheel",
        "follower",
        "--duration",
        "0.01",
    ];
    all.extend_from_slice(args);
    let (code, stdout, stderr) = polywear(&all);
    assert_eq!(code, 0, "{args:?}: {stderr}");
    let v = serde_json::from_str(stdout.lines().next().unwrap()).unwrap();
    (v, stderr)
}

#[test]
fn a_parameter_given_twice_on_the_command_line_is_refused() {
    refused(
        &["simulate", "--set", "speed_kmh=80", "--speed", "100"],
        &[
            "`speed_kmh` is given twice",
            "--set speed_kmh=80",
            "--speed 100",
        ],
        None,
    );
    refused(
        &["simulate", "--set", "toe_deg=0.2", "--set", "toe_deg=0.3"],
        &[
            "`toe_deg` is given twice",
            "--set toe_deg=0.2",
            "--set toe_deg=0.3",
        ],
        None,
    );
    // A sweep or a chart's axis varies its parameter: giving it as well is refused.
    refused(
        &[
            "bifurcation",
            "--param",
            "speed_kmh",
            "--from",
            "60",
            "--to",
            "120",
            "--speed",
            "100",
        ],
        &["--speed 100 sets `speed_kmh`, which --param speed_kmh varies"],
        None,
    );
    refused(
        &[
            "chart",
            "--x",
            "speed_kmh",
            "--x-from",
            "60",
            "--x-to",
            "200",
            "--y",
            "toe_deg",
            "--y-from",
            "0.1",
            "--y-to",
            "0.5",
            "--set",
            "toe_deg=0.3",
            "--out",
            "x.parquet",
        ],
        &["--set toe_deg=0.3 sets `toe_deg`, which --y toe_deg varies"],
        None,
    );
}

#[test]
fn a_typed_value_replaces_the_parameter_files_and_says_so() {
    let d = dir("replace");
    let f = write(&d, "toe015.toml", "[params]\ntoe_deg = 0.15\n");
    let (v, stderr) = follower_json(&["--params", &f, "--toe", "0.2"]);
    assert_eq!(v["toe_deg"].as_f64(), Some(0.2));
    assert!(
        stderr.contains(&format!(
            "note: --toe 0.2 replaces toe_deg = 0.15 of --params {f}"
        )),
        "{stderr}"
    );
    let (v, stderr) = follower_json(&["--params", &f, "--set", "toe_deg=0.25"]);
    assert_eq!(v["toe_deg"].as_f64(), Some(0.25));
    assert!(
        stderr.contains("note: --set toe_deg=0.25 replaces toe_deg = 0.15"),
        "{stderr}"
    );
    // The file alone: its value, no note.
    let (v, stderr) = follower_json(&["--params", &f]);
    assert_eq!((v["toe_deg"].as_f64(), stderr.as_str()), (Some(0.15), ""));
    // A sweep over the file's parameter: the sweep's values, said.
    let out = d.join("sweep");
    let (code, _, stderr) = polywear(&[
        "bifurcation",
        "--param",
        "toe_deg",
        "--from",
        "0.1",
        "--to",
        "0.4",
        "--steps",
        "3",
        "--params",
        &f,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("note: --param toe_deg replaces toe_deg = 0.15 of --params"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_parameter_file_and_a_study_or_fleet_that_both_set_it_are_refused() {
    let d = dir("twofiles");
    let out = d.join("out");
    let o = out.to_str().unwrap();
    let toe = write(&d, "toe015.toml", "[params]\ntoe_deg = 0.15\n");
    // The what-if of the issue: the fleet's column would silently win.
    let fleet = shipped("studies/fleet_telematics.toml");
    refused(
        &["explore", fleet.to_str().unwrap(), "--params", &toe, "--out", o],
        &[
            "--params",
            "toe015.toml sets `toe_deg`, and",
            "fleet_telematics.toml gives it per row (column `toe_deg` of its operating-point file fleet_telematics.csv)",
        ],
        Some(&out),
    );
    // A drawn and a fixed parameter of the study.
    let r0 = shipped("studies/params_r0.toml");
    refused(
        &["explore", "--params", r0.to_str().unwrap(), "--out", o],
        &["sets `g_mod`, and built-in default study draws it (`params.g_mod`)"],
        Some(&out),
    );
    let fixed = write(
        &d,
        "fixed.toml",
        "samples = 10\n[params]\ntoe_deg = 0.3\nspeed_kmh = { dist = \"uniform\", min = 60, max = 120 }\n",
    );
    refused(
        &["explore", &fixed, "--params", &toe, "--out", o],
        &[
            "sets `toe_deg`, and",
            "fixed.toml fixes it (`params.toe_deg`)",
        ],
        Some(&out),
    );
    // classify: the points file gives it per point.
    let pts = write(&d, "pts.csv", "speed_kmh,toe_deg\n100,0.3\n");
    let csv = d.join("c.csv");
    refused(
        &[
            "classify",
            &pts,
            "--params",
            &toe,
            "--out",
            csv.to_str().unwrap(),
        ],
        &[
            "sets `toe_deg`, which",
            "pts.csv gives per point (column `toe_deg`)",
        ],
        Some(&csv),
    );
    // chart's band: the study draws what --params or --set gives.
    let band = |extra: &[&str]| {
        let mut a = vec![
            "chart",
            "--x",
            "speed_kmh",
            "--x-from",
            "60",
            "--x-to",
            "200",
            "--y",
            "toe_deg",
            "--y-from",
            "0.1",
            "--y-to",
            "0.5",
            "--study",
        ];
        let s = shipped("studies/default.toml");
        let s = s.to_str().unwrap().to_string();
        let mut owned: Vec<String> = a.drain(..).map(str::to_string).collect();
        owned.extend([s, "--structure-samples".into(), "2".into(), "--out".into()]);
        owned.push(d.join("band.parquet").to_str().unwrap().into());
        owned.extend(extra.iter().map(|x| x.to_string()));
        owned
    };
    for (extra, needle) in [
        (
            vec!["--set", "g_mod=0.9e6"],
            "--set g_mod=900000 sets `g_mod`",
        ),
        (
            vec!["--params", r0.to_str().unwrap()],
            "params_r0.toml sets `g_mod`",
        ),
    ] {
        let args = band(&extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused(
            &args,
            &[needle, "draws per structure for the band"],
            Some(&d.join("band.parquet")),
        );
    }
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_cycle_refuses_what_it_gives_per_step_and_says_what_it_replaces() {
    let d = dir("cycleover");
    let out = d.join("out");
    let o = out.to_str().unwrap();
    let toe_cycle = write(
        &d,
        "toe.csv",
        "time_s,speed_kmh,toe_deg\n0,0,0.3\n1,50,0.3\n2,80,0.2\n",
    );
    let plain = write(&d, "plain.csv", "time_s,speed_kmh\n0,0\n1,50\n2,80\n");
    let toe = write(&d, "toe015.toml", "[params]\ntoe_deg = 0.15\n");
    let speed = write(&d, "speed.toml", "[params]\nspeed_kmh = 120\n");
    refused(
        &["cycle", &toe_cycle, "--set", "toe_deg=0.3", "--out", o],
        &[
            "--set toe_deg=0.3 sets `toe_deg`, which",
            "toe.csv gives at every step",
        ],
        Some(&out),
    );
    refused(
        &["cycle", &toe_cycle, "--params", &toe, "--out", o],
        &[
            "--params",
            "toe015.toml sets `toe_deg`",
            "gives at every step",
        ],
        Some(&out),
    );
    refused(
        &[
            "cycle",
            &plain,
            "--set",
            "toe_deg=0.3",
            "--set",
            "toe_deg=0.2",
            "--out",
            o,
        ],
        &["`toe_deg` is given twice"],
        Some(&out),
    );
    // A study fixing toe-in: a cycle column for it is refused, --set replaces it with a note.
    let fixed = write(
        &d,
        "fixed.toml",
        "[params]\ntoe_deg = 0.3\ng_mod = { dist = \"lognormal\", median = 0.8557e6, sigma = 0.05 }\n",
    );
    refused(
        &[
            "cycle",
            &toe_cycle,
            "--study",
            &fixed,
            "--structure-samples",
            "2",
            "--out",
            o,
        ],
        &[
            "toe.csv (a column) sets `toe_deg`, which --study",
            "fixes (`params.toe_deg`)",
        ],
        Some(&out),
    );
    let (code, _, stderr) = polywear(&[
        "cycle",
        &plain,
        "--study",
        &fixed,
        "--structure-samples",
        "2",
        "--set",
        "toe_deg=0.2",
        "--quiet",
        "--out",
        o,
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("note: --set toe_deg=0.2 replaces --study"),
        "{stderr}"
    );
    assert!(stderr.contains("`params.toe_deg` = 0.3"), "{stderr}");
    let rows = crate::parquet_rows::rows(&out.join("cycle.parquet"));
    assert!(rows.iter().all(|r| r["toe_deg"].to_string() == "0.2"));
    std::fs::remove_dir_all(&out).unwrap();
    // --params' speed: the cycle's, said.
    let (code, _, stderr) = polywear(&["cycle", &plain, "--params", &speed, "--quiet", "--out", o]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("note: the cycle's speed replaces speed_kmh = 120 of --params"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&d).ok();
}

/// A fleet of three vehicles with text ids, hours and km, and the study drawing it.
fn fleet(d: &Path, op: &str) -> String {
    write(
        d,
        "fleet.csv",
        "vehicle_id,speed_kmh,load_n,pressure_kpa,toe_deg,hours,km\n\
         VAN-1,50,3000,210,0.2,10,500\n\
         VAN-2,100,4500,250,0.35,10,1000\n\
         CAR 3,130,3800,230,0.25,20,2600\n",
    );
    write(
        d,
        "fleet.toml",
        &format!(
            "name = \"fleet\"\nseed = 3\nsamples = 30\nchunk_size = 30\n[operating_points]\nfile = \"fleet.csv\"\n{op}\n[params]\ng_mod = {{ dist = \"lognormal\", median = 0.8557e6, sigma = 0.05 }}\n"
        ),
    )
}

#[test]
fn weights_by_hours_or_km_and_columns_passed_through() {
    let d = dir("weights");
    let parse = |op: &str| {
        let s = fleet(&d, op);
        Study::parse_at(&std::fs::read_to_string(&s).unwrap(), Params::default(), &d)
    };
    let both = "pass_through = [\"vehicle_id\", \"hours\", \"km\"]";
    let s = parse(&format!("weight = \"km\"\n{both}")).unwrap();
    let op = s.operating_points.as_ref().unwrap();
    assert_eq!(op.weights, [500.0, 1000.0, 2600.0]);
    assert_eq!(op.weight_kind.as_str(), "distance");
    assert_eq!(op.names, ["speed_kmh", "load_n", "pressure_kpa", "toe_deg"]);
    let s = parse(&format!("weight = \"hours\"\n{both}")).unwrap();
    let op = s.operating_points.as_ref().unwrap();
    assert_eq!(
        (op.weights.clone(), op.weight_kind.as_str()),
        (vec![10.0, 10.0, 20.0], "time")
    );
    // km from hours × speed where the file has no km column.
    let no_km = "pass_through = [\"vehicle_id\"]";
    let s = fleet(&d, &format!("weight = \"km\"\n{no_km}"));
    std::fs::write(
        d.join("fleet.csv"),
        "vehicle_id,speed_kmh,load_n,pressure_kpa,toe_deg,hours\nVAN-1,50,3000,210,0.2,10\nVAN-2,100,4500,250,0.35,10\nCAR 3,130,3800,230,0.25,20\n",
    )
    .unwrap();
    let study =
        Study::parse_at(&std::fs::read_to_string(&s).unwrap(), Params::default(), &d).unwrap();
    let op = study.operating_points.as_ref().unwrap();
    assert_eq!(op.weights, [500.0, 1000.0, 2600.0]);
    assert_eq!(op.weight_computed.as_deref(), Some("hours * speed_kmh"));
    assert!((op.probability(2) - 2600.0 / 4100.0).abs() < 1e-12);
    // explore says so before any work, records the weight and carries the ids.
    let out = d.join("run");
    let (code, _, stderr) =
        polywear(&["explore", &s, "--no-report", "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    let note = stderr.find("weight: ").expect(&stderr);
    assert!(
        stderr[note..].starts_with("weight: ")
            && stderr.contains("has no `km` column; each row's km = hours * speed_kmh"),
        "{stderr}"
    );
    assert!(
        note < stderr.find("samples (").unwrap(),
        "said before the work: {stderr}"
    );
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("_manifest.json")).unwrap())
            .unwrap();
    let rec = &manifest["operating_points"];
    assert_eq!(rec["weight"], "km");
    assert_eq!(rec["weight_kind"], "distance");
    assert_eq!(rec["weight_computed"], "hours * speed_kmh");
    assert_eq!(rec["pass_through"], serde_json::json!(["vehicle_id"]));
    let rows = crate::parquet_rows::rows(&out.join("chunk-0000000.parquet"));
    let ids = ["VAN-1", "VAN-2", "CAR 3"];
    for r in &rows {
        let row: usize = r["operating_point_row"].to_string().parse().unwrap();
        assert_eq!(r["vehicle_id"].to_string(), format!("\"{}\"", ids[row - 1]));
    }
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn weight_and_pass_through_refusals_name_the_key_and_what_is_accepted() {
    let d = dir("weightbad");
    let cases: &[(&str, &[&str])] = &[
        (
            "weight = \"load_n\"\npass_through = [\"vehicle_id\", \"hours\", \"km\"]",
            &["`operating_points.weight` = \"load_n\" names a parameter", "name a column of hours or km"],
        ),
        (
            "weight = \"hours\"\npass_through = [\"vehicle_id\"]",
            &["column `km` (column 7) is not a parameter of `polywear params` nor the weight column `hours`", "named in `operating_points.pass_through`"],
        ),
        (
            "weight = \"hours\"\npass_through = [\"vehicle_idd\", \"km\"]",
            &["`operating_points.pass_through`", "no column `vehicle_idd`; did you mean `vehicle_id`?"],
        ),
        (
            "weight = \"hours\"\npass_through = [\"vehicle_id\", \"km\", \"toe_deg\"]",
            &["`toe_deg` is a parameter of `polywear params`"],
        ),
        (
            "weight = \"hours\"\npass_through = [\"vehicle_id\", \"km\", \"km\"]",
            &["`km` is named twice"],
        ),
        (
            "weight = \"hour\"\npass_through = [\"vehicle_id\", \"km\"]",
            &["no column `hour`, which `operating_points.weight` names; did you mean `hours`?"],
        ),
    ];
    let out = d.join("out");
    for (op, needles) in cases {
        let s = fleet(&d, op);
        refused(
            &["explore", &s, "--out", out.to_str().unwrap()],
            needles,
            Some(&out),
        );
    }
    // km without a km column needs the rows' speeds.
    let s = fleet(&d, "weight = \"km\"\npass_through = [\"vehicle_id\"]");
    std::fs::write(
        d.join("fleet.csv"),
        "vehicle_id,load_n,hours\nA,3000,1\nB,4000,2\n",
    )
    .unwrap();
    refused(
        &["explore", &s, "--out", out.to_str().unwrap()],
        &[
            "no column `km`",
            "only where the file gives each row's speed (a `speed_kmh` column)",
        ],
        Some(&out),
    );
    // A passed-through column may not take an output column's name.
    let s = fleet(&d, "weight = \"hours\"\npass_through = [\"class\", \"km\"]");
    std::fs::write(
        d.join("fleet.csv"),
        "class,speed_kmh,load_n,hours,km\nvan,50,3000,10,500\ncar,100,4000,10,1000\n",
    )
    .unwrap();
    refused(
        &["explore", &s, "--out", out.to_str().unwrap()],
        &[
            "column `class`",
            "is also an output column of polywear; rename it in the file",
        ],
        Some(&out),
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn classify_takes_the_fleet_file_and_carries_its_weight_and_columns() {
    let d = dir("classifyfleet");
    fleet(&d, "");
    let pts = d.join("fleet.csv");
    let p = pts.to_str().unwrap();
    let out = d.join("c.parquet");
    let o = out.to_str().unwrap();
    // Without --weight the extra columns are refused, saying how to name them.
    refused(
        &["classify", p, "--out", o],
        &["column `vehicle_id` (column 1)", "a weight column is named in --weight, a column carried into the output unchanged in --pass-through"],
        Some(&out),
    );
    let (code, _, stderr) = polywear(&[
        "classify",
        p,
        "--weight",
        "km",
        "--pass-through",
        "vehicle_id,hours",
        "--out",
        o,
    ]);
    assert_eq!(code, 0, "{stderr}");
    let rows = crate::parquet_rows::rows(&out);
    assert_eq!(rows.len(), 6);
    let want = [
        ("\"VAN-1\"", 500.0, 10.0, 3000.0),
        ("\"VAN-2\"", 1000.0, 10.0, 4500.0),
        ("\"CAR 3\"", 2600.0, 20.0, 3800.0),
    ];
    for (k, r) in rows.iter().enumerate() {
        let (id, km, hours, load) = want[k / 2];
        assert_eq!(r["vehicle_id"].to_string(), id);
        assert_eq!(r["km"].to_string().parse::<f64>().unwrap(), km);
        assert_eq!(r["hours"].to_string().parse::<f64>().unwrap(), hours);
        assert_eq!(r["load_n"].to_string().parse::<f64>().unwrap(), load);
    }
    let get = |k: &str| crate::parquet_rows::footer_value(&out, k);
    assert_eq!(get("weight").as_deref(), Some("km"));
    assert_eq!(get("weight_kind").as_deref(), Some("distance"));
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_fleet_in_a_cycle_gives_each_structure_sample_one_rows_load_pressure_and_toe() {
    let d = dir("cyclefleet");
    let s = fleet(
        &d,
        "weight = \"hours\"\npass_through = [\"vehicle_id\", \"km\"]",
    );
    let c = write(&d, "c.csv", "time_s,speed_kmh\n0,0\n1,60\n2,90\n3,120\n");
    let out = d.join("out");
    let k = 12;
    let (code, stdout, stderr) = polywear(&[
        "cycle",
        &c,
        "--study",
        &s,
        "--structure-samples",
        &k.to_string(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    // Said first, before the results.
    let first = stdout.lines().next().unwrap();
    assert!(
        first.starts_with("fleet: each of the 12 structure samples drives the cycle with one row of")
            && first.contains("drawn by its `hours` (load_n, pressure_kpa, toe_deg from the row; its `speed_kmh` column is not used: the cycle gives the speed)"),
        "{stdout}"
    );
    // Each sample's rows carry the drawn row's values; the speed is the cycle's.
    let study =
        Study::parse_at(&std::fs::read_to_string(&s).unwrap(), Params::default(), &d).unwrap();
    let op = study.operating_points.as_ref().unwrap();
    let sampler = study.sampler(study.seed, k);
    let rows = crate::parquet_rows::rows(&out.join("cycle.parquet"));
    assert_eq!(rows.len(), 12 * 4 * 2);
    let num = |r: &std::collections::HashMap<String, parquet::record::Field>, c: &str| -> f64 {
        r[c].to_string().parse().unwrap()
    };
    let mut drawn = std::collections::BTreeSet::new();
    for r in &rows {
        let sample = num(r, "sample_id") as u64;
        let (_, _, row) = sampler.sample_with_row(sample);
        let row = row.unwrap();
        drawn.insert(row);
        assert_eq!(num(r, "operating_point_row") as usize, row + 1);
        for (j, name) in op.names.iter().enumerate() {
            if *name != "speed_kmh" {
                assert_eq!(num(r, name), op.values[row][j], "{name}");
            }
        }
        let step = num(r, "step") as usize;
        assert_eq!(num(r, "speed_kmh"), [0.0, 60.0, 90.0, 120.0][step]);
        assert!(r["vehicle_id"]
            .to_string()
            .contains(["VAN-1", "VAN-2", "CAR 3"][row]));
    }
    assert!(
        drawn.len() > 1,
        "the samples drew different rows: {drawn:?}"
    );
    // A study without a fleet says which of its distributions the cycle does not use.
    let (code, stdout, stderr) = polywear(&[
        "cycle",
        &c,
        "--study",
        shipped("studies/default.toml").to_str().unwrap(),
        "--structure-samples",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.lines().next().unwrap().contains("its distributions of speed_kmh, toe_deg, load_n, pressure_kpa are not used: the cycle gives the speed, and toe_deg = 0.3, load_n = 4000, pressure_kpa = 240 hold for the whole cycle"),
        "{stdout}"
    );
    std::fs::remove_dir_all(&d).ok();
}
