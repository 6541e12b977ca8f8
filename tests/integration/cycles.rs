//! Drive cycles: the shipped standard cycles against their published duration, distance and top
//! speed; `polywear cycle` classifying every step as `polywear classify` does point by point,
//! standstill reported as such, the summary's shares recomputed from the rows, bad input refused
//! (exit 2, file, row and column), the same rows whatever the threads, and the distribution over
//! tire structures.

use crate::{common, parquet_rows};
use std::path::{Path, PathBuf};

use crate::common::polywear;
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::record::Field;
use polywear_study::cycle::DriveCycle;

fn dir(name: &str) -> PathBuf {
    let d = common::fresh_dir(&format!("cycle-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/cycles")
        .join(name)
}

/// (duration s, distance km, top speed km/h) of a cycle file: the distance is Σ v·Δt with each
/// step held until the next (every shipped cycle ends at standstill, so this is also the
/// trapezoidal distance).
fn measures(c: &DriveCycle) -> (f64, f64, f64) {
    let dt = c.step_durations_s();
    let km: f64 = (0..c.len()).map(|i| c.speed_kmh[i] * dt[i] / 3600.0).sum();
    let top = c.speed_kmh.iter().copied().fold(0.0, f64::max);
    (c.time_s[c.len() - 1] - c.time_s[0], km, top)
}

#[test]
fn standard_cycles_match_their_published_duration_distance_and_top_speed() {
    const MI: f64 = 1.609_344;
    // (file, duration s, distance km, top speed km/h, distance tolerance km), published:
    // EPA (40 CFR 86 App. I, 40 CFR 600): HWFET 765 s, 10.26 mi, 59.9 mph; US06 600 s schedule
    // (596 s of driving), 8.01 mi, 80.3 mph; UDDS 1369 s, 7.45 mi, 56.7 mph. UN GTR No. 15
    // Annex 1: WLTC class 3b 1800 s, 23,266 m, 131.3 km/h.
    let published = [
        ("hwfet.csv", 765.0, 10.26 * MI, 59.9 * MI, 0.01 * MI),
        ("us06.csv", 600.0, 8.01 * MI, 80.3 * MI, 0.01 * MI),
        ("udds.csv", 1369.0, 7.45 * MI, 56.7 * MI, 0.01 * MI),
        ("wltc_class3b.csv", 1800.0, 23.266, 131.3, 0.005),
    ];
    for (file, duration, km, top, tol) in published {
        let c = DriveCycle::read(&shipped(file)).unwrap();
        let (d, k, t) = measures(&c);
        assert_eq!(d, duration, "{file} duration");
        assert!((k - km).abs() <= tol, "{file}: {k} km, published {km}");
        assert!(
            (t - top).abs() < 0.06,
            "{file}: top {t} km/h, published {top}"
        );
        assert!(
            c.standstill(0) && c.standstill(c.len() - 1),
            "{file} starts and ends at rest"
        );
        assert!(c.names.is_empty(), "{file}: time_s and speed_kmh only");
    }
}

/// Every row of a Parquet file as (column name → field).
fn rows(path: &Path) -> Vec<Vec<(String, Field)>> {
    let r = SerializedFileReader::new(std::fs::File::open(path).unwrap()).unwrap();
    r.get_row_iter(None)
        .unwrap()
        .map(|row| {
            row.unwrap()
                .get_column_iter()
                .map(|(n, f)| (n.clone(), f.clone()))
                .collect()
        })
        .collect()
}

fn get<'a>(row: &'a [(String, Field)], name: &str) -> &'a Field {
    &row.iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no {name}"))
        .1
}

fn text(f: &Field) -> String {
    match f {
        Field::Str(s) => s.clone(),
        other => other.to_string(),
    }
}

fn num(f: &Field) -> f64 {
    match f {
        Field::Double(x) => *x,
        Field::Long(x) => *x as f64,
        other => panic!("not a number: {other}"),
    }
}

/// A short cycle through the follower's Hopf window (~93 km/h at the defaults), with
/// standstill at both ends and in the middle, and a per-step toe-in column.
const SHORT: &str = "time_s,speed_kmh,toe_deg\n\
                     0,0,0.3\n1,20,0.3\n2,60,0.3\n3,90,0.3\n4,100,0.3\n5,110,0.3\n6,130,0.3\n\
                     7,130,0.3\n8,130,0.1\n9,150,0.3\n10,0,0.3\n11,0,0.3\n12,95,0.3\n13,100,0.3\n";

