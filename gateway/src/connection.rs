//! One JSON connection: read bytes, frame them into commands, execute them one after the
//! other, write one result line each; deliver spontaneous safety errors and TORQUE_CONTROL
//! status results in between, and notices about the MCM's own life (`crate::lifecycle`): the
//! core shutting down or gone, and a last ERROR line when the gateway shuts down.
//!
//! A connection only ever waits on its own socket and its own commands, so a slow or hostile
//! client cannot delay another one. Its memory is bounded by the framing limit.

use crate::access::{Channel, Client, run_command};
use crate::cmd::Command;
use crate::exec::Context;
use crate::framing::{Decoder, Frame, MAX_COMMAND_BYTES};
use crate::lifecycle::CoreWatch;
use crate::result;
use crate::shutdown::Shutdown;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::Mode;
use serde_json::Value;
use std::time::Duration;
use tokio::io::{AsyncReadExt, AsyncWriteExt, BufWriter};
use tokio::net::TcpStream;
use tokio::net::tcp::OwnedWriteHalf;
use tokio::sync::broadcast::error::RecvError;
use tokio::time::Instant;

/// How often a connection in a torque session checks the mode when it sends no status.
const MODE_CHECK: Duration = Duration::from_millis(20);

struct TorqueSession {
    /// Interval of spontaneous status results; `None`: only the final one.
    interval: Option<Duration>,
    next: Instant,
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
}

/// Decide what to do with one frame; never panics, whatever the bytes were.
pub fn step(frame: Frame, cfg: &RobotConfig) -> Step {
    match frame {
        Frame::Oversize => Step::Close(result::error(format!(
            "command longer than the limit of {MAX_COMMAND_BYTES} bytes; closing the connection"
        ))),
        Frame::Invalid { reason } => Step::Reply(result::error(reason)),
        Frame::Object(text) => match Command::from_json(&text, cfg) {
            Ok(cmd) => Step::Run(cmd),
            Err(e) => Step::Reply(result::error(e.to_string())),
        },
    }
}

/// Serve one JSON connection until the peer closes it or the server shuts down.
pub async fn serve(socket: TcpStream, ctx: Context, mut shutdown: Shutdown) -> std::io::Result<()> {
    socket.set_nodelay(true)?;
    let peer = socket.peer_addr()?;
    let (mut rd, wr) = socket.into_split();
    let mut wr = BufWriter::new(wr);
    // Dropped when this function returns, however: the core then hears the client is gone.
    let client = Client::new(&ctx.clients, &ctx.bridge, Channel::Json, peer);
    let mut decoder = Decoder::new();
    let mut errors = ctx.bridge.subscribe_errors();
    let mut torque: Option<TorqueSession> = None;
    let mut core = CoreWatch::new(ctx.bridge.watch_state());
    let mut buf = vec![0u8; 4096];

    loop {
        while let Some(frame) = decoder.next_frame() {
            let cmd = match step(frame, &ctx.cfg) {
                Step::Run(cmd) => cmd,
                Step::Reply(v) => {
                    send(&mut wr, &v).await?;
                    continue;
                }
                Step::Close(v) => {
                    send(&mut wr, &v).await?;
                    return Ok(());
                }
            };
            let fut = run_command(&ctx, &client, &cmd);
            tokio::pin!(fut);
            let outcome = loop {
                tokio::select! {
                    out = &mut fut => break out,
                    e = errors.recv() => forward_error(&mut wr, e).await?,
                    () = shutdown.recv() => return goodbye(&mut wr).await,
                }
            };
            if let Some(r) = &outcome.result {
                send(&mut wr, r).await?;
            }
            if let Some(dt) = outcome.torque_session {
                let interval = (dt > 0.0).then(|| Duration::from_secs_f64(dt));
                torque = Some(TorqueSession {
                    interval,
                    next: Instant::now() + interval.unwrap_or(MODE_CHECK),
                });
            } else if matches!(cmd, Command::Hold | Command::Release | Command::Pvt(_)) {
                torque = None;
            }
        }

        let tick = torque.as_ref().map(|t| t.next);
        tokio::select! {
            n = rd.read(&mut buf) => {
                match n? {
                    0 => return Ok(()),
                    n => decoder.extend(&buf[..n]),
                }
            }
            e = errors.recv() => forward_error(&mut wr, e).await?,
            n = core.next() => send(&mut wr, &n).await?,
            () = async { tokio::time::sleep_until(tick.expect("guarded")).await }, if tick.is_some() => {
                let session = torque.as_mut().expect("guarded");
                let state = ctx.bridge.latest_state();
                let in_torque = state.as_ref().is_some_and(|s| s.mode == Mode::TorqueControl.to_wire());
                match (&state, in_torque) {
                    (Some(s), true) => {
                        if session.interval.is_some() {
                            send(&mut wr, &result::status(s, false)).await?;
                        }
                        session.next += session.interval.unwrap_or(MODE_CHECK);
                        let now = Instant::now();
                        if session.next < now {
                            session.next = now;
                        }
                    }
                    (Some(s), false) => {
                        // Left TORQUE_CONTROL (timeout fallback to HOLD, or a safety stop).
                        send(&mut wr, &result::status(s, false)).await?;
                        torque = None;
                    }
                    (None, _) => torque = None,
                }
            }
            () = shutdown.recv() => return goodbye(&mut wr).await,
        }
    }
}

/// The last line before the gateway closes the connection on shutdown (bounded: a client that
/// does not read does not hold the shutdown up).
async fn goodbye(wr: &mut BufWriter<OwnedWriteHalf>) -> std::io::Result<()> {
    let bye = crate::lifecycle::gateway_stopping();
    let _ = tokio::time::timeout(Duration::from_secs(1), send(wr, &bye)).await;
    Ok(())
}

async fn forward_error(
    wr: &mut BufWriter<OwnedWriteHalf>,
    e: Result<crate::bridge::SafetyEvent, RecvError>,
) -> std::io::Result<()> {
    match e {
        Ok(ev) => send(wr, &result::safety_event(&ev)).await,
        Err(RecvError::Lagged(n)) => {
            send(
                wr,
                &result::error(format!(
                    "{n} safety errors were not delivered to this slow connection"
                )),
            )
            .await
        }
        Err(RecvError::Closed) => Ok(()),
    }
}

/// Write one result line (pure ASCII: non-ASCII characters as `\uXXXX`).
pub async fn send(wr: &mut BufWriter<OwnedWriteHalf>, v: &Value) -> std::io::Result<()> {
    let mut line = crate::json::to_ascii(v);
    line.push('\n');
    wr.write_all(line.as_bytes()).await?;
    wr.flush().await
}

#[cfg(test)]
mod tests;
