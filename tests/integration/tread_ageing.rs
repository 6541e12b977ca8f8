//! The tread's usable depth and its ageing law (MODEL.md#the-long-term-loop): the new tyre's
//! usable groove depth may not exceed the tread height, the worn-out depth must stay below it,
//! and every command refuses a value that breaks either rule (or its own range) before any
//! work, exit 2, naming the parameter and its accepted range; a study refuses such a value
//! fixed, given by `--params`, or reachable by its draws.

use crate::common::{fresh_dir, polywear};

/// Exit 2 with every needle in stderr and nothing written to `out` (if given).
fn refused(args: &[&str], needles: &[&str], out: Option<&std::path::Path>) {
    let (code, stdout, stderr) = polywear(args);
    assert_eq!(code, 2, "{args:?}: exit {code}: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "{args:?}: stderr lacks `{n}`: {stderr}");
    }
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    assert!(
        stdout.trim().is_empty(),
        "{args:?} printed results: {stdout}"
    );
    if let Some(out) = out {
        assert!(
            !out.exists(),
            "{args:?}: wrote {} before refusing",
            out.display()
        );
    }
}

/// The three rules, as `--set` gives them, and what the refusal must name.
const BAD_SETS: [(&str, &[&str]); 5] = [
    (
        "tread_depth_new_mm=16",
        &[
            "`tread_depth_new_mm` = 16 mm",
            "(0, 15] mm",
            "`tread_height` = 0.015 m",
        ],
    ),
    (
        "tread_depth_new_mm=0",
        &["tread_depth_new_mm", "(0, 200] mm"],
    ),
    (
        "tread_depth_worn_out_mm=8",
        &[
            "`tread_depth_worn_out_mm` = 8 mm",
            "[0, 8) mm",
            "`tread_depth_new_mm` = 8 mm",
        ],
    ),
    (
        "tread_depth_worn_out_mm=-1",
        &["tread_depth_worn_out_mm", "[0, 200] mm"],
    ),
    ("carcass_share=1.2", &["carcass_share", "[0, 1]"]),
];

