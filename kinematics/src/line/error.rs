//! Why a straight line was refused: what was wrong, where on the path, the value and what is
//! allowed. Lengths in metres, angles in degrees.

use crate::IkError;
use core::fmt;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::ranges::Num;

/// A place on the path: the fraction of the way from the start (0) to the target (1) and the
/// TCP's position there (base frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPoint {
    pub fraction: f64,
    pub position: [f64; 3],
}

impl fmt::Display for PathPoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [x, y, z] = self.position;
        write!(
            f,
            "{} % of the path (the TCP at [{}, {}, {}] m)",
            Num(self.fraction * 100.0),
            Num(x),
            Num(y),
            Num(z)
        )
    }
}

/// One of the arm's singularities ([`crate::Singularities`]): the contract's, which the
/// core's refusal of a line carries.
pub use mcm_shared::reply::Singularity;

/// Why [`crate::LinePlan::plan`] refused a line; nothing has moved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LineError {
    /// The start configuration or the target is not made of finite numbers.
    #[error("the {what} has {value}; it needs finite numbers")]
    NotFinite { what: &'static str, value: f64 },
    /// The requested TCP speed or acceleration is outside what the planner accepts.
    #[error(
        "move_linear {name} = {} {unit} is not allowed: it needs more than 0 and at most {} \
         {unit}",
        Num(*.value),
        Num(*.max)
    )]
    Argument {
        name: &'static str,
        value: f64,
        max: f64,
        unit: &'static str,
    },
    /// An axis's limit given to the planner is not a finite value above 0.
    #[error("axis {axis}'s {name} limit is {value}; it needs a finite value above 0")]
    Limit {
        /// 1-based.
        axis: usize,
        name: &'static str,
        value: f64,
    },
    /// No configuration of the start's branch puts the TCP there.
    #[error("unreachable at {at}: {cause}")]
    Unreachable { at: PathPoint, cause: IkError },
    /// An axis would leave its reachable range.
    #[error(
        "out of range at {at}: axis {axis} would be at {} deg, outside its reachable range \
         {} to {} deg",
        Num(*.value_deg),
        Num(*.min_deg),
        Num(*.max_deg)
    )]
    OutOfRange {
        at: PathPoint,
        /// 1-based.
        axis: usize,
        value_deg: f64,
        min_deg: f64,
        max_deg: f64,
    },
    /// The path comes nearer to a singularity than its margin.
    #[error(
        "unreachable at {at}: the path comes within {} {} of the {singularity}; it must stay \
         at least {} {} away",
        Num(*.value),
        singularity.unit(),
        Num(*.margin),
        singularity.unit()
    )]
    Singular {
        at: PathPoint,
        singularity: Singularity,
        /// The measure there ([`Singularity::unit`]).
        value: f64,
        margin: f64,
    },
    /// The start's branch cannot follow the line continuously: an axis would jump.
    #[error(
        "unreachable at {at}: axis {axis} would jump by {} deg within {} % of the path, \
         where its rate allows at most {} deg; the arm cannot follow the line there in the \
         start's configuration",
        Num(*.step_deg),
        Num(*.within * 100.0),
        Num(*.allowed_deg)
    )]
    JointJump {
        at: PathPoint,
        /// 1-based.
        axis: usize,
        step_deg: f64,
        /// The share of the path the step is made in (0 to 1).
        within: f64,
        allowed_deg: f64,
    },
}

impl LineError {
    /// The protocol's `error_code`: `out_of_range` for an argument or an axis outside its
    /// range, `unreachable` for a path the arm cannot follow.
    pub fn error_code(&self) -> ErrorCode {
        match self {
            LineError::NotFinite { .. }
            | LineError::Argument { .. }
            | LineError::Limit { .. }
            | LineError::OutOfRange { .. } => ErrorCode::OutOfRange,
            LineError::Unreachable { .. }
            | LineError::Singular { .. }
            | LineError::JointJump { .. } => ErrorCode::Unreachable,
        }
    }

    /// Where on the path, for the errors found on it.
    pub fn at(&self) -> Option<PathPoint> {
        match self {
            LineError::NotFinite { .. } | LineError::Argument { .. } | LineError::Limit { .. } => {
                None
            }
            LineError::Unreachable { at, .. }
            | LineError::OutOfRange { at, .. }
            | LineError::Singular { at, .. }
            | LineError::JointJump { at, .. } => Some(*at),
        }
    }
}
