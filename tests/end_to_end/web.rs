//! End to end, the browser pendant (`docs/web.md`) in a real browser: Debian's Chromium driven
//! by `playwright-core` from node scripts in `tests/web/` (`node:test`), against the real MCM
//! (launcher, `mcm-rt`, `mcm-gateway`) serving its page.
//!
//! One MCM, one calibration: `tests/web/pendant.test.mjs` runs its steps in order (load,
//! calibrate from the page, keyboard jog and release, `hold` from a key during a jog and a
//! move, the truth at non-zero angles, the tab closed while jogging, an injected fault and its
//! flight record, the page reconnecting after the gateway is killed). Then the same instance is
//! started again (the drives keep the calibration) with `[gateway.access] motion_networks`
//! excluding loopback, and `tests/web/readonly.test.mjs` checks the read-only page. The page's
//! port is fixed for each run (a free port chosen here), so that the restarted gateway serves
//! the page where it was.
//!
//! Needs `node`, `npm` and Chromium (`MCM_CHROMIUM`, else `chromium` on the PATH); without
//! them the test says it is skipped, or fails when `CI` is set (`.ci/run` installs them as
//! root). The scripts run from a copy under the target directory (`web-node` in
//! `CARGO_TARGET_TMPDIR`), where `npm ci` installs the node packages on the first run
//! (file-locked; again when `package-lock.json` changes). With
//! `MCM_WEB_SCREENSHOTS=1` the scripts write the screenshots of `docs/web.md` to `docs/web/`.

use crate::common;

use common::python::{FileLock, repo_root, run};
use common::{Mcm, alive, assert_ok, config_file, find_program, skip, unique_instance};
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::io::Read;
use std::os::unix::process::CommandExt;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The longest a node script may run before it is killed (with its browser) and fails.
const SCRIPT_LIMIT: Duration = Duration::from_secs(300);

/// The programs the browser tests run.
struct Tools {
    node: PathBuf,
    npm: PathBuf,
    chromium: PathBuf,
}

/// `node`, `npm` and Chromium, or `None` after saying the test is skipped (a failure under
/// `CI`).
fn tools_or_skip(test: &str) -> Option<Tools> {
    let chromium = std::env::var_os("MCM_CHROMIUM")
        .map(PathBuf::from)
        .or_else(|| find_program("chromium"))
        .or_else(|| find_program("chromium-browser"));
    let node = find_program("node");
    if let Some(n) = &node
        && let Some(version) = too_old(n)
    {
        skip(
            test,
            &format!(
                "{} is node {version}; playwright-core needs node 20 or newer (Debian 12's \
                 nodejs is 18: install node 20 from Debian's backports or NodeSource)",
                n.display()
            ),
        );
        return None;
    }
    match (node, find_program("npm"), chromium) {
        (Some(node), Some(npm), Some(chromium)) => Some(Tools {
            node,
            npm,
            chromium,
        }),
        (node, npm, chromium) => {
            let missing: Vec<&str> = [
                (node.is_none(), "node"),
                (npm.is_none(), "npm"),
                (chromium.is_none(), "chromium (or MCM_CHROMIUM)"),
            ]
            .into_iter()
            .filter_map(|(m, name)| m.then_some(name))
            .collect();
            skip(
                test,
                &format!(
                    "{} not found (Debian: apt-get install chromium nodejs npm)",
                    missing.join(", ")
                ),
            );
            None
        }
    }
}

/// `node`'s version when it is older than 20 (what playwright-core needs); `None` when new
/// enough or when it cannot tell (then the scripts say what is wrong).
fn too_old(node: &std::path::Path) -> Option<String> {
    let out = Command::new(node).arg("--version").output().ok()?;
    let version = String::from_utf8_lossy(&out.stdout).trim().to_string();
    let major: u32 = version
        .trim_start_matches('v')
        .split('.')
        .next()?
        .parse()
        .ok()?;
    (major < 20).then_some(version)
}

/// The scripts' directory in the repository.
fn web_dir() -> PathBuf {
    repo_root().join("tests/web")
}

/// Where the scripts run: a copy of `tests/web` under the target directory, with the node
/// packages beside them (`node_modules` stays out of the source tree, as the Python venv does).
fn run_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("web-node")
}

