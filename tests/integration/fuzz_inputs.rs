//! Property ("fuzz") tests over study files, parameter files and command lines: never a panic,
//! never a hang, and either success or a refusal (exit 2) whose message names what was changed:
//! the mutated key of a file (or its parameter), or a flag, path or parameter of the command line.
//!
//! Cases come from a fixed-seed generator (splitmix64), so a failure reproduces exactly: the
//! assertion prints the case. Thousands of study and parameter-file texts run in-process
//! (cheap); a few hundred command lines run through the binary, each under a time limit. Their
//! values are hostile (negative, zero, NaN, infinite, huge, not numbers, empty) or small valid
//! ones, so that most cases are refused before any work and the rest run in milliseconds.
//! Tiny positive physical values (e.g. `--toe 1e-200`) are left out: the classifier's budget
//! for them is tested in tests/integration/budget.rs.

use crate::common;
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

/// One place of a seed text a mutation may hit: a key or a value, on one line.
struct Site {
    /// Byte range in the seed text.
    start: usize,
    end: usize,
    /// 1-based line number.
    line: usize,
    /// 1-based line number of the next entry (after blank and comment lines), or of the end.
    next_line: usize,
    /// The names a refusal of this mutation must mention (one of them): the top-level key, or
    /// the parameter and, inside its table, the key.
    names: Vec<String>,
    /// Whether the site is a key (its mutated text is then a name the refusal may quote).
    is_key: bool,
}

/// Splits `s` (a value's text starting at byte `at` of the line) at depth-0 commas.
fn split_top(s: &str, at: usize) -> Vec<(usize, &str)> {
    let (mut depth, mut quoted, mut from) = (0i32, false, 0);
    let mut out = Vec::new();
    for (i, c) in s.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '[' | '{' if !quoted => depth += 1,
            ']' | '}' if !quoted => depth -= 1,
            ',' if !quoted && depth == 0 => {
                out.push((at + from, &s[from..i]));
                from = i + 1;
            }
            _ => {}
        }
    }
    out.push((at + from, &s[from..]));
    out
}

/// The trimmed span of `part` (at byte `at`) as (start, end).
fn trimmed(at: usize, part: &str) -> (usize, usize) {
    let lead = part.len() - part.trim_start().len();
    (at + lead, at + lead + part.trim().len())
}

/// Every key and value of a seed text written one entry per line (as the shipped studies are):
/// top-level keys, table headers, `[params]` entries, and the keys, values and array elements
/// of their inline tables.
fn sites(text: &str) -> Vec<Site> {
    let mut out = Vec::new();
    let mut table = String::new();
    let mut offset = 0;
    for (n, line) in text.split_inclusive('\n').enumerate() {
        let at = offset;
        offset += line.len();
        let mut push = |(start, end): (usize, usize), names: &[&str], is_key: bool| {
            out.push(Site {
                start,
                end,
                line: n + 1,
                next_line: 0,
                names: names
                    .iter()
                    .filter(|n| !n.is_empty())
                    .map(|n| n.to_string())
                    .collect(),
                is_key,
            })
        };
        // The entry without its comment (no `#` inside the seeds' strings).
        let body = line.split('#').next().unwrap().trim_end();
        if body.trim().is_empty() {
            continue;
        }
        if body.trim_start().starts_with('[') {
            let name = body.trim().trim_matches(['[', ']']);
            table = name.to_string();
            let start = at + body.find(name).unwrap();
            push((start, start + name.len()), &[name], true);
            continue;
        }
        let Some(eq) = body.find('=') else { continue };
        let key = body[..eq].trim();
        let (vs, ve) = trimmed(at + eq + 1, &body[eq + 1..]);
        push(trimmed(at, &body[..eq]), &[key], true);
        push((vs, ve), &[key], false);
        // The inside of an inline table or array, and where it starts.
        let inner = |start: usize, value: &str| -> Option<(usize, String)> {
            let open = value.chars().next()?;
            let close = value.chars().last()?;
            (matches!((open, close), ('{', '}') | ('[', ']')) && value.len() >= 2)
                .then(|| (start + 1, value[1..value.len() - 1].to_string()))
        };
        let Some((is, inside)) = inner(vs, &text[vs..ve]) else {
            continue;
        };
        let param = if table == "params" { key } else { "" };
        for (pa, part) in split_top(&inside, is) {
            let Some(peq) = part.find('=') else {
                // An array's element (`variants = ["paper", ...]`).
                push(trimmed(pa, part), &[key], false);
                continue;
            };
            let k = part[..peq].trim();
            let (es, ee) = trimmed(pa + peq + 1, &part[peq + 1..]);
            push(trimmed(pa, &part[..peq]), &[param, k], true);
            push((es, ee), &[param, k], false);
            if let Some((ais, arr)) = inner(es, &text[es..ee]) {
                for (ea, elem) in split_top(&arr, ais) {
                    push(trimmed(ea, elem), &[param, k], false);
                }
            }
        }
    }
    let entries: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map(|(i, _)| i + 1)
        .collect();
    for s in &mut out {
        s.next_line = entries
            .iter()
            .copied()
            .find(|l| *l > s.line)
            .unwrap_or(text.lines().count() + 1);
    }
    out
}

