//! Executing one parsed command: through the bridge to the real-time core (or locally, for
//! `sleep`), and turning the reply into the protocol's result. Shared by the JSON channel and
//! the text HMI, so both behave the same.

use crate::bridge::{Bridge, BridgeError};
use crate::cmd::Command;
use crate::result;
use mcm_shared::config::RobotConfig;
use mcm_shared::reply::{self, Done};
use mcm_shared::sample::{STATE_SIMULATED, StateSample};
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
    /// The access rules and their refusal counters.
    pub access: Arc<crate::access::Access>,
    /// This gateway's connections, to name a client in words.
    pub clients: crate::access::Clients,
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
    if let Command::Authenticate(_) = cmd {
        return Outcome::only(result::error(
            "authenticate: answered by the connection's access rules (crate::access::run_command), \
             not by the real-time core"
                .to_string(),
        ));
    }
    let timeout = if matches!(cmd, Command::Calibrate(_)) {
        CALIBRATION_TIMEOUT
    } else {
        REPLY_TIMEOUT
    };
    let answer = ctx.bridge.request(client_id, cmd.requests(), timeout).await;
    let (response, state) = match answer {
        Ok(a) => a,
        Err(e) => return Outcome::only(result::error(bridge_message(cmd.name(), &e))),
    };
    let done = match response.outcome {
        reply::Outcome::Done(done) => done,
        refused_or_failed => {
            return Outcome {
                result: Some(crate::access::reply_error(
                    ctx,
                    cmd.name(),
                    &refused_or_failed,
                )),
                state: Some(state),
                torque_session: None,
            };
        }
    };
    let result = success(ctx, cmd, &done, &state);
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

fn success(ctx: &Context, cmd: &Command, done: &Done, state: &StateSample) -> Option<Value> {
    Some(match (cmd, done) {
        (Command::Status(s), _) => result::status(state, s.detail),
        (Command::Hold | Command::Release | Command::Pvt(_) | Command::TorqueControl(_), _) => {
            result::status(state, false)
        }
        (Command::Info, Done::Info(info)) => {
            crate::cmd::info::render(&ctx.cfg, info, state.flags & STATE_SIMULATED != 0)
        }
        (Command::MoveAll(_), Done::MoveAll(plan)) => crate::cmd::move_all::render(plan),
        (Command::Info | Command::MoveAll(_), other) => result::error(format!(
            "{}: the real-time core's answer carries no figures ({other:?}); mcm-rt and the \
             gateway are from different MCM versions: rebuild both from the same version",
            cmd.name()
        )),
        (Command::Sim(_), _) => crate::cmd::sim::render(state),
        (Command::SetTorques(_), _) => return None,
        (Command::Calibrate(_) | Command::MoveAxis(_) | Command::PvtPoints(_), _) => result::ok(),
        (Command::Sleep(_), _) => result::ok(),
        (Command::TakeControl | Command::ReleaseControl | Command::Authenticate(_), _) => {
            result::ok()
        }
    })
}

fn bridge_message(command: &str, e: &BridgeError) -> String {
    match e {
        // Not "failed": the command may well have been done; its answer is what is unknown.
        BridgeError::Undecodable(_) => format!("{command}: {e}"),
        _ => format!("{command} failed: {e}"),
    }
}
