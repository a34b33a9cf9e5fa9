//! The Cartesian commands the gateway executes itself (`docs/cartesian.md`): `inverse_kinematics`
//! (a computation: no control, no round trip to the core) and `move_to_pose` (the pose solved
//! here, then the same `move_all` request `move_all` sends, so that the core's rules on mode,
//! control, range and re-planning apply unchanged and the answer is the `move_all` result). A
//! pose no solution reaches is refused with `unreachable` before anything is sent.
//!
//! The kinematics are the configuration's ([`Context::kinematics`]) with the active tool's TCP
//! ([`active_tcp`]). Runs in the gateway's async tasks, never in the cycle.

use super::{Context, Outcome, STATE_GRACE, bridge_error};
use mcm_kinematics::{IkError, Kinematics, KinematicsError, TcpError, isometry, tcp_transform};
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Axis, MoveAll};
use mcm_shared::config::RobotConfig;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::mode::CommandKind;
use mcm_shared::protocol::results::{Answer, ErrorOutcome, Generic, InverseKinematicsResult};
use mcm_shared::protocol::{Command, InverseKinematics, MoveToPose, Pose};
use mcm_shared::ranges::Num;
use mcm_shared::reply::Reason;
use mcm_shared::sample::{AXIS_CALIBRATED, StateSample};
use mcm_shared::tool::Tool;
use nalgebra::Isometry3;

/// The active tool: the one the core reports in `state`, the newest state (`set_tool`'s, or
/// the configuration's from start); the configured tool when there is no state yet (the core
/// starts with it).
pub(crate) fn active_tool(cfg: &RobotConfig, state: Option<&StateSample>) -> Tool {
    match state {
        Some(s) => Tool::from(&s.tool),
        None => cfg.arm.tool.active(),
    }
}

/// The TCP of the active tool ([`active_tool`]): its pose in the flange frame.
pub(crate) fn active_tcp(cfg: &RobotConfig, state: Option<&StateSample>) -> Isometry3<f64> {
    tcp_transform(&active_tool(cfg, state).tcp)
}

/// `inverse_kinematics`: every solution, the nearest to the seed first. Without a seed, the
/// present position of the newest state is the seed (waiting at most [`STATE_GRACE`] for one).
pub(crate) async fn inverse_kinematics(ctx: &Context, ik: &InverseKinematics) -> Outcome {
    let name = "inverse_kinematics";
    let state = match ik.seed_deg {
        Some(_) => ctx.bridge.latest_state(),
        None => match ctx.bridge.state_within(STATE_GRACE).await {
            Some(state) => Some(state),
            None => return Outcome::only(bridge_error(name, &ctx.bridge.unavailable())),
        },
    };
    let result = match solve(ctx, &ik.pose, ik.seed_deg, state.as_deref()) {
        Ok(solutions) => Answer::InverseKinematics(InverseKinematicsResult::new(solutions)),
        Err(refused) => Answer::Generic(refused.answer(name)),
    };
    Outcome {
        result: Some(result),
        state,
        mode_session: None,
    }
}

/// `move_to_pose`: control of the arm checked first (in the core's order), then the pose
/// solved from the present position, then the `move_all` of the nearest solution sent to the
/// core. Its refusals and failures name `move_to_pose` and the joint move it sent.
pub(crate) async fn move_to_pose(ctx: &Context, client_id: u64, m: &MoveToPose) -> Outcome {
    let name = "move_to_pose";
    let Some(state) = ctx.bridge.state_within(STATE_GRACE).await else {
        return Outcome::only(bridge_error(name, &ctx.bridge.unavailable()));
    };
    if let Err(reason) = super::control_of_the_arm(&state, client_id) {
        let mut refused = super::refused(ctx, CommandKind::MoveAll, reason, state);
        name_the_command(&mut refused, name, None);
        return refused;
    }
    let nearest = solve(ctx, &m.pose, None, Some(&state))
        .and_then(|solutions| solutions.first().copied().ok_or(PoseRefusal::NoneFound));
    let targets_deg = match nearest {
        Ok(targets) => targets,
        Err(refused) => {
            return Outcome {
                result: Some(Answer::Generic(refused.answer(name))),
                state: Some(state),
                mode_session: None,
            };
        }
    };
    let joint_move = Command::MoveAll(MoveAll {
        targets_deg,
        velocity_factor: m.velocity_factor,
    });
    let mut outcome = super::through_core(ctx, client_id, &joint_move).await;
    name_the_command(&mut outcome, name, Some(&targets_deg));
    outcome
}

