//! End to end, hostile clients against the connection limits (issue 11, items 3 and 7): with
//! 64 idle and 64 "slowloris" connections open on each port, a loopback operator still
//! connects to both ports and gets `hold` answered; the oldest attackers were closed with a
//! one-line reason. And one line that used to panic the connection task is answered with an
//! ERROR on each port, the connection staying alive. Every wait is bounded.

use crate::common;

use common::{Mcm, WAIT, assert_status};
use serde_json::Value;
use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, SocketAddrV4, TcpStream};
use std::os::fd::FromRawFd;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// The line that used to panic the connection task (an excerpt cut inside a multi-byte
/// character); `raw`: with a raw `é` (as typed at the HMI) instead of `\u00e9`.
fn panicking_line(raw: bool) -> String {
    let e = if raw { "\u{e9}" } else { "\\u00e9" };
    format!(
        "{{\"command\":\"calibrate\",\"arguments\":{{\"which\":\"{}{e}\"}}}}",
        "a".repeat(58)
    )
}

/// Connect from `ip` (any 127.x.y.z is this machine) to the IPv4 address `to`.
fn connect_from(ip: &str, to: SocketAddr) -> TcpStream {
    let sockaddr = |a: SocketAddrV4| libc::sockaddr_in {
        sin_family: libc::AF_INET as libc::sa_family_t,
        sin_port: a.port().to_be(),
        sin_addr: libc::in_addr {
            s_addr: u32::from(*a.ip()).to_be(),
        },
        sin_zero: [0; 8],
    };
    let SocketAddr::V4(to) = to else {
        panic!("the test binds 127.0.0.1")
    };
    let from = sockaddr(SocketAddrV4::new(ip.parse().unwrap(), 0));
    let to = sockaddr(to);
    let len = std::mem::size_of::<libc::sockaddr_in>() as libc::socklen_t;
    // SAFETY: plain socket calls on a descriptor we own; the addresses are valid
    // `sockaddr_in`s of `len` bytes that outlive the calls; the descriptor is handed to
    // `TcpStream` (which closes it) only once it is a connected TCP socket.
    let stream = unsafe {
        let fd = libc::socket(libc::AF_INET, libc::SOCK_STREAM | libc::SOCK_CLOEXEC, 0);
        assert!(fd >= 0, "socket: {}", std::io::Error::last_os_error());
        let bound = libc::bind(fd, (&raw const from).cast(), len);
        assert_eq!(bound, 0, "bind {ip}: {}", std::io::Error::last_os_error());
        let connected = libc::connect(fd, (&raw const to).cast(), len);
        assert_eq!(connected, 0, "connect: {}", std::io::Error::last_os_error());
        TcpStream::from_raw_fd(fd)
    };
    stream.set_read_timeout(Some(WAIT)).unwrap();
    stream
}

/// Read until `done` holds for the text received (or EOF, or [`WAIT`]); returns it.
fn read_until(s: &mut TcpStream, done: impl Fn(&str) -> bool) -> String {
    let deadline = Instant::now() + WAIT;
    let mut got = Vec::new();
    let mut buf = [0u8; 4096];
    while !done(&String::from_utf8_lossy(&got)) {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(
            !left.is_zero(),
            "not in time; got {:?}",
            String::from_utf8_lossy(&got)
        );
        s.set_read_timeout(Some(left)).unwrap();
        match s.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => got.extend_from_slice(&buf[..n]),
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) => panic!("read: {e}; got {:?}", String::from_utf8_lossy(&got)),
        }
    }
    String::from_utf8_lossy(&got).into_owned()
}

/// 64 idle connections from 127.0.0.1 (the operator's own address: the per-peer cap) and 64
/// slowloris connections from 127.0.0.2..=5 (one byte every 100 ms of a line never ended:
/// the total cap). Returns the idle ones, oldest first, and the drip's stop flag.
fn attack(port: SocketAddr, stop: &Arc<AtomicBool>) -> Vec<TcpStream> {
    let idle: Vec<TcpStream> = (0..64).map(|_| connect_from("127.0.0.1", port)).collect();
    let slow: Vec<TcpStream> = (0..64)
        .map(|i| connect_from(&format!("127.0.0.{}", 2 + i % 4), port))
        .collect();
    let stop = stop.clone();
    std::thread::spawn(move || {
        let mut slow = slow;
        let line = br#"{"command":"status","arguments":{"detail":true}}"#;
        let mut i = 0;
        while !stop.load(Ordering::Relaxed) {
            for s in &mut slow {
                let _ = s.write_all(&[line[i % line.len()]]);
            }
            i += 1;
            std::thread::sleep(Duration::from_millis(100));
        }
    });
    idle
}