/// Mutates one site of `text` with 1–4 random edits inside it (TOML punctuation, letters,
/// digits and hostile words; never a line break or a comment, so the entry stays one line).
/// Returns the text and the site's text after the edits.
fn mutate(rng: &mut Rng, text: &str, site: &Site) -> (String, String) {
    let alphabet = b"[]{}=\",.-_0123456789eE abcdefghijklmnopqrstuvwxyz+";
    let words: [&str; 14] = [
        "nan", "inf", "-inf", "-5", "0", "1e308", "levels", "dist", "\"grid\"", "[]", "{}", "é",
        "\"x\"", "true",
    ];
    let mut b = text.as_bytes()[site.start..site.end].to_vec();
    for _ in 0..1 + rng.below(4) {
        let pos = rng.below(b.len() + 1);
        match rng.below(5) {
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
            3 if !site.is_key => {
                // The whole value replaced by a hostile one.
                b = words[rng.below(words.len())].as_bytes().to_vec();
            }
            _ if pos < b.len() => b[pos] = alphabet[rng.below(alphabet.len())],
            _ => {}
        }
    }
    let edited = String::from_utf8_lossy(&b).into_owned();
    let out = format!("{}{}{}", &text[..site.start], edited, &text[site.end..]);
    (out, edited)
}

/// Whether a refusal of a mutation at `site` names it: one of the site's names (the top-level
/// key, or the parameter or the key of its table), or, for a mutated key, the key as the file now
/// spells it. A file that no longer parses as TOML is named by the parser's line: the mutated
/// line, or the next entry's (where an array left open is found to be unclosed).
fn names_the_site(msg: &str, site: &Site, edited: &str) -> bool {
    let edited = edited.trim().trim_matches('"');
    site.names.iter().any(|n| msg.contains(n.as_str()))
        || (site.is_key && !edited.is_empty() && msg.contains(edited))
        || (msg.contains("malformed TOML")
            && (site.line..=site.next_line).any(|l| msg.contains(&format!("at line {l},"))))
}

#[test]
fn study_and_parameter_files_never_panic_and_refusals_name_the_mutated_key() {
    let seeds = [
        DEFAULT_STUDY,
        include_str!("../../studies/grid_4axes.toml"),
        include_str!("../../studies/wide_structure.toml"),
        "[params]\npressure_kpa = { dist = \"levels\", levels = [200, 240, 280] }\n",
    ];
    let param_seeds = [
        "[params]\ng_mod = 0.9e6\nmu_s = 0.6\n",
        "[params]\nspeed_kmh = 120\n",
    ];
    let seed_sites: Vec<Vec<Site>> = seeds.iter().map(|t| sites(t)).collect();
    let param_sites: Vec<Vec<Site>> = param_seeds.iter().map(|t| sites(t)).collect();
    // The site finder sees every entry: the grid study's four axes with their keys and values.
    assert!(seed_sites[1]
        .iter()
        .any(|s| s.names == ["toe_deg", "levels"] && !s.is_key));
    assert!(seed_sites[0]
        .iter()
        .any(|s| s.names == ["seed"] && !s.is_key));
    let mut rng = Rng(13);
    let t0 = Instant::now();
    let (mut accepted, mut refused, mut by_text) = (0, 0, 0);
    for case in 0..4000 {
        let study = case % 4 != 3;
        let (seed, all) = if study {
            (seeds[case % seeds.len()], &seed_sites[case % seeds.len()])
        } else {
            (
                param_seeds[case % param_seeds.len()],
                &param_sites[case % param_seeds.len()],
            )
        };
        let site = &all[rng.below(all.len())];
        let (text, edited) = mutate(&mut rng, seed, site);
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
            Ok(Err(msg)) => {
                refused += 1;
                by_text += usize::from(!site.names.iter().any(|n| msg.contains(n.as_str())));
                assert!(
                    names_the_site(&msg, site, &edited),
                    "case {case}: `{msg}` names none of {:?} (mutated to `{edited}`); text:\n{text}",
                    site.names
                )
            }
            Ok(Ok(())) => accepted += 1,
        }
    }
    eprintln!(
        "{accepted} accepted, {refused} refused ({by_text} named by the mutated text or line)"
    );
    assert!(
        refused > 1000 && accepted > 100,
        "{accepted} accepted, {refused} refused"
    );
    // A hang guard, not a speed test: the cases take seconds.
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

