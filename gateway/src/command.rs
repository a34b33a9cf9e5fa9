//! Executing one parsed command: through the bridge to the real-time core (or locally, for
//! `sleep` and the Cartesian commands of [`cartesian`]), and turning the reply into the
//! protocol's result. Shared by every transport (the
//! JSON channel, the text HMI, ZeroMQ), so all behave the same.
//!
//! `status` reads the bridge's newest state and never waits for a cycle; a `pvt_points` batch
//! is checked against the newest state and the configuration before any of it is sent
//! ([`mcm_shared::protocol::PvtPoints::check`]); every other command goes through the core and
//! is answered after the cycle that executed it.
//!
//! The transports do not call [`execute`] directly: [`access::run_command`] first applies the
//! access rules of `[gateway.access]` to the connection's client. [`result`] writes the typed
//! results as the JSON values the transports send.

pub(crate) mod access;
pub(crate) mod cartesian;
pub(crate) mod result;

use crate::core_link::bridge::{Bridge, BridgeError};
use mcm_shared::config::RobotConfig;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::mode::CommandKind;
use mcm_shared::protocol::results::{
    Answer, ErrorOutcome, Info, MoveAllResult, MoveLinearResult, PayloadResult, SimResult,
};
use mcm_shared::protocol::{Command, Success};
use mcm_shared::reply::{self, Done};
use mcm_shared::sample::{STATE_SIMULATED, StateSample};
use std::sync::Arc;
use std::time::Duration;

/// Longest wait for the core's reply to a command other than `calibrate` (the contract's,
/// [`Command::reply_within`] gives each command's).
pub use mcm_shared::protocol::REPLY_TIMEOUT;

/// What a connection needs to execute commands.
#[derive(Clone)]
pub struct Context {
    pub cfg: Arc<RobotConfig>,
    pub bridge: Bridge,
    /// The access rules and their refusal counters.
    pub access: Arc<crate::command::access::Access>,
    /// This gateway's connections, to name a client in words.
    pub clients: crate::command::access::Clients,
    /// The limits a `pvt_points` batch is checked against before it is sent (from `cfg`).
    pub pvt_limits: mcm_shared::pvt::PointLimits,
    /// The arm's kinematics (from `cfg`, the TCP on the flange), or why the configured arm
    /// has none ([`cartesian`] refuses its commands with it).
    pub kinematics: Result<mcm_kinematics::Kinematics, mcm_kinematics::KinematicsError>,
}

impl Context {
    /// The context of a gateway with the configuration `cfg`, its `bridge` to the core and
    /// the `access` rules (built by the caller: production reads them from the configuration
    /// before it binds anything), with no connection known yet.
    pub fn new(
        cfg: Arc<RobotConfig>,
        bridge: Bridge,
        access: crate::command::access::Access,
    ) -> Context {
        Context {
            pvt_limits: mcm_shared::pvt::PointLimits::from_config(&cfg),
            kinematics: mcm_kinematics::Kinematics::from_config(&cfg),
            cfg,
            bridge,
            access: Arc::new(access),
            clients: crate::command::access::Clients::default(),
        }
    }
}

/// The outcome of one command.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// The result to send; `None` for a command that answers nothing on success
    /// ([`Success::Nothing`]: `set_torques`, `set_velocities`).
    pub result: Option<Answer>,
    /// The reply's state, when the command went to the core.
    pub state: Option<Box<StateSample>>,
    /// Set when this command put the robot into TORQUE_CONTROL or VELOCITY_CONTROL: the
    /// status interval [s] (0: none) of the connection's mode session.
    pub mode_session: Option<f64>,
}

impl Outcome {
    fn only(result: Answer) -> Self {
        Self {
            result: Some(result),
            state: None,
            mode_session: None,
        }
    }
}

/// Execute `cmd` for the connection `client_id`.
pub async fn execute(ctx: &Context, client_id: u64, cmd: &Command) -> Outcome {
    match cmd {
        Command::Sleep(s) => {
            tokio::time::sleep(s.duration).await;
            return Outcome::only(Answer::ok());
        }
        Command::Status(s) => return status(ctx, s.detail).await,
        Command::InverseKinematics(ik) => return cartesian::inverse_kinematics(ctx, ik).await,
        Command::MoveToPose(m) => return cartesian::move_to_pose(ctx, client_id, m).await,
        Command::PvtPoints(p) => {
            // Checked in the core's order: control of the arm first, then the batch.
            if let Some(state) = ctx.bridge.latest_state() {
                let checked = control_of_the_arm(&state, client_id)
                    .and_then(|()| p.check(&ctx.pvt_limits, &state));
                if let Err(reason) = checked {
                    return refused(ctx, CommandKind::PvtPoints, reason, state);
                }
            }
        }
        _ => {}
    }
    if let Command::Authenticate(_) = cmd {
        return Outcome::only(Answer::answer_error(
            ErrorOutcome::Invalid,
            ErrorCode::InternalError,
            "authenticate: answered by the connection's access rules (crate::command::access::run_command), \
             not by the real-time core"
                .to_string(),
        ));
    }
    through_core(ctx, client_id, cmd).await
}

/// Whether the client `client_id` may move the arm, as the core decides it from `state`.
fn control_of_the_arm(state: &StateSample, client_id: u64) -> Result<(), reply::Reason> {
    let owner = state.owner_client_id;
    if CommandKind::may_control(owner, client_id) {
        Ok(())
    } else {
        Err(reply::Reason::NotOwner { owner })
    }
}

