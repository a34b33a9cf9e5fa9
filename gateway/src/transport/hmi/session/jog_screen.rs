//! The jog screen of a session (`jog AXIS [SPEED]` and `jog x|y|z|rx|ry|rz [SPEED] [base|tool]`,
//! see [`crate::transport::hmi::jog`]): enter VELOCITY_CONTROL, send the held direction's
//! velocity (of the axis, or of the TCP) every period, show the axis or the TCP live, and leave
//! with `hold`.

use super::{Flow, Session};
use crate::transport::hmi::jog::{
    Held, JOG_PERIOD, JOG_TIMEOUT_S, JogKey, JogKeys, Jogged, TcpDirection, status_line,
    tcp_status_line, velocities,
};
use crate::transport::hmi::render;
use mcm_shared::command::{self, SetVelocities};
use mcm_shared::mode::Mode;
use mcm_shared::protocol::results::{Answer, Generic};
use mcm_shared::protocol::{Command, Hold, VelocityControl};
use std::io;
use tokio::io::AsyncReadExt;
use tokio::time::{Instant, MissedTickBehavior, interval};

/// What ended a jog.
enum End {
    Quit,
    /// The mode changed under the jog (a safety trip, `hold` from elsewhere), or a command
    /// failed: the reason.
    Lost(String),
    Closed,
}

impl Session {
    pub(super) async fn jog(&mut self, jogged: Jogged) -> io::Result<Flow> {
        let enter = Command::VelocityControl(VelocityControl {
            request: command::VelocityControl {
                timeout_s: Some(JOG_TIMEOUT_S),
            },
            dt_status: 0.0,
        });
        if let Some(error) = self.jog_command(&enter).await {
            self.say(&render::error("velocity_control", &error, None));
            return Ok(Flow::Continue);
        }
        let name = match jogged {
            Jogged::Axis { axis, speed } => {
                let name = render::axis_name(&self.ctx.cfg, axis.index()).into_owned();
                self.say(&format!(
                    "jogging axis {axis} ({name}) at {speed} deg/s: hold `+` or `-` (or the arrow \
                     keys) to move, any other key stops, `q` stops and leaves (mode HOLD)\n"
                ));
                name
            }
            Jogged::Tcp(tcp) => {
                let (speed, unit) = tcp.speed();
                self.say(&format!(
                    "jogging the TCP {} in the {} frame at {speed} {unit}: hold `+` or `-` (or \
                     the arrow keys) to move; `x` `y` `z` move along, `X` `Y` `Z` turn about \
                     that axis, `f` switches the frame (base/tool); any other key stops, `q` \
                     stops and leaves (mode HOLD)\n",
                    tcp.direction.word(),
                    tcp.frame.as_str()
                ));
                String::new()
            }
        };
        self.out.extend_from_slice(b"\x1b[?25l");
        self.flush().await?;
        let end = self.jog_loop(jogged, &name).await?;
        self.out.extend_from_slice(b"\r\n\x1b[?25h");
        let reason = match end {
            End::Quit => None,
            End::Lost(why) => Some(why),
            End::Closed => {
                // The connection is gone: its `client_gone` stops the axis.
                return Ok(Flow::Quit);
            }
        };
        if let Some(why) = reason {
            self.say(&format!(
                "{}jog ended:{} {why}\n",
                render::RED,
                render::RESET
            ));
        }
        let hold = self.jog_command(&Command::Hold(Hold)).await;
        let state = self.ctx.bridge.latest_state();
        let mode = state
            .as_deref()
            .and_then(|s| Mode::try_from(s.mode).ok())
            .map_or("unknown", Mode::as_str);
        match hold {
            None => self.say(&format!("jog ended; mode {mode}\n")),
            Some(e) => self.say(&render::error("hold", &e, state.as_deref())),
        }
        Ok(Flow::Continue)
    }

    /// Run `cmd` for this session; the ERROR result when it was not done.
    async fn jog_command(&mut self, cmd: &Command) -> Option<Generic> {
        let (ctx, client) = (self.ctx.clone(), self.client.clone());
        let out = crate::command::access::run_command(&ctx, &client, cmd).await;
        match out.result? {
            Answer::Generic(g) if !g.is_ok() => Some(g),
            _ => None,
        }
    }

    async fn jog_loop(&mut self, mut jogged: Jogged, name: &str) -> io::Result<End> {
        let mut tick = interval(JOG_PERIOD);
        tick.set_missed_tick_behavior(MissedTickBehavior::Skip);
        let mut keys = JogKeys::default();
        let mut held = Held::default();
        loop {
            tokio::select! {
                _ = tick.tick() => {
                    let now = Instant::now().into_std();
                    let direction = held.direction(now);
                    let set = match jogged {
                        Jogged::Axis { axis, speed } => Command::SetVelocities(SetVelocities {
                            velocities_deg_s: velocities(axis, speed, direction),
                        }),
                        Jogged::Tcp(tcp) => Command::SetCartesianVelocity(tcp.velocity(direction)),
                    };
                    if let Some(e) = self.jog_command(&set).await {
                        return Ok(End::Lost(e.message().to_string()));
                    }
                    let Some(s) = self.ctx.bridge.latest_state() else {
                        return Ok(End::Lost("the real-time core publishes no state".into()));
                    };
                    if s.mode != Mode::VelocityControl.to_wire() {
                        let mode = Mode::try_from(s.mode).map_or("unknown", Mode::as_str);
                        return Ok(End::Lost(format!("the mode changed to {mode}")));
                    }
                    let line = match jogged {
                        Jogged::Axis { axis, speed } => {
                            let i = axis.index();
                            status_line(axis, name, s.position[i], s.velocity[i], speed, direction)
                        }
                        Jogged::Tcp(tcp) => tcp_status_line(&tcp, &s, direction),
                    };
                    self.out.extend_from_slice(b"\r");
                    self.say(&line);
                    self.out.extend_from_slice(b"\x1b[K");
                }
                n = self.rd.read(&mut self.buf), if !self.closed => {
                    let n = n?;
                    if n == 0 {
                        self.closed = true;
                        return Ok(End::Closed);
                    }
                    let mut inputs = Vec::new();
                    self.telnet.feed(&self.buf[..n], &mut inputs, &mut self.out);
                    let now = Instant::now().into_std();
                    for input in inputs {
                        match keys.feed(input) {
                            Some(JogKey::Plus) => held.press(1, now),
                            Some(JogKey::Minus) => held.press(-1, now),
                            Some(JogKey::Stop) => held.stop(),
                            Some(JogKey::Choose(d)) => choose(&mut jogged, &mut held, Some(d)),
                            Some(JogKey::Frame) => choose(&mut jogged, &mut held, None),
                            Some(JogKey::Quit) => return Ok(End::Quit),
                            None => {}
                        }
                    }
                }
                e = self.errors.recv(), if self.errors_open => {
                    if let Some(text) = self.error_text(e) {
                        self.out.extend_from_slice(b"\r\n");
                        self.say(&text);
                    }
                }
                why = self.slot.evicted() => return Ok(End::Lost(why)),
            }
            self.flush().await?;
        }
    }
}

/// A key choosing the TCP's direction (`Some`) or switching its frame (`None`): the jog stops,
/// then a TCP jog takes the new direction or frame; an axis jog only stops.
fn choose(jogged: &mut Jogged, held: &mut Held, direction: Option<TcpDirection>) {
    held.stop();
    if let Jogged::Tcp(tcp) = jogged {
        match direction {
            Some(d) => tcp.direction = d,
            None => tcp.toggle_frame(),
        }
    }
}
