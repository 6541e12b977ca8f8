//! The documents hold together: every `NAME.md#anchor` cited in code, studies and documents names
//! a heading that exists, every citation of MODEL.md in code names a section, no file points
//! outside the repository (only `.ci/` may reach the shared reference copy), MODEL.md's parameter
//! table is what `polywear params --markdown` prints, the book's output-column table is what
//! `records::columns_markdown()` prints, every page of the book is in its SUMMARY.md, and every
//! command of `polywear --help` has a row in README's command table and a reference page of its
//! own in the book.

use crate::common;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The book's pages (mdBook's `src`), from the repository's root.
const BOOK: &str = "docs/book/src";

/// The text files of the project: root documents and manifests, and every file under the source
/// (`src/` and the workspace's `crates/`),
/// test, bench, study, example and docs folders, the book's pages (`docs/book/src/`) among them
/// (outputs under `data/` and `target/` excluded).
fn project_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else {
                out.push(p);
            }
        }
    }
    let r = root();
    let mut files = Vec::new();
    for d in [
        "src", "crates", "tests", "benches", "studies", "examples", "docs", ".ci",
    ] {
        walk(&r.join(d), &mut files);
    }
    for e in std::fs::read_dir(&r).unwrap().flatten() {
        let p = e.path();
        let hidden = e.file_name().to_string_lossy().starts_with('.');
        if p.is_file() && !hidden {
            files.push(p);
        }
    }
    files.push(r.join("data/README.md"));
    files.retain(|p| std::fs::read_to_string(p).is_ok());
    files.sort();
    files
}

fn is_markdown(p: &Path) -> bool {
    p.extension().is_some_and(|e| e == "md")
}

fn rel(p: &Path) -> String {
    p.strip_prefix(root()).unwrap().display().to_string()
}

/// GitHub's anchor for a heading: lower case, punctuation dropped (letters, digits, spaces,
/// hyphens and underscores kept), spaces turned into hyphens.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a Markdown file's headings (outside fenced code blocks).
fn anchors(markdown: &str) -> BTreeSet<String> {
    let mut fenced = false;
    let mut out = BTreeSet::new();
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if !fenced && line.starts_with('#') {
            out.insert(anchor(line.trim_start_matches('#')));
        }
    }
    out
}

/// One cited section: the document's path as written, the anchor, and whether the citation is
/// a Markdown link's target (`[text](../../../../MODEL.md#variants)`).
struct Citation {
    doc: String,
    anchor: String,
    link: bool,
}

/// Every `PATH.md#anchor` in a text (the path with its folders, `../` included), and every bare
/// `#step-...` that continues a MODEL.md citation ("MODEL.md#step-1-deflection to
/// #step-3-tread-block").
fn citations(text: &str) -> Vec<Citation> {
    let mut out = Vec::new();
    let bytes = text.as_bytes();
    let word = |c: u8| c.is_ascii_alphanumeric() || c == b'-' || c == b'_';
    let path_char = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '/' | '.');
    for (i, _) in text.match_indices(".md#") {
        let start = text[..i]
            .char_indices()
            .rev()
            .find(|(_, c)| !path_char(*c))
            .map_or(0, |(s, c)| s + c.len_utf8());
        let mut end = i + 4;
        while end < bytes.len() && word(bytes[end]) {
            end += 1;
        }
        out.push(Citation {
            doc: text[start..i + 3].to_string(),
            anchor: text[i + 4..end].to_string(),
            link: text[..start].ends_with("]("),
        });
    }
    for (i, _) in text.match_indices(" #step-") {
        let mut end = i + 2;
        while end < bytes.len() && word(bytes[end]) {
            end += 1;
        }
        out.push(Citation {
            doc: "MODEL.md".into(),
            anchor: text[i + 2..end].to_string(),
            link: false,
        });
    }
    out
}

#[test]
fn every_cited_section_exists() {
    let files = project_files();
    assert!(
        files.iter().any(|f| rel(f) == format!("{BOOK}/SUMMARY.md")),
        "the scan does not reach the book's pages ({BOOK}/)"
    );
    let mut bad = Vec::new();
    let mut n = 0;
    for f in files {
        if rel(&f) == "tests/integration/docs.rs" {
            continue;
        }
        let text = std::fs::read_to_string(&f).unwrap();
        for c in citations(&text) {
            // A Markdown link resolves from the citing document's folder, as GitHub resolves it
            // (a book page reaches MODEL.md as ../../../../MODEL.md); code, studies and running
            // text name the path from the repository's root (MODEL.md#variants,
            // docs/book/src/reference/explore.md#explore).
            let base = if c.link && is_markdown(&f) {
                f.parent().unwrap().to_path_buf()
            } else {
                root()
            };
            let ok = std::fs::read_to_string(base.join(&c.doc))
                .map(|t| anchors(&t).contains(&c.anchor))
                .unwrap_or(false);
            n += 1;
            if !ok {
                bad.push(format!("{}: {}#{}", rel(&f), c.doc, c.anchor));
            }
        }
        // Links within one Markdown document: [text](#anchor).
        if is_markdown(&f) {
            let own = anchors(&text);
            for (i, _) in text.match_indices("](#") {
                let a: String = text[i + 3..].chars().take_while(|c| *c != ')').collect();
                n += 1;
                if !own.contains(&a) {
                    bad.push(format!("{}: #{a}", rel(&f)));
                }
            }
        }
    }
    assert!(
        n > 50,
        "only {n} citations found: is the scan looking in the right places?"
    );
    assert!(
        bad.is_empty(),
        "citations of missing sections:\n{}",
        bad.join("\n")
    );
}

