//! End to end, HTTP sent to the JSON and telnet HMI ports (`docs/security.md`): a web page can
//! make a browser send a POST whose body holds command lines to either port. Over raw sockets
//! against the real processes: a connection whose first line is an HTTP request line or header
//! is closed, and none of the body's `calibrate` and `release` ran (the arm stays OFF and
//! uncalibrated, read over a fresh JSON connection). The same from a page in real Chromium:
//! `web::cross_protocol_requests_from_a_page_in_chromium` (`tests/web/cross_protocol.test.mjs`).

use crate::common;

use common::{Mcm, WAIT};
use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::Instant;

/// The request a browser's `fetch(url, {method: "POST", mode: "no-cors", body})` sends, with
/// `first` as its first line (a request line, or a header when a proxy cut the request line).
fn browser_request(first: &str, to: SocketAddr, body: &str) -> String {
    format!(
        "{first}\r\nHost: {to}\r\nConnection: keep-alive\r\nContent-Length: {}\r\n\
         Content-Type: text/plain;charset=UTF-8\r\nOrigin: http://attacker.example\r\n\
         Sec-Fetch-Mode: no-cors\r\n\r\n{body}",
        body.len()
    )
}

/// Send `request` to `to` and read until the server closes the connection (EOF or reset) or
/// [`WAIT`] passes; whether it closed, and what it sent.
fn send_and_read_to_close(to: SocketAddr, request: &str) -> (bool, String) {
    let mut s = TcpStream::connect(to).expect("connect");
    s.write_all(request.as_bytes()).expect("send the request");
    let deadline = Instant::now() + WAIT;
    let mut got = Vec::new();
    let mut buf = [0u8; 4096];
    let closed = loop {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            break false;
        }
        s.set_read_timeout(Some(left)).unwrap();
        match s.read(&mut buf) {
            Ok(0) => break true,
            Ok(n) => got.extend_from_slice(&buf[..n]),
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                break false;
            }
            // Closed with the request's unread bytes still queued: a reset.
            Err(e) if e.kind() == ErrorKind::ConnectionReset => break true,
            Err(e) => panic!("read: {e}"),
        }
    };
    (closed, String::from_utf8_lossy(&got).into_owned())
}

#[test]
fn http_to_the_json_and_hmi_ports_is_closed_and_runs_nothing() {
    let mcm = Mcm::start("cross-protocol");
    let mut c = mcm.client();
    let before = c.wait_drives_online();
    assert_eq!(before["operating_mode"], "OFF", "{before}");
    assert_eq!(before["detail"]["all_calibrated"], false, "{before}");

    let json_body = "\n{\"command\":\"calibrate\"}\n{\"command\":\"release\"}\n";
    let hmi_body = "\ncalibrate\r\nrelease\r\n";
    let cases = [
        ("JSON", mcm.json, "POST / HTTP/1.1", json_body),
        ("JSON", mcm.json, "Host: robot", json_body),
        ("HMI", mcm.hmi, "POST / HTTP/1.1", hmi_body),
        ("HMI", mcm.hmi, "User-Agent: Mozilla/5.0", hmi_body),
    ];
    for (port, to, first, body) in cases {
        let (closed, said) = send_and_read_to_close(to, &browser_request(first, to, body));
        // Whatever the connection did, it did before it closed; read over a fresh connection.
        let after = c.request(r#"{"command":"status","arguments":{"detail":true}}"#);
        assert_eq!(
            (&after["operating_mode"], &after["detail"]["all_calibrated"]),
            (&"OFF".into(), &false.into()),
            "the {port} port ran the body of a request starting `{first}`; it answered \
             {said:?}; status now: {after}"
        );
        assert!(
            closed,
            "the {port} port kept a connection starting `{first}` open for {WAIT:?}; it \
             answered {said:?}"
        );
        assert!(
            !said.contains("error_status"),
            "the {port} port answered the HTTP lines: {said:?}"
        );
    }
}
