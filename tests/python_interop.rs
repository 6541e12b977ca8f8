//! The Parquet files open in pandas (pyarrow) with their metadata. Needs python3 with pandas and
//! pyarrow, which `.ci/run` installs; the test fails loudly rather than skipping without them.

use std::process::Command;

#[test]
fn pandas_reads_simulate_parquet_with_metadata() {
    let dir = std::env::temp_dir().join(format!("polywear-py-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("ts.parquet");
    let st = Command::new(env!("CARGO_BIN_EXE_polywear"))
        .args([
            "simulate",
            "--duration",
            "0.1",
            "--out",
            file.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(st.status.success());
    let script = r#"
import sys, json
import pandas as pd, pyarrow.parquet as pq
df = pd.read_parquet(sys.argv[1])
assert list(df.columns) == ["wheel", "t_s", "z_m", "y_m", "v_mps"], df.columns
assert len(df) == 2 * 2001, len(df)
assert set(df.wheel) == {"follower", "driving"}
md = pq.read_metadata(sys.argv[1]).metadata
assert md[b"variant"] == b"paper"
assert json.loads(md[b"params"])["speed_kmh"] == 100.0
assert json.loads(md[b"units"])["v_mps"] == "m/s"
print("ok", len(df))
"#;
    let out = Command::new("python3")
        .arg("-c")
        .arg(script)
        .arg(&file)
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "pandas could not read the file: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::remove_dir_all(&dir).ok();
}
