//! A drive cycle's lifetime verdict reads every wear column it accepts
//! (MODEL.md#along-a-drive-cycle): a column of a constant of the tire's life gives the whole
//! life that value, as `--set` does, and one that changes from step to step is refused; the
//! cycle's file holds each name once; `wear --cycle --estimate` answers on the cycle's speeds,
//! not at the default point.

use std::path::{Path, PathBuf};

use crate::common::{fresh_dir, polywear};

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// A cycle file in `dir`: steps of 60 s at `speeds` [km/h] (the last held as long), with an
/// extra column `(name, value per step)` where given.
fn cycle(
    dir: &Path,
    file: &str,
    speeds: &[f64],
    extra: Option<(&str, &dyn Fn(usize) -> f64)>,
) -> PathBuf {
    let mut text = String::from("time_s,speed_kmh");
    if let Some((name, _)) = extra {
        text.push_str(&format!(",{name}"));
    }
    text.push('\n');
    for (i, v) in speeds.iter().enumerate() {
        text.push_str(&format!("{},{v}", 60 * i));
        if let Some((_, value)) = extra {
            text.push_str(&format!(",{}", value(i)));
        }
        text.push('\n');
    }
    let path = dir.join(file);
    std::fs::write(&path, text).unwrap();
    path
}

/// The lifetime verdict's lines of `polywear cycle` (the lines after each wheel's).
fn verdicts(args: &[&str]) -> Vec<String> {
    let (code, stdout, stderr) = polywear(args);
    assert_eq!(code, 0, "{args:?}: {stderr}");
    stdout
        .lines()
        .filter(|l| l.contains("driving this cycle all its life"))
        .map(|l| {
            l.split(" (calibration band")
                .next()
                .unwrap()
                .trim()
                .to_string()
        })
        .collect()
}

const SPEEDS: [f64; 6] = [95.0, 100.0, 104.0, 108.0, 103.0, 98.0];

