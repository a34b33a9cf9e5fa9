//! The systemd units restart as the launcher does: the gateway's unit carries the numbers of
//! `mcm_shared::restart::GATEWAY_RESTART` (the launcher's own back-off, systemd 254 or later),
//! with a start limit that the back-off never reaches but that ends a restart every 0.1 s (an
//! older systemd, which ignores the back-off), and it is stopped with the core and after it, as
//! the launcher stops them; the core's unit never restarts it, as the launcher never does. Reads
//! the files of `deploy/systemd/`.

use mcm_shared::restart::GATEWAY_RESTART;
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
    assert!(exec.starts_with("/usr/local/bin/mcm-ros2 "), "{exec}");
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
