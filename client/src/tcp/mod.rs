//! The JSON protocol over TCP (`docs/protocol.md`), blocking.
//!
//! ```no_run
//! use mcm_client::tcp::TcpClient;
//! let mut mcm = TcpClient::connect("127.0.0.1:18010")?;
//! mcm.hold()?;
//! mcm.calibrate(Default::default())?;
//! mcm.pvt(0.01)?;
//! let plan = mcm.move_all([0.0, 10.0, 20.0, 0.0, 0.0, 0.0], 0.5)?;
//! println!("arrives in {:.2} s", plan.max_time_to_target);
//! # Ok::<(), mcm_client::tcp::Error>(())
//! ```
//!
//! Each call writes one command line and reads lines until that command's result; lines that
//! answer no command (safety errors, the status ticks of a TORQUE_CONTROL or VELOCITY_CONTROL
//! session, notices) are queued for [`TcpClient::next_event`]. `set_torques`,
//! `set_velocities` and `set_cartesian_velocity` have no result on success: they return once
//! written, and a refusal arrives later as [`Event::CommandError`].
//!
//! **Reconnecting.** When the connection breaks, the call that saw it fails and the client is
//! disconnected; so does a call whose result does not come in time ([`Error::Timeout`]: a
//! late result must not answer the next call). [`TcpClient::reconnect`] opens a new connection (and repeats `authenticate`
//! if it was given). Control of the arm does *not* survive: the old connection closing makes
//! the gateway release its control, and what it drove (a move, a PVT stream, RELEASE,
//! TORQUE_CONTROL, VELOCITY_CONTROL) ends in HOLD. Take control again (`take_control`) after a reconnect. With
//! [`TcpOptions::reconnect_on_next_call`] the next call reconnects by itself first.

mod error;
mod steps;
mod types;
mod wire;

pub use error::{Error, ErrorKind, McmError, ProtocolProblem};
pub use types::{
    AxisInfo, AxisStates, Calibrate, CartesianState, Detail, Event, Info, InverseKinematicsResult,
    MoveAllResult, MoveLinear, MoveLinearResult, PayloadResult, Pose, PvtQueue, SimResult, Six,
    Status, TorqueOptions, VelocityOptions,
};

