//! Whole sessions over real TCP sockets against [`run`], with a bridge whose real-time core
//! is not running: commands that need the core answer "not running", everything the gateway
//! decides itself (parsing, validation, help, `sleep`) works.

use super::render::strip_ansi;
use super::telnet::{DO, IAC, OPT_ECHO, OPT_SGA, SB, SE, WILL};
use super::*;
use crate::core_link::bridge::BridgeThread;
use crate::test_support::offline_context;
use mcm_shared::config::RobotConfig;
use std::net::SocketAddr;
use std::time::Duration;
use tokio::io::AsyncReadExt;
use tokio::net::TcpStream;
use tokio::sync::oneshot;
use tokio::task::JoinHandle;

const PROMPT: &str = "mcm NO-CORE> ";
const WAIT: Duration = Duration::from_secs(10);

struct Gateway {
    addr: SocketAddr,
    instance: String,
    stop: Option<oneshot::Sender<()>>,
    task: JoinHandle<()>,
    bridge: BridgeThread,
}

async fn start() -> Gateway {
    let (ctx, thread, instance) = offline_context("hmi", RobotConfig::prob2_default());
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let (stop, stopped) = oneshot::channel::<()>();
    let task = tokio::spawn(run(listener, ctx, async move {
        let _ = stopped.await;
    }));
    Gateway {
        addr,
        instance,
        stop: Some(stop),
        task,
        bridge: thread,
    }
}

impl Gateway {
    async fn shutdown(mut self) {
        let _ = self.stop.take().unwrap().send(());
        tokio::time::timeout(WAIT, self.task)
            .await
            .expect("run() returns after shutdown")
            .unwrap();
        self.bridge.stop();
    }
}

/// A test client: keeps everything received; `reply` returns the text since the last call.
struct Client {
    stream: TcpStream,
    raw: Vec<u8>,
    mark: usize,
}

/// Remove telnet commands from what the server sent.
fn without_iac(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] != IAC {
            out.push(bytes[i]);
            i += 1;
            continue;
        }
        match bytes.get(i + 1) {
            Some(&IAC) => {
                out.push(IAC);
                i += 2;
            }
            Some(&(251..=254)) => i += 3,
            Some(&SB) => {
                while i + 1 < bytes.len() && !(bytes[i] == IAC && bytes[i + 1] == SE) {
                    i += 1;
                }
                i += 2;
            }
            _ => i += 2,
        }
    }
    out
}

impl Client {
    async fn connect(gw: &Gateway) -> Client {
        Client {
            stream: TcpStream::connect(gw.addr).await.unwrap(),
            raw: Vec::new(),
            mark: 0,
        }
    }

    fn since_mark(&self) -> String {
        strip_ansi(&String::from_utf8_lossy(&without_iac(
            &self.raw[self.mark..],
        )))
    }

    /// Read until `end` shows up after the mark; return the text (IAC and ANSI removed).
    async fn until(&mut self, end: &str) -> String {
        let mut buf = [0u8; 4096];
        let read = async {
            while !self.since_mark().contains(end) {
                let n = self.stream.read(&mut buf).await.unwrap();
                assert!(n > 0, "closed before {end:?}; got {:?}", self.since_mark());
                self.raw.extend_from_slice(&buf[..n]);
            }
        };
        if tokio::time::timeout(WAIT, read).await.is_err() {
            panic!("no {end:?} within {WAIT:?}; got {:?}", self.since_mark());
        }
        let text = self.since_mark();
        self.mark = self.raw.len();
        text
    }

    async fn send(&mut self, bytes: &[u8]) {
        use tokio::io::AsyncWriteExt;
        self.stream.write_all(bytes).await.unwrap();
    }

    /// Send a line (telnet's CR NUL) and return everything up to the next prompt.
    async fn command(&mut self, line: &str) -> String {
        self.send(format!("{line}\r\0").as_bytes()).await;
        self.until(PROMPT).await
    }

    /// Read until the server closes the connection; return the rest of the text.
    async fn until_closed(&mut self) -> String {
        let mut buf = [0u8; 4096];
        let read = async {
            loop {
                match self.stream.read(&mut buf).await {
                    Ok(0) | Err(_) => break,
                    Ok(n) => self.raw.extend_from_slice(&buf[..n]),
                }
            }
        };
        tokio::time::timeout(WAIT, read)
            .await
            .expect("the server closes the connection");
        self.since_mark()
    }
}

