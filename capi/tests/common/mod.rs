//! What the test crates of `capi/tests/` share: the check of a generated, checked-in file (or
//! its update, never under CI) and the skip of a test that lacks a tool (a failure under CI),
//! both saying so on stderr past the test harness's output capture.

#![allow(dead_code)]

use std::io::Write;
use std::path::Path;

/// Say that `test` is skipped because `why`, or fail when the environment variable `CI` is
/// set: CI must run every test. The message goes straight to stderr, so that it shows also when
/// the test passes (`eprintln!` would be captured and dropped). The caller returns right after.
pub fn skip(test: &str, why: &str) {
    if std::env::var_os("CI").is_some() {
        panic!("{test} cannot run: {why}; CI is set, where a skipped test is a failure");
    }
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED {test}: {why} (with CI set this is a failure)"
    );
}

/// Where `old` and `new` first differ (1-based line) and their lengths, for a message.
pub fn difference(old: &str, new: &str) -> String {
    let (a, b): (Vec<&str>, Vec<&str>) = (old.lines().collect(), new.lines().collect());
    match (0..a.len().max(b.len())).find(|&i| a.get(i) != b.get(i)) {
        None => "the same lines".to_string(),
        Some(i) => format!(
            "first difference at line {}: {:?} became {:?}; {} lines became {}",
            i + 1,
            a.get(i).unwrap_or(&"(end of file)"),
            b.get(i).unwrap_or(&"(end of file)"),
            a.len(),
            b.len()
        ),
    }
}

/// The checked-in file `file` (a path from the repository's root) must be `generated` (what
/// `source` generates now). With the environment variable `update` set the file is written
/// instead (when it differs) and the run says what changed, comparing nothing; `update` under
/// `CI` is refused, so that CI always compares. `command` is the test command that regenerates
/// the file with `update` set.
pub fn check_generated(file: &str, source: &str, generated: &str, update: &str, command: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(file);
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    if std::env::var_os(update).is_some() {
        assert!(
            std::env::var_os("CI").is_none(),
            "{update} is set together with CI: CI compares {file}, it never writes it"
        );
        let news = if checked_in == generated {
            "unchanged".to_string()
        } else {
            std::fs::write(&path, generated)
                .unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
            format!("written: {}", difference(&checked_in, generated))
        };
        let _ = writeln!(
            std::io::stderr(),
            "{update}: {file} {news}; not compared (run again without {update} to check it)"
        );
    } else {
        assert!(
            checked_in == generated,
            "{file} differs from what {source} generates now ({}); regenerate it with \
             `{update}=1 {command}` and commit it",
            difference(&checked_in, generated)
        );
    }
}
