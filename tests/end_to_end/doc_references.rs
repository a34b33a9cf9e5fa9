//! Every file the documentation and the doc comments cite exists in the repository.
//!
//! Scans the Markdown files and the Rust sources of the workspace for paths to repository
//! files (`docs/protocol.md`, `deploy/prob2.toml`, `rt-core/src/cycle.rs`, ...) and for
//! relative Markdown links, and fails naming every citation that does not resolve. A bare file
//! name ending in `.md` (e.g. `SOMETHING.md`) must resolve too: at the root or under `docs/`.

use std::path::{Path, PathBuf};

/// Top-level folders whose files may be cited.
const ROOTS: &[&str] = &[
    "docs/",
    "deploy/",
    "scripts/",
    "shared/",
    "rt-core/",
    "gateway/",
    "bus/",
    "sim/",
    "dynamics/",
    "kinematics/",
    "src/",
    "tests/",
    "bench/",
    "client/",
    "capi/",
    "examples/",
    "python/",
    ".ci/",
];
const EXTENSIONS: &[&str] = &[".md", ".rs", ".toml", ".sh", ".service", ".py"];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        let name = e.file_name();
        let name = name.to_string_lossy();
        if p.is_dir() {
            // vendor/ holds other projects' sources as published, citing their own files.
            if name != "target" && name != "vendor" && !name.starts_with('.') || name == ".ci" {
                sources(&p, out);
            }
        } else if name.ends_with(".rs") || name.ends_with(".md") {
            out.push(p);
        }
    }
}

fn is_path_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/')
}

/// The path-like words of a text that end in one of [`EXTENSIONS`].
fn cited(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    for word in text.split(|c: char| !is_path_char(c)) {
        let word = word.trim_end_matches('.');
        if !EXTENSIONS.iter().any(|e| word.ends_with(e)) || word.starts_with('.') {
            continue;
        }
        let rooted = ROOTS.iter().any(|r| word.starts_with(r));
        let bare_doc = !word.contains('/') && word.ends_with(".md");
        if rooted || bare_doc {
            found.push(word.to_string());
        }
    }
    found
}

fn resolves(root: &Path, citing: &Path, word: &str) -> bool {
    if word.contains('/') {
        root.join(word).exists() || citing.parent().is_some_and(|d| d.join(word).exists())
    } else {
        root.join(word).exists()
            || root.join("docs").join(word).exists()
            || citing.parent().is_some_and(|d| d.join(word).exists())
    }
}

#[test]
fn every_cited_file_exists() {
    let root = repo();
    let mut files = Vec::new();
    sources(&root, &mut files);
    assert!(
        files.len() > 50,
        "the scan found only {} files under {}",
        files.len(),
        root.display()
    );
    let mut missing = Vec::new();
    let mut checked = 0;
    // This file names missing files on purpose, in its own tests.
    let this = root.join(file!());
    for f in files.iter().filter(|f| **f != this) {
        let text = std::fs::read_to_string(f).unwrap_or_default();
        for (n, line) in text.lines().enumerate() {
            for word in cited(line) {
                checked += 1;
                if !resolves(&root, f, &word) {
                    missing.push(format!(
                        "{}:{}: `{word}`",
                        f.strip_prefix(&root).unwrap_or(f).display(),
                        n + 1
                    ));
                }
            }
        }
    }
    assert!(
        checked > 20,
        "only {checked} citations found: the scan is broken"
    );
    assert!(
        missing.is_empty(),
        "citations of files that are not in the repository:\n{}",
        missing.join("\n")
    );
}

#[test]
fn the_scanner_finds_paths_and_bare_documents() {
    assert_eq!(
        cited("see `docs/protocol.md`, \"Status\" and deploy/prob2.toml."),
        ["docs/protocol.md", "deploy/prob2.toml"]
    );
    assert_eq!(cited("as DRIVE_PROFILE.md says"), ["DRIVE_PROFILE.md"]);
    assert!(cited("https://example.org/docs/x.md and lib.rs").is_empty());
}