/// A request of `kind` refused by the gateway before it was sent, for `reason`, in the words
/// and with the code the core gives the same refusal.
fn refused(
    ctx: &Context,
    kind: CommandKind,
    reason: reply::Reason,
    state: Box<StateSample>,
) -> Outcome {
    let refused = reply::Outcome::Refused(reason);
    Outcome {
        result: Some(Answer::Generic(crate::command::access::reply_error(
            ctx, kind, &refused,
        ))),
        state: Some(state),
        mode_session: None,
    }
}

/// `cmd` sent to the core, and its answer as the command's result.
async fn through_core(ctx: &Context, client_id: u64, cmd: &Command) -> Outcome {
    let answer = ctx
        .bridge
        .request(client_id, cmd.requests(), cmd.reply_within())
        .await;
    let (response, state) = match answer {
        Ok(a) => a,
        Err(e) => return Outcome::only(bridge_error(cmd.name(), &e)),
    };
    let done = match response.outcome {
        reply::Outcome::Done(done) => done,
        refused_or_failed => {
            return Outcome {
                result: Some(Answer::Generic(crate::command::access::reply_error(
                    ctx,
                    // Every command sent to the core has its kind (the gateway's own
                    // commands returned before).
                    cmd.def().kind.unwrap_or(response.kind),
                    &refused_or_failed,
                ))),
                state: Some(state),
                mode_session: None,
            };
        }
    };
    let result = success(ctx, cmd, &done, &state);
    let mode_session = match cmd {
        Command::TorqueControl(t) => Some(t.dt_status),
        Command::VelocityControl(v) => Some(v.dt_status),
        _ => None,
    };
    Outcome {
        result,
        state: Some(state),
        mode_session,
    }
}

/// How long `status` waits for a state when the bridge has none: the gateway just started (its
/// bridge has not read the core's first state yet) or the core is restarting.
pub const STATE_GRACE: Duration = Duration::from_millis(300);

/// `status`: from the newest state, without waiting for a cycle. With no state yet, waits at most
/// [`STATE_GRACE`] for one before saying the core is not running.
async fn status(ctx: &Context, detail: bool) -> Outcome {
    match ctx.bridge.state_within(STATE_GRACE).await {
        Some(state) => Outcome {
            result: Some(crate::command::result::status_answer(
                "status", &state, detail,
            )),
            state: Some(state),
            mode_session: None,
        },
        None => Outcome::only(bridge_error("status", &ctx.bridge.unavailable())),
    }
}

/// The result of `cmd` done by the core, as its definition says it answers
/// ([`mcm_shared::protocol::CommandDef::success`]).
fn success(ctx: &Context, cmd: &Command, done: &Done, state: &StateSample) -> Option<Answer> {
    // Done, but its figures do not read: what it did is for the state to tell.
    let mismatch = |other: &Done| {
        Answer::answer_error(
            ErrorOutcome::Unknown,
            ErrorCode::VersionMismatch,
            format!(
                "{}: the real-time core's answer carries no figures ({other:?}); mcm-rt and the \
             gateway are from different MCM versions: rebuild both from the same version",
                cmd.name()
            ),
        )
    };
    Some(match cmd.def().success {
        Success::Nothing => return None,
        Success::Ok => Answer::ok(),
        // `status` itself never comes here ([`execute`] answers it from the newest state): these
        // are the commands answered with the status of their cycle, without the detail.
        Success::Status => crate::command::result::status_answer(cmd.name(), state, false),
        Success::Initialization => match done {
            Done::Info(info) => Answer::Initialization(Info::new(
                &ctx.cfg,
                info,
                state.flags & STATE_SIMULATED != 0,
            )),
            other => mismatch(other),
        },
        Success::MoveAll => match done {
            Done::MoveAll(plan) => Answer::MoveAll(MoveAllResult::from(plan)),
            other => mismatch(other),
        },
        Success::Payload => match done {
            Done::Payload(p) => Answer::Payload(PayloadResult::from(p)),
            other => mismatch(other),
        },
        Success::MoveLinear => match done {
            Done::MoveLinear(plan) => Answer::MoveLinear(MoveLinearResult::from(plan)),
            other => mismatch(other),
        },
        Success::Sim => Answer::Sim(SimResult::from_state(state)),
        // Answered by the gateway ([`cartesian`]), never after the core's reply.
        Success::InverseKinematics => mismatch(done),
    })
}

/// The ERROR result of a request the bridge could not complete ([`bridge_message`]): `failed`
/// only when the command surely was not executed, else `unknown`.
pub fn bridge_error(command: &str, e: &BridgeError) -> Answer {
    let outcome = if e.surely_not_executed() {
        ErrorOutcome::Failed
    } else {
        ErrorOutcome::Unknown
    };
    Answer::answer_error(outcome, e.code(), bridge_message(command, e))
}

/// The error text of a request the bridge could not complete: "failed" only when the command
/// surely was not executed.
pub fn bridge_message(command: &str, e: &BridgeError) -> String {
    if e.surely_not_executed() {
        format!("{command} failed: {e}")
    } else {
        // Not "failed": the command may well have been done; its answer is what is unknown.
        format!("{command}: {e}")
    }
}

#[cfg(test)]
mod tests;
