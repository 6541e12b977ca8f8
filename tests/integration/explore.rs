//! `polywear explore`: reproducibility across threads and shards, resume after kill -9, bad
//! input (exit 2 before any work), no panic on arbitrary study files.

use crate::common;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::polywear;
use crate::parquet_rows::{self, rows_in_dir};

fn tmp(name: &str) -> PathBuf {
    let d = common::fresh_dir(&format!("explore-{name}"));
    d
}

/// A small random study with small chunks, written to a temp file.
fn small_study(dir: &Path, extra: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join("small.toml");
    std::fs::write(
        &path,
        format!(
            r#"name = "small"
seed = 11
samples = 600
chunk_size = 64
variants = ["paper", "combined"]
{extra}
[params]
speed_kmh = {{ dist = "uniform", min = 60, max = 220 }}
toe_deg = {{ dist = "uniform", min = 0.05, max = 0.8 }}
load_n = {{ dist = "truncated_normal", mean = 4000, sd = 800, min = 2500, max = 6500 }}
pressure_kpa = {{ dist = "levels", levels = [200, 240, 280] }}
g_mod = {{ dist = "lognormal", median = 0.8645e6, sigma = 0.05 }}
"#
        ),
    )
    .unwrap();
    path
}

fn explore(args: &[&str]) {
    let (code, _, stderr) = polywear(&[&["explore", "--quiet"], args].concat());
    assert_eq!(code, 0, "{args:?}: {stderr}");
}

#[test]
fn same_rows_whatever_threads_and_shards() {
    let base = tmp("repro");
    let study = small_study(&base, "");
    let s = study.to_str().unwrap();
    let one = base.join("t1");
    let two = base.join("t2");
    explore(&[s, "--threads", "1", "--out", one.to_str().unwrap()]);
    explore(&[s, "--threads", "2", "--out", two.to_str().unwrap()]);
    let rows1 = rows_in_dir(&[&one]);
    assert_eq!(rows1.len(), 600 * 4, "600 samples x 2 variants x 2 wheels");
    assert_eq!(rows1, rows_in_dir(&[&two]));
    let shards: Vec<PathBuf> = (0..3).map(|k| base.join(format!("shard{k}"))).collect();
    for (k, d) in shards.iter().enumerate() {
        explore(&[
            s,
            "--shard",
            &format!("{k}/3"),
            "--out",
            d.to_str().unwrap(),
        ]);
    }
    let shard_dirs: Vec<&Path> = shards.iter().map(|p| p.as_path()).collect();
    assert_eq!(
        rows1,
        rows_in_dir(&shard_dirs),
        "union of 3 shards differs from one run"
    );
    // Another seed gives other rows.
    let other = base.join("seed2");
    explore(&[s, "--seed", "2", "--out", other.to_str().unwrap()]);
    assert_ne!(rows1, rows_in_dir(&[&other]));
    std::fs::remove_dir_all(&base).ok();
}

#[test]
fn resume_after_kill_gives_the_uninterrupted_rows() {
    let base = tmp("resume");
    let study = small_study(&base, "");
    let s = study.to_str().unwrap();
    let killed = base.join("killed");
    let samples = "6000"; // 94 chunks of 64: several seconds of work.
    let mut child = Command::new(env!("CARGO_BIN_EXE_polywear"))
        .args([
            "explore",
            "--quiet",
            s,
            "--samples",
            samples,
            "--out",
            killed.to_str().unwrap(),
        ])
        .spawn()
        .unwrap();
    let count = || {
        std::fs::read_dir(&killed)
            .map(|rd| {
                rd.filter(|e| {
                    e.as_ref()
                        .unwrap()
                        .path()
                        .extension()
                        .is_some_and(|x| x == "parquet")
                })
                .count()
            })
            .unwrap_or(0)
    };
    let t0 = std::time::Instant::now();
    while count() < 3 && t0.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().unwrap(); // SIGKILL: no chance to clean up
    child.wait().unwrap();
    let at_kill = count();
    assert!(
        (3..94).contains(&at_kill),
        "kill came at {at_kill} of 94 chunks"
    );
    // Without --resume the directory is refused.
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        s,
        "--samples",
        samples,
        "--out",
        killed.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--resume"), "{stderr}");
    explore(&[
        s,
        "--samples",
        samples,
        "--out",
        killed.to_str().unwrap(),
        "--resume",
    ]);
    let whole = base.join("whole");
    explore(&[s, "--samples", samples, "--out", whole.to_str().unwrap()]);
    let resumed = rows_in_dir(&[&killed]);
    assert_eq!(resumed.len(), 6000 * 4);
    assert_eq!(resumed, rows_in_dir(&[&whole]));
    // Resuming with another seed is refused: it is another run.
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        s,
        "--samples",
        samples,
        "--seed",
        "5",
        "--out",
        killed.to_str().unwrap(),
        "--resume",
    ]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("--seed 5 contradicts the run's seed 11"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&base).ok();
}