/// A column `wear_share_straight = 1` at every step was used in each step's row, while the
/// lifetime verdict kept the default φ_s ("no polygon before the tire is worn out", where
/// `--set wear_share_straight=1` gives a polygon): the column and the flag now give the same
/// verdict, and so do `visible_depth_mm` and `wear_rate_driven_factor`.
#[test]
fn a_constant_wear_column_is_the_whole_life_s_as_set_makes_it() {
    let dir = fresh_dir("cycle-life-column");
    std::fs::create_dir_all(&dir).unwrap();
    for (name, value) in [
        ("wear_share_straight", 1.0),
        ("visible_depth_mm", 0.05),
        ("wear_rate_driven_factor", 1.1),
    ] {
        let by_column = cycle(
            &dir,
            &format!("{name}.csv"),
            &SPEEDS,
            Some((name, &|_| value)),
        );
        let plain_cycle = cycle(&dir, "plain.csv", &SPEEDS, None);
        let set = format!("{name}={value}");
        let out = |tag: &str| s(&dir.join(format!("{name}-{tag}")));
        let column = verdicts(&[
            "cycle",
            &s(&by_column),
            "--set",
            "toe_deg=0.3",
            "--calibration-band",
            "off",
            "--quiet",
            "--out",
            &out("column"),
        ]);
        let flag = verdicts(&[
            "cycle",
            &s(&plain_cycle),
            "--set",
            "toe_deg=0.3",
            "--set",
            &set,
            "--calibration-band",
            "off",
            "--quiet",
            "--out",
            &out("flag"),
        ]);
        let default = verdicts(&[
            "cycle",
            &s(&plain_cycle),
            "--set",
            "toe_deg=0.3",
            "--calibration-band",
            "off",
            "--quiet",
            "--out",
            &out("default"),
        ]);
        assert_eq!(column, flag, "{name}");
        assert_ne!(column, default, "{name}: the value moves the verdict");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A constant of the tire's life cannot change from step to step (the steps share one tread):
/// a column that does is refused before any work, naming the row and column; the speed spread,
/// which a cycle does not use (its speeds are its spread), is refused as a column and as `--set`.
#[test]
fn a_life_constant_that_changes_by_step_and_the_unused_spread_are_refused() {
    let dir = fresh_dir("cycle-life-varying");
    std::fs::create_dir_all(&dir).unwrap();
    let varying = cycle(
        &dir,
        "varying.csv",
        &SPEEDS,
        Some(("wear_share_straight", &|i| if i < 3 { 0.12 } else { 0.5 })),
    );
    let out = dir.join("out");
    let (code, _, stderr) = polywear(&["cycle", &s(&varying), "--out", &s(&out)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("row 4")
            && stderr.contains("`wear_share_straight` = 0.5 differs from the first step's 0.12")
            && stderr.contains("constant of the tire's whole life"),
        "{stderr}"
    );
    let spread = cycle(
        &dir,
        "spread.csv",
        &SPEEDS,
        Some(("speed_spread_kmh", &|_| 5.0)),
    );
    let (code, _, stderr) = polywear(&["cycle", &s(&spread), "--out", &s(&out)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("column `speed_spread_kmh`") && stderr.contains("speeds are its spread"),
        "{stderr}"
    );
    let plain_cycle = cycle(&dir, "plain.csv", &SPEEDS, None);
    let (code, _, stderr) = polywear(&[
        "cycle",
        &s(&plain_cycle),
        "--set",
        "speed_spread_kmh=50",
        "--out",
        &s(&out),
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("--set speed_spread_kmh") && stderr.contains("speeds are its spread"),
        "{stderr}"
    );
    assert!(!out.exists(), "wrote {} before refusing", out.display());
    std::fs::remove_dir_all(&dir).ok();
}

/// `cycle.parquet` wrote a wear column twice (the cycle's `wear_share_straight` and the wear
/// stage's column of that name), and pyarrow's dataset reader failed with "Multiple matches".
#[test]
fn a_cycle_s_file_holds_each_name_once() {
    let dir = fresh_dir("cycle-one-name");
    std::fs::create_dir_all(&dir).unwrap();
    let by_column = cycle(
        &dir,
        "phi.csv",
        &SPEEDS,
        Some(("wear_share_straight", &|_| 0.3)),
    );
    let out = dir.join("out");
    let (code, _, stderr) = polywear(&["cycle", &s(&by_column), "--quiet", "--out", &s(&out)]);
    assert_eq!(code, 0, "{stderr}");
    use parquet::file::reader::{FileReader, SerializedFileReader};
    let file = std::fs::File::open(out.join("cycle.parquet")).unwrap();
    let reader = SerializedFileReader::new(file).unwrap();
    let schema = reader.metadata().file_metadata().schema_descr();
    let mut names: Vec<String> = schema
        .columns()
        .iter()
        .map(|c| c.name().to_string())
        .collect();
    let n = names.len();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), n, "a name twice among {names:?}");
    assert!(names.iter().any(|c| c == "wear_share_straight"));
    std::fs::remove_dir_all(&dir).ok();
}

/// `wear --cycle --estimate` printed its estimate lines at the default point (100 km/h): a
/// constant 60 km/h cycle and a constant 150 km/h one printed the same 19-gon. The estimates
/// are now the cycle's speeds'.
#[test]
fn the_loop_s_estimates_on_a_cycle_are_the_cycle_s() {
    let dir = fresh_dir("wear-cycle-estimate");
    std::fs::create_dir_all(&dir).unwrap();
    let lines = |speed: f64| -> Vec<String> {
        let c = cycle(&dir, &format!("c{speed}.csv"), &[speed; 4], None);
        let (code, stdout, stderr) = polywear(&[
            "wear",
            "--cycle",
            &s(&c),
            "--estimate",
            "--distance-km",
            "100",
            "--calibration-band",
            "off",
            "--out",
            &s(&dir.join(format!("w{speed}"))),
        ]);
        assert_eq!(code, 0, "{stderr}");
        assert!(!stdout.contains("new tire"), "{stdout}");
        stdout
            .lines()
            .filter(|l| l.contains(": estimate "))
            .map(str::to_string)
            .collect()
    };
    let (slow, fast) = (lines(60.0), lines(150.0));
    // One wear answer per wheel.
    assert_eq!(slow.len(), 2, "{slow:?}");
    assert!(
        slow.iter().all(|l| l.contains("on the cycle's")),
        "{slow:?}"
    );
    assert_ne!(slow, fast);
    std::fs::remove_dir_all(&dir).ok();
}
