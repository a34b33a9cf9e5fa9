//! The web port over real sockets on 127.0.0.1:0 with a bridge whose real-time core is not
//! running: HTTP as raw bytes, the WebSocket through an independent client (tungstenite).

use super::*;
use crate::core_link::bridge::BridgeThread;
use crate::test_support::offline_context;
use futures_util::{SinkExt, StreamExt};
use mcm_shared::config::RobotConfig;
use serde_json::Value;
use std::net::SocketAddr;
use std::time::Duration;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::sync::oneshot;
use tokio::task::JoinHandle;
use tokio_tungstenite::tungstenite::Message;

const WAIT: Duration = Duration::from_secs(10);

struct Server {
    addr: SocketAddr,
    stop: oneshot::Sender<()>,
    task: JoinHandle<()>,
    bridge: BridgeThread,
    instance: String,
}

async fn start(cfg: RobotConfig) -> Server {
    let (ctx, bridge, instance) = offline_context("web", cfg);
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let (stop, stopped) = oneshot::channel::<()>();
    let shutdown = async move {
        let _ = stopped.await;
    };
    let task = tokio::spawn(run(listener, ctx, instance.clone(), shutdown));
    Server {
        addr,
        stop,
        task,
        bridge,
        instance,
    }
}

impl Server {
    async fn stop(self) {
        let _ = self.stop.send(());
        tokio::time::timeout(WAIT, self.task)
            .await
            .unwrap()
            .unwrap();
        self.bridge.stop();
    }
}

/// One raw HTTP/1.1 GET (`connection: close`): the response's head and body.
async fn get(addr: SocketAddr, path: &str, extra: &str) -> (String, Vec<u8>) {
    raw(
        addr,
        &format!("GET {path} HTTP/1.1\r\nhost: {addr}\r\nconnection: close\r\n{extra}\r\n"),
    )
    .await
}

/// Send `request` as it is; the response's head (lower case) and body, to the connection's end.
async fn raw(addr: SocketAddr, request: &str) -> (String, Vec<u8>) {
    let mut s = TcpStream::connect(addr).await.unwrap();
    s.write_all(request.as_bytes()).await.unwrap();
    let mut bytes = Vec::new();
    tokio::time::timeout(WAIT, s.read_to_end(&mut bytes))
        .await
        .unwrap()
        .unwrap();
    let split = bytes.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
    let head = String::from_utf8_lossy(&bytes[..split]).to_lowercase();
    (head, bytes[split + 4..].to_vec())
}

#[tokio::test]
async fn the_page_the_model_and_the_records_are_served() {
    let srv = start(RobotConfig::prob2_default()).await;
    let (head, body) = get(srv.addr, "/", "").await;
    assert!(head.starts_with("http/1.1 200"), "{head}");
    assert!(head.contains("content-type: text/html"), "{head}");
    // The pendant's own page: its Hold button is in the markup itself.
    let page = String::from_utf8_lossy(&body);
    assert!(
        page.contains("<html") && page.contains("id=\"hold\""),
        "{page}"
    );
    let (head, _) = get(srv.addr, "/", "accept-encoding: gzip\r\n").await;
    assert!(head.contains("content-encoding: gzip"), "{head}");

    let (head, body) = get(srv.addr, "/api/model", "").await;
    assert!(head.contains("application/json"), "{head}");
    let model: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(model["instance"], srv.instance);
    assert_eq!(model["axes"].as_array().unwrap().len(), 6);

    // The page's own socket is one of the connections.
    let _page = ws(srv.addr).await;
    let (_, body) = get(srv.addr, "/api/connections", "").await;
    let conns: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(conns["clients"][0]["channel"], "browser pendant", "{conns}");

    let (head, body) = get(srv.addr, "/api/flight-records", "").await;
    assert!(head.starts_with("http/1.1 200"), "{head}");
    let list: Value = serde_json::from_slice(&body).unwrap();
    assert!(list["records"].is_array(), "{list}");

    for path in [
        "/api/flight-records/..%2F..%2Fetc%2Fpasswd",
        "/api/flight-records/mcm-other-1-following_error.csv",
        "/no/such/file.js",
    ] {
        let (head, body) = get(srv.addr, path, "").await;
        assert!(head.starts_with("http/1.1 404"), "{path}: {head}");
        assert!(!body.is_empty(), "{path}: a 404 says why");
    }
    srv.stop().await;
}