#[test]
fn every_command_with_set_refuses_a_bad_tread_depth_before_any_work() {
    let dir = fresh_dir("tread-depth-set");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    for (set, needles) in BAD_SETS {
        let commands: [Vec<&str>; 5] = [
            vec!["simulate", "--set", set],
            vec!["wear", "--quiet", "--set", set, "--out", o],
            vec!["cycle", "data/cycles/hwfet.csv", "--set", set, "--out", o],
            vec![
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
                set,
                "--out",
            ],
            vec![
                "bifurcation",
                "--param",
                "speed_kmh",
                "--from",
                "60",
                "--to",
                "200",
                "--set",
                set,
                "--out",
                o,
            ],
        ];
        for mut args in commands {
            if args[0] == "chart" {
                args.push(o);
            }
            refused(&args, needles, Some(&out));
        }
    }
    // A tread height that leaves less than the usable depth is refused by the same rule.
    refused(
        &["simulate", "--set", "tread_height=0.007"],
        &[
            "`tread_depth_new_mm` = 8 mm",
            "(0, 7] mm",
            "`tread_height` = 0.007 m",
        ],
        None,
    );
    // At the bounds the rules hold: the usable depth may be the whole tread.
    let (code, _, err) = polywear(&[
        "simulate",
        "--set",
        "tread_height=0.008",
        "--set",
        "tread_depth_worn_out_mm=0",
    ]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn a_study_refuses_a_bad_tread_depth_fixed_in_a_parameter_file_or_reachable_by_its_draws() {
    let dir = fresh_dir("tread-depth-study");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let study = |name: &str, params: &str| {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(
            &path,
            format!(
                "name = \"{name}\"\nseed = 3\nsamples = 32\nchunk_size = 16\n[params]\nspeed_kmh = {{ dist = \"uniform\", min = 60, max = 200 }}\n{params}\n"
            ),
        )
        .unwrap();
        path
    };
    let fixed = study("fixed", "tread_depth_new_mm = 20");
    refused(
        &["explore", "--quiet", fixed.to_str().unwrap(), "--out", o],
        &["tread_depth_new_mm", "(0, 15] mm"],
        Some(&out),
    );
    let worn_out = study("worn_out", "tread_depth_worn_out_mm = 9");
    refused(
        &["explore", "--quiet", worn_out.to_str().unwrap(), "--out", o],
        &["tread_depth_worn_out_mm", "[0, 8) mm"],
        Some(&out),
    );
    let drawn = study(
        "drawn",
        "tread_height = { dist = \"uniform\", min = 0.006, max = 0.016 }",
    );
    refused(
        &["explore", "--quiet", drawn.to_str().unwrap(), "--out", o],
        &[
            "`tread_depth_new_mm` is fixed at 8",
            "`params.tread_height` is drawn down to 0.006",
            "the usable groove depth is part of the tread",
        ],
        Some(&out),
    );
    let drawn_depth = study(
        "drawn_depth",
        "tread_depth_new_mm = { dist = \"uniform\", min = 1.0, max = 9.0 }",
    );
    refused(
        &[
            "explore",
            "--quiet",
            drawn_depth.to_str().unwrap(),
            "--out",
            o,
        ],
        &[
            "`tread_depth_worn_out_mm` is fixed at 1.6",
            "`params.tread_depth_new_mm` is drawn down to 1",
            "stays below tread_depth_new_mm",
        ],
        Some(&out),
    );
    let ok = study("ok", "");
    let file = dir.join("p.toml");
    std::fs::write(&file, "[params]\ntread_depth_worn_out_mm = 8.5\n").unwrap();
    refused(
        &[
            "explore",
            "--quiet",
            ok.to_str().unwrap(),
            "--params",
            file.to_str().unwrap(),
            "--out",
            o,
        ],
        &["tread_depth_worn_out_mm", "[0, 8) mm"],
        Some(&out),
    );
    // The shipped wide-structure study draws the tread height down to the usable depth, no
    // lower: it is accepted.
    let wide = std::fs::read_to_string("studies/wide_structure.toml").unwrap();
    assert!(polywear::study::Study::parse(&wide).is_ok());
}

/// A tread whose usable depth is all of it (15 mm of a 15 mm tread, worn out at 0 mm) is
/// accepted and handled: its frequency is unbounded at the end (no mass left), and the walk over
/// the tread's life once laid out every order ν passes (an allocation of 206 GB, exit 134, in
/// `wear`, `explore` and `cycle` alike). Each command now answers.
#[test]
fn a_tread_worn_to_nothing_is_answered_by_every_command() {
    let dir = fresh_dir("worn-to-nothing");
    std::fs::create_dir_all(&dir).unwrap();
    let sets = [
        "--set",
        "tread_depth_new_mm=15",
        "--set",
        "tread_depth_worn_out_mm=0",
    ];
    let out = dir.join("wear");
    let mut args = vec!["wear", "--distance-km", "100", "--estimate"];
    args.extend(sets);
    args.extend(["--calibration-band", "off", "--out", out.to_str().unwrap()]);
    let (code, stdout, stderr) = polywear(&args);
    assert_eq!(code, 0, "{stderr}");
    // Each wheel's one wear answer is given in words: no order is called "NaN" (where every
    // order stays below its seed, none is named).
    assert!(
        stdout.lines().filter(|l| l.contains(": estimate ")).count() == 2
            && stdout.contains("worn out at")
            && !stdout.contains("NaN"),
        "{stdout}"
    );
    let study = dir.join("study.toml");
    std::fs::write(
        &study,
        "name = \"worn_to_nothing\"\nsamples = 6\n[params]\nspeed_kmh = { dist = \"uniform\", min = 90, max = 140 }\ntoe_deg = { dist = \"uniform\", min = 0.3, max = 0.7 }\ntread_depth_new_mm = 15\ntread_depth_worn_out_mm = 0\n",
    )
    .unwrap();
    let run = dir.join("run");
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        study.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let cycle = dir.join("cycle.csv");
    std::fs::write(&cycle, "time_s,speed_kmh\n0,100\n60,120\n120,110\n").unwrap();
    let mut args = vec!["cycle", cycle.to_str().unwrap()];
    args.extend(sets);
    let cyc_out = dir.join("cycle_out");
    args.extend(["--quiet", "--out", cyc_out.to_str().unwrap()]);
    let (code, stdout, stderr) = polywear(&args);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("worn out at"), "{stdout}");
}
