//! One HMI session: a telnet (or `nc`) connection. Greets, shows a prompt with the current
//! mode, edits lines ([`super::editor`]), parses them ([`super::words`]), executes commands
//! through the same path as the JSON channel ([`crate::command::access::run_command`]: the
//! access rules, then `crate::command::execute`) and prints the results for people
//! ([`super::render`]). Safety errors are printed as they happen without breaking the line
//! being typed. Runs in the gateway's async tasks, not in the real-time cycle.
//!
//! Time per session is bounded by the idle and line timeouts of `[gateway.connections]` (a
//! command that runs or `watch` is not idle) and by
//! [`crate::transport::server::timeouts::WRITE_TIMEOUT`]; when the port needs the slot the
//! session is evicted (`crate::transport::server::admission`). Each ends the session with one
//! line saying why.
//!
//! A session whose first line is HTTP ([`crate::transport::http_line`]) ends at once, without
//! executing anything.
//!
//! Memory per session is bounded: the line ([`super::MAX_LINE_BYTES`]), the history, the
//! type-ahead while a command runs ([`MAX_PENDING`]) and the output buffer (flushed after
//! every batch of input, and written with back-pressure).

use super::editor::{Action, Editor};
use super::telnet::{Input, Telnet};
use super::words::{Line, LineError};
use super::{MAX_LINE_BYTES, cartesian, help, render};
use crate::command::Context;
use crate::command::access::{Channel, Client, run_command};
use crate::command::cartesian::active_tool;
use crate::command::result;
use crate::core_link::lifecycle::{CoreWatch, Notice};
use crate::transport::http_line;
use crate::transport::server::FAREWELL_TIMEOUT;
use crate::transport::server::admission::Slot;
use crate::transport::server::timeouts::{Expiry, WRITE_TIMEOUT, deadline};
use crate::transport::shutdown::Shutdown;
use mcm_shared::command::SetTool;
use mcm_shared::protocol::Command;
use mcm_shared::protocol::results::Answer;
use std::collections::VecDeque;
use std::io;
use std::net::SocketAddr;
use std::time::Duration;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::net::tcp::{OwnedReadHalf, OwnedWriteHalf};
use tokio::sync::broadcast::{self, error::RecvError};
use tokio::time::{Instant, MissedTickBehavior, interval};

mod jog_screen;
#[cfg(test)]
mod tests;

/// Most inputs kept as type-ahead while a command runs (reading pauses beyond it).
pub const MAX_PENDING: usize = MAX_LINE_BYTES + 4096;
/// Refresh period of `watch`.
pub const WATCH_PERIOD: Duration = Duration::from_millis(200);
/// How often the prompt is checked against the current mode while a line is edited.
pub const PROMPT_CHECK: Duration = Duration::from_millis(250);
/// Longest wait for the core's first state before the banner (just after the gateway started,
/// the bridge may not have read it yet).
const FIRST_STATE_WAIT: Duration = Duration::from_secs(1);

/// Words for Tab completion: every protocol command and the session's own commands.
pub fn completions() -> Vec<&'static str> {
    mcm_shared::protocol::command_names()
        .chain(super::words::SESSION_COMMANDS.iter().copied())
        .collect()
}

/// The escape sequences text for the terminal may hold: the HMI's own colours. Cursor and
/// line control (`ESC [ K`, hiding the cursor, ...) is written by the session directly, never
/// as text.
const OWN_COLOURS: [&str; 5] = [
    render::RED,
    render::GREEN,
    render::YELLOW,
    render::BOLD,
    render::RESET,
];

