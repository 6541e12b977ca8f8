//! Nothing written where it should not be, nothing read that was damaged: a link planted at
//! every file name a command writes is replaced, never followed (its target stays as it was);
//! devices, FIFOs and directories given as input files are refused at once; a damaged chunk is
//! refused by analyze with the file and the way to recover; a full disk and a read-only folder
//! say what is saved and how to go on.

use std::os::unix::fs::symlink;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::common::{fresh_dir, polywear, polywear_within, Mount};
use crate::parquet_rows;

const STUDY: &str = r#"name = "links"
seed = 3
samples = 60
chunk_size = 20
variants = ["paper", "sliding_share"]
[params]
speed_kmh = { dist = "uniform", min = 60, max = 250 }
toe_deg = { dist = "uniform", min = 0.1, max = 0.5 }
load_n = { dist = "uniform", min = 3000, max = 5000 }
pressure_kpa = { dist = "uniform", min = 200, max = 300 }
"#;

/// Every file under `dir`, as paths relative to it.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    out.sort();
    out
}

/// Targets of planted links, each holding a sentinel; checked untouched at the end.
struct Targets {
    dir: PathBuf,
    /// Each planted link and what its target holds.
    planted: Vec<(PathBuf, Vec<u8>)>,
}

impl Targets {
    fn new(dir: &Path) -> Targets {
        let dir = dir.join("targets");
        std::fs::create_dir_all(&dir).unwrap();
        Targets {
            dir,
            planted: Vec::new(),
        }
    }

    /// Plants a link at `at` (replacing what is there) to a fresh file holding `content`.
    fn plant_holding(&mut self, at: &Path, content: Vec<u8>) {
        let target = self.dir.join(format!("t{}", self.planted.len()));
        std::fs::write(&target, &content).unwrap();
        if std::fs::symlink_metadata(at).is_ok() {
            std::fs::remove_file(at).unwrap();
        }
        std::fs::create_dir_all(at.parent().unwrap()).unwrap();
        symlink(&target, at).unwrap();
        self.planted.push((at.to_path_buf(), content));
    }

    /// Plants a link at `at` to a sentinel file.
    fn plant(&mut self, at: &Path) {
        let sentinel = format!("sentinel {}", self.planted.len()).into_bytes();
        self.plant_holding(at, sentinel);
    }

    /// Plants a link at `at` and at its temporary name `_NAME.partial`.
    fn plant_with_partial(&mut self, at: &Path) {
        self.plant(at);
        let name = at.file_name().unwrap().to_string_lossy();
        self.plant(&at.with_file_name(format!("_{name}.partial")));
    }

    /// Every target holds what it held, no file appeared beside them, and every planted name
    /// that still exists is a file (no temporary name is left).
    fn check(&self, what: &str) {
        self.check_targets(what);
        for (at, _) in &self.planted {
            if let Ok(m) = std::fs::symlink_metadata(at) {
                assert!(
                    !m.file_type().is_symlink(),
                    "{what}: {} is still a link",
                    at.display()
                );
                assert!(
                    !at.to_string_lossy().ends_with(".partial"),
                    "{what}: {} is left behind",
                    at.display()
                );
            }
        }
    }

    /// Every target holds what it held and no file appeared beside them (for a refusal, which
    /// leaves the links where they are).
    fn check_targets(&self, what: &str) {
        for (i, (at, content)) in self.planted.iter().enumerate() {
            let t = self.dir.join(format!("t{i}"));
            assert_eq!(
                &std::fs::read(&t).unwrap(),
                content,
                "{what}: the link at {} was written through",
                at.display()
            );
        }
        assert_eq!(
            files_under(&self.dir).len(),
            self.planted.len(),
            "{what}: a file was created beside the targets"
        );
    }
}

/// Runs `args(out)` once into a clean folder to learn the file names it writes, then again into
/// a folder where a link is planted at each of them (and at each temporary name): the command
/// must succeed, write the same names, and leave every link's target as it was.
fn links_are_replaced(name: &str, args: impl Fn(&Path) -> Vec<String>) {
    let dir = fresh_dir(&format!("links-{name}"));
    let clean = dir.join("clean");
    std::fs::create_dir_all(&clean).unwrap();
    let run = |out: &Path| {
        let a = args(out);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        polywear(&a)
    };
    let (code, _, stderr) = run(&clean);
    assert_eq!(code, 0, "{name}: {stderr}");
    let written = files_under(&clean);
    assert!(!written.is_empty(), "{name} wrote nothing");
    let hostile = dir.join("hostile");
    let mut targets = Targets::new(&dir);
    for f in &written {
        targets.plant_with_partial(&hostile.join(f));
    }
    let (code, _, stderr) = run(&hostile);
    assert_eq!(code, 0, "{name} with links planted: {stderr}");
    targets.check(name);
    assert_eq!(files_under(&hostile), written, "{name}: the same files");
    std::fs::remove_dir_all(&dir).ok();
}