#[tokio::test]
async fn every_embedded_file_is_served_with_its_type() {
    let srv = start(RobotConfig::prob2_default()).await;
    let paths = assets::paths();
    assert!(paths.iter().any(|p| p == "index.html"), "{paths:?}");
    for p in paths {
        let (head, _) = get(srv.addr, &format!("/{p}"), "").await;
        assert!(head.starts_with("http/1.1 200"), "{p}: {head}");
        if p.ends_with(".js") {
            assert!(head.contains("javascript"), "{p}: {head}");
        }
    }
    srv.stop().await;
}

type Ws = tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<TcpStream>>;

async fn ws(addr: SocketAddr) -> Ws {
    let (ws, _) = tokio_tungstenite::connect_async(format!("ws://{addr}/ws"))
        .await
        .unwrap();
    ws
}

/// The next text message as JSON.
async fn next(ws: &mut Ws) -> Value {
    loop {
        let msg = tokio::time::timeout(WAIT, ws.next())
            .await
            .expect("a message within the wait")
            .expect("the socket is open")
            .unwrap();
        match msg {
            Message::Text(t) => return serde_json::from_str(&t).unwrap(),
            Message::Ping(_) | Message::Pong(_) => continue,
            other => panic!("unexpected {other:?}"),
        }
    }
}

#[tokio::test]
async fn the_socket_carries_the_json_protocol_one_result_per_command() {
    let srv = start(RobotConfig::prob2_default()).await;
    let mut ws = ws(srv.addr).await;
    // Refused by the framing and the parser, as on the TCP port.
    ws.send(Message::text("{\"command\":\"fly\"}"))
        .await
        .unwrap();
    let r = next(&mut ws).await;
    assert_eq!(r["error_status"], "ERROR", "{r}");
    assert!(r["error_message"].as_str().unwrap().contains("fly"), "{r}");
    assert_eq!(r["error_code"], "unknown_command", "{r}");
    ws.send(Message::binary(vec![0xff, 0x00, 0x7b]))
        .await
        .unwrap();
    let r = next(&mut ws).await;
    assert_eq!(r["error_status"], "ERROR", "{r}");
    // Executed by the gateway: `sleep` answers OK.
    ws.send(Message::text(
        "{\"command\":\"sleep\",\"arguments\":{\"duration\":0.01}}",
    ))
    .await
    .unwrap();
    let r = next(&mut ws).await;
    assert_eq!(r["error_status"], "OK", "{r}");
    // The core is not running: said so, "failed" since it was surely not sent.
    ws.send(Message::text("{\"command\":\"hold\"}"))
        .await
        .unwrap();
    let r = next(&mut ws).await;
    let m = r["error_message"].as_str().unwrap();
    assert!(
        m.starts_with("hold failed") && m.contains("not running"),
        "{r}"
    );
    // Shutdown: the last line, then the socket closes.
    let _ = srv.stop.send(());
    let last = next(&mut ws).await;
    assert!(
        last["error_message"]
            .as_str()
            .unwrap()
            .contains("the MCM is shutting down"),
        "{last}"
    );
    tokio::time::timeout(WAIT, srv.task).await.unwrap().unwrap();
    srv.bridge.stop();
}

#[tokio::test]
async fn an_over_long_command_is_answered_then_the_socket_closes() {
    let srv = start(RobotConfig::prob2_default()).await;
    let mut ws = ws(srv.addr).await;
    let long = format!(
        "{{\"command\":\"status\",\"pad\":\"{}\"}}",
        "x".repeat(mcm_shared::protocol::MAX_COMMAND_BYTES)
    );
    ws.send(Message::text(long)).await.unwrap();
    let r = next(&mut ws).await;
    assert!(
        r["error_message"].as_str().unwrap().contains("longer than"),
        "{r}"
    );
    assert_eq!(r["error_code"], "line_too_long", "{r}");
    let end = tokio::time::timeout(WAIT, async {
        loop {
            match ws.next().await {
                None | Some(Err(_)) | Some(Ok(Message::Close(_))) => return,
                Some(Ok(_)) => {}
            }
        }
    })
    .await;
    assert!(end.is_ok(), "the socket stays open");
    srv.stop().await;
}

