//! # The text HMI: a telnet session for people (default TCP port 18011)
//!
//! Next to the JSON channel the gateway serves a human-machine interface: connect with
//! `telnet <host> 18011` (or `nc <host> 18011`), get a banner with the version, the robot and
//! its mode, and type commands as words, e.g. `move_axis 1 30 0.5`, `move_all 0 10 20 0 0 0
//! vf=0.5`, `calibrate which=WRIST`, `status detail`. `help` lists the commands, `help CMD`
//! explains one; results come back as aligned tables with units; `watch` refreshes the status
//! table in place; `quit`, `exit` or Ctrl-D leave. A line starting with `{` is a JSON command
//! and is answered in (pretty) JSON.
//!
//! It runs in the gateway's async tasks, never inside the real-time cycle. It shares the JSON
//! channel's command path: the words become a JSON `arguments` object parsed by
//! [`mcm_shared::protocol::Command::parse`] and executed under the same access rules by
//! [`crate::command::access::run_command`], so both channels accept and refuse exactly the same
//! things.
//!
//! Layout: [`telnet`] (option negotiation, NVT line ends) -> [`keys`] (the one key decoder:
//! escape sequences read whole) -> [`editor`] (line editing, echo, history) -> [`words`] (the
//! line parser, after each command's definition in [`mcm_shared::protocol`]) ->
//! `crate::command` -> [`render`] (results for people); [`cartesian`] reads and shows poses
//! and tools in millimetres and degrees (`pose`, `tool`, `moveto`, `movel`); [`help`] holds the
//! help texts and [`session`] ties one connection together; [`jog`] holds the keys, timing and
//! velocities of the `jog` screen (an axis, or the TCP; read through [`keys`] too), whose loop
//! is the session's (`session/jog_screen.rs`).
//! [`run`] accepts connections.
//!
//! Telnet choice: the server offers `WILL ECHO` and `WILL SUPPRESS-GO-AHEAD`, i.e. character
//! mode with the server echoing (see [`telnet`]); clients that do not negotiate (`nc`) keep
//! their terminal's own line editing and get no echo.

mod cartesian;
mod editor;
mod help;
mod jog;
mod keys;
mod render;
pub(crate) mod session;
mod telnet;
pub(crate) mod words;

use crate::command::Context;
use crate::transport::server::Port;
use crate::transport::server::admission::is_loopback;
use std::future::Future;
use tokio::net::TcpListener;

/// Longest line a person may type (64 KiB); a longer one is dropped with a message.
pub const MAX_LINE_BYTES: usize = 64 * 1024;

/// Accept HMI sessions on `listener` until `shutdown` resolves, then tell every session to
/// stop (each gets a goodbye line) and wait for them.
pub async fn run(listener: TcpListener, ctx: Context, shutdown: impl Future) {
    crate::transport::server::run(listener, ctx, shutdown, HMI_PORT, session::serve).await;
}

/// The HMI port: refusals as one line of text.
pub const HMI_PORT: Port = Port {
    what: "HMI session",
    refusal: hmi_line,
    is_local: is_loopback,
};

/// One line of text for a refused or closed session, written as every text of the HMI is
/// ([`session::terminal_text`]).
pub fn hmi_line(message: &str) -> String {
    let mut out = Vec::new();
    let line = format!("MCM HMI: {}\n", render::visible(message));
    session::terminal_text(&line, &mut out);
    // `terminal_text` writes only ASCII: nothing is lost.
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod proptests;
#[cfg(test)]
mod tests;