#[test]
fn every_step_is_classified_as_classify_does_and_the_summary_follows_from_the_rows() {
    let d = dir("short");
    let c = d.join("short.csv");
    std::fs::write(&c, SHORT).unwrap();
    let out = d.join("out");
    let (code, stdout, err) =
        polywear(&["cycle", c.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("follower") && stdout.contains("driving"),
        "{stdout}"
    );
    for f in [
        "cycle.parquet",
        "cycle_summary.csv",
        "cycle_summary.parquet",
        "cycle.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let rows = rows(&out.join("cycle.parquet"));
    assert_eq!(rows.len(), 14 * 2);
    // The same points through `polywear classify` (moving steps only).
    let moving: Vec<usize> = (0..14).filter(|&i| ![0, 10, 11].contains(&i)).collect();
    let lines: Vec<&str> = SHORT.lines().skip(1).collect();
    let mut pts = String::from("speed_kmh,toe_deg\n");
    for &i in &moving {
        let cells: Vec<&str> = lines[i].split(',').collect();
        pts.push_str(&format!("{},{}\n", cells[1], cells[2]));
    }
    std::fs::write(d.join("points.csv"), pts).unwrap();
    let cls = d.join("classified.parquet");
    let (code, _, err) = polywear(&[
        "classify",
        d.join("points.csv").to_str().unwrap(),
        "--out",
        cls.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let reference = self::rows(&cls);
    let mut vibrating = [0usize; 2];
    for (i, pair) in rows.chunks(2).enumerate() {
        for (w, row) in pair.iter().enumerate() {
            assert_eq!(num(get(row, "step")) as usize, i);
            assert_eq!(num(get(row, "time_s")), i as f64);
            assert_eq!(text(get(row, "wheel")), ["follower", "driving"][w]);
            let class = text(get(row, "class"));
            if [0, 10, 11].contains(&i) {
                assert_eq!(class, "standstill", "step {i}");
                assert_eq!(num(get(row, "speed_kmh")), 0.0);
                continue;
            }
            let k = moving.iter().position(|&m| m == i).unwrap();
            let r = &reference[2 * k + w];
            assert_eq!(class, text(get(r, "class")), "step {i} wheel {w}");
            for q in ["eig_re_max", "toe_deg", "speed_kmh"] {
                assert_eq!(num(get(row, q)), num(get(r, q)), "step {i} {q}");
            }
            let (a, b) = (num(get(row, "polygon_order")), num(get(r, "polygon_order")));
            assert!(
                (a - b).abs() <= 1e-6 * b.abs().max(1.0),
                "step {i}: order {a} vs {b}"
            );
            if class == "limit_cycle" || class == "bistable" {
                vibrating[w] += 1;
            }
        }
    }
    assert!(
        vibrating[0] > 0,
        "the short cycle crosses the follower's window"
    );
    // The summary's shares: equal steps of 1 s, so shares of steps.
    let summary = std::fs::read_to_string(out.join("cycle_summary.csv")).unwrap();
    let header: Vec<&str> = summary.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for (w, line) in summary.lines().skip(1).enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells[col("wheel")], ["follower", "driving"][w]);
        assert_eq!(cells[col("statistic")], "value");
        let share: f64 = cells[col("time_share")].parse().unwrap();
        assert!((share - vibrating[w] as f64 / 14.0).abs() < 1e-12, "{line}");
        let still: f64 = cells[col("standstill_share")].parse().unwrap();
        assert!((still - 3.0 / 14.0).abs() < 1e-12);
    }
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn bad_cycles_exit_2_naming_file_row_and_column_before_any_work() {
    let d = dir("bad");
    let cases = [
        (
            "time_s,speed_kmh\n0,10\n1,NaN\n",
            "row 2 (line 3), column `speed_kmh`",
        ),
        (
            "time_s,speed_kmh\n0,10\n0,20\n",
            "row 2 (line 3), column `time_s`",
        ),
        (
            "time_s,speed_kmh\n0,10\n1,500\n",
            "row 2 (line 3), column `speed_kmh`",
        ),
        (
            "time_s,speed_kmh,pressure_kpa\n0,10,240\n1,20,0\n",
            "row 2 (line 3), column `pressure_kpa`",
        ),
        ("time_s,speed_kmh,gear\n0,10,1\n1,20,2\n", "column `gear`"),
        (
            "time_s,speed_kmh,toe_dg\n0,10,0.3\n1,20,0.3\n",
            "column `toe_dg` (column 3) is neither `time_s` nor a parameter of `polywear params`; did you mean `toe_deg`?",
        ),
        (
            "time_s,speed_kmh,mu_s\n0,10,0.6\n1,20,0.9\n",
            "row 2 (line 3)",
        ),
        ("", "empty file"),
    ];
    for (k, (body, needle)) in cases.iter().enumerate() {
        let c = d.join(format!("bad{k}.csv"));
        std::fs::write(&c, body).unwrap();
        let out = d.join(format!("out{k}"));
        let (code, _, err) =
            polywear(&["cycle", c.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        assert_eq!(code, 2, "{body}: {err}");
        assert!(
            err.contains(&format!("bad{k}.csv")) && err.contains(needle),
            "{body}: {err}"
        );
        assert!(!out.exists(), "work started for {body}");
    }
    let c = d.join("ok.csv");
    std::fs::write(&c, "time_s,speed_kmh\n0,10\n1,20\n").unwrap();
    let out = d.join("o");
    for (args, needle) in [
        (vec!["--set", "g_mod=-1"], "g_mod"),
        (vec!["--set", "speed_kmh=50"], "the cycle gives the speed"),
        (vec!["--structure-samples", "4"], "--study"),
        (vec!["--study", "x.toml"], "--structure-samples"),
    ] {
        let (code, _, err) = polywear(
            &[
                &["cycle", c.to_str().unwrap(), "--out", out.to_str().unwrap()],
                &args[..],
            ]
            .concat(),
        );
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    // The saturated level's speed bins over many structures would not fit: refused, naming
    // the flag and how many structures fit, before any work.
    let wltc = shipped("wltc_class3b.csv");
    let study = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/default.toml");
    let (code, _, err) = polywear(&[
        "cycle",
        wltc.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--study",
        study.to_str().unwrap(),
        "--structure-samples",
        "100",
        "--wear-estimate",
        "tread_life_saturated",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--structure-samples") && err.contains("at most 38 structures"),
        "{err}"
    );
    assert!(!out.exists(), "work started");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn same_rows_whatever_threads_and_shares_over_structures() {
    let d = dir("threads");
    let c = shipped("hwfet.csv");
    let (one, two) = (d.join("t1"), d.join("t2"));
    for (t, o) in [("1", &one), ("2", &two)] {
        let (code, stdout, err) = polywear(&[
            "cycle",
            c.to_str().unwrap(),
            "--threads",
            t,
            "--quiet",
            "--out",
            o.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        // Quiet hides the chatter, not the answer.
        assert!(
            stdout.contains("rear (follower): in vibration") && !stdout.contains("wrote"),
            "{stdout}"
        );
    }
    let a = parquet_rows::rows_in_dir(&[&one]);
    assert_eq!(
        a.len(),
        766 * 2 + 2,
        "cycle rows and the summary sidecar's 2 rows"
    );
    assert_eq!(a, parquet_rows::rows_in_dir(&[&two]));
    // Structure samples from the default study: mean and 90% interval per wheel.
    let study = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/default.toml");
    let s = d.join("structures");
    let (code, stdout, err) = polywear(&[
        "cycle",
        c.to_str().unwrap(),
        "--study",
        study.to_str().unwrap(),
        "--structure-samples",
        "8",
        "--out",
        s.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("90% interval"), "{stdout}");
    let summary = std::fs::read_to_string(s.join("cycle_summary.csv")).unwrap();
    let stats: Vec<String> = summary
        .lines()
        .skip(1)
        .map(|l| l.split(',').take(2).collect::<Vec<_>>().join(","))
        .collect();
    assert_eq!(
        stats,
        [
            "follower,mean",
            "follower,p05",
            "follower,p95",
            "driving,mean",
            "driving,p05",
            "driving,p95"
        ]
    );
    let rows = rows(&s.join("cycle.parquet"));
    assert_eq!(rows.len(), 8 * 766 * 2);
    let g: Vec<f64> = rows
        .iter()
        .step_by(766 * 2)
        .map(|r| num(get(r, "g_mod")))
        .collect();
    let mut distinct = g.clone();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    assert_eq!(distinct.len(), 8, "one structure per sample: {g:?}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_parquet_cycle_reads_as_its_csv() {
    use polywear_study::parquet_out::{write_table, Column};
    let d = dir("parquet");
    let csv = DriveCycle::read(&shipped("us06.csv")).unwrap();
    let cols = vec![
        Column::i64(
            "time_s",
            "s",
            csv.time_s.iter().map(|t| *t as i64).collect(),
        ),
        Column::f64("speed_kmh", "km/h", csv.speed_kmh.clone()),
    ];
    let p = d.join("us06.parquet");
    write_table(&p, &cols, &[]).unwrap();
    let pq = DriveCycle::read(&p).unwrap();
    assert_eq!((pq.time_s, pq.speed_kmh), (csv.time_s, csv.speed_kmh));
    std::fs::remove_dir_all(&d).ok();
}