#[tokio::test]
async fn an_idle_page_makes_room_and_is_told_why() {
    let mut cfg = RobotConfig::prob2_default();
    cfg.gateway.web.max_per_peer = 1;
    let srv = start(cfg).await;
    let mut first = ws(srv.addr).await;
    let (head, _) = get(srv.addr, "/", "").await;
    assert!(head.starts_with("http/1.1 200"), "{head}");
    let r = next(&mut first).await;
    assert_eq!(r["error_status"], "ERROR", "{r}");
    assert!(
        r["error_message"]
            .as_str()
            .unwrap()
            .contains("to make room"),
        "{r}"
    );
    assert_eq!(r["error_code"], "evicted", "{r}");
    srv.stop().await;
}

#[test]
fn a_refusal_is_a_whole_http_response() {
    let r = http_refusal("too many connections from 10.0.0.1 (16 allowed)");
    let (head, body) = r.split_once("\r\n\r\n").unwrap();
    assert!(head.starts_with("HTTP/1.1 503 "), "{head}");
    let len: usize = head
        .lines()
        .find_map(|l| l.strip_prefix("content-length: "))
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(len, body.len());
    assert!(body.contains("16 allowed"));
}

#[tokio::test]
async fn a_page_from_another_origin_may_not_open_the_socket() {
    use tokio_tungstenite::tungstenite::client::IntoClientRequest;
    let srv = start(RobotConfig::prob2_default()).await;
    let url = format!("ws://{}/ws", srv.addr);
    let mut foreign = url.clone().into_client_request().unwrap();
    foreign
        .headers_mut()
        .insert("origin", "http://evil.example".parse().unwrap());
    let refused = tokio_tungstenite::connect_async(foreign).await;
    match refused {
        Err(tokio_tungstenite::tungstenite::Error::Http(r)) => assert_eq!(r.status(), 403),
        other => panic!("a foreign origin got {other:?}"),
    }
    let mut own = url.into_client_request().unwrap();
    let origin = format!("http://{}", srv.addr);
    own.headers_mut().insert("origin", origin.parse().unwrap());
    assert!(tokio_tungstenite::connect_async(own).await.is_ok());
    srv.stop().await;
}

/// The vendored libraries are the published files: each matches the checksum `VERSIONS` records
/// for its package (so a hand edit, or a copy from another version, fails here).
#[test]
fn the_vendored_files_match_their_recorded_checksums() {
    use crate::command::access::sha256;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("web/vendor");
    let versions = std::fs::read_to_string(dir.join("VERSIONS")).unwrap();
    let mut checked = Vec::new();
    for line in versions
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let words: Vec<&str> = line.split_whitespace().collect();
        let [file, package, _path, hash] = words[..] else {
            panic!("VERSIONS: {line:?} is not `file package@version path sha256`");
        };
        let bytes = std::fs::read(dir.join(file)).unwrap();
        let want = sha256::from_hex(hash).unwrap_or_else(|| panic!("{file}: bad hash {hash}"));
        assert_eq!(sha256::digest(&bytes), want, "{file} is not {package}'s");
        checked.push(file.to_string());
    }
    let mut present: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n != "VERSIONS" && n != "LICENSES")
        .collect();
    present.sort();
    checked.sort();
    assert_eq!(
        present, checked,
        "every vendored file is listed in VERSIONS"
    );
}

const CODES_JS: &str = "web/codes.js";

/// `gateway/web/codes.js`, the pendant's list of error codes, as the contract's table
/// ([`mcm_shared::error_code`]) gives it.
fn codes_js() -> String {
    use mcm_shared::error_code::ErrorCode;
    let text = |s: &str| serde_json::to_string(s).expect("a string");
    let mut js = String::from(
        "// The error codes (`error_code` of every ERROR result): what each means and what to do.\n\
         // GENERATED from shared/src/error_code.rs by gateway/src/transport/web/tests.rs; do not\n\
         // edit by hand: `MCM_UPDATE_WEB=1 cargo test -p mcm-gateway --lib web::tests` writes it anew.\n\n\
         export const ERROR_CODES = {\n",
    );
    for c in ErrorCode::ALL {
        js.push_str(&format!(
            "  {}: {{ meaning: {}, remedy: {}, spontaneous: {} }},\n",
            c.as_str(),
            text(c.meaning()),
            text(c.remedy()),
            c.is_spontaneous()
        ));
    }
    js.push_str("};\n");
    js
}