/// The fixtures in a folder of their own (`name`): tests that run at once must not share it.
fn fixtures(name: &str) -> Fixtures {
    let dir = common::fresh_dir(name);
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

/// What a refusal of `args` may name: a flag of the line (not the harmless `--quiet` and
/// `--no-report`), a path on it (the study, the input, the output), the parameter of a `--set`
/// (or the assignment, when it has no name), or the stray argument after the command.
fn line_names(args: &[String]) -> Vec<String> {
    let mut names = Vec::new();
    for (i, a) in args.iter().enumerate().skip(1) {
        if a.starts_with("--") && a != "--quiet" && a != "--no-report" {
            names.push(a.clone());
        }
        if a.contains('/') {
            names.push(a.clone());
        }
        if args[i - 1] == "--set" {
            let name = a.split('=').next().unwrap_or("");
            names.push(if name.is_empty() {
                a.clone()
            } else {
                name.to_string()
            });
        }
    }
    // A stray argument right after the command (`simulate -5`).
    if args.len() > 1 && args[1].starts_with('-') && !args[1].starts_with("--") {
        names.push(args[1].clone());
    }
    names.retain(|n| !n.is_empty());
    names
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
fn command_lines_never_panic_or_hang_and_refusals_name_what_they_refuse() {
    let fx = fixtures("fuzz-cli");
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
                let names = line_names(&args);
                assert!(
                    names.iter().any(|n| stderr.contains(n.as_str())),
                    "refusal names none of {names:?}: polywear {line}\n{stderr}"
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

/// The values every numeric field of an input file is set to, one at a time.
const HOSTILE_NUMBERS: [&str; 10] = [
    "nan", "-nan", "inf", "-inf", "1e308", "-1e308", "0", "-5", "4.9e-324", "\"x\"",
];

#[test]
fn every_numeric_field_of_a_targets_file_or_a_table_takes_hostile_values_without_panic() {
    use polywear_study::calibrate::parse_problem;
    // Each numeric field of a targets file, with the key a refusal must name.
    let targets = "prior_sigma = 0.5\nfit = [\"g_mod\"]\n[params]\ng_mod = 0.9e6\n[choices]\nphi = [0.9, 0.94]\n[[target]]\nkind = \"hopf\"\nparam = \"speed_kmh\"\nfrom = 40\nto = 150\nvalue = 80\nweight = 1\ntolerance = 0.2\n[[target]]\nkind = \"frequency\"\nat = { speed_kmh = 100 }\nvalue = 270\n";
    let fields = [
        ("prior_sigma = 0.5", "prior_sigma = {}", "prior_sigma"),
        ("g_mod = 0.9e6", "g_mod = {}", "params.g_mod"),
        ("phi = [0.9, 0.94]", "phi = [0.9, {}]", "choices.phi[1]"),
        ("from = 40", "from = {}", "target[0]"),
        ("to = 150", "to = {}", "target[0]"),
        ("value = 80", "value = {}", "target[0]"),
        ("weight = 1", "weight = {}", "target[0].weight"),
        ("tolerance = 0.2", "tolerance = {}", "target[0].tolerance"),
        (
            "speed_kmh = 100",
            "speed_kmh = {}",
            "target[1].at.speed_kmh",
        ),
        ("value = 270", "value = {}", "target[1]"),
    ];
    let mut refused = 0;
    for (from, to, key) in fields {
        for x in HOSTILE_NUMBERS {
            let text = targets.replacen(from, &to.replace("{}", x), 1);
            let r = std::panic::catch_unwind(|| parse_problem(&text).map_err(|e| e.to_string()));
            match r {
                Err(_) => panic!("panic on {key} = {x}"),
                Ok(Err(msg)) => {
                    refused += 1;
                    assert!(msg.contains(key), "{key} = {x}: `{msg}` does not name it");
                }
                Ok(Ok(_)) => {}
            }
        }
    }
    assert!(refused > 60, "{refused} refused");
    // Each cell of a drive cycle and of an operating-point table.
    let dir = common::fresh_dir("fuzz-tables");
    std::fs::create_dir_all(&dir).unwrap();
    let cycle = "time_s,speed_kmh,load_n\n0,0,4000\n1,60,4000\n2,120,4200\n";
    for (row, line) in cycle.lines().enumerate().skip(1) {
        for col in 0..3 {
            for x in HOSTILE_NUMBERS {
                let mut cells: Vec<&str> = line.split(',').collect();
                cells[col] = x;
                let text = cycle.replacen(line, &cells.join(","), 1);
                let p = dir.join("c.csv");
                std::fs::write(&p, &text).unwrap();
                let r = std::panic::catch_unwind(|| {
                    polywear_study::cycle::DriveCycle::read(&p).map_err(|e| e.to_string())
                });
                match r {
                    Err(_) => panic!("panic on row {row} column {col} = {x}"),
                    Ok(Err(msg)) => assert!(
                        msg.contains("c.csv"),
                        "row {row} column {col} = {x}: `{msg}` does not name the file"
                    ),
                    Ok(Ok(_)) => {}
                }
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn links_devices_and_damaged_chunks_never_panic_or_hang() {
    let fx = fixtures("fuzz-links");
    let dir = &fx.dir;
    let fifo = dir.join("fifo");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: mkfifo on a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let link = dir.join("zero-link");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let hostile: Vec<String> = vec![
        "/dev/zero".into(),
        "/dev/null".into(),
        fifo.to_string_lossy().into_owned(),
        link.to_string_lossy().into_owned(),
        dir.to_string_lossy().into_owned(),
    ];
    let out = dir.join("o.csv").to_string_lossy().into_owned();
    let out_dir = dir.join("o").to_string_lossy().into_owned();
    for h in &hostile {
        for args in [
            vec![
                "explore".to_string(),
                h.clone(),
                "--out".into(),
                out_dir.clone(),
            ],
            vec!["cycle".into(), h.clone(), "--out".into(), out_dir.clone()],
            vec!["classify".into(), h.clone(), "--out".into(), out.clone()],
            vec!["calibrate".into(), h.clone(), "--out".into(), out.clone()],
            vec!["simulate".into(), "--params".into(), h.clone()],
        ] {
            let (code, stderr) = run_bounded(&args, Duration::from_secs(20));
            assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
            assert_eq!(code, 2, "{args:?}: {stderr}");
            assert!(stderr.contains(h.as_str()), "{args:?}: {stderr}");
        }
    }
    // Damaged chunks: bit flips and truncations, in the run's directory (refused by the journal)
    // and copied out of it (read as they are): exit 0 or 2, never a panic.
    let mut rng = Rng(33);
    let run = Path::new(&fx.explore_out);
    let chunks: Vec<PathBuf> = std::fs::read_dir(run)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "parquet"))
        .collect();
    for case in 0..16 {
        let in_run = case % 2 == 0;
        let target = if in_run {
            let copy = dir.join(format!("run{case}"));
            std::fs::create_dir_all(&copy).unwrap();
            for e in std::fs::read_dir(run).unwrap() {
                let p = e.unwrap().path();
                if p.is_file() {
                    std::fs::copy(&p, copy.join(p.file_name().unwrap())).unwrap();
                }
            }
            copy
        } else {
            let bare = dir.join(format!("bare{case}"));
            std::fs::create_dir_all(&bare).unwrap();
            for c in &chunks {
                std::fs::copy(c, bare.join(c.file_name().unwrap())).unwrap();
            }
            bare
        };
        let victim = target.join(chunks[rng.below(chunks.len())].file_name().unwrap());
        let mut bytes = std::fs::read(&victim).unwrap();
        if rng.below(3) == 0 {
            bytes.truncate(rng.below(bytes.len()));
        } else {
            for _ in 0..1 + rng.below(3) {
                let at = rng.below(bytes.len());
                bytes[at] ^= 1 << rng.below(8);
            }
        }
        std::fs::write(&victim, &bytes).unwrap();
        let args = vec!["analyze".to_string(), target.to_string_lossy().into_owned()];
        let (code, stderr) = run_bounded(&args, Duration::from_secs(60));
        assert!(!stderr.contains("panicked"), "case {case}: {stderr}");
        if in_run {
            assert_eq!(
                code, 2,
                "case {case}: a damaged chunk in its run is refused: {stderr}"
            );
            assert!(stderr.contains("explore --resume"), "case {case}: {stderr}");
        } else {
            assert!(code == 0 || code == 2, "case {case}: exit {code}: {stderr}");
        }
    }
    std::fs::remove_dir_all(dir).ok();
}
