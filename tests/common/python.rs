//! Python for the tests of the Python client (`python/`) and its examples (`examples/python/`).
//!
//! [`venv`] makes one virtual environment under the target directory (`python-venv` in
//! `CARGO_TARGET_TMPDIR`) and installs `./python[shm]` and matplotlib into it, once: test
//! binaries run in parallel, so the work is done under an exclusive file lock, and a stamp file
//! records what was installed (the package is installed again when its sources change).
//! Without `python3` or its `venv` module the test is skipped, saying so ([`super::skip`]), or
//! fails when the environment variable `CI` is set. A pip install that fails (no network, a
//! package that does not build) fails the test, with pip's output.

use std::collections::hash_map::DefaultHasher;
use std::ffi::OsStr;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Packages installed next to the `mcm` package (the flight-recorder plot needs matplotlib;
/// the ZeroMQ tests and example, `tests/end_to_end/zmq.rs`, need pyzmq).
const EXTRA_PACKAGES: &[&str] = &["matplotlib", "pyzmq"];

/// The repository's root.
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Why there is no virtual environment.
#[derive(Debug)]
pub enum VenvError {
    /// Python or its `venv` module is missing on this machine: the test is skipped (fails
    /// under `CI`).
    Missing(String),
    /// Making it failed (pip, the file system): the test fails.
    Failed(String),
}

/// What a test needs from Python is missing: fail under CI, else say (visibly) it is skipped.
/// Returns `None` to the test, which then returns early.
pub fn missing<T>(test: &str, why: &str) -> Option<T> {
    super::skip(
        test,
        &format!(
            "{why} (install python3 with its venv module; Debian: apt-get install python3-venv)"
        ),
    );
    None
}

/// The virtual environment's Python ([`venv`]); `None` after saying the test is skipped when
/// Python is missing (a failure under `CI`); panics, with pip's output, when making it failed.
pub fn venv_or_skip(test: &str) -> Option<PathBuf> {
    // Making the venv (pip) loads the machine; the test then starts an MCM.
    super::machine::share();
    or_skip(test, venv())
}

/// The venv's Python; `None` after saying the test is skipped when it is [`VenvError::Missing`]
/// (a failure under `CI`); panics when making it failed.
fn or_skip(test: &str, venv: Result<PathBuf, VenvError>) -> Option<PathBuf> {
    match venv {
        Ok(py) => Some(py),
        Err(VenvError::Missing(why)) => missing(test, &why),
        Err(VenvError::Failed(why)) => panic!("{test}: {why}"),
    }
}

/// `python3` on the PATH, if it is 3.9 or newer.
pub fn system_python() -> Result<PathBuf, String> {
    let out = Command::new("python3")
        .args([
            "-c",
            "import sys; print('%d.%d' % sys.version_info[:2]); sys.exit(sys.version_info < (3, 9))",
        ])
        .output()
        .map_err(|e| format!("python3 cannot be run: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "python3 {} is too old: the mcm package needs 3.9 or newer",
            String::from_utf8_lossy(&out.stdout).trim()
        ));
    }
    Ok(PathBuf::from("python3"))
}

