//! The Parquet files open in pandas (pyarrow) with their metadata. Needs python3 with pandas and
//! pyarrow: without them each test says it is skipped, unless `POLYWEAR_REQUIRE_PYTHON=1` (set by
//! `.ci/run`, which installs them) makes their absence a failure.

use crate::common::{explore_default, fresh_dir, polywear, python, python_has};

#[test]
fn pandas_reads_simulate_parquet_with_metadata() {
    if !python_has(&["pandas", "pyarrow"]) {
        return;
    }
    let dir = fresh_dir("py-simulate");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("ts.parquet");
    let (code, _, stderr) = polywear(&[
        "simulate",
        "--duration",
        "0.1",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let script = r#"
import sys, json
import pandas as pd, pyarrow.parquet as pq
df = pd.read_parquet(sys.argv[1])
assert list(df.columns) == ["wheel", "t_s", "z_m", "y_m", "v_mps"], df.columns
assert len(df) == 2 * 2001, len(df)
assert set(df.wheel) == {"follower", "driving"}
md = pq.read_metadata(sys.argv[1]).metadata
assert md[b"variant"] == b"sliding_share"
assert json.loads(md[b"params"])["speed_kmh"] == 100.0
assert json.loads(md[b"units"])["v_mps"] == "m/s"
print("ok", len(df))
"#;
    python(script, &[file.to_str().unwrap()]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn pandas_and_pyarrow_read_an_explore_directory() {
    if !python_has(&["pandas", "pyarrow"]) {
        return;
    }
    let dir = fresh_dir("py-explore");
    explore_default("300", &dir);
    let script = r#"
import sys, glob, pandas as pd, pyarrow.parquet as pq
d = sys.argv[1]
df = pd.read_parquet(d)                      # the whole directory as one table
assert len(df) == 600, len(df)               # 300 samples x 2 wheels
assert df.sample_id.nunique() == 300 and set(df.wheel) == {"follower", "driving"}
for c in ["sample_id", "wheel", "variant", "speed_kmh", "g_mod", "class", "amp_v_mps", "polygon_order"]:
    assert c in df.columns, c
assert str(df.amp_v_mps.dtype) == "float64" and str(df.sample_id.dtype) == "int64"
p = df.groupby("wheel")["class"].apply(lambda s: (s == "limit_cycle").mean())
assert 0.0 < p["follower"] < 1.0, p
md = pq.read_metadata(glob.glob(d + "/*.parquet")[0]).metadata
for k in [b"study_hash", b"seed", b"variant", b"params", b"polywear_version", b"command", b"units"]:
    assert k in md, k
assert md[b"seed"] == b"2014"
print("ok")
"#;
    python(script, &[dir.to_str().unwrap()]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn pandas_polars_and_duckdb_read_the_same_frame_in_one_line_each() {
    if !python_has(&["pandas", "pyarrow", "polars", "duckdb"]) {
        return;
    }
    let dir = fresh_dir("py-readers");
    explore_default("300", &dir);
    // The lines are the ones the explore reference page shows, run against this output.
    let snippet = include_str!("../data/read_run_snippet.py");
    assert!(
        include_str!("../../docs/book/src/reference/explore.md").contains(snippet.trim()),
        "docs/book/src/reference/explore.md must show tests/data/read_run_snippet.py"
    );
    let script = snippet.replace("data/explore_highway_fleet_seed2014", dir.to_str().unwrap())
        + r#"
key = ["sample_id", "variant", "wheel"]
a = rows.sort_values(key).reset_index(drop=True)
b = rows_pl.to_pandas().sort_values(key).reset_index(drop=True)
c = rows_db.sort_values(key).reset_index(drop=True)
assert len(a) == 600 and list(a.columns) == list(b.columns) == list(c.columns), (a.columns, b.columns, c.columns)
pd.testing.assert_frame_equal(a, b, check_dtype=False)
pd.testing.assert_frame_equal(a, c, check_dtype=False)
print("same frame")
"#;
    assert!(python(&script, &[]).contains("same frame"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn guide_pandas_snippet_agrees_with_analyze() {
    if !python_has(&["pandas", "pyarrow"]) {
        return;
    }
    let dir = fresh_dir("py-snippet");
    explore_default("2000", &dir);
    // The snippet is the one printed on the analyze reference page, run against this output.
    let snippet = include_str!("../data/guide_snippet.py");
    assert!(
        include_str!("../../docs/book/src/reference/analyze.md").contains(snippet.trim()),
        "docs/book/src/reference/analyze.md must show tests/data/guide_snippet.py"
    );
    let script = snippet.replace("data/explore_highway_fleet_seed2014", dir.to_str().unwrap())
        + r#"
ours = pd.read_csv(sys.argv[1] + "/_report/occurrence.csv").set_index(["variant", "wheel"])
mine = pd.DataFrame({"p": p, "lo": centre - half, "hi": centre + half})
for key in mine.index:
    for a, b in [("p", "p"), ("lo", "wilson95_lo"), ("hi", "wilson95_hi")]:
        assert abs(mine.loc[key, a] - ours.loc[key, b]) < 1e-12, (key, a, mine.loc[key, a], ours.loc[key, b])
t = pd.crosstab(pair["follower"], pair["driving"]).reindex(index=[False, True], columns=[False, True], fill_value=0)
paired = pd.read_csv(sys.argv[1] + "/_report/paired.csv").iloc[0]
assert t.loc[True, False] == paired.only_follower and t.loc[False, True] == paired.only_driving
assert t.loc[True, True] == paired.both and t.loc[False, False] == paired.neither
print("agree")
"#;
    let script = format!("import sys\n{script}");
    assert!(python(&script, &[dir.to_str().unwrap()]).contains("agree"));
    std::fs::remove_dir_all(&dir).ok();
}

/// Rewrites every chunk of `run` into `out` with pyarrow, changed by `edit` (Python on the
/// table `t` and its metadata `md`, a dict of bytes), the metadata kept (pyarrow adds its own
/// `ARROW:schema`).
fn rewrite(run: &std::path::Path, out: &std::path::Path, edit: &str) {
    let script = format!(
        r#"
import sys, glob, os, pyarrow as pa, pyarrow.parquet as pq, pyarrow.compute as pc
run, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
for f in sorted(glob.glob(run + "/chunk-*.parquet")):
    t = pq.read_table(f)
    md = dict(t.schema.metadata)
{}
    t = t.replace_schema_metadata(md)
    pq.write_table(t, os.path.join(out, os.path.basename(f)))
print("ok")
"#,
        edit.lines()
            .map(|l| format!("    {l}"))
            .collect::<Vec<_>>()
            .join("\n")
    );
    python(&script, &[run.to_str().unwrap(), out.to_str().unwrap()]);
}

#[test]
fn a_chunk_rewritten_by_pyarrow_is_accepted_and_a_changed_one_refused_by_name() {
    if !python_has(&["pandas", "pyarrow"]) {
        return;
    }
    let dir = fresh_dir("py-rewritten");
    explore_default("300", &dir);
    let summary = |out: &str| {
        out.lines()
            .find(|l| l.contains("(follower):"))
            .map(str::to_string)
    };
    let (code, original, stderr) = polywear(&[
        "analyze",
        dir.to_str().unwrap(),
        "--out",
        dir.join("r0").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    // The same data and metadata, written by pyarrow: the same answer (its `ARROW:schema` key
    // is ignored, not parsed).
    let same = dir.join("same");
    rewrite(&dir, &same, "pass");
    let (code, again, stderr) = polywear(&["analyze", same.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(summary(&again), summary(&original));
    assert!(summary(&original).is_some(), "{original}");
    // Changed rewrites are refused, naming the file and what is wrong.
    for (name, edit, needle) in [
        (
            "typed",
            "t = t.set_column(t.schema.get_field_index('speed_kmh'), 'speed_kmh', pc.cast(t['speed_kmh'], pa.string()))",
            "column `speed_kmh` is string (UTF-8), expected double (f64)",
        ),
        (
            "missing",
            "t = t.drop(['class'])",
            "column `class` is missing",
        ),
        (
            "ids",
            "t = t.set_column(t.schema.get_field_index('sample_id'), 'sample_id', pc.add(t['sample_id'], 4096))",
            "lies outside the run's [0, 300)",
        ),
        (
            "variant",
            "t = t.set_column(t.schema.get_field_index('variant'), 'variant', pa.array(['paper'] * len(t)))",
            "every row's variant must be one of the footer's",
        ),
        (
            "seed",
            "md[b'seed'] = b'x' * 300",
            "`seed`: not JSON",
        ),
        (
            "nan",
            "t = t.set_column(t.schema.get_field_index('speed_kmh'), 'speed_kmh', pa.array([float('nan')] * len(t)))",
            "column `speed_kmh` holds",
        ),
    ] {
        let out = dir.join(name);
        rewrite(&dir, &out, edit);
        let (code, _, stderr) = polywear(&["analyze", out.to_str().unwrap()]);
        assert_eq!(code, 2, "{name}: {stderr}");
        assert!(stderr.contains(needle), "{name}: `{needle}` not in {stderr}");
        assert!(!stderr.contains("panicked") && stderr.len() < 600, "{name}: {stderr}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
