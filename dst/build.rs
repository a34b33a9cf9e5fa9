//! Stamps the binary with the commit it was built from, for the failure report of a run.

fn main() {
    let commit = std::process::Command::new("git")
        .args(["rev-parse", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown (not built from a git checkout)".into());
    let dirty = std::process::Command::new("git")
        .args(["status", "--porcelain", "--untracked-files=no"])
        .output()
        .ok()
        .is_some_and(|o| !o.stdout.is_empty());
    let suffix = if dirty {
        " with uncommitted changes"
    } else {
        ""
    };
    println!("cargo:rustc-env=MCM_DST_COMMIT={commit}{suffix}");
    println!("cargo:rerun-if-changed=../.git/HEAD");
}
