use super::*;
use std::os::unix::net::UnixDatagram;
use std::process::Command;

#[test]
fn the_watchdog_is_pinged_at_half_its_timeout_and_not_at_all_without_one() {
    assert_eq!(
        ping_interval(Some(Duration::from_secs(2))),
        Some(Duration::from_secs(1))
    );
    assert_eq!(
        ping_interval(Some(Duration::from_micros(3))),
        Some(Duration::from_nanos(1500))
    );
    assert_eq!(ping_interval(Some(Duration::ZERO)), None);
    assert_eq!(ping_interval(None), None);
}

#[test]
fn progress_is_seen_only_when_the_counter_moved() {
    let mut p = Progress::new(7);
    assert!(!p.advanced(7), "no cycle since the start");
    assert!(p.advanced(8));
    assert!(!p.advanced(8), "a stalled counter stops the pings");
    assert!(p.advanced(1000));
    assert!(p.advanced(3), "a counter that wrapped moved too");
}

/// The child half of [`the_notifications_reach_the_socket_systemd_names`]: run only in a child
/// process whose environment names the socket (setting the variable in this process would race
/// with the other tests' threads).
#[test]
#[ignore = "run by the_notifications_reach_the_socket_systemd_names in a child process"]
fn child_sends_the_notifications() {
    if !Notifier::listening() {
        return;
    }
    let n = Notifier::from_env("notify-test");
    n.ready("serving on test");
    n.status("still serving");
    if n.watchdog_every() == Some(Duration::from_millis(500)) {
        n.watchdog();
    }
    n.stopping("stopping now");
}

#[test]
fn the_notifications_reach_the_socket_systemd_names() {
    let dir = std::env::temp_dir().join(format!("mcm-notify-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("notify.sock");
    let _ = std::fs::remove_file(&path);
    let socket = UnixDatagram::bind(&path).unwrap();
    socket
        .set_read_timeout(Some(Duration::from_secs(30)))
        .unwrap();
    let status = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "notify::tests::child_sends_the_notifications",
            "--ignored",
            "--test-threads=1",
        ])
        .env("NOTIFY_SOCKET", &path)
        .env("WATCHDOG_USEC", "1000000")
        .env_remove("WATCHDOG_PID")
        .status()
        .unwrap();
    assert!(status.success(), "the child test failed: {status}");
    let mut got = Vec::new();
    let mut buf = [0u8; 512];
    for _ in 0..4 {
        let n = socket
            .recv(&mut buf)
            .expect("a datagram within 30 s (4 expected)");
        got.push(String::from_utf8_lossy(&buf[..n]).into_owned());
    }
    assert_eq!(
        got,
        [
            "READY=1\nSTATUS=serving on test\n",
            "STATUS=still serving\n",
            "WATCHDOG=1\n",
            "STOPPING=1\nSTATUS=stopping now\n",
        ]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn without_notify_socket_nothing_is_sent_and_nothing_fails() {
    // This test process is not started by systemd (unless a developer runs the tests as a
    // unit, which the CI does not): every call is a no-op.
    if Notifier::listening() {
        return;
    }
    let n = Notifier::from_env("notify-test");
    n.ready("x");
    n.stopping("y");
    assert!(!n.failed.load(Ordering::Relaxed));
}
