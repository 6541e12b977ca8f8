//! `polywear analyze` on the wear stage's columns: the probabilities and the paired table equal
//! a hand count of a constructed run (distances set by pyarrow, some NaN), unknown wheels are
//! left out of numerator and denominator, McNemar's exact p on the constructed discordant
//! pairs, the report leads with the wear answer, a run without wear keeps the vibration report
//! with one line, and `--within-km` refuses what it cannot use.

use std::path::Path;

use crate::common::{self, explore_default, polywear, python, python_has};

/// Rewrites the chunks of `run` into `out` with distances set per sample: the follower at
/// 1,000 km where `sample_id % 5 == 0`, the driving wheel where `% 11 == 0`, +inf elsewhere,
/// and NaN on the follower where `% 13 == 0`, with a `wear_reason` as the wear stage writes
/// one (its metadata kept); the driving wheel's tire is worn out at 500 km where `% 22 == 0`,
/// before its polygon, which then does not count.
fn constructed(run: &Path, out: &Path) {
    python(
        r#"
import sys, glob, os, numpy as np, pyarrow as pa, pyarrow.parquet as pq
run, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
for f in sorted(glob.glob(run + "/chunk-*.parquet")):
    t = pq.read_table(f)
    md = dict(t.schema.metadata)
    s = t.column("sample_id").to_numpy()
    fol = np.array([w == "follower" for w in t.column("wheel").to_pylist()])
    d = np.where(fol, np.where(s % 5 == 0, 1000.0, np.inf), np.where(s % 11 == 0, 1000.0, np.inf))
    d = np.where(fol & (s % 13 == 0), np.nan, d)
    i = t.schema.get_field_index("distance_to_visible_km")
    t = t.set_column(i, "distance_to_visible_km", pa.array(d, pa.float64()))
    r = t.column("wear_reason").to_pylist()
    r = [x if not (f and k % 13 == 0) else (x or "constructed: no distance") for x, f, k in zip(r, fol, s)]
    j = t.schema.get_field_index("wear_reason")
    t = t.set_column(j, "wear_reason", pa.array(r, pa.string()))
    k = t.schema.get_field_index("tread_life_km")
    life = t.column("tread_life_km").to_numpy()
    t = t.set_column(k, "tread_life_km", pa.array(np.where(~fol & (s % 22 == 0), 500.0, life), pa.float64()))
    t = t.replace_schema_metadata(md)
    pq.write_table(t, os.path.join(out, os.path.basename(f)))
print("ok")
"#,
        &[run.to_str().unwrap(), out.to_str().unwrap()],
    );
}

/// The first `## ` heading of a page.
fn first_section(page: &str) -> &str {
    page.lines().find(|l| l.starts_with("## ")).unwrap_or("")
}

#[test]
fn wear_counts_intervals_and_mcnemar_are_the_hand_count_with_unknown_wheels_left_out() {
    if !python_has(&["pandas", "pyarrow", "numpy"]) {
        return;
    }
    let dir = common::fresh_dir("wear-analysis-counts");
    let run = dir.join("run");
    explore_default("300", &run);
    let edited = dir.join("edited");
    constructed(&run, &edited);
    let (code, stdout, stderr) = polywear(&[
        "analyze",
        edited.to_str().unwrap(),
        "--within-km",
        "500,1000",
    ]);
    assert_eq!(code, 0, "{stderr}");
    // Samples 0..300: the follower is unknown on ⌈300/13⌉ = 24 of them (0, 13, ..., 299).
    let ids = 0..300u64;
    let unknown_f = ids.clone().filter(|s| s % 13 == 0).count() as u64;
    let known_f = 300 - unknown_f;
    let within_f = ids.clone().filter(|s| s % 5 == 0 && s % 13 != 0).count() as u64;
    // The driving wheel's polygons on the tires worn out at 500 km do not count.
    let within_d = ids.clone().filter(|s| s % 11 == 0 && s % 22 != 0).count() as u64;
    assert_eq!((unknown_f, within_f, within_d), (24, 55, 14));
    assert!(
        stdout.contains(&format!("({within_d} of 300 with a distance; 0 unknown)")),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!(
            "({within_f} of {known_f} with a distance; {unknown_f} unknown)"
        )),
        "{stdout}"
    );
    // The tables against the same count by pandas, and Wilson's formula written out here.
    let script = r#"
