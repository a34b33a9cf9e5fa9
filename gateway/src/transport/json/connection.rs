//! One JSON connection: read bytes, frame them into commands, execute them one after the other,
//! write one result line each; deliver spontaneous safety errors and the status results of a
//! TORQUE_CONTROL or VELOCITY_CONTROL session in between, and notices about the MCM's own life
//! (`crate::core_link::lifecycle`): the core shutting down or gone, and a last ERROR line when
//! the gateway shuts down.
//!
//! A connection only ever waits on its own socket and its own commands, so a slow or hostile
//! client cannot delay another one. Its memory is bounded by the framing limit, its time by the
//! idle and line timeouts of `[gateway.connections]` and by [`WRITE_TIMEOUT`]
//! ([`crate::transport::server::timeouts`]); when its port
//! needs the slot, it is evicted (see [`crate::transport::server::admission`]). Each of these
//! ends the connection with one ERROR line saying why.

use crate::command::Context;
use crate::command::access::{Channel, Client, run_command};
use crate::command::result;
use crate::core_link::lifecycle::CoreWatch;
use crate::transport::http_line::HttpLine;
use crate::transport::json::framing::{Decoder, Frame, MAX_COMMAND_BYTES};
use crate::transport::server::FAREWELL_TIMEOUT;
use crate::transport::server::admission::Slot;
use crate::transport::server::timeouts::{WRITE_TIMEOUT, deadline};
use crate::transport::shutdown::Shutdown;
use mcm_shared::config::RobotConfig;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::mode::Mode;
use mcm_shared::protocol::Command;
use mcm_shared::protocol::results::ErrorOutcome;
use mcm_shared::sample::StateSample;
use serde_json::Value;
use std::net::SocketAddr;
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, BufWriter};
use tokio::net::TcpStream;
use tokio::sync::broadcast::error::RecvError;
use tokio::time::Instant;

/// A TORQUE_CONTROL or VELOCITY_CONTROL session of this connection: spontaneous status results
/// on the robot's clock, driven by the states the core publishes (not by a timer of the
/// gateway, which would drift against the cycle and send one state twice and skip the next),
/// and the state of the cycle that left the mode, sent as soon as it is published.
pub(crate) struct ModeSession {
    /// The wire mode the session runs in.
    mode: u32,
    /// Interval of spontaneous status results [ns]; `None`: only the final one.
    interval_ns: Option<u64>,
    /// Robot time (`t_ns`) from which the next status is due.
    next_t_ns: u64,
}

/// What a published state means for a [`ModeSession`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SessionStep {
    /// Nothing to send.
    Quiet,
    /// A status result is due.
    Status,
    /// The mode was left (timeout, safety trip, `hold` from anyone): send this state's status
    /// at once; the session ends.
    Left,
}

impl ModeSession {
    /// A session that the state `started` (the cycle that executed `torque_control` or
    /// `velocity_control`) began, with a status every `dt_s` seconds (none for 0). Its mode is
    /// the mode of `started` (TORQUE_CONTROL when unknown).
    pub(crate) fn new(dt_s: f64, started: Option<&StateSample>) -> Self {
        let interval_ns = (dt_s > 0.0).then(|| (dt_s * 1e9).round() as u64);
        let t0 = started.map_or(0, |s| s.t_ns);
        Self {
            mode: started.map_or(Mode::TorqueControl.to_wire(), |s| s.mode),
            interval_ns,
            next_t_ns: t0.saturating_add(interval_ns.unwrap_or(0)),
        }
    }

    /// What the newly published state `s` asks of the session.
    pub(crate) fn on_state(&mut self, s: &StateSample) -> SessionStep {
        if s.mode != self.mode {
            SessionStep::Left
        } else if self.due(s.t_ns, s.timing.period_ns) {
            SessionStep::Status
        } else {
            SessionStep::Quiet
        }
    }

    /// Whether the state of a cycle that started at `t_ns` (cycles `period_ns` apart) is due
    /// as a status; moves the next due time on. Cycle start times jitter by the wake-up
    /// latency, so a state within half a period of the due time counts; a session that fell
    /// behind starts again from this state instead of sending a burst.
    fn due(&mut self, t_ns: u64, period_ns: u64) -> bool {
        let Some(dt) = self.interval_ns else {
            return false;
        };
        let tolerance = period_ns / 2;
        if t_ns.saturating_add(tolerance) < self.next_t_ns {
            return false;
        }
        self.next_t_ns = self.next_t_ns.saturating_add(dt);
        if self.next_t_ns.saturating_add(tolerance) <= t_ns {
            self.next_t_ns = t_ns.saturating_add(dt);
        }
        true
    }
}

/// What one frame asks of the connection.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// A valid command: execute it (its result is the reply).
    Run(Command),
    /// A refused line: send this ERROR result and go on.
    Reply(Value),
    /// Too long: send this ERROR result and close the connection.
    Close(Value),
    /// The connection's first line is HTTP (a browser sent it): close the connection without
    /// executing anything and without a word.
    Foreign(HttpLine),
}

