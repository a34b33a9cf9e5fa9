//! Real ROS 2 for the tests of the MCM's ROS 2 interface: rclpy with Fast DDS from PyPI, of
//! each distribution in [`Distro`].
//!
//! [`venv`] makes one virtual environment per distribution under the target directory
//! (`ros2-venv` for Kilted, `ros2-jazzy-venv` for Jazzy, in `CARGO_TARGET_TMPDIR`), once:
//! CPython 3.11 (the ROS 2 wheels exist for it only), the distribution's requirements
//! (`tests/ros2/requirements.txt`, `tests/ros2/jazzy/requirements.txt`: rclpy,
//! rmw_fastrtps_cpp, the message packages, the rosidl generators), then
//! `tests/ros2/build-interfaces.sh`, which builds the distribution's control_msgs (not on PyPI)
//! from its vendored definitions into it. Test binaries run in parallel, so the work is done
//! under an exclusive file lock; a stamp file records a hash of what went in, and a change of
//! any of it makes the venv again from nothing. Without Python 3.11 and its `venv` module,
//! cmake, make, a C/C++ compiler or Python's headers the test is skipped, saying so
//! ([`super::skip`]), or fails when `CI` is set; a pip install or a build that fails fails the
//! test, with the tool's output.
//!
//! [`command`] runs a script with that venv's Python and the environment a ROS 2 process of a
//! test needs ([`set_env`]). The wheels need no `LD_LIBRARY_PATH` or `AMENT_PREFIX_PATH` from
//! the caller: their bootstrap (`ros_wheels_bootstrapper.pth`) re-executes the venv's Python at
//! start with `LD_LIBRARY_PATH` naming the venv's `lib/` and the wheels' `ros_*.libs/`, where
//! build-interfaces.sh installs control_msgs' libraries too.

use super::netns::Netns;
use super::python::{FileLock, VenvError, run};
use mcm_client::launch::SimulatedMcm;
use std::collections::hash_map::DefaultHasher;
use std::ffi::OsStr;
use std::hash::{Hash, Hasher};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// A ROS 2 distribution the tests have rclpy of (PyPI's wheels): its venv and the node's
/// `--ros-distro`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distro {
    /// PyPI's `ros-jazzy-*` wheels, control_msgs 5.8.0 (`tests/ros2/jazzy/`).
    Jazzy,
    /// PyPI's `ros-*` wheels (Kilted), control_msgs 6.8.0.
    Kilted,
}

impl Distro {
    /// Its name, as `--ros-distro` and `ROS_DISTRO` spell it.
    pub fn name(self) -> &'static str {
        match self {
            Distro::Jazzy => "jazzy",
            Distro::Kilted => "kilted",
        }
    }

    /// The venv's directory in `CARGO_TARGET_TMPDIR`.
    fn venv_name(self) -> &'static str {
        match self {
            Distro::Jazzy => "ros2-jazzy-venv",
            Distro::Kilted => "ros2-venv",
        }
    }

    /// Its requirements file and its vendored interfaces, relative to `tests/ros2/`.
    fn files(self) -> [&'static str; 2] {
        match self {
            Distro::Jazzy => ["jazzy/requirements.txt", "jazzy/interfaces"],
            Distro::Kilted => ["requirements.txt", "interfaces"],
        }
    }

    /// The files that decide what the venv holds, relative to `tests/ros2/`: a change to any
    /// of them makes the venv again.
    fn inputs(self) -> [&'static str; 4] {
        let [requirements, interfaces] = self.files();
        [
            requirements,
            "build-interfaces.sh",
            "wheel-include-dirs.cmake",
            interfaces,
        ]
    }
}

/// Start the MCM (`mcm --ros2`, serving `distro`'s peers, each of `ros2_args` passed as
/// `--ros2-arg=...`) on the simulated arm inside `ns`; its JSON port is on the namespace's
/// loopback ([`Netns::connect`]). Panics when it does not start.
pub fn mcm_in(ns: &Netns, instance: &str, distro: Distro, ros2_args: &[String]) -> SimulatedMcm {
    super::machine::share();
    let binary = Path::new(env!("CARGO_BIN_EXE_mcm"));
    let mut extra: Vec<String> = vec![
        "--ros2".into(),
        format!("--ros2-arg=--ros-distro={}", distro.name()),
    ];
    extra.extend(ros2_args.iter().map(|a| format!("--ros2-arg={a}")));
    let extra: Vec<&OsStr> = extra.iter().map(OsStr::new).collect();
    SimulatedMcm::start_command(
        ns.command(binary),
        binary,
        instance,
        &extra,
        Stdio::inherit(),
        super::WAIT,
        Some("[mcm] "),
    )
    .unwrap_or_else(|e| panic!("start mcm --ros2 in {}: {e}", ns.name))
}