/// The pendant shows what to do about an error from the contract's table, never from a list
/// of its own.
#[test]
fn the_pendants_error_codes_are_the_contracts() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(CODES_JS);
    let want = codes_js();
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    if have != want && std::env::var_os("MCM_UPDATE_WEB").is_some() {
        std::fs::write(&path, &want).expect("write gateway/web/codes.js");
        return;
    }
    assert!(
        have == want,
        "gateway/{CODES_JS} differs from the error codes of shared/src/error_code.rs; \
         `MCM_UPDATE_WEB=1 cargo test -p mcm-gateway --lib web::tests` writes it anew"
    );
}

/// The head (lower case) of the response to `request`, read up to its blank line: the
/// connection may stay open after it (a WebSocket).
async fn head_of(addr: SocketAddr, request: &str) -> String {
    let mut s = TcpStream::connect(addr).await.unwrap();
    s.write_all(request.as_bytes()).await.unwrap();
    let mut bytes = Vec::new();
    let mut buf = [0u8; 4096];
    tokio::time::timeout(WAIT, async {
        while !bytes.windows(4).any(|w| w == b"\r\n\r\n") {
            let n = s.read(&mut buf).await.unwrap();
            assert!(n > 0, "closed before a response: {bytes:?}");
            bytes.extend_from_slice(&buf[..n]);
        }
    })
    .await
    .expect("a response within the wait");
    String::from_utf8_lossy(&bytes).to_lowercase()
}

/// A WebSocket upgrade of `/ws` addressed to `host` from a page of `origin`.
fn upgrade_request(host: &str, origin: &str) -> String {
    format!(
        "GET /ws HTTP/1.1\r\nhost: {host}\r\norigin: {origin}\r\nconnection: upgrade\r\n\
         upgrade: websocket\r\nsec-websocket-version: 13\r\n\
         sec-websocket-key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n"
    )
}

#[tokio::test]
async fn a_request_for_another_host_is_refused_on_every_route() {
    let mut cfg = RobotConfig::prob2_default();
    cfg.gateway.web.allowed_hosts = vec!["robot-7.cell.example".into()];
    let srv = start(cfg).await;
    let port = srv.addr.port();
    // What a browser sends after DNS rebinding: the attacker's name in both headers.
    let evil = format!("evil.example:{port}");
    let origin = format!("http://{evil}");
    for path in [
        "/",
        "/app.js",
        "/api/model",
        "/api/connections",
        "/api/flight-records",
    ] {
        let (head, body) = raw(
            srv.addr,
            &format!(
                "GET {path} HTTP/1.1\r\nhost: {evil}\r\norigin: {origin}\r\nconnection: close\r\n\r\n"
            ),
        )
        .await;
        assert!(head.starts_with("http/1.1 421"), "{path}: {head}");
        let body = String::from_utf8_lossy(&body);
        assert!(
            body.contains(&evil) && body.contains("[gateway.web] allowed_hosts"),
            "{path}: {body}"
        );
    }
    let head = head_of(srv.addr, &upgrade_request(&evil, &origin)).await;
    assert!(head.starts_with("http/1.1 421"), "/ws: {head}");
    assert!(!head.contains("upgrade: websocket"), "/ws: {head}");
    // HTTP/1.0 without Host.
    let (head, body) = raw(srv.addr, "GET /api/model HTTP/1.0\r\n\r\n").await;
    assert!(head.contains(" 421 "), "no Host: {head}");
    assert!(
        String::from_utf8_lossy(&body).contains("no Host header"),
        "{body:?}"
    );

    for host in [
        "localhost".to_string(),
        format!("localhost:{port}"),
        format!("127.0.0.1:{port}"),
        format!("robot-7.cell.example:{port}"),
    ] {
        let (head, _) = raw(
            srv.addr,
            &format!("GET /api/model HTTP/1.1\r\nhost: {host}\r\nconnection: close\r\n\r\n"),
        )
        .await;
        assert!(head.starts_with("http/1.1 200"), "{host}: {head}");
        let head = head_of(srv.addr, &upgrade_request(&host, &format!("http://{host}"))).await;
        assert!(head.starts_with("http/1.1 101"), "{host}: {head}");
        // The origin check stays: an own name with another page's origin is refused.
        let head = head_of(srv.addr, &upgrade_request(&host, &origin)).await;
        assert!(head.starts_with("http/1.1 403"), "{host}: {head}");
    }
    srv.stop().await;
}