/// Append `text` for the terminal, the one way text reaches it: line ends as CR LF; the HMI's
/// own colours ([`OWN_COLOURS`]) as they are; every non-ASCII character as
/// [`render::NON_ASCII`] (the HMI writes only ASCII). Text from outside the HMI (the robot's
/// and the axes' names, the core's and other clients' words) was made visible where it was
/// inserted ([`render::visible`]), so none of its line ends or escape sequences reaches this
/// point as such; any other control character is still shown in caret notation
/// ([`render::caret`]: ESC as `^[`, BEL as `^G`, CR as `^M`, DEL as `^?`), so that no text can
/// clear the screen, set the window title or overwrite a line.
pub fn terminal_text(text: &str, out: &mut Vec<u8>) {
    let text = render::ascii(text);
    let mut rest = text.as_bytes();
    while let Some((&b, tail)) = rest.split_first() {
        let own = (b == 0x1B)
            .then(|| OWN_COLOURS.iter().find(|c| rest.starts_with(c.as_bytes())))
            .flatten();
        if let Some(colour) = own {
            out.extend_from_slice(colour.as_bytes());
            rest = &rest[colour.len()..];
            continue;
        }
        match b {
            b'\n' => out.extend_from_slice(b"\r\n"),
            0x00..=0x1F | 0x7F => out.extend_from_slice(&render::caret(b)),
            _ => out.push(b),
        }
        rest = tail;
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Flow {
    Continue,
    Quit,
}

enum Event {
    Read(io::Result<usize>),
    Error(Result<crate::core_link::bridge::SafetyEvent, RecvError>),
    Core(Notice),
    Tick,
    /// The idle or line timeout ended the session.
    Expired(Expiry),
    /// The port needed the slot; the reason.
    Evicted(String),
}

/// Serve one HMI connection until the person leaves, the connection closes or the gateway
/// shuts down.
pub async fn serve(
    socket: TcpStream,
    ctx: Context,
    mut shutdown: Shutdown,
    slot: Slot,
) -> io::Result<()> {
    socket.set_nodelay(true)?;
    let peer = socket.peer_addr()?;
    let (rd, wr) = socket.into_split();
    let mut session = Session::new(ctx, rd, wr, peer, slot);
    session.slot.identify(session.client.id);
    let ended = tokio::select! {
        r = session.run() => Some(r),
        () = shutdown.recv() => None,
    };
    match ended {
        Some(r) => r,
        None => {
            // The notice about the core still due (it stopped, or vanished), then the
            // gateway's own last line: the words every channel gets.
            let mut bye = b"\r\n\x1b[?25h".to_vec();
            for n in session.core.last_words() {
                terminal_text(&render::notice(n.code(), n.text()), &mut bye);
            }
            let write = session.wr.write_all(&bye);
            let _ = tokio::time::timeout(FAREWELL_TIMEOUT, write).await;
            Ok(())
        }
    }
}

struct Session {
    ctx: Context,
    rd: OwnedReadHalf,
    wr: OwnedWriteHalf,
    telnet: Telnet,
    editor: Editor,
    /// Inputs received and not processed yet (type-ahead while a command runs).
    pending: VecDeque<Input>,
    /// The client closed its side: finish what is pending, then end.
    closed: bool,
    errors: broadcast::Receiver<crate::core_link::bridge::SafetyEvent>,
    errors_open: bool,
    /// The notices about the core's life (`crate::core_link::lifecycle`).
    core: CoreWatch,
    /// This session's identity; dropped with the session (the core then hears it is gone).
    client: Client,
    out: Vec<u8>,
    buf: Vec<u8>,
    shown_prompt: String,
    slot: Slot,
    /// When the line being typed began (its first byte was read).
    line_start: Option<Instant>,
    /// The peer's address, for the log.
    peer: SocketAddr,
    /// A line that is not blank was entered: the next one is not the session's first.
    first_line_seen: bool,
}

impl Session {
    fn new(
        ctx: Context,
        rd: OwnedReadHalf,
        wr: OwnedWriteHalf,
        peer: SocketAddr,
        slot: Slot,
    ) -> Self {
        Self {
            errors: ctx.bridge.subscribe_errors(),
            core: CoreWatch::new(ctx.bridge.watch_state()),
            client: Client::new(&ctx.clients, &ctx.bridge, Channel::Hmi, peer),
            ctx,
            rd,
            wr,
            telnet: Telnet::new(),
            editor: Editor::new(MAX_LINE_BYTES, completions()),
            pending: VecDeque::new(),
            closed: false,
            errors_open: true,
            out: Vec::new(),
            buf: vec![0; 4096],
            shown_prompt: String::new(),
            slot,
            line_start: None,
            peer,
            first_line_seen: false,
        }
    }

    async fn run(&mut self) -> io::Result<()> {
        self.out.extend_from_slice(&Telnet::greeting());
        // A client that does not speak telnet (nc) prints the greeting: erase it.
        self.out.extend_from_slice(b"\r\x1b[K");
        // Do not greet with "the real-time core is not running" while the bridge is still
        // reading the core's first state.
        let state = self.ctx.bridge.state_within(FIRST_STATE_WAIT).await;
        let banner = render::banner(&self.ctx.cfg, state.as_deref(), self.ctx.bridge.instance());
        self.say(&banner);
        self.prompt();
        // Notices start from what the banner said.
        self.core = CoreWatch::new(self.ctx.bridge.watch_state());
        let mut tick = interval(PROMPT_CHECK);
        tick.set_missed_tick_behavior(MissedTickBehavior::Skip);
        loop {
            while let Some(input) = self.pending.pop_front() {
                if self.handle(input).await? == Flow::Quit {
                    return self.flush().await;
                }
            }
            self.flush().await?;
            if self.closed {
                return Ok(());
            }
            let in_line = !self.editor.text().is_empty() || self.telnet.in_sequence();
            self.line_start = match self.line_start {
                _ if !in_line => None,
                Some(t) => Some(t),
                None => Some(Instant::now()),
            };
            let limits = &self.ctx.cfg.gateway.connections;
            let expiry = deadline(
                limits,
                self.slot.idle_since(),
                self.line_start,
                limits.hmi_line_timeout_s,
            );
            let event = tokio::select! {
                n = self.rd.read(&mut self.buf) => Event::Read(n),
                e = self.errors.recv(), if self.errors_open => Event::Error(e),
                n = self.core.next() => Event::Core(n),
                _ = tick.tick() => Event::Tick,
                () = async { tokio::time::sleep_until(expiry.expect("guarded").0).await }, if expiry.is_some() => {
                    Event::Expired(expiry.expect("guarded").1)
                }
                why = self.slot.evicted() => Event::Evicted(why),
            };
            match event {
                Event::Read(n) => self.received(n?),
                Event::Error(e) => self.interject(e),
                Event::Core(n) => self.interject_text(&render::notice(n.code(), n.text())),
                Event::Tick => self.refresh_prompt(),
                Event::Expired(kind) => {
                    let why = kind.message(&self.ctx.cfg.gateway.connections, true);
                    return self.goodbye(&why).await;
                }
                Event::Evicted(why) => return self.goodbye(&why).await,
            }
        }
    }

    /// Append text, with the terminal's line ends; non-ASCII characters become
    /// [`render::NON_ASCII`].
    fn say(&mut self, text: &str) {
        terminal_text(text, &mut self.out);
    }

    /// End the session with one line saying `why` (after what is still to be written).
    async fn goodbye(&mut self, why: &str) -> io::Result<()> {
        self.out.extend_from_slice(b"\r\n\x1b[?25h");
        let line = format!(
            "{}error:{} {}\n",
            render::RED,
            render::RESET,
            render::visible(why)
        );
        self.say(&line);
        let out = std::mem::take(&mut self.out);
        crate::transport::server::farewell(&mut self.rd, &mut self.wr, &out).await;
        Ok(())
    }

    /// Write what is buffered; a client that takes nothing for [`WRITE_TIMEOUT`] gets a
    /// `TimedOut` error (the session ends).
    async fn flush(&mut self) -> io::Result<()> {
        if !self.out.is_empty() {
            tokio::time::timeout(WRITE_TIMEOUT, self.wr.write_all(&self.out))
                .await
                .map_err(|_| {
                    io::Error::new(
                        io::ErrorKind::TimedOut,
                        format!(
                            "the client took no output for {} s; closing the session",
                            WRITE_TIMEOUT.as_secs()
                        ),
                    )
                })??;
            self.out.clear();
            self.out.shrink_to(64 * 1024);
        }
        Ok(())
    }

    fn current_prompt(&self) -> String {
        render::prompt(self.ctx.bridge.latest_state().as_deref())
    }

    fn prompt(&mut self) {
        let p = self.current_prompt();
        self.out.extend_from_slice(p.as_bytes());
        self.editor.set_prompt(&p);
        self.shown_prompt = p;
    }

    /// Decode bytes read from the client (`0`: the client closed its side).
    fn received(&mut self, n: usize) {
        if n == 0 {
            self.closed = true;
            return;
        }
        let mut inputs = Vec::new();
        self.telnet.feed(&self.buf[..n], &mut inputs, &mut self.out);
        self.pending.extend(inputs);
    }

    /// With server echo, redraw the prompt when the mode changed (e.g. a torque timeout).
    fn refresh_prompt(&mut self) {
        if !self.telnet.server_echoes() {
            return;
        }
        let p = self.current_prompt();
        if p != self.shown_prompt {
            self.editor.set_prompt(&p);
            self.editor.redraw(&mut self.out);
            self.shown_prompt = p;
        }
    }

    fn error_text(
        &mut self,
        e: Result<crate::core_link::bridge::SafetyEvent, RecvError>,
    ) -> Option<String> {
        match e {
            Ok(ev) => Some(render::safety(&result::safety_generic(&ev))),
            Err(RecvError::Lagged(n)) => Some(format!(
                "{}*** {n} safety errors were not shown (this session was too slow){}\n",
                render::RED,
                render::RESET
            )),
            Err(RecvError::Closed) => {
                self.errors_open = false;
                None
            }
        }
    }

    /// Print a spontaneous safety error above the line being typed, then redraw it.
    fn interject(&mut self, e: Result<crate::core_link::bridge::SafetyEvent, RecvError>) {
        if let Some(text) = self.error_text(e) {
            self.interject_text(&text);
        }
    }

    /// Print `text` between the output and the line being typed.
    fn interject_text(&mut self, text: &str) {
        if self.telnet.server_echoes() {
            self.out.extend_from_slice(b"\r\x1b[K");
            self.say(text);
            let p = self.current_prompt();
            self.editor.set_prompt(&p);
            self.editor.redraw(&mut self.out);
            self.shown_prompt = p;
        } else {
            // The client's terminal holds the typed text; leave it and start a new row.
            self.out.extend_from_slice(b"\r\n");
            self.say(text);
            self.prompt();
        }
    }

    async fn handle(&mut self, input: Input) -> io::Result<Flow> {
        let echo = self.telnet.server_echoes();
        match self.editor.feed(input, echo, &mut self.out) {
            None => return Ok(Flow::Continue),
            Some(Action::Line(text)) => {
                self.line_start = None;
                if !text.trim().is_empty() {
                    self.slot.touch();
                    if !std::mem::replace(&mut self.first_line_seen, true)
                        && let Some(kind) = http_line::classify(text.as_bytes())
                    {
                        http_line::log_refused(Channel::Hmi.words(), self.peer, kind);
                        return Ok(Flow::Quit);
                    }
                }
                if self.line(&text).await? == Flow::Quit {
                    return Ok(Flow::Quit);
                }
            }
            Some(Action::Interrupt) => {
                if echo {
                    self.out.extend_from_slice(b"^C");
                }
                self.out.extend_from_slice(b"\r\n");
            }
            Some(Action::Eof) => {
                self.say("\nbye\n");
                return Ok(Flow::Quit);
            }
            Some(Action::TooLong { limit }) => {
                let msg = format!(
                    "{}error:{} line longer than {limit} bytes; it was dropped. Split a long \
                     pvt_points batch into several commands.\n",
                    render::RED,
                    render::RESET
                );
                self.say(&msg);
            }
            Some(Action::Escaped) => {
                let msg = format!(
                    "{}error:{} the line held an escape sequence; nothing was done. Without \
                     telnet's character mode, keys such as the arrows are not edited here but \
                     sent as they are: type the line again without them (or connect with \
                     `telnet`).\n",
                    render::RED,
                    render::RESET
                );
                self.say(&msg);
            }
        }
        self.prompt();
        Ok(Flow::Continue)
    }

    async fn line(&mut self, text: &str) -> io::Result<Flow> {
        let cfg = self.ctx.cfg.clone();
        let (owned, parse_cfg) = (text.to_string(), cfg.clone());
        let parsed = crate::transport::heavy::parse(text.len(), move || {
            super::words::parse_line(&owned, &parse_cfg)
        });
        let Some(parsed) = parsed.await else {
            self.say("error: the line could not be parsed; nothing was done\n");
            return Ok(Flow::Continue);
        };
        match parsed {
            Ok(Line::Empty) => {}
            Ok(Line::Help(None)) => self.say(&help::overview()),
            Ok(Line::Help(Some(t))) => self.say(&help::topic(&t, &cfg)),
            Ok(Line::Clear) => self.out.extend_from_slice(b"\x1b[H\x1b[2J"),
            Ok(Line::Jog(jogged)) => {
                self.slot.set_busy(true);
                let flow = self.jog(jogged).await;
                self.slot.set_busy(false);
                if flow? == Flow::Quit {
                    return Ok(Flow::Quit);
                }
            }
            Ok(Line::Pose) => {
                let state = self.ctx.bridge.latest_state();
                self.say(&cartesian::pose_text(state.as_deref(), &cfg));
            }
            Ok(Line::Tool(None)) => {
                let state = self.ctx.bridge.latest_state();
                self.say(&cartesian::tool_with_note(&active_tool(
                    &cfg,
                    state.as_deref(),
                )));
            }
            Ok(Line::Tool(Some(edit))) => {
                let state = self.ctx.bridge.latest_state();
                match edit.tool(&active_tool(&cfg, state.as_deref())) {
                    Ok(tool) => {
                        let cmd = Command::SetTool(SetTool { tool });
                        if self.command(cmd, false).await? == Flow::Quit {
                            return Ok(Flow::Quit);
                        }
                    }
                    Err(e) => self.say(&render::line_error(&LineError::Session {
                        command: "tool",
                        what: format!("tool: {e}; nothing was sent"),
                    })),
                }
            }
            Ok(Line::Quit) => {
                self.say("bye\n");
                return Ok(Flow::Quit);
            }
            Ok(Line::Watch { detail }) => {
                if self.watch(detail).await? == Flow::Quit {
                    return Ok(Flow::Quit);
                }
            }
            Ok(Line::Command { cmd, json }) => {
                if self.command(cmd, json).await? == Flow::Quit {
                    return Ok(Flow::Quit);
                }
            }
            Err(LineError::Json(e)) => self.say(&render::pretty(&result::invalid_line(&e))),
            Err(e) => self.say(&render::line_error(&e)),
        }
        Ok(Flow::Continue)
    }

    async fn command(&mut self, cmd: Command, json: bool) -> io::Result<Flow> {
        if matches!(cmd, Command::Calibrate(_)) && !json {
            self.say("calibrating; this can take a while (Ctrl-C stops waiting, not the calibration) ...\n");
        }
        self.flush().await?;
        // Work in the core protects the session from eviction; a `sleep` does not.
        self.slot.set_busy(!matches!(cmd, Command::Sleep(_)));
        let result = self.execute(cmd, json).await;
        self.slot.set_busy(false);
        result
    }

    /// Run `cmd`; `Quit` when the session was evicted meanwhile (only possible during a
    /// `sleep`, which does not make a session busy).
    async fn execute(&mut self, cmd: Command, json: bool) -> io::Result<Flow> {
        let (ctx, client) = (self.ctx.clone(), self.client.clone());
        let fut = run_command(&ctx, &client, &cmd);
        tokio::pin!(fut);
        let outcome = loop {
            let event = tokio::select! {
                out = &mut fut => break Some(out),
                e = self.errors.recv(), if self.errors_open => Event::Error(e),
                n = self.rd.read(&mut self.buf), if !self.closed && self.pending.len() < MAX_PENDING => Event::Read(n),
                why = self.slot.evicted() => Event::Evicted(why),
            };
            match event {
                Event::Error(e) => {
                    if let Some(text) = self.error_text(e) {
                        self.say(&text);
                    }
                }
                Event::Read(n) => {
                    self.received(n?);
                    let ctrl_c = self
                        .pending
                        .iter()
                        .position(|i| matches!(i, Input::Interrupt | Input::Byte(0x03)));
                    if let Some(k) = ctrl_c {
                        self.pending.drain(..=k);
                        break None;
                    }
                }
                Event::Evicted(why) => {
                    self.goodbye(&why).await?;
                    return Ok(Flow::Quit);
                }
                Event::Tick | Event::Core(_) | Event::Expired(_) => {}
            }
            self.flush().await?;
        };
        let name = cmd.name();
        let Some(outcome) = outcome else {
            let mut msg = format!("^C - stopped waiting for `{name}`");
            if !matches!(cmd, Command::Sleep(_)) {
                msg.push_str(
                    "; the robot may still be executing it (`status` shows the mode, `hold` stops a motion)",
                );
            }
            self.say(&msg);
            self.say("\n");
            return Ok(Flow::Continue);
        };
        let state = outcome.state.or_else(|| self.ctx.bridge.latest_state());
        let mut text = match (&outcome.result, json) {
            (Some(v), true) => render::pretty(&v.to_value()),
            (None, true) => format!("(no result: {name} answers nothing on success)\n"),
            (Some(v), false) => render::answer(name, v, &self.ctx.cfg, state.as_deref()),
            (None, false) => render::answer(name, &Answer::ok(), &self.ctx.cfg, state.as_deref()),
        };
        let done = match &outcome.result {
            Some(Answer::Generic(g)) => g.is_ok(),
            _ => true,
        };
        if let (Command::SetTool(t), false, true) = (&cmd, json, done) {
            text.push_str(&cartesian::tool_with_note(&t.tool));
        }
        if let (Command::Status(_), false, Some(st)) = (&cmd, json, &state) {
            let control =
                crate::command::access::control_words(&self.ctx, &self.client, st.owner_client_id);
            text.push_str(&render::visible(&control));
            text.push('\n');
        }
        self.say(&text);
        Ok(Flow::Continue)
    }

    /// Refresh the status table in place until a key is pressed. Not timed out as idle, but
    /// evicted like an idle session when the port needs the slot.
    async fn watch(&mut self, detail: bool) -> io::Result<Flow> {
        self.slot.touch();
        self.out.extend_from_slice(b"\x1b[?25l");
        let mut tick = interval(WATCH_PERIOD);
        tick.set_missed_tick_behavior(MissedTickBehavior::Skip);
        let mut drawn = 0usize;
        loop {
            let event = tokio::select! {
                _ = tick.tick() => Event::Tick,
                n = self.rd.read(&mut self.buf), if !self.closed => Event::Read(n),
                e = self.errors.recv(), if self.errors_open => Event::Error(e),
                why = self.slot.evicted() => Event::Evicted(why),
            };
            match event {
                Event::Tick => {
                    let state = self.ctx.bridge.latest_state();
                    let frame = render::watch_frame(
                        state.as_deref(),
                        detail,
                        &self.ctx.cfg,
                        self.ctx.bridge.instance(),
                    );
                    if drawn > 0 {
                        self.out
                            .extend_from_slice(format!("\x1b[{drawn}A").as_bytes());
                    }
                    self.out.push(b'\r');
                    for l in frame.lines() {
                        terminal_text(l, &mut self.out);
                        self.out.extend_from_slice(b"\x1b[K\r\n");
                    }
                    self.out.extend_from_slice(b"\x1b[J");
                    drawn = frame.lines().count();
                }
                Event::Read(n) => {
                    let n = n?;
                    if n == 0 {
                        self.closed = true;
                        break;
                    }
                    let mut keys = Vec::new();
                    self.telnet.feed(&self.buf[..n], &mut keys, &mut self.out);
                    if !keys.is_empty() {
                        break;
                    }
                }
                Event::Error(e) => {
                    if let Some(text) = self.error_text(e) {
                        // Below the table; the next frame starts under it.
                        self.say(&text);
                        drawn = 0;
                    }
                }
                Event::Evicted(why) => {
                    self.out.extend_from_slice(b"\x1b[?25h");
                    self.goodbye(&why).await?;
                    return Ok(Flow::Quit);
                }
                Event::Core(_) | Event::Expired(_) => {}
            }
            self.flush().await?;
        }
        self.slot.touch();
        self.out.extend_from_slice(b"\x1b[?25h");
        Ok(Flow::Continue)
    }
}
