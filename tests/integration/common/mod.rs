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

/// Whether python3 can import `modules`. When it cannot, the test that asks is skipped with a
/// message written past libtest's capture (so it shows in the test output), unless
/// `POLYWEAR_REQUIRE_PYTHON=1` is set (as `.ci/run` sets it): then the missing reader fails the
/// test. `cargo test --release` thus passes on a machine without pandas, and CI cannot skip.
#[allow(dead_code)]
pub fn python_has(modules: &[&str]) -> bool {
    use std::io::Write;
    let import = format!("import {}", modules.join(", "));
    let found = Command::new("python3")
        .args(["-c", &import])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if found {
        return true;
    }
    let required = std::env::var("POLYWEAR_REQUIRE_PYTHON").is_ok_and(|v| v == "1");
    assert!(
        !required,
        "POLYWEAR_REQUIRE_PYTHON=1 but `python3 -c '{import}'` fails: install {}",
        modules.join(" and ")
    );
    // Written to the process's stderr directly: libtest captures only the print macros.
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED ({}): python3 cannot `{import}`; install them, or set \
         POLYWEAR_REQUIRE_PYTHON=1 to make this a failure",
        std::thread::current().name().unwrap_or("test")
    );
    false
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

/// Runs the polywear binary with a time limit: (exit code, stdout, stderr); panics when it does
/// not end in time, so that a hang fails the test instead of stalling the suite.
#[allow(dead_code)]
pub fn polywear_within(limit: std::time::Duration, args: &[&str]) -> (i32, String, String) {
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_polywear"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if start.elapsed() > limit {
            child.kill().ok();
            child.wait().ok();
            panic!("polywear {args:?} did not end within {limit:?}");
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
/// A tmpfs of `size` mounted at `at` (read-only when `ro`) for as long as the value lives; None
/// when this process may not mount (not root), and the test then says so and passes.
#[allow(dead_code)]
pub struct Mount(std::path::PathBuf);

#[allow(dead_code)]
impl Mount {
    pub fn tmpfs(at: &std::path::Path, size: &str, ro: bool) -> Option<Mount> {
        std::fs::create_dir_all(at).unwrap();
        let opts = format!("size={size}{}", if ro { ",ro" } else { "" });
        let ok = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &opts, "tmpfs"])
            .arg(at)
            .stderr(std::process::Stdio::null())
            .status()
            .is_ok_and(|st| st.success());
        if !ok {
            eprintln!(
                "skipped: cannot mount a tmpfs at {} (needs root)",
                at.display()
            );
            return None;
        }
        Some(Mount(at.to_path_buf()))
    }
}

impl Drop for Mount {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg("-l").arg(&self.0).status();
    }
}

pub mod svg;

/// Writes `study` as `dir/name.toml` and runs `explore --quiet` on it into `dir/name`, with
/// `extra` flags; panics on failure. Returns the output folder.
#[allow(dead_code)]
pub fn explore_study(
    dir: &std::path::Path,
    name: &str,
    study: &str,
    extra: &[&str],
) -> std::path::PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, study).unwrap();
    let out = dir.join(name);
    let mut args = vec![
        "explore",
        "--quiet",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, _, stderr) = polywear(&args);
    assert_eq!(code, 0, "{stderr}");
    out
}