/// Copy the files of `tests/web` whose names end in one of `suffixes` to [`run_dir`].
fn copy_sources(suffixes: &[&str]) -> Result<(), String> {
    let entries =
        std::fs::read_dir(web_dir()).map_err(|e| format!("cannot read tests/web: {e}"))?;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().to_string();
        if suffixes.iter().any(|s| name.ends_with(s)) {
            let to = run_dir().join(&name);
            std::fs::copy(e.path(), &to).map_err(|err| {
                format!("cannot copy tests/web/{name} to {}: {err}", to.display())
            })?;
        }
    }
    Ok(())
}

/// Install the node packages of `tests/web/package-lock.json` (`npm ci`) in [`run_dir`] unless
/// the ones installed there are from this very lock file; under an exclusive lock, since test
/// binaries run in parallel. A failed `npm ci` (no registry) is an error with npm's output.
fn node_modules(tools: &Tools) -> Result<(), String> {
    let dir = run_dir();
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let _lock = FileLock::take(&dir.with_extension("lock"))?;
    let lock_file = std::fs::read(web_dir().join("package-lock.json"))
        .map_err(|e| format!("cannot read tests/web/package-lock.json: {e}"))?;
    let mut h = DefaultHasher::new();
    lock_file.hash(&mut h);
    let want = format!("{:x}", h.finish());
    let stamp = dir.join("node_modules/.mcm-installed");
    if std::fs::read_to_string(&stamp).ok().as_deref() == Some(want.as_str()) {
        return Ok(());
    }
    copy_sources(&["package.json", "package-lock.json"])?;
    run(Command::new(&tools.npm)
        .args(["ci", "--no-audit", "--no-fund", "--loglevel=error"])
        .current_dir(&dir))?;
    std::fs::write(&stamp, want).map_err(|e| format!("cannot write {}: {e}", stamp.display()))
}

/// A free TCP port on loopback (bound and released: the MCM binds it right after).
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port()
}

/// Read a child's stream to its end on a thread.
fn drain(mut r: impl Read + Send + 'static) -> std::thread::JoinHandle<String> {
    std::thread::spawn(move || {
        let mut s = String::new();
        let _ = r.read_to_string(&mut s);
        s
    })
}

/// What a node script printed and whether it passed.
struct ScriptRun {
    script: &'static str,
    passed: bool,
    output: String,
    took: Duration,
}

/// Run `tests/web/<script>` with node's test runner against `mcm`, whose page is on `port`;
/// killed (with the browser it started: its own process group) after [`SCRIPT_LIMIT`].
fn run_script(tools: &Tools, script: &'static str, mcm: &Mcm, port: u16) -> ScriptRun {
    let mut cmd = Command::new(&tools.node);
    cmd.env("MCM_WEB_URL", format!("http://127.0.0.1:{port}/"))
        .env("MCM_JSON", mcm.json.to_string())
        .env("MCM_HMI", mcm.hmi.to_string())
        .env("MCM_GATEWAY_PID", mcm.gateway_pid.to_string());
    run_node(cmd, tools, script)
}

