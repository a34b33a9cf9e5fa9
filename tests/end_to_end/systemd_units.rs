//! The systemd units (`deploy/systemd/`, installed by the Debian package, docs/deploy.md
//! "systemd") restart as the launcher does: the gateway's unit carries the numbers of
//! `mcm_shared::restart::GATEWAY_RESTART` (the launcher's own back-off, systemd 254 or later),
//! with a start limit that the back-off never reaches but that ends a restart every 0.1 s (an
//! older systemd, which ignores the back-off), and it is stopped with the core and after it, as
//! the launcher stops them; the core's unit never restarts it, as the launcher never does; the
//! ROS 2 node's unit waits `ROS2_RESTART` as the launcher does. The core and the gateway are
//! `Type=notify` with a watchdog, everything is part of `mcm.target`, the programs are the
//! package's (`/usr/bin`), the CAN interface's networkd file agrees with the configuration, and
//! `deploy/wait-for-bus` waits for the interface the configuration names. Reads the files of
//! `deploy/`; tests/end_to_end/deb_package.rs checks the package built from them.

use crate::common;

use mcm_shared::restart::{GATEWAY_RESTART, ROS2_RESTART};
use std::time::Duration;

/// The text of the unit file `name`.
fn unit_text(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("deploy/systemd")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// The `key=value` lines of `section` in the unit file `name`.
fn section(name: &str, section: &str) -> Vec<String> {
    let mut current = String::new();
    let mut lines = Vec::new();
    for line in unit_text(name).lines().map(str::trim) {
        if line.starts_with('[') {
            current = line.to_string();
        } else if current == format!("[{section}]") && !line.is_empty() && !line.starts_with('#') {
            lines.push(line.to_string());
        }
    }
    lines
}

/// The comments of the unit file `name`, as one line of words.
fn comments(name: &str) -> String {
    let text = unit_text(name);
    let words: Vec<&str> = text
        .lines()
        .filter_map(|l| l.trim().strip_prefix('#'))
        .flat_map(str::split_whitespace)
        .collect();
    words.join(" ")
}

/// The value of the one `key=` line of `lines`.
fn value<'a>(lines: &'a [String], key: &str) -> &'a str {
    let found: Vec<&str> = lines
        .iter()
        .filter_map(|l| l.strip_prefix(key)?.strip_prefix('='))
        .collect();
    assert_eq!(found.len(), 1, "{key}= once: {lines:#?}");
    found[0]
}

/// The most starts within any `interval` of a unit that dies at once and is restarted after
/// `wait(n)` before restart number `n` (1: the first), over an hour.
fn most_starts_in(interval: Duration, wait: impl Fn(u32) -> Duration) -> usize {
    let mut starts = vec![Duration::ZERO];
    let mut n = 1;
    while *starts.last().unwrap() < Duration::from_secs(3600) {
        starts.push(*starts.last().unwrap() + wait(n));
        n += 1;
    }
    (0..starts.len())
        .map(|i| {
            starts[i..]
                .iter()
                .take_while(|&&t| t < starts[i] + interval)
                .count()
        })
        .max()
        .unwrap()
}

#[test]
fn the_gateway_unit_restarts_with_the_launchers_back_off() {
    let service = section("mcm-gateway.service", "Service");
    assert!(
        service.contains(&"Restart=always".to_string()),
        "{service:#?}"
    );
    for line in GATEWAY_RESTART.systemd_lines() {
        assert!(service.contains(&line), "{line} missing: {service:#?}");
    }
    for key in ["RestartSec", "RestartSteps", "RestartMaxDelaySec"] {
        value(&service, key);
    }
}