/// [`step`], a long frame parsed in the heavy lane ([`crate::transport::heavy`]).
pub async fn decide(frame: Frame, cfg: &std::sync::Arc<RobotConfig>) -> Step {
    let len = match &frame {
        Frame::Object(text) => text.len(),
        _ => 0,
    };
    let cfg = cfg.clone();
    crate::transport::heavy::parse(len, move || step(frame, &cfg))
        .await
        .unwrap_or_else(|| {
            Step::Reply(result::answer_error(
                ErrorOutcome::Invalid,
                ErrorCode::InternalError,
                "the command could not be parsed; nothing was done",
            ))
        })
}

/// Decide what to do with one frame; never panics, whatever the bytes were.
pub fn step(frame: Frame, cfg: &RobotConfig) -> Step {
    match frame {
        Frame::Oversize => Step::Close(result::answer_error(
            ErrorOutcome::Invalid,
            ErrorCode::LineTooLong,
            format!(
                "command longer than the limit of {MAX_COMMAND_BYTES} bytes; closing the connection"
            ),
        )),
        Frame::Invalid { reason } => Step::Reply(result::answer_error(
            ErrorOutcome::Invalid,
            ErrorCode::InvalidJson,
            reason,
        )),
        Frame::Http(kind) => Step::Foreign(kind),
        Frame::Object(text) => match Command::from_json(&text, cfg) {
            Ok(cmd) => Step::Run(cmd),
            Err(e) => Step::Reply(result::invalid_line(&e)),
        },
    }
}

/// Serve one JSON connection until the peer closes it or the server shuts down.
pub async fn serve(
    socket: TcpStream,
    ctx: Context,
    shutdown: Shutdown,
    slot: Slot,
) -> std::io::Result<()> {
    socket.set_nodelay(true)?;
    let peer = socket.peer_addr()?;
    let (rd, wr) = socket.into_split();
    serve_stream(rd, wr, Channel::Json, peer, ctx, shutdown, slot).await
}

/// [`serve`] over any byte stream: a TCP connection's halves, or the pipe that carries a browser
/// page's WebSocket messages (`crate::transport::web::socket`), so that every channel of the
/// JSON protocol runs this one connection code. `peer` and `channel` identify the client.
pub async fn serve_stream<R, W>(
    mut rd: R,
    wr: W,
    channel: Channel,
    peer: SocketAddr,
    ctx: Context,
    mut shutdown: Shutdown,
    mut slot: Slot,
) -> std::io::Result<()>
where
    R: AsyncRead + Unpin,
    W: AsyncWrite + Unpin,
{
    let mut wr = BufWriter::new(wr);
    // Dropped when this function returns, however: the core then hears the client is gone.
    let client = Client::new(&ctx.clients, &ctx.bridge, channel, peer);
    slot.identify(client.id);
    let mut decoder = Decoder::new();
    let mut errors = ctx.bridge.subscribe_errors();
    let mut session: Option<ModeSession> = None;
    // Every new state, for the spontaneous statuses of a torque or velocity session.
    let mut states = ctx.bridge.watch_state();
    let mut core = CoreWatch::new(ctx.bridge.watch_state());
    let mut buf = vec![0u8; 4096];
    let mut line_start: Option<Instant> = None;

    loop {
        let mut framed = false;
        while let Some(frame) = decoder.next_frame() {
            framed = true;
            slot.touch();
            let cmd = match decide(frame, &ctx.cfg).await {
                Step::Run(cmd) => cmd,
                Step::Reply(v) => {
                    send(&mut wr, &v).await?;
                    continue;
                }
                Step::Foreign(kind) => {
                    crate::transport::http_line::log_refused(channel.words(), peer, kind);
                    return Ok(());
                }
                Step::Close(v) => {
                    // The client may still be sending its long line: drain it so that the
                    // reason is not lost to a reset.
                    let line = format!("{}\n", mcm_shared::protocol::json::to_ascii(&v));
                    crate::transport::server::farewell(&mut rd, &mut wr, line.as_bytes()).await;
                    return Ok(());
                }
            };
            // Work in the core protects the connection from eviction; a `sleep` does not.
            slot.set_busy(!matches!(cmd, Command::Sleep(_)));
            let fut = run_command(&ctx, &client, &cmd);
            tokio::pin!(fut);
            let outcome = loop {
                tokio::select! {
                    out = &mut fut => break out,
                    e = errors.recv() => forward_error(&mut wr, e).await?,
                    // Only during a `sleep`, which does not protect from eviction.
                    why = slot.evicted() => return say_goodbye(&mut rd, &mut wr, ErrorCode::Evicted, &why).await,
                    () = shutdown.recv() => return goodbye(&mut wr, &mut core).await,
                }
            };
            if let Some(dt) = outcome.mode_session {
                states.borrow_and_update();
                session = Some(ModeSession::new(dt, outcome.state.as_deref()));
            } else if matches!(
                cmd,
                Command::Hold(_) | Command::Release(_) | Command::Pvt(_)
            ) {
                // Its own result is the status of the mode change.
                session = None;
            }
            // Idle (evictable) from now, before the client has the result and may act on it.
            slot.set_busy(session.is_some());
            if let Some(r) = &outcome.result {
                send(&mut wr, &r.to_value()).await?;
            }
        }
        // A line is unfinished: it began with the read that brought its first byte.
        line_start = match line_start {
            _ if decoder.buffered() == 0 => None,
            Some(t) if !framed => Some(t),
            _ => Some(Instant::now()),
        };
        let limits = &ctx.cfg.gateway.connections;
        let expiry = if session.is_some() {
            None
        } else {
            deadline(limits, slot.idle_since(), line_start, limits.line_timeout_s)
        };

        tokio::select! {
            n = rd.read(&mut buf) => {
                match n? {
                    0 => return Ok(()),
                    n => decoder.extend(&buf[..n]),
                }
            }
            e = errors.recv() => forward_error(&mut wr, e).await?,
            n = core.next() => send(&mut wr, &n.result()).await?,
            changed = states.changed(), if session.is_some() => {
                let running = session.as_mut().expect("guarded");
                let state = match changed {
                    Ok(()) => states.borrow_and_update().clone(),
                    Err(_) => None,
                };
                let step = state.as_deref().map(|s| (running.on_state(s), s));
                match step {
                    Some((SessionStep::Quiet, _)) => {}
                    Some((SessionStep::Status, s)) => send(&mut wr, &result::status(s, false)).await?,
                    Some((SessionStep::Left, s)) => {
                        // Left the mode (timeout fallback to HOLD, `hold`, a safety stop):
                        // told at once, with the state of the cycle that left it.
                        send(&mut wr, &result::status(s, false)).await?;
                        session = None;
                        slot.set_busy(false);
                    }
                    None => {
                        session = None;
                        slot.set_busy(false);
                    }
                }
            }
            () = async { tokio::time::sleep_until(expiry.as_ref().expect("guarded").0).await }, if expiry.is_some() => {
                let (code, why) = expiry.map_or((ErrorCode::IdleTimeout, String::new()), |e| (e.1.code(), e.1.message(limits, false)));
                return say_goodbye(&mut rd, &mut wr, code, &why).await;
            }
            why = slot.evicted() => return say_goodbye(&mut rd, &mut wr, ErrorCode::Evicted, &why).await,
            () = shutdown.recv() => return goodbye(&mut wr, &mut core).await,
        }
    }
}

