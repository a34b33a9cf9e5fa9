//! End to end: the real `telnet` program, inside `tmux`, against the running robot's text HMI;
//! the test types with `tmux send-keys` and reads the screen with `tmux capture-pane`, polling
//! (bounded) until the expected text is on it.
//!
//! Needs `tmux` and `telnet` in `PATH` (`.ci/run` installs them on CI). Without them the test
//! says on stderr that it is skipped and why, and passes, except when `CI` is set, where it
//! fails (`common::skip`).

use crate::common;

use common::{Mcm, WAIT, find_program, unique_instance};
use std::path::PathBuf;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// Pause between two looks at the screen while polling.
const POLL: Duration = Duration::from_millis(50);

/// A private tmux server (its own socket) running one session; killed on drop.
struct Tmux {
    socket: String,
    /// The server's socket file (removed on drop; tmux leaves it behind).
    socket_path: Option<PathBuf>,
}

impl Tmux {
    fn cmd(&self, args: &[&str]) -> Output {
        let out = Command::new("tmux")
            .args(["-L", &self.socket, "-f", "/dev/null"])
            .args(args)
            .output()
            .expect("run tmux");
        assert!(
            out.status.success(),
            "tmux {args:?} failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        out
    }

    /// Start `telnet 127.0.0.1 <port>` in a 120x40 window; the pane stays after telnet exits
    /// so that its last screen can be read.
    fn start(socket: String, port: u16) -> Tmux {
        let mut t = Tmux {
            socket,
            socket_path: None,
        };
        let port = port.to_string();
        t.cmd(&[
            "new-session",
            "-d",
            "-s",
            "hmi",
            "-x",
            "120",
            "-y",
            "40",
            "telnet",
            "127.0.0.1",
            &port,
            ";",
            "set-option",
            "-t",
            "hmi",
            "remain-on-exit",
            "on",
        ]);
        let path = t.cmd(&["display-message", "-p", "-t", "hmi", "#{socket_path}"]);
        t.socket_path = Some(String::from_utf8_lossy(&path.stdout).trim().into());
        t
    }

    /// Type `text` literally, then Enter.
    fn type_line(&self, text: &str) {
        self.cmd(&["send-keys", "-t", "hmi", "-l", text]);
        self.cmd(&["send-keys", "-t", "hmi", "Enter"]);
    }

    /// The whole screen with its scrollback, wrapped lines joined.
    fn screen(&self) -> String {
        let out = self.cmd(&["capture-pane", "-p", "-J", "-S", "-", "-t", "hmi"]);
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    fn pane_dead(&self) -> bool {
        let out = self.cmd(&["display-message", "-p", "-t", "hmi", "#{pane_dead}"]);
        String::from_utf8_lossy(&out.stdout).trim() == "1"
    }

    /// Poll the screen until `done` holds; panic with the screen after [`WAIT`].
    fn wait_screen(&self, what: &str, done: impl Fn(&str) -> bool) -> String {
        let deadline = Instant::now() + WAIT;
        loop {
            let s = self.screen();
            if done(&s) {
                return s;
            }
            assert!(
                Instant::now() < deadline,
                "{what}: not on the screen within {WAIT:?}; the screen:\n{s}"
            );
            std::thread::sleep(POLL);
        }
    }

    /// Type `line` at the prompt `mcm <mode>>`, wait until its output is complete (the prompt
    /// `mcm <then>>` is on the last line again) and return that output.
    fn run(&self, mode: &str, line: &str, then: &str) -> String {
        let typed = format!("mcm {mode}> {line}\n");
        let starts = self.screen().matches(&typed).count();
        self.type_line(line);
        let prompt = format!("mcm {then}>");
        let s = self.wait_screen(&format!("the output of `{line}`"), |s| {
            s.matches(&typed).count() > starts && s.trim_end().ends_with(&prompt)
        });
        let from = s.rfind(&typed).unwrap() + typed.len();
        let out = s[from..].trim_end();
        out.strip_suffix(&prompt).unwrap().to_string()
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = Command::new("tmux")
            .args(["-L", &self.socket, "kill-server"])
            .output();
        if let Some(p) = &self.socket_path {
            let _ = std::fs::remove_file(p);
        }
    }
}

/// Check a status table on the screen: the column titles, and six axis rows whose values end
/// under the titles' right edges.
fn assert_status(out: &str, mode: &str, detail: bool) {
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].starts_with(&format!("mode {mode} - ")),
        "mode {mode}:\n{out}"
    );
    let header = lines[1];
    let mut titles = vec!["position", "velocity", "current"];
    if detail {
        titles.extend(["commanded", "measured", "foll. err", "i2t"]);
    }
    for (i, name) in ["base", "shoulder", "elbow", "forearm", "wrist", "flange"]
        .iter()
        .enumerate()
    {
        let row = lines[3 + i];
        assert!(
            row.starts_with(&format!("{:>4}  {name}", i + 1)),
            "row of axis {}: {row:?}",
            i + 1
        );
        for t in &titles {
            let end = header
                .find(t)
                .unwrap_or_else(|| panic!("{t} in {header:?}"))
                + t.len();
            let cell = row[..end].rsplit(' ').next().unwrap();
            assert!(
                cell.parse::<f64>().is_ok() && matches!(row.as_bytes().get(end), None | Some(b' ')),
                "{t} of axis {} is not aligned:\n{header}\n{row}",
                i + 1
            );
        }
        if detail {
            assert!(row.ends_with(" NO") || row.ends_with(" yes"), "{row:?}");
        }
    }
}