fn s(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

#[test]
fn a_link_at_any_name_a_command_writes_is_replaced_never_followed() {
    let dir = fresh_dir("links-inputs");
    std::fs::create_dir_all(&dir).unwrap();
    let cycle = dir.join("cycle.csv");
    std::fs::write(&cycle, "time_s,speed_kmh\n0,0\n1,60\n2,120\n3,150\n").unwrap();
    let points = dir.join("points.csv");
    std::fs::write(&points, "speed_kmh,toe_deg\n100,0.3\n140,0.2\n").unwrap();
    let targets = dir.join("targets.toml");
    std::fs::write(
        &targets,
        "fit = [\"g_mod\"]\n[[target]]\nkind = \"frequency\"\nat = { speed_kmh = 100 }\nvalue = 270\ntolerance = 0.2\n",
    )
    .unwrap();
    let v = |xs: &[&str]| xs.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    links_are_replaced("simulate", |o| {
        let mut a = v(&["simulate", "--out"]);
        a.push(s(&o.join("ts.parquet")));
        a.push("--plot".into());
        a.push(s(&o.join("point.png")));
        a
    });
    links_are_replaced("cycle", |o| {
        vec!["cycle".into(), s(&cycle), "--out".into(), s(&o.join("cyc"))]
    });
    links_are_replaced("wear", |o| {
        v(&["wear", "--quiet", "--distance-km", "20", "--out"])
            .into_iter()
            .chain([s(&o.join("wear"))])
            .collect()
    });
    links_are_replaced("classify", |o| {
        vec![
            "classify".into(),
            s(&points),
            "--out".into(),
            s(&o.join("points.parquet")),
        ]
    });
    links_are_replaced("calibrate", |o| {
        vec![
            "calibrate".into(),
            s(&targets),
            "--out".into(),
            s(&o.join("fit.toml")),
        ]
    });
    links_are_replaced("chart", |o| {
        let mut a = v(&[
            "chart",
            "--x",
            "speed_kmh",
            "--x-from",
            "60",
            "--x-to",
            "200",
            "--y",
            "toe_deg",
            "--y-from",
            "0.1",
            "--y-to",
            "0.5",
            "--out",
        ]);
        a.push(s(&o.join("chart.parquet")));
        a
    });
    links_are_replaced("bifurcation", |o| {
        let mut a = v(&[
            "bifurcation",
            "--param",
            "speed_kmh",
            "--from",
            "60",
            "--to",
            "200",
            "--steps",
            "8",
            "--out",
        ]);
        a.push(s(&o.join("bif")));
        a
    });
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn explore_and_analyze_never_write_through_a_link_in_the_run_directory() {
    let dir = fresh_dir("links-explore");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("links.toml");
    std::fs::write(&study, STUDY).unwrap();
    let clean = dir.join("clean");
    let (code, _, stderr) = polywear(&["explore", &s(&study), "--out", &s(&clean), "-q"]);
    assert_eq!(code, 0, "{stderr}");
    // The same run, one chunk missing as after a kill, with links at every name resume and the
    // report write: the lock, the journal, the chunks, the report's files, each temporary name.
    let hostile = dir.join("hostile");
    std::fs::create_dir_all(&hostile).unwrap();
    for f in files_under(&clean) {
        let to = hostile.join(&f);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(clean.join(&f), &to).unwrap();
    }
    let mut targets = Targets::new(&dir);
    targets.plant(&hostile.join("_lock"));
    let (code, _, stderr) = polywear(&["explore", "--resume", "--out", &s(&hostile), "-q"]);
    assert_eq!(code, 2, "a lock that is a link is refused: {stderr}");
    assert!(stderr.contains("symbolic link"), "{stderr}");
    targets.check_targets("explore, lock");
    std::fs::remove_file(hostile.join("_lock")).unwrap();
    targets.planted.clear();
    std::fs::remove_dir_all(&targets.dir).unwrap();
    std::fs::create_dir_all(&targets.dir).unwrap();
    std::fs::remove_file(hostile.join("chunk-0000001.parquet")).unwrap();
    // The journal's link leads to the journal itself, so that the run is found and resumed.
    let journal = hostile.join("_manifest.chunks.jsonl");
    let recorded = std::fs::read(&journal).unwrap();
    targets.plant_holding(&journal, recorded);
    targets.plant(&hostile.join("__manifest.chunks.jsonl.partial"));
    for f in files_under(&clean) {
        let name = f.to_string_lossy();
        if name.starts_with("chunk-") || name.starts_with("_report/") {
            targets.plant_with_partial(&hostile.join(&f));
        }
    }
    let (code, _, stderr) = polywear(&["explore", "--resume", "--out", &s(&hostile), "-q"]);
    assert_eq!(code, 0, "{stderr}");
    targets.check("explore --resume and its report");
    assert_eq!(
        parquet_rows::rows_in_dir(&[&hostile]),
        parquet_rows::rows_in_dir(&[&clean]),
        "the resumed rows equal the clean run's"
    );
    // A report folder that is a link is refused.
    std::fs::remove_dir_all(hostile.join("_report")).unwrap();
    symlink(&targets.dir, hostile.join("_report")).unwrap();
    let (code, _, stderr) = polywear(&["analyze", &s(&hostile)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("symbolic link"), "{stderr}");
    std::fs::remove_file(hostile.join("_report")).unwrap();
    targets.check_targets("analyze into a linked _report");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn devices_fifos_directories_and_huge_files_are_refused_at_once() {
    let dir = fresh_dir("reads");
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("fifo");
    let c = std::ffi::CString::new(s(&fifo)).unwrap();
    // SAFETY: mkfifo on a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let huge = dir.join("huge.toml");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len(17 << 20)
        .unwrap();
    let zero = dir.join("zero.toml");
    std::fs::write(
        &zero,
        "samples = 10\n[operating_points]\nfile = \"/dev/zero\"\n",
    )
    .unwrap();
    let dir_s = s(&dir);
    let fifo_s = s(&fifo);
    let out_s = s(&dir.join("out.csv"));
    let limit = Duration::from_secs(20);
    for (args, needle) in [
        (
            vec!["explore", &s(&zero)],
            "/dev/zero: is a character device",
        ),
        (vec!["explore", &fifo_s], "FIFO"),
        (vec!["explore", &s(&huge)], "16 MiB"),
        (vec!["simulate", "--params", &dir_s], "is a directory"),
        (
            vec!["cycle", "/dev/zero", "--out", &out_s],
            "character device",
        ),
        (vec!["classify", &fifo_s, "--out", &out_s], "FIFO"),
        (vec!["calibrate", "/dev/zero"], "character device"),
    ] {
        let (code, _, stderr) = polywear_within(limit, &args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(
            stderr.contains(needle),
            "{args:?}: `{needle}` not in {stderr}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_damaged_chunk_is_refused_by_analyze_with_the_file_and_the_way_back() {
    let dir = fresh_dir("damaged");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("links.toml");
    std::fs::write(&study, STUDY).unwrap();
    let run = dir.join("run");
    let (code, _, stderr) = polywear(&[
        "explore",
        &s(&study),
        "--out",
        &s(&run),
        "-q",
        "--no-report",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let chunk = run.join("chunk-0000001.parquet");
    let mut bytes = std::fs::read(&chunk).unwrap();
    // One bit of a value, not of the footer: the file still reads, with a changed value.
    let at = bytes.len() / 3;
    bytes[at] ^= 0x10;
    std::fs::write(&chunk, &bytes).unwrap();
    let (code, _, stderr) = polywear(&["analyze", &s(&run)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("chunk-0000001.parquet")
            && stderr.contains("CRC-32")
            && stderr.contains("explore --resume --out"),
        "{stderr}"
    );
    // The way back works: resume redoes the chunk, and analyze accepts the run.
    let (code, _, stderr) = polywear(&["explore", "--resume", "--out", &s(&run), "-q"]);
    assert_eq!(code, 0, "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_full_disk_says_what_is_saved_and_the_exact_resume_command() {
    let dir = fresh_dir("full-disk");
    let Some(_m) = Mount::tmpfs(&dir, "160k", false) else {
        return;
    };
    let study = dir.join("big.toml");
    std::fs::write(
        &study,
        STUDY
            .replace("samples = 60", "samples = 4000")
            .replace("chunk_size = 20", "chunk_size = 200"),
    )
    .unwrap();
    let out = dir.join("run");
    let (code, _, stderr) = polywear(&["explore", &s(&study), "--out", &s(&out), "-q"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("the disk is full")
            && stderr.contains("samples are saved in")
            && stderr.contains("resume with: ")
            && stderr.contains(&format!("explore --resume --out {}", out.display())),
        "{stderr}"
    );
}

#[test]
fn a_read_only_folder_is_named_with_the_flag_that_chooses_another() {
    let dir = fresh_dir("read-only");
    let ro = dir.join("ro");
    let Some(_m) = Mount::tmpfs(&ro, "1m", true) else {
        return;
    };
    let out = ro.join("run");
    let (code, _, stderr) = polywear(&["explore", "--samples", "10", "--out", &s(&out), "-q"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("read-only") && stderr.contains(&s(&ro)) && stderr.contains("--out"),
        "{stderr}"
    );
    let (code, _, stderr) = polywear(&["simulate", "--out", &s(&ro.join("ts.parquet"))]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("read-only") && stderr.contains("--out"),
        "{stderr}"
    );
}

#[test]
fn what_cannot_be_sampled_or_integrated_is_refused_up_front() {
    use polywear::study::Study;
    let refused = |text: &str, needle: &str| {
        let e = Study::parse(text).unwrap_err().to_string();
        assert!(e.contains(needle), "`{needle}` not in `{e}` for\n{text}");
    };
    // A drawn mu_s above a fixed mu_m, or two draws that can cross, by their bounds.
    refused(
        "[params]\nmu_s = { dist = \"uniform\", min = 0.5, max = 0.9 }\n",
        "`params.mu_s` is drawn up to 0.9 and `mu_m` is fixed at 0.76",
    );
    refused(
        "[params]\nmu_s = { dist = \"uniform\", min = 0.5, max = 0.7 }\nmu_m = { dist = \"levels\", levels = [0.65, 0.8] }\n",
        "`params.mu_m` is drawn down to 0.65",
    );
    refused(
        "[params]\nn_driven = { dist = \"levels\", levels = [2, 6] }\n",
        "`params.n_driven` is drawn up to 6 and `n_wheels` is fixed at 4",
    );
    assert!(
        Study::parse("[params]\nmu_s = { dist = \"uniform\", min = 0.5, max = 0.7 }\n").is_ok()
    );
    refused(
        "[operating_points]\nfile = \"\"\n",
        "`operating_points.file` is empty",
    );
    // A drive cycle whose duration overflows.
    let dir = fresh_dir("sums");
    std::fs::create_dir_all(&dir).unwrap();
    let cycle = dir.join("c.csv");
    std::fs::write(&cycle, "time_s,speed_kmh\n0,10\n1e308,20\n").unwrap();
    let e = polywear_study::cycle::DriveCycle::read(&cycle)
        .unwrap_err()
        .to_string();
    assert!(e.contains("total time is not finite"), "{e}");
    std::fs::write(&cycle, "time_s,speed_kmh\n-1e308,10\n1e308,20\n").unwrap();
    let e = polywear_study::cycle::DriveCycle::read(&cycle)
        .unwrap_err()
        .to_string();
    assert!(e.contains("step duration is not finite"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_small_chunk_size_is_warned_about_with_its_measured_cost() {
    let dir = fresh_dir("chunk-warning");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("s.toml");
    std::fs::write(&study, STUDY.replace("chunk_size = 20", "chunk_size = 30")).unwrap();
    let (code, _, stderr) = polywear(&[
        "explore",
        &s(&study),
        "--out",
        &s(&dir.join("run")),
        "--no-report",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("warning: chunk_size = 30 is below 64") && stderr.contains("30x"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A cycle too long to hold is refused in a second, before its cells are read (a 10-million-row
/// file took 2.5 GB and 30 s without a word); so is one that, over many tire structures,
/// would be; a cycle that is run says its progress in steps.
#[test]
fn a_cycle_too_long_to_hold_is_refused_at_once_and_a_long_one_says_its_progress() {
    let dir = fresh_dir("long_cycle");
    std::fs::create_dir_all(&dir).unwrap();
    let cycle = dir.join("long.csv");
    let mut text = String::from("time_s,speed_kmh\n");
    for i in 0..1_000_001u32 {
        text.push_str(&format!("{i},100\n"));
    }
    std::fs::write(&cycle, text).unwrap();
    let out = dir.join("out");
    let (code, _, stderr) = polywear_within(
        Duration::from_secs(20),
        &["cycle", &s(&cycle), "--out", &s(&out)],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("1,000,001 rows; accepted at most 1,000,000")
            && stderr.contains("resample"),
        "{stderr}"
    );
    assert!(!out.exists());
    let wltc = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/cycles/wltc_class3b.csv");
    let study = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/default.toml");
    let (code, _, stderr) = polywear_within(
        Duration::from_secs(20),
        &[
            "cycle",
            &s(&wltc),
            "--study",
            &s(&study),
            "--structure-samples",
            "600",
            "--out",
            &s(&out),
        ],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("1,801 steps x 600 tire structure(s) = 1,080,600 step evaluations")
            && stderr.contains("fewer --structure-samples"),
        "{stderr}"
    );
    assert!(!out.exists());
    // Run, its stderr is a log: progress lines in steps (the first comes after 10 s, so a
    // short cycle shows none; the line's form is held by the unit test of ProgressLog).
    let short = dir.join("short.csv");
    std::fs::write(&short, "time_s,speed_kmh\n0,100\n1,100\n").unwrap();
    let (code, stdout, stderr) = polywear_within(
        Duration::from_secs(60),
        &["cycle", &s(&short), "--no-wear", "--out", &s(&out)],
    );
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("2 steps"), "{stdout}");
    std::fs::remove_dir_all(&dir).ok();
}
