//! One JSON connection: read bytes, frame them into commands, execute them one after the
//! other, write one result line each; deliver spontaneous safety errors and TORQUE_CONTROL
//! status results in between.
//!
//! A connection only ever waits on its own socket and its own commands, so a slow or hostile
//! client cannot delay another one. Its memory is bounded by the framing limit.

use crate::cmd::Command;
use crate::exec::{Context, execute};
use crate::framing::{Decoder, Frame};
use crate::result;
use crate::shutdown::Shutdown;
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

/// Serve one JSON connection until the peer closes it or the server shuts down.
pub async fn serve(socket: TcpStream, ctx: Context, mut shutdown: Shutdown) -> std::io::Result<()> {
    socket.set_nodelay(true)?;
    let (mut rd, wr) = socket.into_split();
    let mut wr = BufWriter::new(wr);
    let client_id = ctx.bridge.new_client_id();
    let mut decoder = Decoder::new();
    let mut errors = ctx.bridge.subscribe_errors();
    let mut torque: Option<TorqueSession> = None;
    let mut buf = vec![0u8; 4096];

    loop {
        while let Some(frame) = decoder.next_frame() {
            let cmd = match frame {
                Frame::Oversize => {
                    send(&mut wr, &result::error(format!(
                        "command longer than {} bytes without completing; closing the connection",
                        crate::framing::MAX_COMMAND_BYTES
                    )))
                    .await?;
                    return Ok(());
                }
                Frame::Invalid { reason } => {
                    send(&mut wr, &result::error(reason)).await?;
                    continue;
                }
                Frame::Object(text) => match Command::from_json(&text, &ctx.cfg) {
                    Ok(cmd) => cmd,
                    Err(e) => {
                        send(&mut wr, &result::error(e.to_string())).await?;
                        continue;
                    }
                },
            };
            let fut = execute(&ctx, client_id, &cmd);
            tokio::pin!(fut);
            let outcome = loop {
                tokio::select! {
                    out = &mut fut => break out,
                    e = errors.recv() => forward_error(&mut wr, e).await?,
                    () = shutdown.recv() => return Ok(()),
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
            () = shutdown.recv() => return Ok(()),
        }
    }
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

/// Write one result line.
pub async fn send(wr: &mut BufWriter<OwnedWriteHalf>, v: &Value) -> std::io::Result<()> {
    let mut line = serde_json::to_vec(v).expect("a JSON value serialises");
    line.push(b'\n');
    wr.write_all(&line).await?;
    wr.flush().await
}