#[test]
fn real_telnet_in_tmux_shows_help_status_and_hold() {
    let missing: Vec<&str> = ["tmux", "telnet"]
        .into_iter()
        .filter(|p| find_program(p).is_none())
        .collect();
    if !missing.is_empty() {
        common::skip(
            "real_telnet_in_tmux_shows_help_status_and_hold",
            &format!(
                "{} not found in PATH (install with `apt-get install telnet tmux`; .ci/run \
                 does so on CI)",
                missing.join(" and ")
            ),
        );
        return;
    }

    let mcm = Mcm::start("hmi-tmux");
    let tmux = Tmux::start(unique_instance("tmux"), mcm.hmi.port());

    let banner = tmux.wait_screen("the banner and the prompt", |s| {
        s.trim_end().ends_with("mcm OFF>")
    });
    for w in [
        "Connected to 127.0.0.1.",
        &format!(
            "MCM {} - Motion Control Module, text HMI",
            mcm_shared::VERSION
        ),
        "robot: P-Rob2",
        "mode:  OFF - drives powered off",
        "Type `help` for the commands",
    ] {
        assert!(banner.contains(w), "{w:?} on the screen:\n{banner}");
    }

    let help = tmux.run("OFF", "help", "OFF");
    for name in mcm_shared::protocol::command_names() {
        assert!(
            help.lines()
                .any(|l| l.split_whitespace().next() == Some(name)),
            "`help` lists {name}:\n{help}"
        );
    }
    assert!(help.contains("Session commands:"), "{help}");

    let status = tmux.run("OFF", "status", "OFF");
    assert_status(&status, "OFF", false);

    mcm.client().wait_drives_online();
    let hold = tmux.run("OFF", "hold", "HOLD");
    assert_status(&hold, "HOLD", false);

    let detail = tmux.run("HOLD", "status detail", "HOLD");
    assert_status(&detail, "HOLD", true);
    for w in ["calibrated", "hardware:  drives online 6/6", "cycle:"] {
        assert!(detail.contains(w), "{w:?} in:\n{detail}");
    }

    tmux.type_line("quit");
    let end = tmux.wait_screen("the goodbye and telnet's end", |s| {
        s.contains("mcm HOLD> quit\nbye\n") && s.contains("Connection closed by foreign host.")
    });
    let deadline = Instant::now() + WAIT;
    while !tmux.pane_dead() {
        assert!(Instant::now() < deadline, "telnet still runs:\n{end}");
        std::thread::sleep(POLL);
    }

    // Nothing on the screen that a terminal should not show: no escape sequences printed as
    // text, no bytes that are not UTF-8, no echoed negotiation.
    let screen = tmux.screen();
    for bad in ["\u{fffd}", "^[", "[0m", "[K", "\x1b"] {
        assert!(!screen.contains(bad), "{bad:?} on the screen:\n{screen}");
    }
    // Each typed line was shown once, as typed (the server echoes, telnet does not).
    for typed in [
        "mcm OFF> help",
        "mcm OFF> status",
        "mcm OFF> hold",
        "mcm HOLD> status detail",
        "mcm HOLD> quit",
    ] {
        let n = screen.lines().filter(|l| l.trim_end() == typed).count();
        assert_eq!(n, 1, "{typed:?} on the screen {n} times:\n{screen}");
    }
}