/// Run a command, returning its output, or an error naming it and its stderr.
pub fn run(cmd: &mut Command) -> Result<Output, String> {
    let what = format!("{cmd:?}");
    let out = cmd
        .output()
        .map_err(|e| format!("{what} cannot be run: {e}"))?;
    if out.status.success() {
        Ok(out)
    } else {
        Err(format!(
            "{what} failed ({}):\n{}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// Run `python -m unittest <args> -v` in `python/` with `env` set (and no bytecode written);
/// its log (unittest writes it to stderr, echoed here), or an error naming the command and
/// its output.
pub fn unittest(py: &Path, args: &[&str], env: &[(&str, &OsStr)]) -> Result<String, String> {
    let out = run(Command::new(py)
        .args(["-m", "unittest"])
        .args(args)
        .arg("-v") // last: before `discover` it would name a test
        .current_dir(repo_root().join("python"))
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .envs(env.iter().copied()))?;
    let log = String::from_utf8_lossy(&out.stderr).to_string();
    eprintln!("{log}");
    Ok(log)
}

/// The test methods (`def test_...`) that the modules `modules` of `python/tests/` define.
pub fn tests_defined(modules: &[&str]) -> usize {
    modules
        .iter()
        .map(|m| {
            let path = repo_root().join("python/tests").join(format!("{m}.py"));
            std::fs::read_to_string(&path)
                .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
                .lines()
                .filter(|l| l.trim_start().starts_with("def test_"))
                .count()
        })
        .sum()
}

/// Assert that a unittest `log` ([`unittest`], `-v`) ran `expected` tests and that every one
/// of them passed: none skipped (unittest counts skipped tests in its "Ran N tests"), none
/// an expected failure.
pub fn assert_all_passed(log: &str, expected: usize) {
    let ran: usize = log
        .lines()
        .find_map(|l| l.strip_prefix("Ran ")?.split(' ').next()?.parse().ok())
        .unwrap_or_else(|| panic!("no \"Ran N tests\" line in the unittest log:\n{log}"));
    let summary = log
        .lines()
        .rev()
        .find(|l| l.starts_with("OK") || l.starts_with("FAILED"))
        .unwrap_or_else(|| panic!("no OK/FAILED summary in the unittest log:\n{log}"));
    let skipped = log.lines().filter(|l| l.contains(" ... skipped")).count();
    assert!(
        ran == expected && summary == "OK" && skipped == 0,
        "expected {expected} tests to run and pass, none skipped: ran {ran}, {skipped} \
         skipped, summary {summary:?}:\n{log}"
    );
}

/// A hash of the package's sources, so a changed package is installed again.
fn sources_hash(dir: &Path, h: &mut DefaultHasher) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .map(|r| r.filter_map(Result::ok).map(|e| e.path()).collect())
        .unwrap_or_default();
    entries.sort();
    for p in entries {
        let name = p
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        if name == "build" || name.ends_with(".egg-info") || name == "__pycache__" {
            continue;
        }
        if p.is_dir() {
            sources_hash(&p, h);
        } else if let Ok(bytes) = std::fs::read(&p) {
            p.hash(h);
            bytes.hash(h);
        }
    }
}

/// An exclusive lock on a file, released on drop.
pub(crate) struct FileLock(std::fs::File);

impl FileLock {
    pub(crate) fn take(path: &Path) -> Result<FileLock, String> {
        let f = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(path)
            .map_err(|e| format!("cannot open the lock file {}: {e}", path.display()))?;
        use std::os::fd::AsRawFd;
        // SAFETY: flock on a descriptor this struct owns; it blocks until the lock is ours.
        let r = unsafe { libc::flock(f.as_raw_fd(), libc::LOCK_EX) };
        if r != 0 {
            return Err(format!(
                "cannot lock {}: {}",
                path.display(),
                std::io::Error::last_os_error()
            ));
        }
        Ok(FileLock(f))
    }
}

impl Drop for FileLock {
    fn drop(&mut self) {
        use std::os::fd::AsRawFd;
        // SAFETY: unlocking the descriptor this struct owns.
        unsafe { libc::flock(self.0.as_raw_fd(), libc::LOCK_UN) };
    }
}

/// The virtual environment's Python, with `./python[shm]` and the extra packages installed.
pub fn venv() -> Result<PathBuf, VenvError> {
    let root = repo_root();
    let mut h = DefaultHasher::new();
    EXTRA_PACKAGES.hash(&mut h);
    sources_hash(&root.join("python"), &mut h);
    stamped_venv("python-venv", "mcm-installed.stamp", h.finish(), |pip| {
        pip(&["./python[shm]"])
            .and_then(|_| pip(EXTRA_PACKAGES))
            // The same version again: pip keeps an installed package whose version did not
            // change.
            .and_then(|_| pip(&["--force-reinstall", "--no-deps", "./python"]))
            .map(|_| ())
            .map_err(|e| format!("pip could not install the mcm package: {e}"))
    })
}

/// The Python of a virtual environment with the packages of `requirements` (a requirements
/// file, relative to the repository's root) installed: `name` under the target directory,
/// made once and again when the file changes. Without a network (pip cannot reach the
/// package index) the venv is [`VenvError::Missing`]: the test is skipped, or fails under CI.
pub fn requirements_venv(name: &str, requirements: &str) -> Result<PathBuf, VenvError> {
    let path = repo_root().join(requirements);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| VenvError::Failed(format!("cannot read {}: {e}", path.display())))?;
    let mut h = DefaultHasher::new();
    text.hash(&mut h);
    let mut offline = false;
    let made = stamped_venv(name, "requirements.stamp", h.finish(), |pip| {
        pip(&["-r", requirements]).map(|_| ()).map_err(|e| {
            offline = NO_NETWORK.iter().any(|m| e.contains(m));
            format!("pip could not install {requirements}: {e}")
        })
    });
    match made {
        Err(VenvError::Failed(why)) if offline => Err(VenvError::Missing(format!(
            "no network to install the test's Python packages: {why}"
        ))),
        other => other,
    }
}

/// What pip says when it cannot reach the package index.
const NO_NETWORK: &[&str] = &[
    "Failed to establish a new connection",
    "Temporary failure in name resolution",
    "Network is unreachable",
];

/// The [`venv_or_skip`] of [`requirements_venv`].
pub fn requirements_venv_or_skip(test: &str, name: &str, requirements: &str) -> Option<PathBuf> {
    super::machine::share();
    or_skip(test, requirements_venv(name, requirements))
}

/// A virtual environment `name` in `CARGO_TARGET_TMPDIR`, made under an exclusive file lock
/// (test binaries run in parallel); `install` is given pip (`pip install ARGS`, run in the
/// repository's root) and runs when the stamp file `stamp` does not hold `hash`, which is
/// written after it succeeded.
fn stamped_venv(
    name: &str,
    stamp: &str,
    hash: u64,
    install: impl FnOnce(&dyn Fn(&[&str]) -> Result<Output, String>) -> Result<(), String>,
) -> Result<PathBuf, VenvError> {
    let python = system_python().map_err(VenvError::Missing)?;
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(dir.parent().expect("the venv has a parent"))
        .map_err(|e| VenvError::Failed(format!("cannot create {}: {e}", dir.display())))?;
    let _lock = FileLock::take(&dir.with_extension("lock")).map_err(VenvError::Failed)?;
    let venv_python = dir.join("bin").join("python");
    if !venv_python.exists() {
        run(Command::new(&python).args(["-m", "venv"]).arg(&dir)).map_err(|e| {
            // Debian's python3 without python3-venv leaves a venv without pip behind.
            let _ = std::fs::remove_dir_all(&dir);
            VenvError::Missing(format!(
                "cannot create a Python virtual environment (python3-venv missing?): {e}"
            ))
        })?;
    }
    let stamp = dir.join(stamp);
    let want = format!("{hash:x}");
    if std::fs::read_to_string(&stamp).ok().as_deref() == Some(want.as_str()) {
        return Ok(venv_python);
    }
    let root = repo_root();
    let pip = |args: &[&str]| {
        run(Command::new(&venv_python)
            .args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--disable-pip-version-check",
            ])
            .args(args)
            .current_dir(&root))
    };
    install(&pip).map_err(VenvError::Failed)?;
    std::fs::write(&stamp, want)
        .map_err(|e| VenvError::Failed(format!("cannot write {}: {e}", stamp.display())))?;
    Ok(venv_python)
}
