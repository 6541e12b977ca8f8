//! Fault injection: `kill -9` at random moments of a multi-chunk explore run (6 kills), one kept
//! chunk corrupted, then `--resume`: the rows equal an uninterrupted run, row for row, and the
//! resume says which chunk it redid and why. The moments are set by progress (a random number of
//! new chunk files, then a random few milliseconds), not by wall time, so the test does the same
//! on a fast machine and on a loaded one.

use crate::common;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::parquet_rows::rows_in_dir;

const SAMPLES: u64 = 2400;
const CHUNK: u64 = 8;

fn explore(study: &Path, out: &Path, resume: bool) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_polywear"));
    c.args(["explore", "--quiet", "--no-report", "--threads", "1"])
        .arg(study)
        .args(["--samples", &SAMPLES.to_string(), "--out"])
        .arg(out);
    if resume {
        c.arg("--resume");
    }
    c
}

/// splitmix64: the kill moments, reproducible from the seed.
fn next(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

fn chunk_files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with("chunk-") && n.ends_with(".parquet"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn kill_9_at_random_moments_then_corruption_then_resume_gives_the_uninterrupted_rows() {
    let base = common::fresh_dir("fault");
    std::fs::create_dir_all(&base).unwrap();
    let study = base.join("fault.toml");
    std::fs::write(
        &study,
        format!(
            r#"name = "fault"
seed = 7
chunk_size = {CHUNK}
[params]
speed_kmh = {{ dist = "uniform", min = 60, max = 220 }}
toe_deg = {{ dist = "uniform", min = 0.05, max = 0.8 }}
load_n = {{ dist = "truncated_normal", mean = 4000, sd = 800, min = 2500, max = 6500 }}
"#
        ),
    )
    .unwrap();

    let whole = base.join("whole");
    let st = explore(&study, &whole, false).status().unwrap();
    assert!(st.success());
    let expected = rows_in_dir(&[&whole]);
    assert_eq!(expected.len() as u64, SAMPLES * 2);

    // Each start is killed once it has written 1 to 30 new chunk files and then run 0 to 4 ms
    // more (inside the next chunk's work, its write or its journal entry): 6 kills take at most
    // 180 of the 300 chunks, so the run cannot finish before them.
    let killed = base.join("killed");
    let mut rng = 2014u64;
    let mut kills = 0;
    let mut chunks_seen = Vec::new();
    while kills < 6 {
        let target = chunk_files(&killed).len() + 1 + (next(&mut rng) % 30) as usize;
        let extra = Duration::from_micros(next(&mut rng) % 4000);
        let mut child = explore(&study, &killed, true)
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        // A hang guard only: a start that makes no progress for minutes is a failure.
        let started = Instant::now();
        loop {
            if let Some(status) = child.try_wait().unwrap() {
                panic!("the run ended ({status}) before its kill at {target} chunk files");
            }
            if chunk_files(&killed).len() >= target {
                std::thread::sleep(extra);
                break;
            }
            assert!(
                started.elapsed() < Duration::from_secs(300),
                "no chunk file in 300 s (target {target}): a hang"
            );
            std::thread::sleep(Duration::from_millis(1));
        }
        child.kill().unwrap(); // SIGKILL
        child.wait().unwrap();
        kills += 1;
        chunks_seen.push(chunk_files(&killed).len());
    }
    eprintln!(
        "{kills} kills; chunk files at each: {chunks_seen:?} of {}",
        SAMPLES / CHUNK
    );

    // Corrupt one kept chunk: flip a byte in its middle.
    let files = chunk_files(&killed);
    assert!(
        !files.is_empty(),
        "no chunk after {kills} kills: {chunks_seen:?}"
    );
    let victim = &files[files.len() / 2];
    let path = killed.join(victim);
    let mut bytes = std::fs::read(&path).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x01;
    std::fs::write(&path, &bytes).unwrap();

    let out = explore(&study, &killed, true).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains(victim.as_str()) && stderr.contains("CRC-32"),
        "the resume must say it redid {victim} and why: {stderr}"
    );
    assert_eq!(
        rows_in_dir(&[&killed]),
        expected,
        "after {kills} kills: {chunks_seen:?}"
    );
    // No leftovers of the killed runs stay behind.
    for e in std::fs::read_dir(&killed).unwrap() {
        let n = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!n.ends_with(".partial"), "leftover {n}");
    }
    std::fs::remove_dir_all(&base).ok();
}
