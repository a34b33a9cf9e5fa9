//! Stamps the binary with the commit it was built from, for the failure report of a run.
//!
//! Cargo runs this again when HEAD moves: a checkout (`HEAD`), a new commit on the branch
//! checked out (its ref file, or `packed-refs` once git packed it). Whether the checkout has
//! uncommitted changes is not stamped here (an edit changes no file this could watch); the
//! binary looks at run time (`main.rs`).

use std::path::PathBuf;
use std::process::Command;

/// `git <args>`'s output, trimmed; `None` outside a git checkout.
fn git(args: &[&str]) -> Option<String> {
    Command::new("git")
        .args(args)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
}

fn main() {
    let commit = git(&["rev-parse", "HEAD"])
        .unwrap_or_else(|| "unknown (not built from a git checkout)".into());
    println!("cargo:rustc-env=MCM_DST_COMMIT={commit}");
    // The files HEAD resolves through (in a worktree, HEAD is its own, the refs are shared):
    // HEAD, the branch's loose ref, and `packed-refs` where git packed it. A missing file
    // would make cargo run this every time: a branch without a loose ref (packed) is watched
    // through `packed-refs` and its folder, where its next commit writes a loose one.
    let path = |name: &str| {
        git(&["rev-parse", "--path-format=absolute", "--git-path", name]).map(PathBuf::from)
    };
    let mut watched = vec![path("HEAD"), path("packed-refs")];
    if let Some(branch) = git(&["symbolic-ref", "-q", "HEAD"]).and_then(|b| path(&b)) {
        if !branch.exists() {
            watched.push(branch.parent().map(PathBuf::from));
        }
        watched.push(Some(branch));
    }
    for p in watched.into_iter().flatten().filter(|p| p.exists()) {
        println!("cargo:rerun-if-changed={}", p.display());
    }
    // Without any rerun-if-changed line, cargo would run this after every change of the crate.
    println!("cargo:rerun-if-changed=build.rs");
}