/// [`run_script`] with `cmd`, which runs node with the environment the script needs.
fn run_node(mut cmd: Command, tools: &Tools, script: &'static str) -> ScriptRun {
    let started = Instant::now();
    copy_sources(&[".mjs"]).unwrap_or_else(|e| panic!("{e}"));
    cmd.args(["--test", "--test-reporter=spec", script])
        .current_dir(run_dir())
        .env("MCM_CHROMIUM", &tools.chromium)
        .env_remove("MCM_SCREENSHOT_DIR")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .process_group(0);
    if std::env::var("MCM_WEB_SCREENSHOTS").as_deref() == Ok("1") {
        let dir = repo_root().join("docs/web");
        std::fs::create_dir_all(&dir).expect("docs/web");
        cmd.env("MCM_SCREENSHOT_DIR", dir);
    }
    let mut child = cmd
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run {:?}: {e}", cmd.get_program()));
    let out = drain(child.stdout.take().unwrap());
    let err = drain(child.stderr.take().unwrap());
    let deadline = started + SCRIPT_LIMIT;
    let (status, killed) = loop {
        if let Some(s) = child.try_wait().expect("wait for node") {
            break (Some(s), false);
        }
        if Instant::now() > deadline {
            // SAFETY: signalling the process group of the node script this test started.
            unsafe { libc::kill(-(child.id() as i32), libc::SIGKILL) };
            break (child.wait().ok(), true);
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut output = out.join().unwrap_or_default();
    output.push_str(&err.join().unwrap_or_default());
    if killed {
        output.push_str(&format!("\nkilled after {SCRIPT_LIMIT:?}\n"));
    }
    ScriptRun {
        script,
        passed: status.is_some_and(|s| s.success()) && !killed,
        output,
        took: started.elapsed(),
    }
}

/// The MCM of instance `instance` with its page on `port` and `extra` launcher arguments.
fn start(instance: &str, port: u16, extra: &[&str]) -> Mcm {
    let port = port.to_string();
    let mut args = vec!["--http-port", port.as_str()];
    args.extend_from_slice(extra);
    Mcm::start_named(instance, &args)
}

/// Leave every axis calibrated for the read-only run, also when the pendant's run failed
/// before its calibration (so that the read-only run shows its own result): over the JSON port,
/// after the gateway's restart when the pendant's run killed it.
fn calibrated_after(mcm: &mut Mcm) {
    if !alive(mcm.gateway_pid) {
        mcm.wait_ready();
    }
    let mut c = mcm.client();
    let s = c.wait_drives_online();
    if s["detail"]["all_calibrated"] == true {
        return;
    }
    eprintln!("the pendant's run left the arm uncalibrated: calibrating over the JSON port");
    if s["operating_mode"] == "ERROR" {
        c.request(r#"{"command":"hold"}"#);
    }
    assert_ok(&c.request(r#"{"command":"calibrate"}"#));
}

/// Remove the flight-recorder files the run's fault wrote (`mcm-<instance>-<ms>-<check>.csv`).
fn remove_flight_records(instance: &str) {
    let dir = mcm_shared::config::RobotConfig::prob2_default()
        .safety
        .flight_recorder_dir;
    let prefix = format!("mcm-{instance}-");
    for e in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
        if e.file_name().to_string_lossy().starts_with(&prefix) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

fn report(r: &ScriptRun) {
    eprintln!(
        "--- tests/web/{} ({}, {:.1} s) ---\n{}",
        r.script,
        if r.passed { "passed" } else { "FAILED" },
        r.took.as_secs_f64(),
        r.output
    );
}

#[test]
fn the_pendant_in_chromium_against_the_simulated_arm() {
    // The page's jog goes on while its timers resend it, under Chromium's timer throttling:
    // timing, so alone on the machine.
    let _alone = common::machine::alone();
    let test = "the_pendant_in_chromium_against_the_simulated_arm";
    let Some(tools) = tools_or_skip(test) else {
        return;
    };
    common::machine::share();
    node_modules(&tools).unwrap_or_else(|e| panic!("{test}: npm ci in tests/web: {e}"));
    let instance = unique_instance("web");
    let port = free_port();

    let mut mcm = start(&instance, port, &[]);
    let pendant = run_script(&tools, "pendant.test.mjs", &mcm, port);
    report(&pendant);
    calibrated_after(&mut mcm);
    // Stopped with SIGTERM: the simulated drives keep their power and the calibration.
    mcm.stop();

    let config = config_file("web-readonly", |base| {
        format!("{base}\n[gateway.access]\nmotion_networks = [\"10.99.0.0/16\"]\n")
    });
    let mcm = start(&instance, port, &["--config", config.path()]);
    let readonly = run_script(&tools, "readonly.test.mjs", &mcm, port);
    report(&readonly);
    drop(mcm);
    remove_flight_records(&instance);

    let failed: Vec<&str> = [&pendant, &readonly]
        .iter()
        .filter(|r| !r.passed)
        .map(|r| r.script)
        .collect();
    assert!(
        failed.is_empty(),
        "browser tests failed: {} (their output is above)",
        failed.join(", ")
    );
}

/// HTTP sent by a page of any origin to the JSON and telnet HMI ports runs nothing
/// (`tests/web/cross_protocol.test.mjs`; over raw sockets: `cross_protocol::`). The drives are
/// online first, so that a `calibrate` that got through would start.
#[test]
fn cross_protocol_requests_from_a_page_in_chromium() {
    script_against_its_own_mcm(
        "cross_protocol_requests_from_a_page_in_chromium",
        "web-cross",
        "cross_protocol.test.mjs",
        &[],
    );
}

/// Run `script` against an MCM of its own (instance tag `tag`, `extra` launcher arguments)
/// whose drives are online; fail when it fails.
fn script_against_its_own_mcm(test: &str, tag: &str, script: &'static str, extra: &[&str]) {
    let Some(tools) = tools_or_skip(test) else {
        return;
    };
    node_modules(&tools).unwrap_or_else(|e| panic!("{test}: npm ci in tests/web: {e}"));
    let instance = unique_instance(tag);
    let port = free_port();
    let mcm = start(&instance, port, extra);
    mcm.client().wait_drives_online();
    let run = run_script(&tools, script, &mcm, port);
    report(&run);
    drop(mcm);
    assert!(
        run.passed,
        "browser test failed: {} (its output is above)",
        run.script
    );
}

/// The pendant's Cartesian panel (`tests/web/cartesian.test.mjs`): the TCP and its triad, the
/// tool form, the move-to-pose form with its solutions, the TCP's jog buttons and the
/// straight-line form, on the simulation's truth. The core runs
/// at 50 Hz: a cycle longer than the 0.01 s `dt` the page takes for PVT when it can, so that
/// the move from HOLD shows the page entering PVT with a `dt` of one cycle.
#[test]
fn the_pendants_cartesian_panel_in_chromium() {
    let config = config_file("web-cart", |base| {
        let slow = base.replace("\nrate_hz = 200\n", "\nrate_hz = 50\n");
        assert_ne!(slow, base, "the configuration's `rate_hz = 200` line moved");
        slow
    });
    script_against_its_own_mcm(
        "the_pendants_cartesian_panel_in_chromium",
        "web-cart",
        "cartesian.test.mjs",
        &["--config", config.path()],
    );
}

/// The hosts file of a network namespace (`ip netns exec` mounts `/etc/netns/NAME/hosts` over
/// `/etc/hosts`); its directory is removed on drop.
struct NetnsHosts(PathBuf);

impl NetnsHosts {
    fn write(ns: &common::netns::Netns, hosts: &str) -> NetnsHosts {
        let dir = PathBuf::from("/etc/netns").join(&ns.name);
        std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        let made = NetnsHosts(dir);
        std::fs::write(made.0.join("hosts"), hosts).expect("write the namespace's hosts file");
        made
    }
}

impl Drop for NetnsHosts {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// DNS rebinding (docs/security.md): in a namespace whose hosts file maps `evil.example` to
/// the robot, a page from `http://evil.example:PORT/` runs nothing on it
/// (`tests/web/rebinding.test.mjs`), while the pendant by the robot's address still works.
#[test]
fn a_rebound_name_runs_nothing_in_chromium() {
    let test = "a_rebound_name_runs_nothing_in_chromium";
    let Some(tools) = tools_or_skip(test) else {
        return;
    };
    let Some(ns) = common::netns::Netns::or_skip(test, "rebind") else {
        return;
    };
    let _hosts = NetnsHosts::write(
        &ns,
        "127.0.0.1 localhost\n::1 localhost\n127.0.0.1 evil.example\n",
    );
    node_modules(&tools).unwrap_or_else(|e| panic!("{test}: npm ci in tests/web: {e}"));
    let instance = unique_instance("rebind");
    let binary = std::path::Path::new(env!("CARGO_BIN_EXE_mcm"));
    let mcm = mcm_client::launch::SimulatedMcm::start_command(
        ns.command(binary),
        binary,
        &instance,
        &[],
        Stdio::inherit(),
        common::WAIT,
        Some("[mcm] "),
    )
    .unwrap_or_else(|e| panic!("start mcm in {}: {e}", ns.name));
    let port = mcm.web.expect("the pendant is on by default").port();
    let mut cmd = ns.command(&tools.node);
    cmd.env("MCM_WEB_URL", format!("http://evil.example:{port}/"))
        .env("MCM_OWN_URL", format!("http://127.0.0.1:{port}/"))
        .env("MCM_JSON", mcm.json.to_string())
        .env("MCM_GATEWAY_PID", mcm.gateway_pid.to_string());
    let rebinding = run_node(cmd, &tools, "rebinding.test.mjs");
    report(&rebinding);
    drop(mcm);
    assert!(
        rebinding.passed,
        "tests/web/rebinding.test.mjs failed (its output is above)"
    );
}