#[test]
fn the_start_limit_never_stops_the_back_off_but_stops_a_restart_every_first_wait() {
    let unit = section("mcm-gateway.service", "Unit");
    let interval: u64 = value(&unit, "StartLimitIntervalSec")
        .parse()
        .unwrap_or_else(|e| panic!("StartLimitIntervalSec in whole seconds ({e}): {unit:#?}"));
    let burst: usize = value(&unit, "StartLimitBurst")
        .parse()
        .unwrap_or_else(|e| panic!("StartLimitBurst ({e}): {unit:#?}"));
    assert!(interval > 0, "a start limit (0 switches it off): {unit:#?}");
    let interval = Duration::from_secs(interval);
    // systemd 254 and later: the launcher's back-off; the limit must never end it (systemd
    // counts every start, the automatic restarts too, within the interval).
    let with_back_off = most_starts_in(interval, |n| GATEWAY_RESTART.delay(n));
    assert!(
        with_back_off <= burst,
        "with the back-off a gateway that dies at once starts {with_back_off} times in \
         {interval:?}: StartLimitBurst={burst} would stop it"
    );
    // An older systemd waits RestartSec= each time: the limit must end that.
    let without = most_starts_in(interval, |_| GATEWAY_RESTART.first);
    assert!(
        without > burst,
        "restarting every {:?}, {without} starts in {interval:?} stay within \
         StartLimitBurst={burst}: an old systemd would loop forever",
        GATEWAY_RESTART.first
    );
    // The unit's comment states the figure and that the back-off needs systemd 254.
    let text = comments("mcm-gateway.service");
    let claim = format!(
        "starts at most {with_back_off} times in any {} s",
        interval.as_secs()
    );
    assert!(
        text.contains(&claim),
        "the unit's comment should say {claim:?}"
    );
    assert!(text.contains("systemd 254 or later is required"), "{text}");
}

#[test]
fn the_core_unit_is_never_restarted() {
    let service = section("mcm-rt.service", "Service");
    assert!(service.contains(&"Restart=no".to_string()), "{service:#?}");
}

/// systemd stops units in the reverse of their start order: the gateway's unit is ordered
/// before the core's, so that stopping the core (`systemctl stop mcm-rt`, a shutdown) stops the
/// core first and the gateway, bound to it, after it, as the launcher does. Its clients then
/// hear the core's controlled stop before the gateway's last line. `After=mcm-rt.service` would
/// stop the gateway first.
#[test]
fn the_gateway_unit_is_stopped_with_the_core_and_after_it() {
    let unit = section("mcm-gateway.service", "Unit");
    assert_eq!(value(&unit, "BindsTo"), "mcm-rt.service", "{unit:#?}");
    assert_eq!(value(&unit, "Before"), "mcm-rt.service", "{unit:#?}");
    assert!(
        !unit.iter().any(|l| l.starts_with("After=")),
        "the gateway must not be ordered after the core: {unit:#?}"
    );
    let core = section("mcm-rt.service", "Unit");
    assert!(
        !core
            .iter()
            .any(|l| l.starts_with("Before=") || l.starts_with("After=mcm-gateway")),
        "the order is the gateway unit's to give: {core:#?}"
    );
}

/// The ROS 2 node's unit: a client of the core, bound to it and ordered before it like the
/// gateway (so stopped after the core's controlled stop, which ends its goals with words, as
/// the launcher stops them), restarted when it dies, and running the `mcm-ros2` binary the
/// workspace builds.
#[test]
fn the_ros2_unit_is_a_client_stopped_after_the_core() {
    let unit = section("mcm-ros2.service", "Unit");
    assert_eq!(value(&unit, "BindsTo"), "mcm-rt.service", "{unit:#?}");
    assert_eq!(value(&unit, "Before"), "mcm-rt.service", "{unit:#?}");
    assert!(
        !unit.iter().any(|l| l.starts_with("After=")),
        "the node must not be ordered after the core: {unit:#?}"
    );
    let service = section("mcm-ros2.service", "Service");
    assert_eq!(value(&service, "Restart"), "always", "{service:#?}");
    let exec = value(&service, "ExecStart");
    assert!(exec.starts_with("/usr/bin/mcm-ros2 "), "{exec}");
    assert!(exec.contains("--instance default"), "{exec}");
    let urdf = exec
        .split_whitespace()
        .skip_while(|w| *w != "--urdf-out")
        .nth(1)
        .expect("--urdf-out FILE");
    let runtime = value(&service, "RuntimeDirectory");
    assert!(
        urdf.starts_with(&format!("/run/{runtime}/")),
        "the URDF goes into the unit's runtime directory: {urdf}"
    );
    let manifest = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("ros2/Cargo.toml"),
    )
    .expect("ros2/Cargo.toml");
    assert!(
        manifest.contains("name = \"mcm-ros2\""),
        "the unit runs a binary the workspace builds"
    );
}

#[test]
fn the_ros2_unit_restarts_after_the_launchers_wait() {
    let service = section("mcm-ros2.service", "Service");
    for line in ROS2_RESTART.systemd_lines() {
        assert!(service.contains(&line), "{line} missing: {service:#?}");
    }
    assert_eq!(
        ROS2_RESTART.systemd_lines().len(),
        1,
        "a fixed wait is RestartSec= alone"
    );
    value(&service, "RestartSec");
}