import sys, math, pandas as pd
rep = sys.argv[1] + "/_report/"
occ = pd.read_csv(rep + "wear_occurrence.csv").set_index(["wheel", "within_km"])
rows = pd.read_parquet(sys.argv[1])
z = 1.959963984540054
for wheel, g in rows.groupby("wheel"):
    d = g["distance_to_visible_km"]
    life = g["tread_life_km"]
    known = d.notna().sum()
    for km in [500.0, 1000.0, 40000.0]:
        k = ((d <= km) & (d <= life)).sum()
        o = occ.loc[(wheel, km)]
        assert (o.samples, o.within, o.unknown) == (known, k, d.isna().sum()), (wheel, km, o)
        p = k / known
        c = (p + z*z/(2*known)) / (1 + z*z/known)
        h = z / (1 + z*z/known) * math.sqrt(p*(1-p)/known + z*z/(4*known*known))
        assert abs(o.p - p) < 1e-12 and abs(o.wilson95_lo - max(c - h, 0)) < 1e-12 and abs(o.wilson95_hi - min(c + h, 1)) < 1e-12, (wheel, km, o)
d = rows["distance_to_visible_km"]
rows["visible_km"] = d.where((d <= rows["tread_life_km"]) | d.isna(), math.inf)
w = rows.pivot(index="sample_id", columns="wheel", values="visible_km")
w = w[w["follower"].notna() & w["driving"].notna()]
f, dr = w["follower"] <= 1000, w["driving"] <= 1000
b, c = int((f & ~dr).sum()), int((~f & dr).sum())
p = min(1.0, 2 * sum(math.comb(b + c, i) for i in range(min(b, c) + 1)) / 2 ** (b + c))
pr = pd.read_csv(rep + "wear_paired.csv").set_index("within_km").loc[1000.0]
assert (pr.pairs, pr.only_follower, pr.only_driving, pr.both, pr.unclassified_pairs) == (len(w), b, c, int((f & dr).sum()), 300 - len(w)), pr
assert pr.method == "exact" and abs(pr.p_value - p) < 1e-12 * max(p, 1e-300), (pr.p_value, p)
print("agree", b, c)
"#;
    let out = python(script, &[edited.to_str().unwrap()]);
    // Follower only: %5, not %13, the driving wheel's not counted (not %11, or %22: 52);
    // driving only: %11, not %22, not %5, not %13 (10).
    assert!(out.contains("agree 52 10"), "{out}");
    let page = std::fs::read_to_string(edited.join("_report/report.md")).unwrap();
    assert_eq!(first_section(&page), "## The answer: polygonal wear");
    assert!(
        page.contains("cruising at its sample's operating point"),
        "{page}"
    );
    assert!(
        page.contains("Constants are calibrated, not measured"),
        "{page}"
    );
    // It says that a polygon counts only before the tire is worn out, and that the distances'
    // quantiles are the point's own.
    assert!(
        page.contains("**before the tire is worn out**")
            && page.contains("as if the tread never ran out"),
        "{page}"
    );
    assert!(page.contains("24 wheels have no distance"), "{page}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_run_without_wear_keeps_the_vibration_report_with_one_line() {
    let dir = common::fresh_dir("wear-analysis-none");
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        "--no-wear",
        "--samples",
        "60",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, stderr) = polywear(&["analyze", dir.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("wear stage was left out"), "{stdout}");
    let page = std::fs::read_to_string(dir.join("_report/report.md")).unwrap();
    assert_eq!(
        first_section(&page),
        "## How likely is self-excited vibration?"
    );
    assert_eq!(page.matches("wear stage was left out").count(), 1, "{page}");
    assert!(!dir.join("_report/wear_occurrence.csv").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn within_km_outside_its_range_is_refused_by_name_before_any_work() {
    let dir = common::fresh_dir("wear-analysis-refusals");
    explore_default("20", &dir);
    std::fs::remove_dir_all(dir.join("_report")).ok();
    for bad in [
        "0",
        "-5",
        "1000001",
        "2e6",
        "abc",
        "10000,,40000",
        "nan",
        "inf",
    ] {
        let (code, _, stderr) = polywear(&[
            "analyze",
            dir.to_str().unwrap(),
            &format!("--within-km={bad}"),
        ]);
        assert_eq!(code, 2, "{bad}: {stderr}");
        assert!(
            stderr.contains("--within-km") && stderr.contains("(0, 1e6]"),
            "{bad}: {stderr}"
        );
        assert!(!dir.join("_report").exists(), "{bad}: work started");
    }
    std::fs::remove_dir_all(&dir).ok();
}