/// The last lines before the gateway closes the connection on shutdown: the notice about the
/// core still due (it stopped, or vanished), then the gateway's own (bounded: a client that
/// does not read does not hold the shutdown up).
async fn goodbye<W: AsyncWrite + Unpin>(
    wr: &mut BufWriter<W>,
    core: &mut CoreWatch,
) -> std::io::Result<()> {
    let lines = core.last_words();
    let say = async {
        for n in lines {
            send(wr, &n.result()).await?;
        }
        Ok::<_, std::io::Error>(())
    };
    let _ = tokio::time::timeout(FAREWELL_TIMEOUT, say).await;
    Ok(())
}

async fn forward_error<W: AsyncWrite + Unpin>(
    wr: &mut BufWriter<W>,
    e: Result<crate::core_link::bridge::SafetyEvent, RecvError>,
) -> std::io::Result<()> {
    match e {
        Ok(ev) => send(wr, &result::safety_event(&ev)).await,
        Err(RecvError::Lagged(n)) => send(wr, &events_lost(n)).await,
        Err(RecvError::Closed) => Ok(()),
    }
}

/// The ERROR telling a connection that `n` safety errors were not delivered to it.
pub(crate) fn events_lost(n: u64) -> Value {
    result::error(
        ErrorCode::EventsLost,
        format!("{n} safety errors were not delivered to this slow connection"),
    )
}

/// Write one result line (pure ASCII: non-ASCII characters as `\uXXXX`); a client that does
/// not take it within [`WRITE_TIMEOUT`] gets a `TimedOut` error (the connection ends).
pub async fn send<W: AsyncWrite + Unpin>(wr: &mut BufWriter<W>, v: &Value) -> std::io::Result<()> {
    let mut line = mcm_shared::protocol::json::to_ascii(v);
    line.push('\n');
    let write = async {
        wr.write_all(line.as_bytes()).await?;
        wr.flush().await
    };
    tokio::time::timeout(WRITE_TIMEOUT, write)
        .await
        .unwrap_or_else(|_| {
            Err(std::io::Error::new(
                std::io::ErrorKind::TimedOut,
                format!(
                    "the client took no result line for {} s; closing the connection",
                    WRITE_TIMEOUT.as_secs()
                ),
            ))
        })
}

/// End the connection with one ERROR line saying `why`, of `code` (see
/// [`crate::transport::server::farewell`]).
async fn say_goodbye<R: AsyncRead + Unpin, W: AsyncWrite + Unpin>(
    rd: &mut R,
    wr: &mut BufWriter<W>,
    code: ErrorCode,
    why: &str,
) -> std::io::Result<()> {
    let line = super::json_line(code, why);
    crate::transport::server::farewell(rd, wr, line.as_bytes()).await;
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests;