#[test]
fn a_loopback_operator_gets_hold_through_idle_and_slowloris_floods_on_both_ports() {
    let mcm = Mcm::start("hostile-conn");
    mcm.client().wait_drives_online();
    let stop = Arc::new(AtomicBool::new(false));
    let json_idle = attack(mcm.json, &stop);
    let hmi_idle = attack(mcm.hmi, &stop);

    // The JSON operator.
    let mut op = mcm.client();
    let v = op.request(r#"{"command":"hold"}"#);
    assert_status(&v, "HOLD");
    // The HMI operator (typing as `nc` does).
    let mut hmi = connect_from("127.0.0.1", mcm.hmi);
    read_until(&mut hmi, |t| t.contains("> "));
    hmi.write_all(b"hold\n").unwrap();
    // The status table after `hold`, then the prompt showing HOLD.
    read_until(&mut hmi, |t| t.contains("HOLD") && t.ends_with("> "));

    // The oldest idle attackers were closed with one line saying why.
    for (mut s, json) in [(json_idle, true), (hmi_idle, false)].map(|(mut v, j)| (v.remove(0), j)) {
        let text = read_until(&mut s, |_| false);
        assert!(
            text.contains("connection closed to make room for a new one"),
            "{text:?}"
        );
        if json {
            let v: Value = serde_json::from_str(text.trim_end()).expect("one JSON line");
            assert_eq!(v["error_status"], "ERROR");
        }
    }
    stop.store(true, Ordering::Relaxed);
}

#[test]
fn the_line_that_panicked_gets_an_error_on_each_port_and_the_connection_lives_on() {
    let mcm = Mcm::start("hostile-panic");
    let mut c = connect_from("127.0.0.1", mcm.json);
    c.write_all(format!("{}\n", panicking_line(false)).as_bytes())
        .unwrap();
    let line = read_until(&mut c, |t| t.ends_with('\n'));
    assert!(line.is_ascii(), "{line:?}");
    let v: Value = serde_json::from_str(&line).unwrap();
    assert!(common::is_error(&v), "{v}");
    c.write_all(b"{\"command\":\"status\"}\n").unwrap();
    let line = read_until(&mut c, |t| t.ends_with('\n'));
    let v: Value = serde_json::from_str(&line).unwrap();
    assert_eq!(v["result_type"], "status", "{v}");

    let mut hmi = connect_from("127.0.0.1", mcm.hmi);
    read_until(&mut hmi, |t| t.contains("> "));
    hmi.write_all(format!("{}\n", panicking_line(true)).as_bytes())
        .unwrap();
    let text = read_until(&mut hmi, |t| t.ends_with("> "));
    assert!(text.contains("error"), "{text:?}");
    assert!(text.is_ascii(), "{text:?}");
    hmi.write_all(b"info\n").unwrap();
    let text = read_until(&mut hmi, |t| t.contains("P-Rob2") && t.ends_with("> "));
    assert!(text.contains("P-Rob2"), "{text:?}");
}

const DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;

/// An operator who took control, then 16 more connections from the same address (the
/// per-address cap): the connection closed to make room is the longest idle of the others,
/// never the one that controls the arm.
#[test]
fn the_connection_that_controls_the_arm_is_not_closed_to_make_room() {
    let mcm = Mcm::start("hostile-owner");
    let mut owner = mcm.client();
    let v = owner.request(r#"{"command":"take_control"}"#);
    assert_eq!(v["error_status"], "OK", "{v}");
    // The owner is now the longest idle connection of 127.0.0.1; the 17th from it is too many.
    let mut others: Vec<TcpStream> = (0..16)
        .map(|_| connect_from("127.0.0.1", mcm.json))
        .collect();
    let text = read_until(&mut others[0], |_| false);
    assert!(
        text.contains("connection closed to make room for a new one")
            && text.contains("longest idle"),
        "{text:?}"
    );
    let s = owner.request(DETAIL);
    assert_eq!(s["result_type"], "status", "the owner is still served: {s}");
    assert_eq!(s["detail"]["control"]["this_connection"], true, "{s}");
}

/// When the only connection that could make room controls the arm, the newcomer is refused,
/// saying so.
#[test]
fn a_newcomer_is_refused_when_only_the_controlling_connection_could_make_room() {
    let config = common::config_file("owner-cap", |base| {
        format!("{base}\n[gateway.connections]\nmax_per_peer = 1\n")
    });
    let mcm = Mcm::start_with("hostile-owner-cap", &["--config", config.path()]);
    let mut owner = mcm.client();
    let v = owner.request(r#"{"command":"take_control"}"#);
    assert_eq!(v["error_status"], "OK", "{v}");
    let mut late = connect_from("127.0.0.1", mcm.json);
    let text = read_until(&mut late, |_| false);
    let v: Value = serde_json::from_str(text.trim_end()).expect("one JSON line");
    let why = v["error_message"].as_str().unwrap_or_default();
    assert!(
        why.starts_with("connection refused: 127.0.0.1 already has 1 connections")
            && why.contains("controls the arm"),
        "{why}"
    );
    let s = owner.request(DETAIL);
    assert_eq!(s["detail"]["control"]["this_connection"], true, "{s}");
}
