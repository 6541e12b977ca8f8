//! Property ("fuzz") tests over study files, parameter files and command lines: never a panic,
//! never a hang, and either success or a refusal (exit 2) whose message names a field.
//!
//! Cases come from a fixed-seed generator (splitmix64), so a failure reproduces exactly: the
//! assertion prints the case. Thousands of study and parameter-file texts run in-process
//! (cheap); a few hundred command lines run through the binary, each under a time limit. Their
//! values are hostile (negative, zero, NaN, infinite, huge, not numbers, empty) or small valid
//! ones, so that most cases are refused before any work and the rest run in milliseconds.
//! Tiny positive physical values (e.g. `--toe 1e-200`) are left out: the classifier's budget
//! for them is tested in tests/budget.rs.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use polywear::study::{apply_param_file, Study, DEFAULT_STUDY};

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a, T: ?Sized>(&mut self, xs: &[&'a T]) -> &'a T {
        xs[self.below(xs.len())]
    }
}

/// Whether a refusal names what it refuses: a key in backticks, a flag, an argument, a file.
fn names_a_field(msg: &str) -> bool {
    msg.contains('`') || msg.contains("--") || msg.contains('<') || msg.contains("TOML")
}

/// Mutates `text` with 1–8 random byte edits from an alphabet of TOML punctuation and words.
fn mutate(rng: &mut Rng, text: &str) -> String {
    let alphabet = b"[]{}=\",.-_0123456789eE abcdefghijklmnopqrstuvwxyz\n#+";
    let words: [&str; 12] = [
        "nan", "inf", "-inf", "-5", "0", "1e308", "levels", "dist", "\"grid\"", "[]", "{}", "é",
    ];
    let mut b = text.as_bytes().to_vec();
    for _ in 0..1 + rng.below(8) {
        let pos = rng.below(b.len() + 1);
        match rng.below(4) {
            0 if pos < b.len() => {
                b.remove(pos);
            }
            1 => b.insert(pos, alphabet[rng.below(alphabet.len())]),
            2 => {
                let w = words[rng.below(words.len())];
                for (i, c) in w.bytes().enumerate() {
                    b.insert(pos + i, c);
                }
            }
            _ if pos < b.len() => b[pos] = alphabet[rng.below(alphabet.len())],
            _ => {}
        }
    }
    String::from_utf8_lossy(&b).into_owned()
}

#[test]
fn study_and_parameter_files_never_panic_and_refusals_name_a_field() {
    let seeds = [
        DEFAULT_STUDY,
        include_str!("../studies/grid_4axes.toml"),
        include_str!("../studies/wide_structure.toml"),
        "[params]\npressure_kpa = { dist = \"levels\", levels = [200, 240, 280] }\n",
    ];
    let param_seeds = [
        "[params]\ng_mod = 0.9e6\nmu_s = 0.6\n",
        "[params]\nspeed_kmh = 120\n",
    ];
    let mut rng = Rng(13);
    let t0 = Instant::now();
    for case in 0..4000 {
        let study = case % 4 != 3;
        let text = if study {
            mutate(&mut rng, seeds[case % seeds.len()])
        } else {
            mutate(&mut rng, param_seeds[case % param_seeds.len()])
        };
        let result = std::panic::catch_unwind(|| {
            if study {
                match Study::parse(&text) {
                    Ok(s) => {
                        let sampler = s.sampler(s.seed, s.samples);
                        for i in 0..s.samples.min(20) {
                            let _ = sampler.sample(i);
                        }
                        Ok(())
                    }
                    Err(e) => Err(e.to_string()),
                }
            } else {
                apply_param_file(&Default::default(), &text)
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            }
        });
        match result {
            Err(_) => panic!("case {case}: panic on\n{text}"),
            Ok(Err(msg)) => assert!(
                names_a_field(&msg),
                "case {case}: `{msg}` names no field; text:\n{text}"
            ),
            Ok(Ok(())) => {}
        }
    }
    // A hang guard, not a speed test: the cases take well under a minute.
    assert!(
        t0.elapsed() < Duration::from_secs(900),
        "took {:?}: a parser or sampler that hangs",
        t0.elapsed()
    );
}

/// Runs polywear with a time limit: (exit code, stderr); panics on a hang.
fn run_bounded(args: &[String], limit: Duration) -> (i32, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_polywear"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t0.elapsed() > limit {
            child.kill().ok();
            child.wait().ok();
            panic!("hang: polywear {}", args.join(" "));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

struct Fixtures {
    dir: PathBuf,
    studies: Vec<String>,
    csvs: Vec<String>,
    explore_out: String,
}

fn fixtures() -> Fixtures {
    let dir = common::fresh_dir("fuzz-cli");
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, text: &str| -> String {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_string_lossy().into_owned()
    };
    let small = "name = \"tiny\"\nchunk_size = 4\n[params]\nspeed_kmh = { dist = \"uniform\", min = 60, max = 200 }\n";
    let studies = vec![
        write("tiny.toml", small),
        write(
            "bad_levels.toml",
            "[params]\npressure_kpa = { dist = \"levels\", levels = [200, nan] }\n",
        ),
        write("bad_key.toml", "colour = 1\n"),
        write("empty.toml", ""),
        dir.join("missing.toml").to_string_lossy().into_owned(),
    ];
    let csvs = vec![
        write("good.csv", "speed_kmh,toe_deg\n100,0.3\n"),
        write("dup.csv", "speed_kmh,speed_kmh\n100,120\n"),
        write("cell.csv", "speed_kmh\nfast\n"),
        write("range.csv", "toe_deg\n-3\n"),
        write("none.csv", ""),
    ];
    let explore_out = dir.join("run").to_string_lossy().into_owned();
    let (code, _, stderr) = common::polywear(&[
        "explore",
        "--quiet",
        "--no-report",
        &studies[0],
        "--samples",
        "8",
        "--out",
        &explore_out,
    ]);
    assert_eq!(code, 0, "{stderr}");
    Fixtures {
        dir,
        studies,
        csvs,
        explore_out,
    }
}

/// A random command line; `case` makes output paths unique.
fn command_line(rng: &mut Rng, fx: &Fixtures, case: usize) -> Vec<String> {
    let int = [
        "-5",
        "-1",
        "0",
        "1",
        "2",
        "3",
        "1.5",
        "1e3",
        "abc",
        "",
        "99999999999999999999",
    ];
    let real = [
        "-0.3", "-1", "0", "nan", "inf", "-inf", "1e308", "abc", "", "0.3", "120",
    ];
    let set = [
        "mu_s=-1",
        "speed_kmh=nan",
        "nosuch=1",
        "=",
        "g_mod=1e300",
        "toe_deg=0.3",
        "mu_s=0.9",
        "load_n",
        "speed_kmh=1e9",
    ];
    let out = |ext: &str| {
        fx.dir
            .join(format!("o{case}.{ext}"))
            .to_string_lossy()
            .into_owned()
    };
    let mut a: Vec<String> = Vec::new();
    let flag = |a: &mut Vec<String>, name: &str, pool: &[&str], rng: &mut Rng| {
        a.push(name.to_string());
        a.push(rng.pick(pool).to_string());
    };
    match rng.below(7) {
        0 => {
            a.extend(["explore", "--quiet", "--no-report"].map(String::from));
            if rng.below(4) > 0 {
                a.push(fx.studies[rng.below(fx.studies.len())].clone());
            }
            // Always a sample count: valid ones are small.
            flag(
                &mut a,
                "--samples",
                &["-5", "0", "1.5", "abc", "3", "1e99", "8"],
                rng,
            );
            a.extend(["--out".into(), out("d")]);
            for _ in 0..rng.below(3) {
                match rng.below(5) {
                    0 => flag(&mut a, "--seed", &int, rng),
                    1 => flag(&mut a, "--threads", &int, rng),
                    2 => flag(
                        &mut a,
                        "--shard",
                        &["0/1", "1/2", "2/2", "-1/2", "a/b", "3"],
                        rng,
                    ),
                    3 => a.push("--resume".into()),
                    _ => flag(&mut a, "--params", &[fx.csvs[0].as_str(), "nope.toml"], rng),
                }
            }
        }
        1 => {
            a.push("analyze".into());
            let inputs = [
                fx.explore_out.as_str(),
                "no/such/dir",
                fx.dir.to_str().unwrap(),
            ];
            a.push(rng.pick(&inputs).to_string());
            a.extend(["--out".into(), out("report")]);
            for _ in 0..1 + rng.below(2) {
                let f = rng.pick(&["--bins", "--map-bins", "--min-count", "--bootstrap"]);
                flag(&mut a, f, &int, rng);
            }
        }
        2 => {
            a.push("classify".into());
            a.push(fx.csvs[rng.below(fx.csvs.len())].clone());
            // A missing folder is created, so it lies inside the fixture's folder.
            let missing = fx
                .dir
                .join("no/such/dir/x.csv")
                .to_str()
                .unwrap()
                .to_string();
            let outs = [out("csv"), out("txt"), missing];
            a.extend(["--out".into(), outs[rng.below(3)].clone()]);
            if rng.below(2) == 0 {
                flag(&mut a, "--threads", &int, rng);
            }
        }
        3 => {
            a.push("simulate".into());
            for _ in 0..1 + rng.below(3) {
                match rng.below(6) {
                    0 => flag(&mut a, "--toe", &real, rng),
                    1 => flag(&mut a, "--speed", &real, rng),
                    2 => flag(&mut a, "--set", &set, rng),
                    3 => flag(
                        &mut a,
                        "--duration",
                        &["-1", "0", "nan", "inf", "1e9", "abc", "0.05"],
                        rng,
                    ),
                    4 => flag(&mut a, "--kick", &real, rng),
                    _ => flag(&mut a, "--wheel", &["both", "left", "", "driving"], rng),
                }
            }
        }
        4 => {
            a.extend(["bifurcation", "--param"].map(String::from));
            a.push(
                rng.pick(&["speed_kmh", "toe_deg", "nosuch", ""])
                    .to_string(),
            );
            flag(&mut a, "--from", &real, rng);
            flag(&mut a, "--to", &real, rng);
            flag(&mut a, "--steps", &["-4", "0", "1", "abc", "3"], rng);
            a.extend(["--out".into(), out("bif")]);
            if rng.below(2) == 0 {
                flag(&mut a, "--threads", &int, rng);
            }
        }
        5 => {
            // Expensive when valid: always one bad value.
            if rng.below(2) == 0 {
                a.push("reproduce".into());
                flag(&mut a, "--steps", &["-1", "0", "10", "abc", "5000"], rng);
            } else {
                a.push("validate".into());
                flag(
                    &mut a,
                    "--points",
                    &["-1", "0", "abc", "1e9", "100001"],
                    rng,
                );
            }
            a.extend(["--out".into(), out("csv")]);
            flag(&mut a, "--threads", &int, rng);
        }
        _ => {
            // Unknown flags and stray values (never a bare valid `explore`: it would run the
            // default study into data/).
            a.push(
                rng.pick(&["explore", "simulate", "params", "classify"])
                    .to_string(),
            );
            a.push(
                rng.pick(&["--frobnicate", "-x", "--samples", "---", "-5"])
                    .to_string(),
            );
            if a[0] == "explore" {
                a.extend(["--samples".into(), "abc".into()]);
            }
        }
    }
    a
}

#[test]
fn command_lines_never_panic_or_hang_and_refusals_name_a_field() {
    let fx = fixtures();
    let mut rng = Rng(2014);
    let t0 = Instant::now();
    let (mut ok, mut refused) = (0, 0);
    for case in 0..400 {
        let args = command_line(&mut rng, &fx, case);
        let (code, stderr) = run_bounded(&args, Duration::from_secs(60));
        let line = args.join(" ");
        assert!(
            !stderr.contains("panicked"),
            "panic: polywear {line}\n{stderr}"
        );
        match code {
            0 => ok += 1,
            2 => {
                refused += 1;
                // A flag, a key, or the file it concerns (an input path given on the line).
                let names_a_path = args[1..]
                    .iter()
                    .any(|x| x.contains('/') && stderr.contains(x.as_str()));
                assert!(
                    names_a_field(&stderr) || names_a_path,
                    "refusal names no field: polywear {line}\n{stderr}"
                );
            }
            _ => panic!("exit {code}: polywear {line}\n{stderr}"),
        }
    }
    eprintln!(
        "{ok} accepted, {refused} refused in {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    assert!(refused > 100 && ok > 10, "{ok} accepted, {refused} refused");
    std::fs::remove_dir_all(Path::new(&fx.dir)).ok();
}