#[test]
fn bad_inputs_exit_2_before_any_work() {
    let base = tmp("bad");
    std::fs::create_dir_all(&base).unwrap();
    let cases: &[(&str, &str)] = &[
        ("samples = [", "malformed TOML"),
        ("colour = \"red\"\n[params]\nspeed_kmh = { dist = \"uniform\", min = 60, max = 90 }", "unknown key `colour`"),
        ("[params]\nspeed_kmh = { dist = \"uniform\", min = 90, max = 60 }", "min = 90 must be below max = 60"),
        ("[params]\nload_n = { dist = \"normal\", mean = 4000, sd = -5 }", "`params.load_n.sd` = -5 must be positive"),
        ("[params]\nload_n = { dist = \"uniform\", min = -100, max = 4000 }", "load_n"),
        ("[params]\npressure_kpa = { dist = \"levels\", levels = [0, 200] }", "pressure_kpa"),
        ("[params]\nload_n = { dist = \"normal\", mean = 4000, sd = 1000 }", "truncated_normal"),
        ("[params]\nspeed_kmh = { dist = \"uniform\", min = 60, max = 90, mean = 3 }", "`params.speed_kmh.mean`"),
        ("[params]\nspeed_kmh = { dist = \"weibull\" }", "weibull"),
        ("[params]\nwheelbase = 2.7", "unknown parameter `wheelbase`"),
        ("[params]\ntoe_deg = 0\nspeed_kmh = { dist = \"uniform\", min = 60, max = 90 }", "toe_deg"),
        ("design = \"grid\"\n[params]\nspeed_kmh = { dist = \"uniform\", min = 60, max = 90 }", "grid design needs"),
        ("design = \"halton\"\n[params]\nspeed_kmh = { dist = \"uniform\", min = 60, max = 90 }", "halton"),
        ("variants = [\"paper\", \"magic\"]\n[params]\nspeed_kmh = { dist = \"uniform\", min = 60, max = 90 }", "magic"),
        ("[params]\nspeed_kmh = 100", "draws no parameter"),
    ];
    for (i, (text, needle)) in cases.iter().enumerate() {
        let f = base.join(format!("bad{i}.toml"));
        std::fs::write(&f, text).unwrap();
        let out = base.join(format!("out{i}"));
        let (code, stdout, stderr) = polywear(&[
            "explore",
            f.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{text}: {stderr}");
        assert!(
            stderr.contains(needle),
            "{text}: stderr lacks `{needle}`: {stderr}"
        );
        assert!(stdout.is_empty());
        assert!(
            !out.exists(),
            "{text}: output directory created before the input was checked"
        );
    }
    let good = small_study(&base, "");
    let g = good.to_str().unwrap();
    let flag_cases: &[(&[&str], &str)] = &[
        (&["--samples", "1.5"], "--samples"),
        (&["--samples", "0"], "--samples"),
        (&["--shard", "3/3"], "--shard"),
        (&["--threads", "0"], "--threads"),
        (
            &["--out", "/proc/polywear-cannot-write-here"],
            "/proc/polywear-cannot-write-here",
        ),
        (
            // A directory with files but no manifest is not a run to resume.
            &["--resume", "--out", "/etc"],
            "nothing to resume",
        ),
    ];
    for (args, needle) in flag_cases {
        let (code, _, stderr) = polywear(&[&["explore", g], *args].concat());
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
    }
    // Grid size mismatch.
    let grid = base.join("grid.toml");
    std::fs::write(&grid, "design = \"grid\"\n[params]\nspeed_kmh = { dist = \"uniform\", min = 60, max = 90, count = 4 }").unwrap();
    let (code, _, stderr) = polywear(&[
        "explore",
        grid.to_str().unwrap(),
        "--samples",
        "5",
        "--out",
        base.join("g").to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("grid's size 4"), "{stderr}");
    // --resume into an absent directory starts the run.
    let fresh = base.join("fresh");
    let (code, _, stderr) = polywear(&[
        "explore",
        "--quiet",
        g,
        "--samples",
        "64",
        "--resume",
        "--out",
        fresh.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(rows_in_dir(&[&fresh]).len(), 64 * 4);
    // Non-empty output directory without --resume.
    let full = base.join("full");
    std::fs::create_dir_all(&full).unwrap();
    std::fs::write(full.join("other.txt"), "x").unwrap();
    let (code, _, stderr) = polywear(&["explore", g, "--out", full.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(stderr.contains("not empty"), "{stderr}");
    std::fs::remove_dir_all(&base).ok();
}

#[test]
fn arbitrary_study_files_never_panic() {
    use polywear::study::{Study, DEFAULT_STUDY};
    use polywear_core::sampling::bits;
    let seeds: Vec<&str> = vec![
        DEFAULT_STUDY,
        include_str!("../../studies/grid_4axes.toml"),
        include_str!("../../studies/wide_structure.toml"),
    ];
    let alphabet = b"[]{}=\",.-_0123456789eE abcdefghijklmnopqrstuvwxyz\n#";
    for case in 0..3000u64 {
        let mut text: Vec<u8> = seeds[(case % 3) as usize].as_bytes().to_vec();
        let edits = 1 + bits(1, case, 0) % 8;
        for e in 0..edits {
            let r = bits(2, case, e);
            let pos = (r % (text.len() as u64 + 1)) as usize;
            match (r >> 32) % 3 {
                0 if pos < text.len() => {
                    text.remove(pos);
                }
                1 => text.insert(pos, alphabet[((r >> 40) % alphabet.len() as u64) as usize]),
                _ if pos < text.len() => {
                    text[pos] = alphabet[((r >> 40) % alphabet.len() as u64) as usize]
                }
                _ => {}
            }
        }
        let s = String::from_utf8_lossy(&text).into_owned();
        let result = std::panic::catch_unwind(|| {
            if let Ok(study) = Study::parse(&s) {
                // A study that parses must also sample without panicking.
                let n = study.samples.min(50);
                let sampler = study.sampler(study.seed, study.samples);
                for i in 0..n {
                    let _ = sampler.sample(i);
                }
            }
        });
        assert!(result.is_ok(), "panic on study text:\n{s}");
    }
}

#[test]
fn shipped_studies_parse() {
    for f in [
        "studies/default.toml",
        "studies/grid_4axes.toml",
        "studies/wide_structure.toml",
    ] {
        let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(f)).unwrap();
        polywear::study::Study::parse(&text).unwrap_or_else(|e| panic!("{f}: {e}"));
    }
}

/// A study that draws wear_share_straight (φ_s) writes it once: the wear stage's column of that
/// name carries the drawn value, and a second column of the same name left the chunks
/// unreadable by name (pyarrow: "Multiple matches for FieldRef.Name(wear_share_straight)") and
/// the run's own analysis failing with "duplicate column". Without the wear stage the drawn
/// column is the only one.
#[test]
fn a_drawn_wear_share_is_one_column() {
    let dir = tmp("drawn-share");
    let study = dir.join("share.toml");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        &study,
        r#"name = "share"
seed = 5
samples = 12
[params]
speed_kmh = { dist = "uniform", min = 90, max = 130 }
toe_deg = { dist = "uniform", min = 0.2, max = 0.5 }
wear_share_straight = { dist = "uniform", min = 0.1, max = 0.9 }
"#,
    )
    .unwrap();
    for (name, extra) in [("wear", None), ("no-wear", Some("--no-wear"))] {
        let out = dir.join(name);
        let study = study.to_str().unwrap();
        let mut args = vec![
            study,
            "--out",
            out.to_str().unwrap(),
            "--calibration-band",
            "off",
        ];
        args.extend(extra);
        explore(&args);
        let chunk = out.join("chunk-0000000.parquet");
        let rows = parquet_rows::rows(&chunk);
        let reader =
            parquet::file::reader::SerializedFileReader::new(std::fs::File::open(&chunk).unwrap())
                .unwrap();
        use parquet::file::reader::FileReader;
        let schema = reader.metadata().file_metadata().schema_descr_ptr();
        let names: Vec<String> = schema
            .columns()
            .iter()
            .map(|c| c.name().to_string())
            .collect();
        let shares = names.iter().filter(|n| *n == "wear_share_straight").count();
        assert_eq!(shares, 1, "{name}: {names:?}");
        // Each row's φ_s is its own draw (not one shared value).
        let drawn: std::collections::BTreeSet<String> = rows
            .iter()
            .map(|r| r["wear_share_straight"].to_string())
            .collect();
        assert!(drawn.len() > 6, "{name}: {drawn:?}");
    }
}