/// One WebSocket frame from the server (unmasked): its opcode and payload.
async fn read_frame(s: &mut (impl tokio::io::AsyncRead + Unpin)) -> (u8, Vec<u8>) {
    let mut head = [0u8; 2];
    s.read_exact(&mut head).await.unwrap();
    let len = match head[1] & 0x7f {
        126 => u64::from(s.read_u16().await.unwrap()),
        127 => s.read_u64().await.unwrap(),
        n => u64::from(n),
    };
    let mut payload = vec![0u8; len as usize];
    s.read_exact(&mut payload).await.unwrap();
    (head[0] & 0x0f, payload)
}

#[tokio::test]
async fn a_message_trickled_in_is_cut_like_a_slow_line() {
    let mut cfg = RobotConfig::prob2_default();
    cfg.gateway.connections.line_timeout_s = 0.5;
    let srv = start(cfg).await;
    let mut s = TcpStream::connect(srv.addr).await.unwrap();
    let host = srv.addr.to_string();
    s.write_all(upgrade_request(&host, &format!("http://{host}")).as_bytes())
        .await
        .unwrap();
    let mut head = Vec::new();
    while !head.ends_with(b"\r\n\r\n") {
        head.push(s.read_u8().await.unwrap());
    }
    assert!(head.starts_with(b"HTTP/1.1 101"), "{head:?}");
    // A masked text frame of `{"command":"status"}`, one byte every 100 ms: 2.6 s in all.
    let payload = br#"{"command":"status"}"#;
    let mask = [1u8, 2, 3, 4];
    let mut frame = vec![0x81, 0x80 | payload.len() as u8];
    frame.extend_from_slice(&mask);
    frame.extend(payload.iter().enumerate().map(|(i, b)| b ^ mask[i % 4]));
    let (mut rd, mut wr) = s.into_split();
    let trickle = tokio::spawn(async move {
        for b in frame {
            if wr.write_all(&[b]).await.is_err() {
                return;
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    });
    let started = tokio::time::Instant::now();
    // The line-timeout ERROR, then a close with 1008 (policy): within a bound, not after the
    // whole frame arrived.
    let (text, close) = tokio::time::timeout(WAIT, async {
        let mut text = None;
        loop {
            match read_frame(&mut rd).await {
                (0x1, t) => text = Some(String::from_utf8(t).unwrap()),
                (0x8, c) => return (text, c),
                other => panic!("unexpected frame {other:?}"),
            }
        }
    })
    .await
    .expect("the socket is closed within the wait");
    let took = started.elapsed();
    let text = text.expect("a text message before the close");
    let r: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(r["error_code"], "line_timeout", "{r}");
    assert!(
        r["error_message"]
            .as_str()
            .unwrap()
            .contains("gateway.connections.line_timeout_s"),
        "{r}"
    );
    assert_eq!(u16::from_be_bytes([close[0], close[1]]), 1008);
    assert!(
        !trickle.is_finished() && took < Duration::from_millis(2500),
        "cut {took:?} after the first byte, before the frame was complete"
    );
    trickle.abort();
    srv.stop().await;
}

#[tokio::test]
async fn a_flood_of_holds_gets_one_answer_each_in_order() {
    const SENT: usize = 5_000;
    let srv = start(RobotConfig::prob2_default()).await;
    let mut ws = ws(srv.addr).await;
    for _ in 0..SENT {
        ws.feed(Message::text("{\"command\":\"hold\"}"))
            .await
            .unwrap();
    }
    ws.send(Message::text(
        "{\"command\":\"sleep\",\"arguments\":{\"duration\":0.01}}",
    ))
    .await
    .unwrap();
    for i in 0..SENT {
        let r = next(&mut ws).await;
        let m = r["error_message"].as_str().unwrap_or_default();
        assert!(
            m.starts_with("hold failed") && m.contains("not running"),
            "{i}: {r}"
        );
    }
    let r = next(&mut ws).await;
    assert_eq!(r["error_status"], "OK", "the sleep's own answer: {r}");
    srv.stop().await;
}