/// What Linux telnet sends on connect to a telnet port, and its answer to our greeting.
const TELNET_HELLO: &[u8] = &[
    0xFF, 0xFD, 0x03, 0xFF, 0xFB, 0x18, 0xFF, 0xFB, 0x1F, 0xFF, 0xFB, 0x20, 0xFF, 0xFB, 0x21, 0xFF,
    0xFB, 0x22, 0xFF, 0xFB, 0x27, 0xFF, 0xFD, 0x05, 0xFF, 0xFD, 0x01, 0xFF, 0xFA, 0x1F, 0x00, 0x50,
    0x00, 0x18, 0xFF, 0xF0,
];

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn telnet_session() {
    let gw = start().await;
    let mut c = Client::connect(&gw).await;

    // Banner: version, robot, mode (no core), a hint to type help; then the prompt.
    let banner = c.until(PROMPT).await;
    assert_eq!(
        &c.raw[..6],
        &[IAC, WILL, OPT_ECHO, IAC, WILL, OPT_SGA],
        "greeting"
    );
    assert!(
        banner.contains(&format!("MCM {}", mcm_shared::VERSION)),
        "{banner}"
    );
    assert!(banner.contains("robot: P-Rob2"), "{banner}");
    assert!(
        banner.contains(&format!("instance `{}`) is not running", gw.instance)),
        "{banner}"
    );
    assert!(banner.contains("Type `help`"), "{banner}");
    assert!(banner.ends_with(PROMPT), "{banner:?}");

    // The client's negotiation is answered and never shows up; the server then echoes.
    c.send(TELNET_HELLO).await;
    let help = c.command("help").await;
    assert!(help.starts_with("help\r\nRobot commands"), "{help:?}");
    assert!(
        help.contains("  move_axis       move one axis to a target position\r\n"),
        "{help}"
    );
    assert!(help.contains("quit, exit"), "{help}");
    assert!(!help.contains('\u{fffd}'), "no garbage: {help:?}");
    let raw = &c.raw;
    assert!(
        raw.windows(3).any(|w| w == [IAC, 254, 0x18]),
        "DONT TTYPE sent"
    );
    assert!(
        !raw.windows(3).any(|w| w == [IAC, DO, OPT_ECHO]),
        "we never ask the client to echo"
    );

    let text = c.command("help move_axis").await;
    for w in [
        "usage:       move_axis <axis_index>",
        "target angle [deg]",
        "accepted in: PVT",
    ] {
        assert!(text.contains(w), "{w}: {text}");
    }

    // Refused by the gateway before the core: value, range and usage.
    let text = c.command("move_axis 9 0").await;
    assert!(
        text.contains(
            "error [out_of_range]: move_axis: argument \"axis_index\" = 9 is not allowed; expected an axis number from 1 to 6"
        ),
        "{text}"
    );
    assert!(
        text.contains("usage: move_axis <axis_index> <target_position> [velocity_factor]"),
        "{text}"
    );

    let text = c.command("stauts").await;
    assert!(
        text.contains("unknown command \"stauts\" (did you mean \"status\"?)"),
        "{text}"
    );

    let text = c.command("status").await;
    assert!(
        text.contains("error [core_unavailable]: status failed: the real-time core"),
        "{text}"
    );
    assert!(
        text.contains("hint: the real-time core (mcm-rt) is not running"),
        "{text}"
    );

    // Backspace (0x7F and 0x08) and Ctrl-C.
    c.send(b"stat\x03").await;
    let text = c.until(PROMPT).await;
    assert_eq!(text, format!("stat^C\r\n{PROMPT}"));
    let text = c.command("helq\x7Fp sleeo\x08p").await;
    assert!(
        text.contains("sleep - wait before the next command"),
        "{text}"
    );

    // A command the gateway executes itself, and Ctrl-C while waiting for one.
    let text = c.command("sleep 0.01").await;
    assert!(text.contains("OK"), "{text}");
    c.send(b"sleep 100\r\0").await;
    c.until("sleep 100\r\n").await;
    c.send(&[IAC, 244]).await; // IAC IP
    let text = c.until(PROMPT).await;
    assert!(text.contains("stopped waiting for `sleep`"), "{text}");

    // A JSON line is answered in JSON.
    let text = c
        .command(r#"{"command":"move_axis","arguments":{"axis_index":9,"target_position":0}}"#)
        .await;
    assert!(text.contains("\"error_status\": \"ERROR\""), "{text}");
    assert!(text.contains(r#"\"axis_index\" = 9"#), "{text}");

    c.send(b"quit\r\n").await;
    let text = c.until_closed().await;
    assert!(text.contains("bye"), "{text}");
    gw.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn nc_session_ctrl_d_and_shutdown() {
    let gw = start().await;

    // nc: no negotiation, LF line ends, no echo.
    let mut nc = Client::connect(&gw).await;
    nc.until(PROMPT).await;
    nc.send(b"help\n").await;
    let text = nc.until(PROMPT).await;
    assert!(text.starts_with("Robot commands"), "no echo: {text:?}");
    nc.send(b"move_all 1 2 3\n").await;
    let text = nc.until(PROMPT).await;
    assert!(
        text.contains("\"target_positions\" needs 6 numbers, one per axis, got 3"),
        "{text}"
    );
    // A line beyond the limit is dropped with a message; the session goes on.
    let mut long = vec![b'x'; MAX_LINE_BYTES + 100];
    long.push(b'\n');
    nc.send(&long).await;
    let text = nc.until(PROMPT).await;
    assert!(text.contains("line longer than 65536 bytes"), "{text}");
    assert!(nc.command("help quit").await.contains("end the session"));
    // An arrow key cannot be edited without echo: the line is refused, not run shortened
    // (`move_axis 1 3`).
    nc.send(b"move_axis 1 3\x1b[D0\n").await;
    let text = nc.until(PROMPT).await;
    assert!(
        text.contains("error: the line held an escape sequence; nothing was done"),
        "{text}"
    );
    assert!(!text.contains("move_axis"), "nothing ran: {text}");

    // Ctrl-D on an empty line ends a telnet session.
    let mut t = Client::connect(&gw).await;
    t.until(PROMPT).await;
    t.send(&[IAC, DO, OPT_ECHO, 0x04]).await;
    assert!(t.until_closed().await.contains("bye"));

    // Shutdown: the open session gets a goodbye and is closed; run() returns. The goodbye is
    // the words the JSON and ZeroMQ clients get.
    let closing = async {
        let text = nc.until_closed().await;
        assert!(text.contains("shutting down"), "{text}");
        let words = crate::core_link::lifecycle::Notice::GatewayStopping.text();
        assert!(
            strip_ansi(&text).contains(&format!("ERROR [gateway_stopping]: {words}\r\n")),
            "{text}"
        );
    };
    tokio::join!(gw.shutdown(), closing);
}

#[test]
fn completions_are_the_command_names() {
    let mut expected: Vec<&str> = mcm_shared::protocol::command_names().collect();
    expected.extend(words::SESSION_COMMANDS);
    let mut got: Vec<&str> = session::completions();
    expected.sort_unstable();
    got.sort_unstable();
    assert_eq!(got, expected);
}

/// `jog` without a running core: the mode change is refused with the core's reason, the
/// session stays at its prompt; a bad axis never reaches the core.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn jog_without_a_core_says_why_and_keeps_the_session() {
    let gw = start().await;
    let mut c = Client::connect(&gw).await;
    c.until(PROMPT).await;
    c.send(TELNET_HELLO).await;
    let text = c.command("jog 2").await;
    assert!(
        text.contains("error [core_unavailable]: velocity_control failed: the real-time core"),
        "{text}"
    );
    assert!(!text.contains("jogging axis"), "{text}");
    let text = c.command("jog 9").await;
    assert!(text.contains("axis = 9 is not allowed"), "{text}");
    let text = c.command("help").await;
    assert!(text.contains("jog AXIS [SPEED]"), "{text}");
    assert!(text.contains("velocity_control"), "{text}");
    let text = c.command("help set_velocities").await;
    assert!(text.contains("accepted in: VELOCITY_CONTROL"), "{text}");
    c.send(b"quit\r\n").await;
    c.until_closed().await;
    gw.shutdown().await;
}
