//! The Debian package (docs/deploy.md, "The Debian package") installed and run in the test guest
//! (tests/common/vm.rs: Debian 13, systemd as PID 1, vcan0 up at boot, QEMU software emulation).
//! The package is made as tests/end_to_end/deb_package.rs makes it (`cargo deb --no-build` around
//! this test build's `mcm`), twice (the second with a higher version, for the upgrade), under the
//! target directory that the guest sees read-only. In the guest, as root: install it; point the
//! conffile at vcan0 with the emulated timing (tests/common/virtual_arm.rs, `EMULATED`); start the
//! virtual arm (a transient unit); `systemctl enable --now mcm.target`. From the host, through
//! forwarded ports: drives online, calibrate, a move, reached on the arm's truth. Then: the
//! gateway killed with SIGKILL is started again by systemd while the core holds the arm;
//! `systemctl stop mcm.target` ends with the core's controlled stop (its journal line); a reboot
//! brings the enabled MCM back by itself (a completed boot with vcan0 up); the upgrade keeps the
//! edited conffile; purge leaves nothing behind.

use crate::common::{self, virtual_arm, vm};
use serde_json::Value;
use std::io::{BufRead, BufReader, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The gateway's JSON protocol port in the guest.
const JSON_PORT: u16 = 18010;
/// The virtual arm's control port in the guest.
const ARM_PORT: u16 = 18020;
/// The guest ports this part needs forwarded to the host.
pub const FORWARDED: [u16; 2] = [JSON_PORT, ARM_PORT];
/// The longest one command in the guest may take (it bounds its own waits below this).
const RUN_WAIT: Duration = Duration::from_secs(240);
/// The longest the host waits for the MCM to answer, for the drives, for a move.
const HOST_WAIT: Duration = Duration::from_secs(180);
/// The upgrade's version (the first package has the manifest's).
const UPGRADE_VERSION: &str = "0.1.0-2";
/// The move's targets [deg].
const TARGETS: [f64; 6] = [10.0, -10.0, 20.0, 5.0, -5.0, 15.0];

/// The conffile's edits (`section`, `key`, `value`): the bus on vcan0 and the emulated
/// machine's timing the other guest tests use ([`virtual_arm::EMULATED`]).
fn edits() -> Vec<(&'static str, &'static str, &'static str)> {
    let mut e = vec![
        ("bus", "backend", "\"socketcan\""),
        ("bus", "interface", "\"vcan0\""),
    ];
    e.extend_from_slice(virtual_arm::EMULATED);
    e
}

const CONF: &str = "/etc/mcm/prob2.toml";

/// The two packages (the manifest's version, then [`UPGRADE_VERSION`]) under the target
/// directory, or why not (a missing tool).
pub fn packages() -> Result<(PathBuf, PathBuf), String> {
    common::deb::cargo_deb_installed()?;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("vm-package");
    let mut debs = common::deb::build(
        &dir,
        &[
            ("mcm.deb", None),
            ("mcm-upgrade.deb", Some(UPGRADE_VERSION)),
        ],
    );
    let upgrade = debs.pop().unwrap();
    Ok((debs.pop().unwrap(), upgrade))
}

/// A sed script that applies [`edits`] within their sections.
fn sed_script() -> String {
    edits()
        .iter()
        .map(|(section, key, value)| {
            format!("-e '/^\\[{section}\\]/,/^\\[/s/^{key} *=.*/{key} = {value}/'")
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// A guest script that waits (at most `secs` s) until every one of `units` is active; on
/// timeout it prints their status and journal and fails.
fn wait_active(units: &[&str], secs: u32) -> String {
    let all = units
        .iter()
        .map(|u| format!("systemctl is-active -q {u}"))
        .collect::<Vec<_>>()
        .join(" && ");
    let names = units.join(" ");
    format!(
        "for i in $(seq 1 {}); do if {all}; then exit 0; fi; sleep 0.5; done; \
         echo 'not all active within {secs} s: {names}'; systemctl --no-pager status {names}; \
         journalctl --no-pager -n 60 -u mcm-rt -u mcm-gateway -u mcm-virtual-arm; exit 1",
        secs * 2
    )
}

/// The virtual arm as a transient unit.
fn start_arm() -> String {
    format!(
        "systemd-run --unit=mcm-virtual-arm /usr/bin/mcm-virtual-arm --interface vcan0 \
         --control 0.0.0.0:{ARM_PORT} --config {CONF} --fifo-priority 70 && {}",
        wait_active(&["mcm-virtual-arm"], 30)
    )
}

/// One JSON request on a fresh connection to `addr`, its result (spontaneous safety errors
/// skipped), or why not within `wait`.
fn ask(addr: SocketAddr, json: &str, wait: Duration) -> Result<Value, String> {
    let mut s = TcpStream::connect(addr).map_err(|e| format!("connect {addr}: {e}"))?;
    s.set_read_timeout(Some(wait)).unwrap();
    writeln!(s, "{json}").map_err(|e| format!("send to {addr}: {e}"))?;
    let mut reader = BufReader::new(s);
    loop {
        let mut line = String::new();
        match reader.read_line(&mut line) {
            Ok(0) => {
                return Err(format!(
                    "{addr} closed the connection (no result for {json})"
                ));
            }
            Ok(_) => {}
            Err(e) => return Err(format!("no result for {json} from {addr}: {e}")),
        }
        let v: Value =
            serde_json::from_str(&line).map_err(|e| format!("not JSON ({e}): {line:?}"))?;
        if !common::is_event(&v) {
            return Ok(v);
        }
    }
}

/// One connection that keeps control of the arm.
struct Control {
    stream: TcpStream,
    reader: BufReader<TcpStream>,
}

impl Control {
    fn connect(addr: SocketAddr) -> Control {
        let stream = TcpStream::connect(addr).unwrap_or_else(|e| panic!("connect {addr}: {e}"));
        let reader = BufReader::new(stream.try_clone().unwrap());
        Control { stream, reader }
    }

    /// Send `json`, its result within `wait` (spontaneous safety errors skipped).
    fn request(&mut self, json: &str, wait: Duration) -> Value {
        self.stream.set_read_timeout(Some(wait)).unwrap();
        writeln!(self.stream, "{json}").unwrap_or_else(|e| panic!("send {json}: {e}"));
        loop {
            let mut line = String::new();
            match self.reader.read_line(&mut line) {
                Ok(0) => panic!("the MCM closed the connection (no result for {json})"),
                Ok(_) => {}
                Err(e) => panic!("no result for {json} within {wait:?}: {e}"),
            }
            let v: Value =
                serde_json::from_str(&line).unwrap_or_else(|e| panic!("not JSON ({e}): {line:?}"));
            if !common::is_event(&v) {
                return v;
            }
        }
    }
}

/// Poll the detailed status (retrying connections: QEMU accepts on a forwarded port before the
/// guest listens) until `pred` holds; panics after [`HOST_WAIT`] with the last answer.
fn wait_status(addr: SocketAddr, what: &str, pred: impl Fn(&Value) -> bool) -> Value {
    let started = Instant::now();
    loop {
        let last = ask(
            addr,
            r#"{"command":"status","arguments":{"detail":true}}"#,
            Duration::from_secs(20),
        );
        if let Ok(s) = &last
            && pred(s)
        {
            return s.clone();
        }
        assert!(
            started.elapsed() < HOST_WAIT,
            "{what}: not within {HOST_WAIT:?}; the last status (or error): {last:?}"
        );
        std::thread::sleep(Duration::from_millis(250));
    }
}

fn drives_online(s: &Value) -> bool {
    s["result_type"] == "status"
        && s["detail"]["drive_online"]
            .as_array()
            .is_some_and(|a| a.len() == 6 && a.iter().all(|x| x == true))
}

fn assert_ok(v: &Value, what: &str) {
    assert!(
        v["result_type"] == "generic" && v["error_status"] == "OK",
        "{what}: expected a generic OK, got {v}"
    );
}

/// A MainPID from `systemctl show -p MainPID [--value]`.
fn main_pid(out: &str) -> u32 {
    out.trim()
        .trim_start_matches("MainPID=")
        .parse()
        .unwrap_or_else(|e| panic!("MainPID from {out:?}: {e}"))
}

/// Install, run, restart, stop, reboot, upgrade and purge the packages `(deb, upgrade)` of
/// [`packages`] in `guest` (booted with [`FORWARDED`]).
pub fn run(guest: &mut vm::Guest, (deb, upgrade): &(PathBuf, PathBuf)) {
    let log = guest.log().display().to_string();
    let json: SocketAddr = ([127, 0, 0, 1], guest.host_port(JSON_PORT)).into();
    let arm: SocketAddr = ([127, 0, 0, 1], guest.host_port(ARM_PORT)).into();
    let deb_in_guest = guest.guest_path(deb);
    let upgrade_in_guest = guest.guest_path(upgrade);

    // Install: starts nothing.
    let install_started = Instant::now();
    let out = guest.run_ok(
        &format!(
            "DEBIAN_FRONTEND=noninteractive dpkg -i {deb_in_guest} </dev/null && \
             echo \"rt_runtime=$(cat /proc/sys/kernel/sched_rt_runtime_us)\" && \
             (systemctl is-active mcm-rt mcm-gateway mcm.target || true)"
        ),
        RUN_WAIT,
    );
    eprintln!("install:\n{out}");
    assert!(
        !out.lines().any(|l| l.trim() == "active"),
        "installing started a unit:\n{out}\n(log: {log})"
    );
    assert!(
        !out.contains("not found") && out.lines().any(|l| l == "rt_runtime=-1"),
        "the maintainer scripts did not set kernel.sched_rt_runtime_us = -1 at install:\n{out}"
    );
    let edited = guest.run_ok(
        &format!(
            "sed -i {} {CONF} && grep -E '^({})' {CONF}",
            sed_script(),
            edits().iter().map(|e| e.1).collect::<Vec<_>>().join("|")
        ),
        RUN_WAIT,
    );
    for (_, key, value) in edits() {
        assert!(
            edited.lines().any(|l| l == format!("{key} = {value}")),
            "the edit {key} = {value} is not in {CONF}; its lines:\n{edited}"
        );
    }

    // Start: the virtual arm, then the MCM, enabled.
    guest.run_ok(&start_arm(), RUN_WAIT);
    guest.run_ok(
        &format!(
            "systemctl enable --now mcm.target && {}",
            wait_active(&["mcm-rt", "mcm-gateway", "mcm.target"], 120)
        ),
        RUN_WAIT,
    );
    let active_after = install_started.elapsed();
    wait_status(
        json,
        "all drives online after the first start",
        drives_online,
    );
    eprintln!(
        "install to active {active_after:.1?}, to drives online {:.1?}",
        install_started.elapsed()
    );

    // Calibrate and move, on one connection (the client that controls the arm); the arm's
    // truth reaches the targets.
    let mut control = Control::connect(json);
    assert_ok(
        &control.request(r#"{"command":"calibrate"}"#, Duration::from_secs(120)),
        "calibrate",
    );
    let r = control.request(
        r#"{"command":"pvt","arguments":{"dt":0.02}}"#,
        Duration::from_secs(20),
    );
    assert!(
        r["result_type"] == "status" && r["operating_mode"] == "PVT",
        "pvt: expected a status in PVT, got {r}"
    );
    let move_started = Instant::now();
    let r = control.request(&common::move_all(&TARGETS, 0.5), Duration::from_secs(20));
    assert_eq!(
        r["result_type"], "move_all",
        "move_all: expected its result, got {r}"
    );
    loop {
        let t = virtual_arm::ask(arm, r#"{"command":"sim"}"#);
        assert_eq!(t["result_type"], "sim", "the virtual arm's truth: {t}");
        let p = common::six(&t["true_position"]);
        if common::max_diff(&p, &TARGETS) < 0.1 {
            eprintln!("move reached {p:?} after {:.1?}", move_started.elapsed());
            break;
        }
        assert!(
            move_started.elapsed() < HOST_WAIT,
            "the arm did not reach {TARGETS:?} within 0.1 deg in {HOST_WAIT:?}: at {p:?}"
        );
        std::thread::sleep(Duration::from_millis(200));
    }

    // The gateway killed with SIGKILL: systemd starts a new one, the core holds the arm.
    let pids = |guest: &mut vm::Guest| {
        let out = guest.run_ok(
            "systemctl show -p MainPID --value mcm-rt; systemctl show -p MainPID --value mcm-gateway",
            RUN_WAIT,
        );
        let v: Vec<u32> = out.lines().map(main_pid).collect();
        assert_eq!(v.len(), 2, "MainPIDs: {out}");
        (v[0], v[1])
    };
    let (core, gateway) = pids(guest);
    assert!(
        core > 0 && gateway > 0,
        "MainPIDs: core {core}, gateway {gateway}"
    );
    let out = guest.run_ok(
        &format!(
            "kill -9 {gateway}; for i in $(seq 1 120); do \
             p=$(systemctl show -p MainPID --value mcm-gateway); \
             if [ \"$p\" != 0 ] && [ \"$p\" != {gateway} ] && systemctl is-active -q mcm-gateway; \
             then echo \"new gateway $p\"; exit 0; fi; sleep 0.5; done; \
             echo 'no new gateway within 60 s'; systemctl --no-pager status mcm-gateway; exit 1"
        ),
        RUN_WAIT,
    );
    eprintln!("{}", out.trim());
    let (core_after, _) = pids(guest);
    assert_eq!(
        core_after, core,
        "the core's MainPID changed when the gateway was killed: {core} -> {core_after}"
    );
    let s = wait_status(json, "HOLD after the gateway's restart", |s| {
        s["result_type"] == "status" && s["operating_mode"] == "HOLD"
    });
    eprintln!("after the gateway's restart: {}", s["operating_mode"]);

    // Stop: the core's controlled stop, in its journal.
    let stop_started = Instant::now();
    guest.run_ok("systemctl stop mcm.target", RUN_WAIT);
    let stop_took = stop_started.elapsed();
    let out = guest.run_ok(
        "for i in $(seq 1 40); do \
         l=$(journalctl --no-pager -u mcm-rt | grep 'controlled stop took'); \
         if [ -n \"$l\" ]; then echo \"$l\"; exit 0; fi; sleep 0.5; done; \
         journalctl --no-pager -n 40 -u mcm-rt; exit 1",
        RUN_WAIT,
    );
    eprintln!(
        "systemctl stop mcm.target took {stop_took:.1?}; the core: {}",
        out.trim()
    );
    let inactive = guest.run("systemctl is-active mcm-rt mcm-gateway", RUN_WAIT);
    assert!(
        !inactive.output.lines().any(|l| l.trim() == "active"),
        "a unit is still active after stopping mcm.target:\n{}",
        inactive.output
    );
    guest.run_ok(
        &format!(
            "systemctl start mcm.target && {}",
            wait_active(&["mcm-rt", "mcm-gateway", "mcm.target"], 120)
        ),
        RUN_WAIT,
    );

    // Reboot: the enabled MCM comes back by itself.
    let reboot_started = Instant::now();
    guest.reboot();
    guest.check_rebooted();
    guest.run_ok(&start_arm(), RUN_WAIT);
    guest.run_ok(
        &wait_active(&["mcm-rt", "mcm-gateway", "mcm.target"], 120),
        RUN_WAIT,
    );
    wait_status(json, "all drives online after the reboot", drives_online);
    eprintln!("reboot to drives online {:.1?}", reboot_started.elapsed());

    // Upgrade: the edited conffile stays.
    let out = guest.run_ok(
        &format!(
            "DEBIAN_FRONTEND=noninteractive dpkg -i {upgrade_in_guest} </dev/null && \
             dpkg-query -W -f '${{Version}}\\n' mcm && cat {CONF}"
        ),
        RUN_WAIT,
    );
    assert!(
        out.lines().any(|l| l == UPGRADE_VERSION),
        "the installed version is not {UPGRADE_VERSION} after the upgrade:\n{out}"
    );
    for (_, key, value) in edits() {
        assert!(
            out.lines().any(|l| l == format!("{key} = {value}")),
            "the upgrade lost the edit {key} = {value} of {CONF}:\n{out}"
        );
    }

    // Purge: nothing is left.
    guest.run_ok(
        "systemctl stop mcm-virtual-arm; DEBIAN_FRONTEND=noninteractive apt-get purge -y mcm </dev/null",
        RUN_WAIT,
    );
    let out = guest.run(
        "dpkg -L mcm >/dev/null 2>&1 && echo 'dpkg -L mcm still lists files'; \
         dpkg -s mcm >/dev/null 2>&1 && echo 'dpkg -s mcm still knows the package'; \
         [ -e /etc/mcm ] && echo '/etc/mcm is still there'; \
         ls -d /usr/lib/systemd/system/mcm.target /usr/lib/systemd/system/mcm-rt.service* \
            /usr/lib/systemd/system/mcm-gateway.service* /usr/lib/systemd/system/mcm-ros2.service* \
            /etc/systemd/system/mcm.target* /etc/systemd/system/mcm-rt.service* \
            /etc/systemd/system/mcm-gateway.service* /etc/systemd/system/mcm-ros2.service* \
            /etc/systemd/system/*/mcm.target /etc/systemd/system/*/mcm-rt.service \
            /etc/systemd/system/*/mcm-gateway.service /etc/systemd/system/*/mcm-ros2.service \
            /usr/lib/mcm /usr/bin/mcm* 2>/dev/null; \
         getent passwd mcm && echo 'the user mcm is still there'; \
         getent group mcm && echo 'the group mcm is still there'; \
         systemctl is-active mcm-rt mcm-gateway mcm.target | grep -x active; \
         true",
        RUN_WAIT,
    );
    assert!(
        out.output.trim().is_empty(),
        "purge left something behind:\n{}",
        out.output
    );
}
