//! Helpers shared by the command-line tests.

use std::process::Command;

/// Runs the polywear binary: (exit code, stdout, stderr).
pub fn polywear(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_polywear"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Runs a Python script with arguments; panics with its stderr unless it succeeds.
#[allow(dead_code)]
pub fn python(script: &str, args: &[&str]) -> String {
    let out = Command::new("python3")
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "python failed: {}\n{}",
        String::from_utf8_lossy(&out.stderr),
        String::from_utf8_lossy(&out.stdout)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A fresh temporary directory named for the test.
#[allow(dead_code)]
pub fn fresh_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("polywear-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    d
}

/// `polywear explore --quiet --samples N --out DIR` on the default study; panics on failure.
#[allow(dead_code)]
pub fn explore_default(samples: &str, dir: &std::path::Path) {
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        "--samples",
        samples,
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
}