use mcm_shared::command::{
    CartesianFrame, IdentifyPayload, MoveAll, MoveAxis, Pvt, PvtPoint, SetCartesianVelocity,
    SetTool, SetTorques, SetVelocities, SimCommand,
};
use mcm_shared::mode::Mode;
use mcm_shared::protocol::results::Answer;
use mcm_shared::protocol::{self, Command};
use mcm_shared::tool::Tool;
use std::collections::VecDeque;
use std::io::{ErrorKind as IoKind, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::{Duration, Instant};
use wire::Line;

/// The MCM's JSON port.
pub const DEFAULT_PORT: u16 = 18010;
/// Most points the MCM takes in one `pvt_points` command.
pub const MAX_POINTS_PER_COMMAND: usize = protocol::MAX_POINTS_PER_BATCH;
/// Longest command line this client writes (without its newline): the MCM's limit. A
/// `pvt_points` batch is cut to fit by an estimate that never falls short of the line's length.
const MAX_LINE: usize = protocol::MAX_COMMAND_BYTES;

/// How the client connects and waits.
#[derive(Debug, Clone, PartialEq)]
pub struct TcpOptions {
    pub connect_timeout: Duration,
    /// Longest wait for a command's result (the MCM itself answers within
    /// [`protocol::REPLY_TIMEOUT`], 5 s, or says the outcome is unknown). A command the MCM may
    /// take longer to answer waits that much longer
    /// ([`Command::extra_reply_time`](mcm_shared::protocol::Command::extra_reply_time):
    /// `calibrate` up to 600 s, `sleep` its duration).
    pub reply_timeout: Duration,
    /// A call on a broken connection reconnects first (see the module docs on control).
    pub reconnect_on_next_call: bool,
}

impl Default for TcpOptions {
    fn default() -> Self {
        TcpOptions {
            connect_timeout: Duration::from_secs(5),
            reply_timeout: Duration::from_secs(10),
            reconnect_on_next_call: false,
        }
    }
}

/// A session with this `dt_status` sends status ticks.
fn ticking(dt_status_s: Option<f64>) -> bool {
    dt_status_s.is_some_and(|d| d > 0.0)
}

struct Conn {
    stream: TcpStream,
    buf: Vec<u8>,
}

/// A connection to the MCM's JSON port. See the module docs.
pub struct TcpClient {
    addr: String,
    opts: TcpOptions,
    conn: Option<Conn>,
    events: VecDeque<Event>,
    /// The mode whose session (TORQUE_CONTROL or VELOCITY_CONTROL) sends this connection
    /// status ticks; `None`: no ticks.
    ticks: Option<Mode>,
    secret: Option<String>,
}

/// The error for `answer`, which is not what the command `def` answers on success.
fn unexpected(def: &protocol::CommandDef, answer: &Answer) -> Error {
    Error::Protocol {
        command: def.name.to_string(),
        problem: ProtocolProblem::Unexpected {
            got: answer.result_type(),
            expected: def.success.result_type().unwrap_or("none"),
        },
        line: answer.to_value().to_string(),
    }
}

impl TcpClient {
    /// Connect to `addr` (`host:port`) with the default options.
    pub fn connect(addr: &str) -> Result<TcpClient, Error> {
        TcpClient::connect_with(addr, TcpOptions::default())
    }

    pub fn connect_with(addr: &str, opts: TcpOptions) -> Result<TcpClient, Error> {
        let mut c = TcpClient {
            addr: addr.to_string(),
            opts,
            conn: None,
            events: VecDeque::new(),
            ticks: None,
            secret: None,
        };
        c.open()?;
        Ok(c)
    }

    fn open(&mut self) -> Result<(), Error> {
        let err = |source| Error::Connect {
            addr: self.addr.clone(),
            source,
        };
        let mut last = None;
        let addrs = self.addr.to_socket_addrs().map_err(err)?;
        for a in addrs {
            match TcpStream::connect_timeout(&a, self.opts.connect_timeout) {
                Ok(stream) => {
                    stream.set_nodelay(true).map_err(err)?;
                    self.conn = Some(Conn {
                        stream,
                        buf: Vec::new(),
                    });
                    self.ticks = None;
                    return Ok(());
                }
                Err(e) => last = Some(e),
            }
        }
        Err(err(last.unwrap_or_else(|| {
            std::io::Error::new(IoKind::NotFound, "the address resolves to nothing")
        })))
    }

    /// Close this connection and open a new one; `authenticate` is repeated if it was given.
    /// Control of the arm is lost with the old connection (what it drove ends in HOLD).
    pub fn reconnect(&mut self) -> Result<(), Error> {
        self.conn = None;
        self.open()?;
        if let Some(secret) = self.secret.clone() {
            self.authenticate(&secret)?;
        }
        Ok(())
    }

    /// The connection is open (as far as this client knows).
    pub fn is_connected(&self) -> bool {
        self.conn.is_some()
    }

    /// The address this client connects to.
    pub fn addr(&self) -> &str {
        &self.addr
    }

    fn ensure(&mut self) -> Result<(), Error> {
        if self.conn.is_none() {
            if self.opts.reconnect_on_next_call {
                self.reconnect()?;
            } else {
                return Err(Error::NotConnected);
            }
        }
        Ok(())
    }

    fn write(&mut self, command: &str, line: &str) -> Result<(), Error> {
        self.ensure()?;
        let conn = self.conn.as_mut().ok_or(Error::NotConnected)?;
        let r = conn
            .stream
            .write_all(line.as_bytes())
            .and_then(|()| conn.stream.write_all(b"\n"));
        r.map_err(|source| {
            self.conn = None;
            Error::Io {
                command: command.to_string(),
                source,
            }
        })
    }

    /// The next line, or `None` when `deadline` passed first.
    fn read_line(&mut self, command: &str, deadline: Instant) -> Result<Option<String>, Error> {
        let conn = self.conn.as_mut().ok_or(Error::NotConnected)?;
        loop {
            if let Some(i) = conn.buf.iter().position(|&b| b == b'\n') {
                let line: Vec<u8> = conn.buf.drain(..=i).collect();
                let text = String::from_utf8_lossy(&line).trim().to_string();
                if text.is_empty() {
                    continue;
                }
                return Ok(Some(text));
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Ok(None);
            }
            let io = |source| Error::Io {
                command: command.to_string(),
                source,
            };
            conn.stream
                .set_read_timeout(Some(left.max(Duration::from_millis(1))))
                .map_err(io)?;
            let mut chunk = [0u8; 8192];
            match conn.stream.read(&mut chunk) {
                Ok(0) => {
                    self.conn = None;
                    let reason = self.events.iter().rev().find_map(|e| match e {
                        Event::Notice(n) => Some(n.clone()),
                        _ => None,
                    });
                    return Err(Error::Closed { reason });
                }
                Ok(n) => conn.buf.extend_from_slice(&chunk[..n]),
                Err(e) if matches!(e.kind(), IoKind::WouldBlock | IoKind::TimedOut) => {}
                Err(e) if e.kind() == IoKind::Interrupted => {}
                Err(e) => {
                    self.conn = None;
                    return Err(io(e));
                }
            }
        }
    }

    fn queue(&mut self, e: Event) {
        if let Event::Status(s) = &e
            && self.ticks.is_some_and(|m| m != s.mode)
        {
            self.ticks = None;
        }
        self.events.push_back(e);
    }

    /// Send `cmd` and read lines until its result: what its definition says it answers on
    /// success ([`protocol::CommandDef::success`]), and nothing else. `mode`: the mode of the
    /// status the command answers, when known (in a session with ticks, TORQUE_CONTROL or
    /// VELOCITY_CONTROL, a status in another mode is one of the session's ticks, and a tick is
    /// what a `status` call may get there). When no result comes within
    /// [`TcpClient::wait_for`] the connection is closed: its late result would otherwise
    /// answer the next call.
    fn call(&mut self, cmd: &Command, mode: Option<Mode>) -> Result<Answer, Error> {
        let timeout = self.wait_for(cmd);
        self.call_line(cmd.def(), &cmd.to_json(), mode, timeout)
    }

    /// The longest wait for the result of `cmd`: [`TcpOptions::reply_timeout`], plus the time
    /// the MCM may take beyond its usual bound for this command.
    fn wait_for(&self, cmd: &Command) -> Duration {
        self.opts.reply_timeout + cmd.extra_reply_time()
    }

    /// [`TcpClient::call`] with the command's line given: `line` is a command `def` (written by
    /// [`Command::to_json`] but for a value the typed command cannot hold).
    fn call_line(
        &mut self,
        def: &'static protocol::CommandDef,
        line: &serde_json::Value,
        mode: Option<Mode>,
        timeout: Duration,
    ) -> Result<Answer, Error> {
        let command = def.name;
        self.write(command, &line.to_string())?;
        let deadline = Instant::now() + timeout;
        loop {
            let Some(line) = self.read_line(command, deadline)? else {
                // The result may still come: on this connection it would answer the next call.
                self.conn = None;
                return Err(Error::Timeout {
                    command: command.to_string(),
                    waited: timeout,
                });
            };
            let parsed = wire::parse(&line).map_err(|problem| Error::Protocol {
                command: command.to_string(),
                problem,
                line: line.clone(),
            })?;
            let answer = match parsed {
                Line::Event(e) => {
                    self.queue(e);
                    continue;
                }
                Line::Error(g) => {
                    return Err(McmError::from_generic(command, &g).into());
                }
                Line::Status(s) => {
                    let tick = self.ticks.is_some()
                        && (def.success != protocol::Success::Status
                            || mode.is_some_and(|m| m != s.mode));
                    if tick {
                        self.queue(Event::Status(s));
                        continue;
                    }
                    Answer::Status(s)
                }
                Line::Ok => Answer::ok(),
                Line::Other(a) => a,
            };
            if def.success.answers(&answer) {
                return Ok(answer);
            }
            return Err(unexpected(def, &answer));
        }
    }

    fn call_ok(&mut self, cmd: impl Into<Command>) -> Result<(), Error> {
        self.call(&cmd.into(), None).map(|_| ())
    }

    fn call_status(
        &mut self,
        cmd: impl Into<Command>,
        mode: Option<Mode>,
    ) -> Result<Status, Error> {
        let cmd = cmd.into();
        match self.call(&cmd, mode)? {
            Answer::Status(s) => Ok(*s),
            other => Err(unexpected(cmd.def(), &other)),
        }
    }

    /// [`TcpClient::call`] for a command whose typed result `typed` takes out of its answer.
    fn call_typed<T>(
        &mut self,
        cmd: impl Into<Command>,
        typed: impl FnOnce(Answer) -> Result<T, Box<Answer>>,
    ) -> Result<T, Error> {
        let cmd = cmd.into();
        let answer = self.call(&cmd, None)?;
        typed(answer).map_err(|other| unexpected(cmd.def(), &other))
    }

    /// Any command of the protocol, typed ([`mcm_shared::protocol::Command`]), and its result:
    /// `None` for a command that answers nothing on success (`set_torques`,
    /// `set_velocities`: it returns once written, and a refusal comes later as
    /// [`Event::CommandError`]). The methods below are this call with typed results; a command
    /// without its own method is still reachable here. It waits [`TcpOptions::reply_timeout`]
    /// for the result, plus the time the MCM may take beyond its usual bound for the command
    /// (`calibrate`, `sleep`).
    ///
    /// ```no_run
    /// use mcm_client::tcp::TcpClient;
    /// use mcm_shared::protocol::{results::Answer, Hold};
    /// let mut mcm = TcpClient::connect("127.0.0.1:18010")?;
    /// let Some(Answer::Status(s)) = mcm.command(Hold)? else { unreachable!() };
    /// println!("mode {}", s.mode);
    /// # Ok::<(), mcm_client::tcp::Error>(())
    /// ```
    pub fn command(&mut self, cmd: impl Into<Command>) -> Result<Option<Answer>, Error> {
        let cmd = cmd.into();
        if cmd.def().success == protocol::Success::Nothing {
            self.write(cmd.name(), &cmd.to_json().to_string())?;
            return Ok(None);
        }
        self.call(&cmd, None).map(Some)
    }

    /// The newest state (`status`). In a TORQUE_CONTROL or VELOCITY_CONTROL session with
    /// `dt_status` this may be
    /// one of the session's ticks (a state as fresh); the ticks are better read as events.
    pub fn status(&mut self) -> Result<Status, Error> {
        self.call_status(protocol::Status { detail: false }, None)
    }

    /// `status` with `detail`: `hardware_status` and `detail` are set.
    pub fn status_detail(&mut self) -> Result<Status, Error> {
        self.call_status(protocol::Status { detail: true }, None)
    }

    /// Robot, version, cycle time and the limits of every axis (`info`).
    pub fn info(&mut self) -> Result<Info, Error> {
        self.call_typed(protocol::Info, |a| match a {
            Answer::Initialization(i) => Ok(i),
            other => Err(Box::new(other)),
        })
    }

    /// Enter HOLD (clears errors and powers the drives from OFF/ERROR; stops a motion). Open
    /// to every client.
    pub fn hold(&mut self) -> Result<Status, Error> {
        let s = self.call_status(protocol::Hold, Some(Mode::Hold))?;
        self.ticks = None;
        Ok(s)
    }

    /// Home the axes; returns when the calibration has finished (about 12 s on the simulated
    /// P-Rob2), with the arm back at zero in HOLD.
    pub fn calibrate(&mut self, o: Calibrate) -> Result<(), Error> {
        let cmd = Command::Calibrate(o);
        self.call(&cmd, None).map(|_| ())
    }

    /// Enter RELEASE (the arm can be moved by hand).
    pub fn release(&mut self) -> Result<Status, Error> {
        let s = self.call_status(protocol::Release, Some(Mode::Release))?;
        self.ticks = None;
        Ok(s)
    }

    /// Enter PVT with points spaced `dt_s` seconds (one cycle to 1 s).
    pub fn pvt(&mut self, dt_s: f64) -> Result<Status, Error> {
        let s = self.call_status(Pvt { dt_s }, Some(Mode::Pvt))?;
        self.ticks = None;
        Ok(s)
    }

    /// Enter TORQUE_CONTROL. With `dt_status_s` the MCM sends a status every `dt_status_s`
    /// ([`Event::Status`]); with `dt_status_s` equal to the cycle period every cycle's state
    /// comes exactly once, and a `set_torques` sent in answer is applied in the next cycle.
    pub fn torque_control(&mut self, o: TorqueOptions) -> Result<Status, Error> {
        let cmd = protocol::TorqueControl::from(o);
        let s = self.call_status(cmd, Some(Mode::TorqueControl))?;
        self.ticks = ticking(o.dt_status_s).then_some(Mode::TorqueControl);
        Ok(s)
    }

    /// Set the joint torques [Nm] in TORQUE_CONTROL (added to the gravity compensation unless
    /// it was switched off). Returns once written: there is no result on success, and a
    /// refusal comes later as [`Event::CommandError`].
    pub fn set_torques(&mut self, torques_nm: Six) -> Result<(), Error> {
        self.command(SetTorques { torques_nm }).map(|_| ())
    }

    /// Enter VELOCITY_CONTROL: every axis starts at target velocity 0. `timeout_s` and
    /// `dt_status_s` are those of `torque_control`: with `dt_status_s` the MCM sends a status
    /// every `dt_status_s` ([`Event::Status`]), and one when the mode is left (timeout, `hold`).
    pub fn velocity_control(&mut self, o: VelocityOptions) -> Result<Status, Error> {
        let cmd = protocol::VelocityControl::from(o);
        let s = self.call_status(cmd, Some(Mode::VelocityControl))?;
        self.ticks = ticking(o.dt_status_s).then_some(Mode::VelocityControl);
        Ok(s)
    }

    /// Set the joint velocities [deg/s] in VELOCITY_CONTROL (each within its axis's
    /// `max_velocity`; the arm ramps to them within the acceleration and jerk limits).
    /// Returns once written: there is no result on success, and a refusal comes later as
    /// [`Event::CommandError`].
    pub fn set_velocities(&mut self, velocities_deg_s: Six) -> Result<(), Error> {
        self.command(SetVelocities { velocities_deg_s }).map(|_| ())
    }

    /// Set the TCP's velocity in VELOCITY_CONTROL: linear [m/s] and angular [deg/s], in the
    /// axes of the base frame or of the TCP's own (`frame`); each component within its range
    /// (1 m/s, 180 deg/s). The arm follows within every axis's limits, slower along the same
    /// direction where an axis or a singularity needs it (`docs/cartesian.md`). Returns once
    /// written: there is no result on success, and a refusal comes later as
    /// [`Event::CommandError`].
    pub fn set_cartesian_velocity(
        &mut self,
        linear_m_s: [f64; 3],
        angular_deg_s: [f64; 3],
        frame: CartesianFrame,
    ) -> Result<(), Error> {
        self.command(SetCartesianVelocity {
            linear_m_s,
            angular_deg_s,
            frame,
        })
        .map(|_| ())
    }

    /// Set the tool the arm carries (its TCP and load; build it with [`Tool::new`]), from the
    /// next cycle; in HOLD, or PVT at standstill.
    pub fn set_tool(&mut self, tool: Tool) -> Result<(), Error> {
        self.call_ok(SetTool { tool })
    }

    /// Estimate the load on the flange (in HOLD at rest, calibrated): the arm moves through a
    /// few poses and back (under 30 s); with `apply` the estimate becomes the tool's mass and
    /// centre of mass.
    pub fn identify_payload(&mut self, apply: bool) -> Result<PayloadResult, Error> {
        self.call_typed(IdentifyPayload { apply }, |a| match a {
            Answer::Payload(p) => Ok(p),
            other => Err(Box::new(other)),
        })
    }

    /// Move one axis (1..6) to `target_deg` at `velocity_factor` (0, 1] of its limits; OK as
    /// the motion starts (PVT mode).
    pub fn move_axis(
        &mut self,
        axis: u8,
        target_deg: f64,
        velocity_factor: f64,
    ) -> Result<(), Error> {
        let typed = |axis| MoveAxis {
            axis,
            target_deg,
            velocity_factor,
        };
        match mcm_shared::command::Axis::new(axis) {
            Some(a) => self.call_ok(typed(a)),
            None => {
                // Not an axis: sent as given, so that the MCM refuses it in its own words, as
                // it refuses every other value out of range.
                let cmd = Command::MoveAxis(typed(mcm_shared::command::Axis::ALL[0]));
                let mut line = cmd.to_json();
                line["arguments"]["axis_index"] = axis.into();
                let t = self.wait_for(&cmd);
                self.call_line(cmd.def(), &line, None, t).map(|_| ())
            }
        }
    }

    /// Move all axes together to `targets_deg` (PVT mode); the move the MCM planned.
    pub fn move_all(
        &mut self,
        targets_deg: Six,
        velocity_factor: f64,
    ) -> Result<MoveAllResult, Error> {
        let cmd = MoveAll {
            targets_deg,
            velocity_factor,
        };
        self.call_typed(cmd, |a| match a {
            Answer::MoveAll(m) => Ok(m),
            other => Err(Box::new(other)),
        })
    }

    /// Move the TCP to `pose` (base frame: position [m], orientation a unit quaternion
    /// `[x, y, z, w]`): a joint move, as [`TcpClient::move_all`], to the inverse kinematics'
    /// solution nearest the present position (PVT mode); the move the MCM planned.
    pub fn move_to_pose(
        &mut self,
        pose: Pose,
        velocity_factor: f64,
    ) -> Result<MoveAllResult, Error> {
        let cmd = protocol::MoveToPose {
            pose,
            velocity_factor,
        };
        self.call_typed(cmd, |a| match a {
            Answer::MoveAll(m) => Ok(m),
            other => Err(Box::new(other)),
        })
    }

    /// Move the TCP on a straight line to `line.position` (PVT mode; `docs/cartesian.md`):
    /// answered once the MCM has checked the whole path, with the time to the target and each
    /// axis's position there; a path the arm cannot follow is refused (`unreachable`,
    /// `out_of_range`) and nothing moves.
    pub fn move_linear(&mut self, line: MoveLinear) -> Result<MoveLinearResult, Error> {
        self.call_typed(line, |a| match a {
            Answer::MoveLinear(m) => Ok(m),
            other => Err(Box::new(other)),
        })
    }

    /// Every joint configuration [deg] that puts the TCP at `pose`, each within the axis
    /// limits, the nearest to `seed_deg` (`None`: the present position) first. Nothing moves.
    pub fn inverse_kinematics(
        &mut self,
        pose: Pose,
        seed_deg: Option<Six>,
    ) -> Result<InverseKinematicsResult, Error> {
        let cmd = protocol::InverseKinematics { pose, seed_deg };
        self.call_typed(cmd, |a| match a {
            Answer::InverseKinematics(r) => Ok(r),
            other => Err(Box::new(other)),
        })
    }

    /// Queue PVT points (spaced by `pvt`'s `dt`). Up to [`MAX_POINTS_PER_COMMAND`] points that
    /// fit one line go in one command, queued whole or not at all; longer lists go as several
    /// commands in order, and the first refused one ends the call (the commands before it
    /// stay queued; the MCM's words count its points from 1 within that command).
    pub fn pvt_points(&mut self, points: &[PvtPoint]) -> Result<(), Error> {
        if points.is_empty() {
            return Err(Error::Argument {
                command: "pvt_points".into(),
                problem: "no points given; send 1 or more".into(),
            });
        }
        // The length of one point in the line: the command of that point alone, less the
        // command around it.
        let bare = Command::PvtPoints(protocol::PvtPoints { points: Vec::new() })
            .to_json()
            .to_string()
            .len();
        let mut batch: Vec<PvtPoint> = Vec::new();
        let mut len = bare;
        for p in points {
            let one = Command::PvtPoints(protocol::PvtPoints { points: vec![*p] });
            let n = one.to_json().to_string().len() - bare + 1;
            if !batch.is_empty() && (len + n > MAX_LINE || batch.len() == MAX_POINTS_PER_COMMAND) {
                let points = std::mem::take(&mut batch);
                self.call_ok(protocol::PvtPoints { points })?;
                len = bare;
            }
            len += n;
            batch.push(*p);
        }
        self.call_ok(protocol::PvtPoints { points: batch })
    }

    /// Take control of the arm's motion (refused while another client controls it).
    pub fn take_control(&mut self) -> Result<(), Error> {
        self.call_ok(protocol::TakeControl)
    }

    /// Give up control; what this connection drove ends in HOLD.
    pub fn release_control(&mut self) -> Result<(), Error> {
        self.call_ok(protocol::ReleaseControl)
    }

    /// Present the shared secret (needed before taking control when the MCM has one). It is
    /// kept to authenticate again after a reconnect.
    pub fn authenticate(&mut self, secret: &str) -> Result<(), Error> {
        self.call_ok(protocol::Authenticate {
            secret: protocol::Secret(secret.to_string()),
        })?;
        self.secret = Some(secret.to_string());
        Ok(())
    }

    /// Fault injection into the simulated robot (from loopback); the simulation's ground truth.
    pub fn sim(&mut self, c: SimCommand) -> Result<SimResult, Error> {
        self.call_typed(c, |a| match a {
            Answer::Sim(r) => Ok(r),
            other => Err(Box::new(other)),
        })
    }

    /// The next spontaneous message: a queued one at once, else the first to arrive within
    /// `timeout` (`None`: none came).
    pub fn next_event(&mut self, timeout: Duration) -> Result<Option<Event>, Error> {
        if let Some(e) = self.events.pop_front() {
            return Ok(Some(e));
        }
        self.ensure()?;
        let deadline = Instant::now() + timeout;
        if let Some(line) = self.read_line("(events)", deadline)? {
            let event = match wire::parse(&line) {
                Ok(Line::Event(e)) => e,
                Ok(Line::Status(s)) => Event::Status(s),
                Ok(Line::Error(g)) => Event::Notice(g.message().to_string()),
                // A result no call waits for (a timed-out call closed its connection, so
                // not its late result): its words.
                Ok(Line::Ok | Line::Other(..)) | Err(_) => Event::Notice(line),
            };
            self.queue(event);
            return Ok(self.events.pop_front());
        }
        Ok(None)
    }
}

#[cfg(test)]
mod tests;
