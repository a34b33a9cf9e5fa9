//! Executing one parsed command: through the bridge to the real-time core (or locally, for
//! `sleep`), and turning the reply into the protocol's result. Shared by the JSON channel and
//! the text HMI, so both behave the same.

use crate::bridge::{Bridge, BridgeError};
use crate::cmd::Command;
use crate::result;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, ReplyStatus};
use mcm_shared::sample::{Reply, StateSample};
use serde_json::Value;
use std::sync::Arc;
use std::time::Duration;

/// Longest wait for a calibration to finish.
pub const CALIBRATION_TIMEOUT: Duration = Duration::from_secs(600);
/// Longest wait for any other reply.
pub const REPLY_TIMEOUT: Duration = Duration::from_secs(5);

/// What a connection needs to execute commands.
#[derive(Clone)]
pub struct Context {
    pub cfg: Arc<RobotConfig>,
    pub bridge: Bridge,
}

/// The outcome of one command.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// The result to send; `None` for a successful `set_torques` (the protocol sends nothing).
    pub result: Option<Value>,
    /// The reply's state, when the command went to the core.
    pub state: Option<Box<StateSample>>,
    /// Set when this command put the robot into TORQUE_CONTROL: the status interval [s] (0: none).
    pub torque_session: Option<f64>,
}

impl Outcome {
    fn only(result: Value) -> Self {
        Self {
            result: Some(result),
            state: None,
            torque_session: None,
        }
    }
}

/// Execute `cmd` for the connection `client_id`.
pub async fn execute(ctx: &Context, client_id: u64, cmd: &Command) -> Outcome {
    if let Command::Sleep(s) = cmd {
        tokio::time::sleep(s.duration).await;
        return Outcome::only(result::ok());
    }
    let timeout = if matches!(cmd, Command::Calibrate(_)) {
        CALIBRATION_TIMEOUT
    } else {
        REPLY_TIMEOUT
    };
    let answer = ctx.bridge.request(client_id, cmd.samples(), timeout).await;
    let (reply, state) = match answer {
        Ok(a) => a,
        Err(e) => return Outcome::only(result::error(bridge_message(cmd.name(), &e))),
    };
    let status = ReplyStatus::try_from(reply.status).unwrap_or(ReplyStatus::Rejected);
    if status != ReplyStatus::Ok {
        return Outcome {
            result: Some(result::reply_error(cmd.name(), &reply)),
            state: Some(state),
            torque_session: None,
        };
    }
    let result = success(ctx, cmd, &reply, &state);
    let torque_session = match cmd {
        Command::TorqueControl(t) => Some(t.dt_status),
        _ => None,
    };
    Outcome {
        result,
        state: Some(state),
        torque_session,
    }
}

fn success(ctx: &Context, cmd: &Command, reply: &Reply, state: &StateSample) -> Option<Value> {
    let kind = CommandKind::try_from(reply.kind).ok();
    Some(match cmd {
        Command::Status(s) => result::status(state, s.detail),
        Command::Hold | Command::Release | Command::Pvt(_) | Command::TorqueControl(_) => {
            result::status(state, false)
        }
        Command::Info => result::initialization(&ctx.cfg, reply, state),
        Command::MoveAll(_) => result::move_all(reply),
        Command::Sim(_) => result::sim(state),
        Command::SetTorques(_) => return None,
        Command::Calibrate(_)
        | Command::MoveAxis(_)
        | Command::PvtPoints(_)
        | Command::Sleep(_) => {
            debug_assert!(kind.is_some());
            result::ok()
        }
    })
}

fn bridge_message(command: &str, e: &BridgeError) -> String {
    format!("{command} failed: {e}")
}