/// An ERROR of the `move_all` that `command` sent (to `targets`) says so: the core's words
/// name the request it got.
fn name_the_command(outcome: &mut Outcome, command: &str, targets: Option<&[f64; NUM_AXES]>) {
    if let Some(Answer::Generic(g)) = &mut outcome.result
        && !g.is_ok()
    {
        let joint_move = match targets {
            Some(t) => format!(" (the joint move to {} deg)", shown(t)),
            None => String::new(),
        };
        g.error_message = Some(format!("{command}{joint_move}: {}", g.message()));
    }
}

/// Why a pose has no solution to answer or to move to.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub(crate) enum PoseRefusal {
    #[error("the configured arm has no inverse kinematics: {0}")]
    NoKinematics(KinematicsError),
    #[error("the active tool's TCP cannot be used: {0}")]
    Tcp(TcpError),
    /// The present position is the seed, and it is not known.
    #[error("{} (the present position is the seed)", Reason::NotCalibrated { axis: *axis })]
    NotCalibrated { axis: Axis },
    #[error("no state of the real-time core to take the present position from")]
    NoState,
    #[error(
        "position {} m, orientation {}: {error}",
        shown(&pose.position),
        shown(&pose.orientation)
    )]
    NoSolution { pose: Pose, error: IkError },
    /// The solver answered no solution and no reason (it always gives one or the other).
    #[error("unreachable: the inverse kinematics found no solution")]
    NoneFound,
}

impl PoseRefusal {
    /// Its `error_code`.
    pub(crate) fn code(&self) -> ErrorCode {
        match self {
            PoseRefusal::NoKinematics(_) => ErrorCode::NotAvailable,
            PoseRefusal::Tcp(_) => ErrorCode::InternalError,
            PoseRefusal::NotCalibrated { .. } => ErrorCode::NotCalibrated,
            PoseRefusal::NoState => ErrorCode::CoreUnavailable,
            PoseRefusal::NoSolution {
                error: IkError::NotFinite { .. },
                ..
            } => ErrorCode::InvalidArgument,
            PoseRefusal::NoSolution { .. } | PoseRefusal::NoneFound => ErrorCode::Unreachable,
        }
    }

    /// The ERROR answering `command` (refused: nothing was sent); a command that takes a
    /// `seed` is told it may give one instead of the present position.
    pub(crate) fn answer(&self, command: &str) -> Generic {
        let seed = matches!(self, PoseRefusal::NotCalibrated { .. })
            && mcm_shared::protocol::find(command).is_some_and(|d| d.arg("seed").is_some());
        Generic::answer_error(
            ErrorOutcome::Refused,
            self.code(),
            format!(
                "{command} refused: {self}{}",
                if seed { ", or give a `seed`" } else { "" }
            ),
        )
    }
}

/// The solutions [deg] for `pose`, the nearest to `seed_deg` (`None`: the present position of
/// `state`) first.
pub(crate) fn solve(
    ctx: &Context,
    pose: &Pose,
    seed_deg: Option<[f64; NUM_AXES]>,
    state: Option<&StateSample>,
) -> Result<Vec<[f64; NUM_AXES]>, PoseRefusal> {
    let mut kin: Kinematics = ctx.kinematics.clone().map_err(PoseRefusal::NoKinematics)?;
    kin.set_tcp(active_tcp(&ctx.cfg, state))
        .map_err(PoseRefusal::Tcp)?;
    let seed_deg = match (seed_deg, state) {
        (Some(seed), _) => seed,
        (None, Some(state)) => match uncalibrated(state) {
            None => state.position,
            Some(axis) => return Err(PoseRefusal::NotCalibrated { axis }),
        },
        // The callers wait for a state when they need one; none came.
        (None, None) => return Err(PoseRefusal::NoState),
    };
    let seed = seed_deg.map(f64::to_radians);
    match kin.inverse(&isometry(pose.position, pose.orientation), &seed) {
        Ok(solutions) => Ok(solutions.iter().map(|s| s.q.map(f64::to_degrees)).collect()),
        Err(error) => Err(PoseRefusal::NoSolution { pose: *pose, error }),
    }
}

/// The first axis that is not calibrated in `state`.
fn uncalibrated(state: &StateSample) -> Option<Axis> {
    let i = state
        .axis_flags
        .iter()
        .position(|f| f & AXIS_CALIBRATED == 0)?;
    Axis::ALL.get(i).copied()
}

/// `[a, b, c]` as the MCM writes numbers.
fn shown<const N: usize>(v: &[f64; N]) -> String {
    let parts: Vec<String> = v.iter().map(|x| Num(*x).to_string()).collect();
    format!("[{}]", parts.join(", "))
}

#[cfg(test)]
mod tests;