/// The core and the gateway say when they are ready (`READY=1`, from the main process only)
/// and have a watchdog; the node cannot (it is ready only after the core, which starts after
/// it) and is `Type=exec`.
#[test]
fn the_core_and_the_gateway_notify_systemd_and_the_node_is_exec() {
    for unit in ["mcm-rt.service", "mcm-gateway.service"] {
        let service = section(unit, "Service");
        assert_eq!(value(&service, "Type"), "notify", "{unit}: {service:#?}");
        assert_eq!(
            value(&service, "NotifyAccess"),
            "main",
            "{unit}: {service:#?}"
        );
        let watchdog = value(&service, "WatchdogSec");
        let secs: u64 = watchdog
            .strip_suffix('s')
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("{unit}: WatchdogSec={watchdog} in whole seconds (`2s`)"));
        assert!(
            (2..=30).contains(&secs),
            "{unit}: WatchdogSec={watchdog}: at least 2 s (pinged every half), at most 30 s"
        );
    }
    let node = section("mcm-ros2.service", "Service");
    assert_eq!(value(&node, "Type"), "exec", "{node:#?}");
    assert!(
        !node.iter().any(|l| l.starts_with("WatchdogSec=")),
        "{node:#?}"
    );
}

/// One controlled stop: the core gets SIGTERM once and the time its stop is bounded by.
#[test]
fn the_core_gets_one_sigterm_and_time_for_its_controlled_stop() {
    let service = section("mcm-rt.service", "Service");
    assert_eq!(value(&service, "KillSignal"), "SIGTERM", "{service:#?}");
    let timeout: u64 = value(&service, "TimeoutStopSec").parse().unwrap();
    assert!(
        timeout >= 10,
        "TimeoutStopSec={timeout}: the controlled stop takes a few seconds"
    );
    assert!(
        !service.iter().any(|l| l.starts_with("ExecStop=")),
        "no ExecStop=: systemd's one SIGTERM starts the controlled stop: {service:#?}"
    );
}

/// `mcm.target` starts the core and the gateway and is active while the core runs; the three
/// units are stopped with it; the node joins it when enabled.
#[test]
fn mcm_target_starts_and_stops_the_mcm() {
    let target = section("mcm.target", "Unit");
    assert_eq!(value(&target, "BindsTo"), "mcm-rt.service", "{target:#?}");
    assert_eq!(
        value(&target, "Wants"),
        "mcm-gateway.service",
        "{target:#?}"
    );
    let after: Vec<&str> = value(&target, "After").split_whitespace().collect();
    assert_eq!(
        after,
        ["mcm-rt.service", "mcm-gateway.service"],
        "{target:#?}"
    );
    assert_eq!(
        value(&section("mcm.target", "Install"), "WantedBy"),
        "multi-user.target"
    );
    for unit in ["mcm-rt.service", "mcm-gateway.service", "mcm-ros2.service"] {
        assert_eq!(
            value(&section(unit, "Unit"), "PartOf"),
            "mcm.target",
            "{unit}"
        );
    }
    assert_eq!(
        value(&section("mcm-ros2.service", "Install"), "WantedBy"),
        "mcm.target"
    );
    for unit in ["mcm-rt.service", "mcm-gateway.service"] {
        assert!(
            section(unit, "Install").is_empty(),
            "{unit} is started through mcm.target, not enabled by itself"
        );
    }
}

/// The programs are the package's, in /usr/bin, running as the package's user, with the
/// packaged configuration.
#[test]
fn the_units_run_the_packaged_programs_as_the_packaged_user() {
    let user = std::fs::read_to_string(deploy("sysusers.d/mcm.conf")).unwrap();
    assert!(
        user.lines().any(|l| l.starts_with("u mcm ")),
        "sysusers.d creates the user mcm: {user}"
    );
    for (unit, program) in [
        ("mcm-rt.service", "mcm-rt"),
        ("mcm-gateway.service", "mcm-gateway"),
        ("mcm-ros2.service", "mcm-ros2"),
    ] {
        let service = section(unit, "Service");
        let exec = value(&service, "ExecStart");
        assert!(
            exec.starts_with(&format!("/usr/bin/{program} --config /etc/mcm/prob2.toml ")),
            "{unit}: {exec}"
        );
        assert_eq!(value(&service, "User"), "mcm", "{unit}");
    }
    let realtime = dropin_section("realtime.conf");
    for line in [
        "LimitRTPRIO=99",
        "LimitMEMLOCK=infinity",
        "AmbientCapabilities=CAP_SYS_NICE CAP_IPC_LOCK",
    ] {
        assert!(
            realtime.contains(&line.to_string()),
            "{line}: {realtime:#?}"
        );
    }
    let sysctl = std::fs::read_to_string(deploy("sysctl.d/60-mcm-realtime.conf")).unwrap();
    assert!(
        sysctl
            .lines()
            .any(|l| l.replace(' ', "") == "kernel.sched_rt_runtime_us=-1"),
        "{sysctl}"
    );
}