#[test]
fn code_cites_model_md_by_section() {
    let mut bad = Vec::new();
    for f in project_files() {
        let r = rel(&f);
        if r.ends_with(".md") || r == "tests/integration/docs.rs" || r == "CITATION.cff" {
            continue;
        }
        let text = std::fs::read_to_string(&f).unwrap();
        for (no, line) in text.lines().enumerate() {
            for (i, _) in line.match_indices("MODEL.md") {
                if !line[i + 8..].starts_with('#') {
                    bad.push(format!("{r}:{}: {}", no + 1, line.trim()));
                }
            }
        }
    }
    assert!(
        bad.is_empty(),
        "MODEL.md cited without a section:\n{}",
        bad.join("\n")
    );
}

#[test]
fn nothing_points_outside_the_repository() {
    let mut bad = Vec::new();
    for f in project_files() {
        let r = rel(&f);
        if r.starts_with(".ci/") || r == "tests/integration/docs.rs" {
            continue;
        }
        let text = std::fs::read_to_string(&f).unwrap();
        for (no, line) in text.lines().enumerate() {
            if ["../shared", "/work/", "seed/000_"]
                .iter()
                .any(|s| line.contains(s))
            {
                bad.push(format!("{r}:{}: {}", no + 1, line.trim()));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "references outside the repository:\n{}",
        bad.join("\n")
    );
}

#[test]
fn markdown_links_point_at_files_that_exist() {
    let mut bad = Vec::new();
    for f in project_files() {
        if !is_markdown(&f) {
            continue;
        }
        let text = std::fs::read_to_string(&f).unwrap();
        for (i, _) in text.match_indices("](") {
            let target: String = text[i + 2..]
                .chars()
                .take_while(|c| !matches!(c, ')' | '#' | ' '))
                .collect();
            if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            if !f.parent().unwrap().join(&target).exists() {
                bad.push(format!("{}: {target}", rel(&f)));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "links to missing files:\n{}",
        bad.join("\n")
    );
}

#[test]
fn model_md_parameter_table_is_current() {
    let (code, table, _) = common::polywear(&["params", "--markdown"]);
    assert_eq!(code, 0);
    let model = std::fs::read_to_string(root().join("MODEL.md")).unwrap();
    assert!(
        model.contains(&table),
        "MODEL.md's parameter table differs from `polywear params --markdown`:\n{table}"
    );
}

/// MODEL.md's field-fact table is the shipped data file's, and the file is the one the code reads.
#[test]
fn model_md_field_fact_table_is_the_data_file() {
    let file =
        std::fs::read_to_string(root().join(polywear_study::field_facts::SHIPPED_NAME)).unwrap();
    assert_eq!(file, polywear_study::field_facts::SHIPPED);
    let table = polywear_study::field_facts::FieldFacts::shipped().markdown();
    let model = std::fs::read_to_string(root().join("MODEL.md")).unwrap();
    assert!(
        model.contains(&table),
        "MODEL.md's field-fact table differs from data/field_facts.toml:\n{table}"
    );
}

#[test]
fn book_output_column_table_is_the_column_table() {
    let table = polywear::records::columns_markdown();
    let page = format!("{BOOK}/reference/output-files.md");
    let text = std::fs::read_to_string(root().join(&page)).unwrap();
    assert!(
        text.contains(&table),
        "{page}'s output-column table differs from polywear::records::columns_markdown():\n{table}"
    );
}

/// mdBook renders only the pages its SUMMARY.md lists: a page left out would read on GitHub but
/// be missing from the book.
#[test]
fn every_book_page_is_in_the_summary() {
    let book = root().join(BOOK);
    let summary = std::fs::read_to_string(book.join("SUMMARY.md")).unwrap();
    let mut missing = Vec::new();
    let mut pages = 0;
    for f in project_files() {
        let Ok(page) = f.strip_prefix(book.as_path()) else {
            continue;
        };
        if !is_markdown(&f) || page == Path::new("SUMMARY.md") {
            continue;
        }
        pages += 1;
        let page = page.display().to_string();
        if !summary.contains(&format!("]({page})")) {
            missing.push(page);
        }
    }
    assert!(pages > 20, "only {pages} pages found under {BOOK}/");
    assert!(
        missing.is_empty(),
        "pages of {BOOK}/ that its SUMMARY.md does not list:\n{}",
        missing.join("\n")
    );
}

#[test]
fn every_command_is_in_the_readme_table_and_the_book() {
    let (code, help, _) = common::polywear(&["--help"]);
    assert_eq!(code, 0);
    let commands: Vec<&str> = help
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(commands.len() >= 9, "{help}");
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let summary = std::fs::read_to_string(root().join(BOOK).join("SUMMARY.md")).unwrap();
    let mut missing = Vec::new();
    for c in commands {
        if !readme.contains(&format!("| `polywear {c}")) {
            missing.push(format!(
                "README.md: no row `| `polywear {c}...` in the command table"
            ));
        }
        // Each command has a reference page of its own, which shows it, in the book's contents.
        let page = format!("{BOOK}/reference/{c}.md");
        match std::fs::read_to_string(root().join(&page)) {
            Ok(text) if text.contains(&format!("polywear {c}")) => {}
            Ok(_) => missing.push(format!("{page}: `polywear {c}` never shown")),
            Err(_) => missing.push(format!("{page}: no reference page for `polywear {c}`")),
        }
        if !summary.contains(&format!("(reference/{c}.md)")) {
            missing.push(format!("{BOOK}/SUMMARY.md: reference/{c}.md not listed"));
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}