/// A JSON client of `mcm` from inside `ns`, once the drives are online and the arm calibrated,
/// control released again, so that the node (or any other client) may take it.
pub fn calibrated_client(ns: &Netns, mcm: &SimulatedMcm) -> super::Client {
    let mut json = super::Client::on(
        ns.connect(mcm.json)
            .expect("the JSON port, from the namespace"),
    );
    json.wait_drives_online();
    super::assert_ok(&json.request(r#"{"command":"calibrate"}"#));
    super::assert_ok(&json.request(r#"{"command":"release_control"}"#));
    json
}

/// Start `script args...` with the venv's Python `py` inside `ns`, in the ROS 2 domain
/// `domain`: its name (for messages), the child, and its stdout lines (each also echoed as
/// `[name] line`) as they come.
pub fn spawn_in(
    ns: &Netns,
    py: &Path,
    domain: u32,
    script: &Path,
    args: &[&str],
) -> (String, Child, std::sync::mpsc::Receiver<String>) {
    let tag = script.file_name().map_or_else(
        || script.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let mut cmd = ns.command(py);
    cmd.arg(script).args(args);
    set_env(&mut cmd, domain, Discovery::Subnet);
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap_or_else(|e| panic!("run {tag}: {e}"));
    let out = child.stdout.take().expect("piped");
    let (tx, rx) = std::sync::mpsc::channel();
    let echo = tag.clone();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            eprintln!("[{echo}] {line}");
            let _ = tx.send(line);
        }
    });
    (tag, child, rx)
}

/// Run `script args...` with the venv's Python `py` inside `ns`, in the ROS 2 domain `domain`
/// (multicast discovery: the namespace keeps it in), echoing each line of its stdout as
/// `[tag] line`. Returns the lines; panics with them when it fails or is not done `within`.
pub fn run_in(
    ns: &Netns,
    py: &Path,
    domain: u32,
    script: &Path,
    args: &[&str],
    within: Duration,
) -> Vec<String> {
    let (tag, mut child, rx) = spawn_in(ns, py, domain, script, args);
    let deadline = Instant::now() + within;
    let mut lines = Vec::new();
    loop {
        match rx.recv_timeout(Duration::from_millis(200)) {
            Ok(l) => lines.push(l),
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break,
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{tag} {args:?} took longer than {within:?}; its lines: {lines:#?}");
        }
    }
    let status = child.wait().expect("wait for the script");
    assert!(
        status.success(),
        "{tag} {args:?} failed ({status}); its lines: {lines:#?}"
    );
    lines
}

/// The `joint=value` pairs of the last line of `out` that starts with `prefix` (a script's
/// `at: base=1.0 shoulder=2.0 ... deg`).
pub fn joint_values(out: &str, prefix: &str) -> Vec<(String, f64)> {
    let line = out
        .lines()
        .rev()
        .find(|l| l.starts_with(prefix))
        .unwrap_or_else(|| panic!("no {prefix:?} line in: {out}"));
    line[prefix.len()..]
        .trim_end_matches(" deg")
        .split_whitespace()
        .map(|pair| {
            let (n, v) = pair
                .split_once('=')
                .unwrap_or_else(|| panic!("{pair:?} is not joint=value in {line:?}"));
            let v = v
                .parse()
                .unwrap_or_else(|e| panic!("{v:?} in {line:?}: {e}"));
            (n.to_string(), v)
        })
        .collect()
}

/// The simulated arm's joints, in order.
pub const JOINTS: [&str; 6] = ["base", "shoulder", "elbow", "forearm", "wrist", "flange"];

/// The last `at: name=deg ...` line of a peer's output `out` names the simulated arm's joints in
/// order, each within 0.01 deg of the position the MCM measures now (`json`'s `status`): what
/// the peer decoded is the arm's state.
pub fn assert_read_the_arm(out: &str, json: &mut super::Client) {
    let at = joint_values(out, "at: ");
    let measured = super::six(&json.request(r#"{"command":"status"}"#)["axis_states"]["position"]);
    assert_eq!(at.len(), 6, "{out}");
    for (i, (n, deg)) in at.iter().enumerate() {
        assert_eq!(n, JOINTS[i], "{out}");
        assert!(
            (deg - measured[i]).abs() < 0.01,
            "{n}: the peer read {deg} deg, the MCM measures {} deg",
            measured[i]
        );
    }
}

/// `tests/ros2/` of the repository.
pub fn dir() -> PathBuf {
    super::python::repo_root().join("tests").join("ros2")
}

/// How a ROS 2 process of a test finds its peers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Discovery {
    /// `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`: Fast DDS discovers by unicast on 127.0.0.1
    /// only, so nothing leaves the machine's loopback.
    Localhost,
    /// ROS 2's default (`SUBNET`): multicast on every interface the process sees. Only for a
    /// process inside a network namespace the test made itself: elsewhere it sends to the
    /// machine's network.
    Subnet,
}

/// The Python of `distro`'s virtual environment ([`venv`]); `None` after saying the test is
/// skipped when a tool is missing (a failure under `CI`); panics, with the tool's output, when
/// making it failed.
pub fn venv_or_skip(test: &str, distro: Distro) -> Option<PathBuf> {
    // Making the venv (pip, a type-support build) loads the machine.
    super::machine::share();
    match venv(distro) {
        Ok(py) => Some(py),
        Err(VenvError::Missing(why)) => {
            super::skip(test, &why);
            None
        }
        Err(VenvError::Failed(why)) => panic!("{test}: {why}"),
    }
}

/// A command that runs `script` with the venv's Python `py` ([`venv_or_skip`]) in the ROS 2
/// domain `domain_id`, finding its peers as `discovery` says ([`set_env`]).
pub fn command(py: &Path, script: &Path, domain_id: u32, discovery: Discovery) -> Command {
    let mut cmd = Command::new(py);
    cmd.arg(script);
    set_env(&mut cmd, domain_id, discovery);
    cmd
}

/// Set the environment of a ROS 2 process of a test on `cmd` (which may be `py` itself or,
/// say, `ip netns exec NS py ...`): Fast DDS as the middleware, the domain, the discovery
/// range, unbuffered output, ROS's log files under the target directory; and no ROS settings
/// inherited from the caller's environment that would change the process's world (a profile
/// file, static peers, the bootstrap's guard, which would skip setting `LD_LIBRARY_PATH`).
/// `domain_id` must be at most 101: higher domains use UDP ports in Linux's ephemeral range.
pub fn set_env(cmd: &mut Command, domain_id: u32, discovery: Discovery) -> &mut Command {
    assert!(
        domain_id <= 101,
        "ROS_DOMAIN_ID {domain_id} is out of range: at most 101 (Fast DDS's ports of higher \
         domains fall into Linux's ephemeral port range)"
    );
    for var in [
        "_ROS_WHEELS_BOOTSTRAP_COMPLETE",
        "ROS_AUTOMATIC_DISCOVERY_RANGE",
        "ROS_STATIC_PEERS",
        "ROS_LOCALHOST_ONLY",
        "ROS_DISCOVERY_SERVER",
        "FASTDDS_DEFAULT_PROFILES_FILE",
        "FASTRTPS_DEFAULT_PROFILES_FILE",
        "RMW_FASTRTPS_USE_QOS_FROM_XML",
        "ROS_SECURITY_ENABLE",
        "CYCLONEDDS_URI",
    ] {
        cmd.env_remove(var);
    }
    if discovery == Discovery::Localhost {
        cmd.env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST");
    }
    cmd.env("RMW_IMPLEMENTATION", "rmw_fastrtps_cpp")
        .env("ROS_DOMAIN_ID", domain_id.to_string())
        .env("ROS_LOG_DIR", log_dir())
        .env("PYTHONUNBUFFERED", "1")
        .env("PYTHONDONTWRITEBYTECODE", "1")
}

/// Where ROS's log files of the tests go (not `~/.ros/log`).
pub fn log_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("ros2-log")
}

/// A ROS domain for one test, 1..=101, different for each call in this process and likely
/// different from other test processes' (it starts from the process id). Tests should also put
/// a unique tag in their topic and action names ([`super::unique_instance`]), so that a
/// collision with another run on the machine cannot mix their messages.
pub fn unique_domain_id() -> u32 {
    static NEXT: AtomicU32 = AtomicU32::new(0);
    (std::process::id() + 37 * NEXT.fetch_add(1, Ordering::Relaxed)) % 101 + 1
}

/// CPython 3.11, the ROS 2 wheels' only Python: the first `python3.11`, else `python3`, on
/// `PATH` that runs and is 3.11 (a version manager's shim may be first and fail).
fn python311() -> Result<PathBuf, String> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    let dirs: Vec<PathBuf> = std::env::split_paths(&path).collect();
    for name in ["python3.11", "python3"] {
        for candidate in dirs.iter().map(|d| d.join(name)).filter(|p| p.is_file()) {
            let out = Command::new(&candidate)
                .args(["-c", "import sys; print('%d.%d' % sys.version_info[:2])"])
                .output();
            if let Ok(out) = out
                && out.status.success()
                && String::from_utf8_lossy(&out.stdout).trim() == "3.11"
            {
                return Ok(candidate);
            }
        }
    }
    Err(
        "no CPython 3.11 (python3.11, or python3 being 3.11): PyPI's ROS 2 wheels are \
         for CPython 3.11 only (Debian 12: apt-get install python3-venv python3-dev)"
            .to_string(),
    )
}

/// What building control_msgs needs besides Python: cmake, make (its default generator), a C
/// and a C++ compiler, and `python`'s headers.
fn build_tools(python: &Path) -> Result<(), String> {
    for tool in ["cmake", "make", "cc", "c++"] {
        if super::find_program(tool).is_none() {
            return Err(format!(
                "{tool} is not on PATH: building control_msgs' type support needs cmake, \
                 make and a C/C++ compiler (Debian: apt-get install cmake make g++)"
            ));
        }
    }
    let out = run(Command::new(python).args([
        "-c",
        "import os, sysconfig; p = os.path.join(sysconfig.get_paths()['include'], 'Python.h'); \
         print(p); raise SystemExit(not os.path.exists(p))",
    ]));
    out.map(|_| ()).map_err(|e| {
        format!("Python's headers are missing (Debian: apt-get install python3-dev): {e}")
    })
}

/// A hash of the file or directory tree `path` (names and contents, in order).
fn hash_tree(path: &Path, h: &mut DefaultHasher) {
    if path.is_dir() {
        let mut entries: Vec<_> = std::fs::read_dir(path)
            .map(|r| r.filter_map(Result::ok).map(|e| e.path()).collect())
            .unwrap_or_default();
        entries.sort();
        for p in entries {
            hash_tree(&p, h);
        }
    } else if let Ok(bytes) = std::fs::read(path) {
        path.hash(h);
        bytes.hash(h);
    }
}

/// The Python of `distro`'s virtual environment, with its requirements and control_msgs
/// installed.
pub fn venv(distro: Distro) -> Result<PathBuf, VenvError> {
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let venv = tmp.join(distro.venv_name());
    let [requirements, interfaces] = distro.files();
    std::fs::create_dir_all(&tmp)
        .map_err(|e| VenvError::Failed(format!("cannot create {}: {e}", tmp.display())))?;
    let _lock = FileLock::take(&venv.with_extension("lock")).map_err(VenvError::Failed)?;
    let venv_python = venv.join("bin").join("python");
    let mut h = DefaultHasher::new();
    for input in distro.inputs() {
        hash_tree(&dir().join(input), &mut h);
    }
    let want = format!("{:x}", h.finish());
    let stamp = venv.join("mcm-ros2-installed.stamp");
    if venv_python.exists()
        && std::fs::read_to_string(&stamp).ok().as_deref() == Some(want.as_str())
    {
        return Ok(venv_python);
    }
    let python = python311().map_err(VenvError::Missing)?;
    build_tools(&python).map_err(VenvError::Missing)?;
    // From nothing: pip would leave packages of an older requirements.txt behind.
    if venv.exists() {
        std::fs::remove_dir_all(&venv)
            .map_err(|e| VenvError::Failed(format!("cannot remove {}: {e}", venv.display())))?;
    }
    run(Command::new(&python).args(["-m", "venv"]).arg(&venv)).map_err(|e| {
        // Debian's python3 without python3-venv leaves a venv without pip behind.
        let _ = std::fs::remove_dir_all(&venv);
        VenvError::Missing(format!(
            "cannot create a Python virtual environment (Debian: apt-get install \
             python3-venv): {e}"
        ))
    })?;
    let fail = |what: &str, e: String| {
        // No half-made venv is left for the next test to trust (there is no stamp anyway).
        let _ = std::fs::remove_dir_all(&venv);
        VenvError::Failed(format!("{what}: {e}"))
    };
    run(Command::new(&venv_python)
        .args(["-m", "pip", "install", "--disable-pip-version-check", "-r"])
        .arg(dir().join(requirements)))
    .map_err(|e| {
        fail(
            &format!("pip could not install tests/ros2/{requirements}"),
            e,
        )
    })?;
    run(Command::new("bash")
        .arg(dir().join("build-interfaces.sh"))
        .arg(&venv)
        .arg(tmp.join(format!("{}-interfaces-build", distro.venv_name())))
        .arg(dir().join(interfaces)))
    .map_err(|e| {
        fail(
            &format!("tests/ros2/build-interfaces.sh could not build tests/ros2/{interfaces}"),
            e,
        )
    })?;
    std::fs::write(&stamp, want)
        .map_err(|e| VenvError::Failed(format!("cannot write {}: {e}", stamp.display())))?;
    Ok(venv_python)
}