/// Nothing in deploy/ points at /usr/local any more: the package installs to /usr.
#[test]
fn nothing_refers_to_usr_local() {
    let mut stack = vec![deploy("")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let text = std::fs::read_to_string(&path).unwrap_or_default();
                assert!(
                    !text.contains("/usr/local/bin"),
                    "{} refers to /usr/local/bin",
                    path.display()
                );
            }
        }
    }
}

/// systemd-networkd brings the configuration's CAN interface up at its bit rate, with the
/// restart after bus-off and the transmit queue of deploy/can-setup.sh.
#[test]
fn the_can_interface_files_agree_with_the_configuration() {
    let config = mcm_shared::config::RobotConfig::prob2_default();
    let network = std::fs::read_to_string(deploy("networkd/80-mcm-can0.network")).unwrap();
    let key = |text: &str, k: &str| {
        text.lines()
            .find_map(|l| l.trim().strip_prefix(k)?.strip_prefix('='))
            .unwrap_or_else(|| panic!("{k}= in {text}"))
            .to_string()
    };
    assert_eq!(key(&network, "Name"), config.bus.interface);
    let bitrate = key(&network, "BitRate");
    let bits: u32 = match bitrate.strip_suffix('K') {
        Some(k) => k.parse::<u32>().unwrap() * 1000,
        None => bitrate.parse().unwrap(),
    };
    assert_eq!(bits, config.bus.bitrate, "BitRate={bitrate}");
    assert_eq!(key(&network, "RestartSec"), "100ms");
    assert_eq!(key(&network, "RequiredForOnline"), "no");
    let link = std::fs::read_to_string(deploy("networkd/80-mcm-can0.link")).unwrap();
    assert_eq!(key(&link, "OriginalName"), config.bus.interface);
    let script = std::fs::read_to_string(deploy("can-setup.sh")).unwrap();
    let queue = key(&link, "TransmitQueueLength");
    assert!(
        script.contains(&format!("txqueuelen {queue}")),
        "the same queue as can-setup.sh"
    );
    let bus = dropin_section("bus.conf");
    assert_eq!(
        value(&bus, "ExecStartPre"),
        "/usr/lib/mcm/wait-for-bus /etc/mcm/prob2.toml 30"
    );
}

/// `deploy/wait-for-bus`, with the launcher built here as its `mcm`: the simulated bus starts at
/// once, an interface that is up (loopback stands in for a CAN interface) is found, and one that
/// does not exist ends the wait after the timeout, naming it.
#[test]
fn wait_for_bus_waits_for_the_configured_interface() {
    let run = |config: &common::TempConfig, timeout: &str| {
        std::process::Command::new(deploy("wait-for-bus"))
            .args([config.path(), timeout])
            .env("MCM_LAUNCHER", env!("CARGO_BIN_EXE_mcm"))
            .output()
            .unwrap()
    };
    let sim = common::config_file("waitbus-sim", str::to_string);
    let out = run(&sim, "1");
    assert!(out.status.success(), "{out:?}");
    assert!(out.stdout.is_empty(), "nothing to wait for: {out:?}");
    let socketcan = |iface: &str| {
        let iface = iface.to_string();
        common::config_file("waitbus-can", move |t| {
            t.replace("backend = \"sim\"", "backend = \"socketcan\"")
                .replace("interface = \"can0\"", &format!("interface = \"{iface}\""))
        })
    };
    let up = socketcan("lo");
    let out = run(&up, "1");
    assert!(out.status.success(), "{out:?}");
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "wait-for-bus: lo is up\n"
    );
    let missing = socketcan("mcmnone9");
    let out = run(&missing, "1");
    assert!(!out.status.success(), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("the CAN interface mcmnone9 (bus.interface in") && err.contains("after 1 s"),
        "{err}"
    );
}

/// The path of `rel` under deploy/.
fn deploy(rel: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("deploy")
        .join(rel)
}

/// The `key=value` lines of the `[Service]` section of the core's drop-in `name`.
fn dropin_section(name: &str) -> Vec<String> {
    section(&format!("mcm-rt.service.d/{name}"), "Service")
}
