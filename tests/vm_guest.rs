//! The test guest itself (tests/common/vm.rs), what the tests that run the MCM in it rely on:
//! systemd is PID 1 and the boot completes, vcan0 is up, a guest TCP port is reached from the
//! host through its forwarded port while the guest reaches nothing of the host's (QEMU's
//! `restrict=on`), the read-only share cannot be written, and a reboot comes back by itself,
//! with vcan0 up again; then the guest powers off.

mod common;

use common::vm;
use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::time::{Duration, Instant};

/// The guest port the test serves on.
const GUEST_PORT: u16 = 18080;
/// The longest any one command in the guest may take.
const RUN_WAIT: Duration = Duration::from_secs(120);

/// GET `/path` from the guest's web server through the forwarded port, retried until it
/// answers (the server starts in the background) or `wait` passed.
fn http_get(port: u16, path: &str, wait: Duration) -> String {
    let started = Instant::now();
    loop {
        let attempt = (|| -> std::io::Result<String> {
            let mut s = TcpStream::connect(("127.0.0.1", port))?;
            s.set_read_timeout(Some(Duration::from_secs(20)))?;
            s.write_all(format!("GET {path} HTTP/1.0\r\n\r\n").as_bytes())?;
            let mut text = String::new();
            s.read_to_string(&mut text)?;
            Ok(text)
        })();
        match attempt {
            Ok(text) if text.starts_with("HTTP/1.0 200") => return text,
            other if started.elapsed() > wait => {
                panic!("GET {path} on 127.0.0.1:{port} within {wait:?}: {other:?}")
            }
            _ => std::thread::sleep(Duration::from_millis(200)),
        }
    }
}

#[test]
fn the_guest_boots_serves_a_forwarded_port_is_isolated_and_reboots() {
    let image = match vm::image() {
        Ok(image) => image,
        Err(why) => return common::skip("vm_guest", &why),
    };
    let share = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(common::unique_instance("vm-guest-ro"));
    std::fs::create_dir_all(&share).unwrap();
    std::fs::write(share.join("shared.txt"), "from the host\n").unwrap();
    let started = Instant::now();
    let mut guest = vm::Guest::boot("guest", &image, &share, &[GUEST_PORT]);
    let booted = started.elapsed();
    let log = guest.log().display().to_string();

    let out = guest.run_ok(
        "cat /proc/1/comm; systemctl is-system-running --wait; ip -br link show vcan0",
        RUN_WAIT,
    );
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines.first(),
        Some(&"systemd"),
        "PID 1: {out}\n(log: {log})"
    );
    assert_eq!(
        lines.get(1),
        Some(&"running"),
        "the boot: {out}\n(log: {log})"
    );
    assert!(
        lines
            .get(2)
            .is_some_and(|l| l.starts_with("vcan0") && l.contains("UP")),
        "vcan0: {out}\n(log: {log})"
    );

    // The shares: the read-only one reads and refuses writes; the writable one reaches the
    // host.
    let out = guest.run(
        &format!(
            "cat {ro}/shared.txt && echo from the guest >{rw}/guest.txt && ! touch {ro}/x",
            ro = vm::GUEST_RO,
            rw = vm::GUEST_RW
        ),
        RUN_WAIT,
    );
    assert_eq!(out.status, 0, "the shares: {}\n(log: {log})", out.output);
    assert!(out.output.starts_with("from the host\n"), "{}", out.output);
    assert_eq!(
        std::fs::read_to_string(guest.results().join("guest.txt")).unwrap(),
        "from the guest\n"
    );
    assert!(
        !share.join("x").exists(),
        "the guest wrote into the read-only share"
    );

    // A forwarded port: a web server in the guest serves a file the host wrote.
    std::fs::write(
        guest.results().join("token.txt"),
        format!("token {}\n", std::process::id()),
    )
    .unwrap();
    guest.run_ok(
        &format!(
            "systemd-run --unit=test-web python3 -m http.server --directory {} {GUEST_PORT}",
            vm::GUEST_RW
        ),
        RUN_WAIT,
    );
    let page = http_get(guest.host_port(GUEST_PORT), "/token.txt", RUN_WAIT);
    assert!(
        page.ends_with(&format!("token {}\n", std::process::id())),
        "{page}"
    );

    // Isolation: without `restrict=on`, 10.0.2.2 would be the host's loopback, where this
    // listener waits; the guest must not get through.
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    listener.set_nonblocking(true).unwrap();
    let port = listener.local_addr().unwrap().port();
    let out = guest.run(
        &format!(
            "python3 -c 'import socket; socket.create_connection((\"10.0.2.2\", {port}), timeout=5)' \
             && echo REACHED"
        ),
        RUN_WAIT,
    );
    assert!(
        out.status != 0 && !out.output.contains("REACHED"),
        "the guest reached the host's 127.0.0.1:{port}: {}\n(log: {log})",
        out.output
    );
    assert!(
        listener.accept().is_err(),
        "the host's listener got a connection from the guest"
    );

    // A reboot comes back by itself (a new boot id), with vcan0 up again.
    let started = Instant::now();
    guest.reboot();
    let rebooted = started.elapsed();
    let out = guest.run_ok(
        "systemctl is-system-running --wait; ip -br link show vcan0",
        RUN_WAIT,
    );
    assert!(
        out.starts_with("running\nvcan0") && out.contains("UP"),
        "after the reboot: {out}\n(log: {log})"
    );

    let started = Instant::now();
    let status = guest.shutdown();
    assert!(status.success(), "QEMU ended with {status} (log: {log})");
    eprintln!(
        "guest: boot {:.1} s, reboot {:.1} s, power-off {:.1} s",
        booted.as_secs_f64(),
        rebooted.as_secs_f64(),
        started.elapsed().as_secs_f64()
    );
    let _ = std::fs::remove_dir_all(&share);
}
