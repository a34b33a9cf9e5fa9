//! The typed answers of the real-time core: a [`Response`] to each request, the [`Reason`]
//! of every refusal, failure or safety trip, and the [`SafetyError`] record; each with the one
//! `encode`/`decode` pair that maps it onto the wire structs of [`crate::sample`].
//!
//! Nothing outside this module reads `Reply::values` or `ErrorRecord::values` by position.
//! Decoding checks every number, so an answer from another MCM version is a [`DecodeError`]
//! naming what was unknown, never a silent "no error". Encoding and decoding never allocate.
//!
//! ```
//! use mcm_shared::command::Axis;
//! use mcm_shared::mode::CommandKind;
//! use mcm_shared::reply::{Outcome, Reason, Response};
//! let r = Response {
//!     client_id: 1,
//!     request_id: 9,
//!     kind: CommandKind::MoveAxis,
//!     outcome: Outcome::Refused(Reason::Busy { remaining_s: 0.25 }),
//! };
//! assert_eq!(Response::decode(&r.encode()), Ok(r));
//! assert_eq!(
//!     Reason::NotCalibrated { axis: Axis::new(3).unwrap() }.to_string(),
//!     "axis 3 is not calibrated; run `calibrate` first"
//! );
//! ```

use crate::NUM_AXES;
use crate::command::{Axis, DecodeError};
use crate::mode::{CommandKind, Mode, RejectCode, ReplyStatus};
use crate::ranges::{Arg, ArgRefusal, Num};
use crate::sample::{CommandSample, ErrorRecord, Reply};
use core::fmt;

/// What a calibration that failed could not do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CalibrationFailure {
    /// No mechanical stop within the distance searched [deg].
    NoStop { searched_deg: f64 },
    /// No light-barrier edge within the distance searched [deg].
    NoEdge { searched_deg: f64 },
    /// The axis's drive stopped answering.
    DriveLost,
    /// Two approaches to the same stop or edge disagree by more than the tolerance: the first
    /// found it at `first_deg` (taken as the configured position), the last at `second_deg`
    /// in the same frame (a contact in free air, or a stop that gives way).
    Inconsistent {
        first_deg: f64,
        second_deg: f64,
        tolerance_deg: f64,
    },
    /// The stop or edge was found at `found_deg` in the frame of the axis's previous, valid
    /// calibration, more than the tolerance away from where the configuration puts it
    /// (`configured_deg`): an obstacle in the way, or a stop not where the configuration says.
    Implausible {
        found_deg: f64,
        configured_deg: f64,
        tolerance_deg: f64,
    },
    /// The axis fell `lag_deg` behind its search target, more than the search allows
    /// (`bound_deg`), and no contact was seen: something holds it (an obstacle) or it cannot
    /// move (a derated current), and its current did not show a stop. The search stopped
    /// there rather than let its target run on.
    Blocked { lag_deg: f64, bound_deg: f64 },
}

/// Which limit a PVT point breaks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PvtQuantity {
    Position,
    Velocity,
    Acceleration,
}

impl PvtQuantity {
    fn code(self) -> f64 {
        match self {
            PvtQuantity::Position => 1.0,
            PvtQuantity::Velocity => 2.0,
            PvtQuantity::Acceleration => 3.0,
        }
    }

    fn unit(self) -> &'static str {
        match self {
            PvtQuantity::Position => "deg",
            PvtQuantity::Velocity => "deg/s",
            PvtQuantity::Acceleration => "deg/s^2",
        }
    }

    fn name(self) -> &'static str {
        match self {
            PvtQuantity::Position => "position",
            PvtQuantity::Velocity => "velocity",
            PvtQuantity::Acceleration => "acceleration",
        }
    }
}

/// Why a command was refused or failed, or which safety check tripped, with its figures.
/// `Display` gives the words for a person: what was wrong, the value, and what is allowed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reason {
    /// Not allowed in the current mode.
    WrongMode {
        mode: Mode,
    },
    NotCalibrated {
        axis: Axis,
    },
    /// The emergency stop is pressed.
    EmergencyStop,
    /// The drive does not answer on the bus. `also`: bit `i` set for every further axis
    /// (index `i`) whose drive was lost in the same cycle, e.g. by a power cycle (0: only
    /// `axis`).
    DriveDisconnected {
        axis: Axis,
        also: u8,
    },
    /// A drive is in fault (`axis` unknown when the drive could not be told apart).
    DriveFault {
        axis: Option<Axis>,
        code: u16,
    },
    /// A value outside its allowed range (`axis`: the axis it belongs to, if any).
    OutOfRange {
        axis: Option<Axis>,
        value: f64,
        min: f64,
        max: f64,
    },
    /// An argument of the protocol ([`crate::ranges`]) outside its range: on the wire an
    /// `out_of_range` that carries the argument's code, worded exactly as the gateway words
    /// the same value.
    InvalidArgument(ArgRefusal),
    /// The command exists in the manual but this build does not implement it yet.
    NotAvailable,
    /// The command needs the simulated robot.
    NotSimulated,
    /// The PVT queue cannot take the batch; nothing was queued.
    QueueFull {
        offered: u32,
        free: u32,
    },
    PositionLimit {
        axis: Axis,
        position_deg: f64,
        limit_deg: f64,
    },
    VelocityLimit {
        axis: Axis,
        velocity_deg_s: f64,
        limit_deg_s: f64,
    },
    BrakingDistance {
        axis: Axis,
        stop_deg: f64,
        limit_deg: f64,
    },
    FollowingError {
        axis: Axis,
        error_deg: f64,
        band_deg: f64,
    },
    CalibrationFailed {
        axis: Axis,
        cause: CalibrationFailure,
    },
    /// Superseded by another command or a mode change before it finished.
    Aborted,
    /// A motion is in progress.
    Busy {
        remaining_s: f64,
    },
    /// A PVT point (1-based `point`) breaks a limit; nothing was queued.
    PvtPoint {
        axis: Axis,
        point: u32,
        quantity: PvtQuantity,
        value: f64,
        limit: f64,
    },
    /// The target is outside the reachable range (the limits less the safety margin).
    Unreachable {
        axis: Axis,
        target_deg: f64,
        min_deg: f64,
        max_deg: f64,
    },
    /// Another client controls the arm's motion: `owner` is its client id. The gateway names
    /// the owner in its words (peer address or client name).
    NotOwner {
        owner: u64,
    },
    /// The MCM is shutting down: the arm is being stopped and its drives disabled.
    ShuttingDown,
    /// An axis derated by i2t (its motor hot) needs more than its derated current to hold
    /// where it is: its current stood at the derated limit `limit_a` (it was `current_a`).
    /// The drives are powered off, so that the holding brakes hold the arm while the motor
    /// cools.
    Overload {
        axis: Axis,
        current_a: f64,
        limit_a: f64,
    },
}

/// The wire form of a reason: its code, axis (0: none) and figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WireReason {
    pub code: RejectCode,
    pub axis: u32,
    pub values: [f64; 4],
}

impl Reason {
    /// The code naming this reason (and the safety check, for trips).
    pub fn code(&self) -> RejectCode {
        self.to_wire().code
    }

    /// The axis it concerns, if any.
    pub fn axis(&self) -> Option<Axis> {
        match *self {
            Reason::NotCalibrated { axis }
            | Reason::DriveDisconnected { axis, .. }
            | Reason::PositionLimit { axis, .. }
            | Reason::VelocityLimit { axis, .. }
            | Reason::BrakingDistance { axis, .. }
            | Reason::FollowingError { axis, .. }
            | Reason::Overload { axis, .. }
            | Reason::CalibrationFailed { axis, .. }
            | Reason::PvtPoint { axis, .. }
            | Reason::Unreachable { axis, .. } => Some(axis),
            Reason::DriveFault { axis, .. } | Reason::OutOfRange { axis, .. } => axis,
            Reason::InvalidArgument(r) => r.axis,
            _ => None,
        }
    }

    /// The argument refused, when this reason is a value of an argument of `kind` outside its
    /// range: an [`Reason::InvalidArgument`], or an [`Reason::Unreachable`] target of
    /// `move_axis` (`target_position`) or `move_all` (`target_positions[i]`). The gateway words
    /// these as it words its own refusal of the same value (`move_axis: argument ...`).
    pub fn argument(&self, kind: CommandKind) -> Option<ArgRefusal> {
        match *self {
            Reason::InvalidArgument(r) => Some(r),
            Reason::Unreachable {
                axis,
                target_deg,
                min_deg,
                max_deg,
            } => {
                let arg = match kind {
                    CommandKind::MoveAxis => Arg::TargetPosition,
                    CommandKind::MoveAll => Arg::TargetPositions,
                    _ => return None,
                };
                Some(ArgRefusal {
                    arg,
                    axis: Some(axis),
                    value: target_deg,
                    min: min_deg,
                    max: max_deg,
                })
            }
            _ => None,
        }
    }

    /// The code of the core's refusal of a value of `arg` outside its range, which is worded
    /// as the argument ([`Reason::argument`]): `unreachable` for a target position,
    /// `out_of_range` (an [`Reason::InvalidArgument`]) for every other argument.
    pub fn argument_code(arg: Arg) -> RejectCode {
        match arg {
            Arg::TargetPosition | Arg::TargetPositions => RejectCode::Unreachable,
            _ => RejectCode::OutOfRange,
        }
    }

    /// The wire form.
    pub fn to_wire(&self) -> WireReason {
        let w = |code, axis: Option<Axis>, values| WireReason {
            code,
            axis: Axis::to_wire(axis),
            values,
        };
        let a = Some;
        match *self {
            Reason::WrongMode { mode } => w(
                RejectCode::WrongMode,
                None,
                [f64::from(mode.to_wire()), 0.0, 0.0, 0.0],
            ),
            Reason::NotCalibrated { axis } => w(RejectCode::NotCalibrated, a(axis), [0.0; 4]),
            Reason::EmergencyStop => w(RejectCode::EmergencyStop, None, [0.0; 4]),
            Reason::DriveDisconnected { axis, also } => w(
                RejectCode::DriveDisconnected,
                a(axis),
                [f64::from(also), 0.0, 0.0, 0.0],
            ),
            Reason::DriveFault { axis, code } => w(
                RejectCode::DriveFault,
                axis,
                [f64::from(code), 0.0, 0.0, 0.0],
            ),
            Reason::OutOfRange {
                axis,
                value,
                min,
                max,
            } => w(RejectCode::OutOfRange, axis, [value, min, max, 0.0]),
            Reason::InvalidArgument(r) => w(
                RejectCode::OutOfRange,
                r.axis,
                [r.value, r.min, r.max, f64::from(r.arg as u8)],
            ),
            Reason::NotAvailable => w(RejectCode::NotAvailable, None, [0.0; 4]),
            Reason::NotSimulated => w(RejectCode::NotSimulated, None, [0.0; 4]),
            Reason::QueueFull { offered, free } => w(
                RejectCode::QueueFull,
                None,
                [f64::from(offered), f64::from(free), 0.0, 0.0],
            ),
            Reason::PositionLimit {
                axis,
                position_deg,
                limit_deg,
            } => w(
                RejectCode::PositionLimit,
                a(axis),
                [position_deg, limit_deg, 0.0, 0.0],
            ),
            Reason::VelocityLimit {
                axis,
                velocity_deg_s,
                limit_deg_s,
            } => w(
                RejectCode::VelocityLimit,
                a(axis),
                [velocity_deg_s, limit_deg_s, 0.0, 0.0],
            ),
            Reason::BrakingDistance {
                axis,
                stop_deg,
                limit_deg,
            } => w(
                RejectCode::BrakingDistance,
                a(axis),
                [stop_deg, limit_deg, 0.0, 0.0],
            ),
            Reason::FollowingError {
                axis,
                error_deg,
                band_deg,
            } => w(
                RejectCode::FollowingError,
                a(axis),
                [error_deg, band_deg, 0.0, 0.0],
            ),
            Reason::Overload {
                axis,
                current_a,
                limit_a,
            } => w(
                RejectCode::Overload,
                a(axis),
                [current_a, limit_a, 0.0, 0.0],
            ),
            Reason::CalibrationFailed { axis, cause } => {
                let values = match cause {
                    CalibrationFailure::NoStop { searched_deg } => [1.0, searched_deg, 0.0, 0.0],
                    CalibrationFailure::NoEdge { searched_deg } => [2.0, searched_deg, 0.0, 0.0],
                    CalibrationFailure::DriveLost => [3.0, 0.0, 0.0, 0.0],
                    CalibrationFailure::Inconsistent {
                        first_deg,
                        second_deg,
                        tolerance_deg,
                    } => [4.0, first_deg, second_deg, tolerance_deg],
                    CalibrationFailure::Implausible {
                        found_deg,
                        configured_deg,
                        tolerance_deg,
                    } => [5.0, found_deg, configured_deg, tolerance_deg],
                    CalibrationFailure::Blocked { lag_deg, bound_deg } => {
                        [6.0, lag_deg, bound_deg, 0.0]
                    }
                };
                w(RejectCode::CalibrationFailed, a(axis), values)
            }
            Reason::Aborted => w(RejectCode::Aborted, None, [0.0; 4]),
            Reason::Busy { remaining_s } => w(RejectCode::Busy, None, [remaining_s, 0.0, 0.0, 0.0]),
            Reason::PvtPoint {
                axis,
                point,
                quantity,
                value,
                limit,
            } => w(
                RejectCode::PvtPoint,
                a(axis),
                [f64::from(point), quantity.code(), value, limit],
            ),
            Reason::Unreachable {
                axis,
                target_deg,
                min_deg,
                max_deg,
            } => w(
                RejectCode::Unreachable,
                a(axis),
                [target_deg, min_deg, max_deg, 0.0],
            ),
            // A client id does not fit an f64's 53-bit mantissa: it travels as two halves.
            Reason::NotOwner { owner } => w(
                RejectCode::NotOwner,
                None,
                [(owner >> 32) as f64, (owner & 0xFFFF_FFFF) as f64, 0.0, 0.0],
            ),
            Reason::ShuttingDown => w(RejectCode::ShuttingDown, None, [0.0; 4]),
        }
    }

    /// The reason a wire code, axis and figures stand for. `RejectCode::None` is no reason.
    pub fn from_wire(code: u32, axis: u32, values: &[f64; 4]) -> Result<Reason, DecodeError> {
        let code = RejectCode::try_from(code).map_err(|e| DecodeError::Unknown {
            what: e.what,
            value: e.value,
        })?;
        let axis = Axis::from_wire(axis).map_err(|value| DecodeError::Unknown {
            what: "axis",
            value,
        })?;
        let need = |axis: Option<Axis>| {
            axis.ok_or(DecodeError::Unknown {
                what: "axis (missing) of reason",
                value: code.to_wire(),
            })
        };
        let whole = |x: f64, what: &'static str| -> Result<u32, DecodeError> {
            if x.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&x) {
                Ok(x as u32)
            } else {
                Err(DecodeError::Unknown {
                    what,
                    value: x as u32,
                })
            }
        };
        let [v0, v1, v2, v3] = *values;
        Ok(match code {
            RejectCode::None => {
                return Err(DecodeError::Unknown {
                    what: "reason (none given) of a refusal",
                    value: 0,
                });
            }
            RejectCode::WrongMode => {
                let m = whole(v0, "mode")?;
                Reason::WrongMode {
                    mode: Mode::try_from(m).map_err(|e| DecodeError::Unknown {
                        what: e.what,
                        value: e.value,
                    })?,
                }
            }
            RejectCode::NotCalibrated => Reason::NotCalibrated { axis: need(axis)? },
            RejectCode::EmergencyStop => Reason::EmergencyStop,
            RejectCode::DriveDisconnected => Reason::DriveDisconnected {
                axis: need(axis)?,
                also: u8::try_from(whole(v0, "axes also lost")?)
                    .ok()
                    .filter(|m| *m < 1 << NUM_AXES)
                    .ok_or(DecodeError::Unknown {
                        what: "axes also lost",
                        value: v0 as u32,
                    })?,
            },
            RejectCode::DriveFault => Reason::DriveFault {
                axis,
                code: u16::try_from(whole(v0, "drive error code")?).map_err(|_| {
                    DecodeError::Unknown {
                        what: "drive error code",
                        value: v0 as u32,
                    }
                })?,
            },
            RejectCode::OutOfRange if v3 == 0.0 => Reason::OutOfRange {
                axis,
                value: v0,
                min: v1,
                max: v2,
            },
            RejectCode::OutOfRange => {
                let code = whole(v3, "argument code")?;
                Reason::InvalidArgument(ArgRefusal {
                    arg: Arg::from_code(code).ok_or(DecodeError::Unknown {
                        what: "argument code",
                        value: code,
                    })?,
                    axis,
                    value: v0,
                    min: v1,
                    max: v2,
                })
            }
            RejectCode::NotAvailable => Reason::NotAvailable,
            RejectCode::NotSimulated => Reason::NotSimulated,
            RejectCode::QueueFull => Reason::QueueFull {
                offered: whole(v0, "points offered")?,
                free: whole(v1, "free places")?,
            },
            RejectCode::PositionLimit => Reason::PositionLimit {
                axis: need(axis)?,
                position_deg: v0,
                limit_deg: v1,
            },
            RejectCode::VelocityLimit => Reason::VelocityLimit {
                axis: need(axis)?,
                velocity_deg_s: v0,
                limit_deg_s: v1,
            },
            RejectCode::BrakingDistance => Reason::BrakingDistance {
                axis: need(axis)?,
                stop_deg: v0,
                limit_deg: v1,
            },
            RejectCode::FollowingError => Reason::FollowingError {
                axis: need(axis)?,
                error_deg: v0,
                band_deg: v1,
            },
            RejectCode::Overload => Reason::Overload {
                axis: need(axis)?,
                current_a: v0,
                limit_a: v1,
            },
            RejectCode::CalibrationFailed => Reason::CalibrationFailed {
                axis: need(axis)?,
                cause: match whole(v0, "calibration failure")? {
                    1 => CalibrationFailure::NoStop { searched_deg: v1 },
                    2 => CalibrationFailure::NoEdge { searched_deg: v1 },
                    3 => CalibrationFailure::DriveLost,
                    4 => CalibrationFailure::Inconsistent {
                        first_deg: v1,
                        second_deg: v2,
                        tolerance_deg: v3,
                    },
                    5 => CalibrationFailure::Implausible {
                        found_deg: v1,
                        configured_deg: v2,
                        tolerance_deg: v3,
                    },
                    6 => CalibrationFailure::Blocked {
                        lag_deg: v1,
                        bound_deg: v2,
                    },
                    n => {
                        return Err(DecodeError::Unknown {
                            what: "calibration failure",
                            value: n,
                        });
                    }
                },
            },
            RejectCode::Aborted => Reason::Aborted,
            RejectCode::Busy => Reason::Busy { remaining_s: v0 },
            RejectCode::PvtPoint => Reason::PvtPoint {
                axis: need(axis)?,
                point: whole(v0, "PVT point number")?,
                quantity: match whole(v1, "PVT quantity")? {
                    1 => PvtQuantity::Position,
                    2 => PvtQuantity::Velocity,
                    3 => PvtQuantity::Acceleration,
                    n => {
                        return Err(DecodeError::Unknown {
                            what: "PVT quantity",
                            value: n,
                        });
                    }
                },
                value: v2,
                limit: v3,
            },
            RejectCode::Unreachable => Reason::Unreachable {
                axis: need(axis)?,
                target_deg: v0,
                min_deg: v1,
                max_deg: v2,
            },
            RejectCode::NotOwner => Reason::NotOwner {
                owner: (u64::from(whole(v0, "owner (high half)")?) << 32)
                    | u64::from(whole(v1, "owner (low half)")?),
            },
            RejectCode::ShuttingDown => Reason::ShuttingDown,
        })
    }
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Reason::WrongMode { mode } => write!(f, "not allowed in mode {mode}"),
            Reason::NotCalibrated { axis } => {
                write!(f, "axis {axis} is not calibrated; run `calibrate` first")
            }
            Reason::EmergencyStop => {
                f.write_str("the emergency stop is pressed; release it, then send `hold`")
            }
            Reason::DriveDisconnected { axis, also } => {
                let more = also & !(1 << axis.index());
                if more == 0 {
                    return write!(f, "the drive of axis {axis} does not answer on the bus");
                }
                let all = more | 1 << axis.index();
                let n = all.count_ones();
                f.write_str("the drives of axes ")?;
                for (k, a) in Axis::ALL
                    .iter()
                    .filter(|a| all & 1 << a.index() != 0)
                    .enumerate()
                {
                    let sep = match k {
                        0 => "",
                        _ if k + 1 == n as usize => " and ",
                        _ => ", ",
                    };
                    write!(f, "{sep}{a}")?;
                }
                f.write_str(" do not answer on the bus")
            }
            Reason::DriveFault { axis, code } => match axis {
                Some(axis) => write!(
                    f,
                    "the drive of axis {axis} is in fault (error code 0x{code:04X})"
                ),
                None => write!(f, "a drive is in fault (error code 0x{code:04X})"),
            },
            Reason::OutOfRange {
                axis,
                value,
                min,
                max,
            } => {
                if let Some(axis) = axis {
                    write!(f, "axis {axis}: ")?;
                }
                if min == f64::MIN && max == f64::MAX {
                    return write!(
                        f,
                        "value {} is not allowed; expected a finite number",
                        Num(value)
                    );
                }
                write!(
                    f,
                    "value {} is outside the allowed range [{}, {}]",
                    Num(value),
                    Num(min),
                    Num(max)
                )
            }
            Reason::InvalidArgument(r) => write!(f, "{r}"),
            Reason::NotAvailable => f.write_str("not available yet in this MCM version"),
            Reason::NotSimulated => {
                f.write_str("only available when the simulated robot is running")
            }
            Reason::QueueFull { offered, free } => write!(
                f,
                "queue full: {offered} points offered, {free} places free; nothing was queued"
            ),
            Reason::PositionLimit {
                axis,
                position_deg,
                limit_deg,
            } => write!(
                f,
                "position limit: axis {axis} at {position_deg:.3} deg, limit {limit_deg:.3} deg"
            ),
            Reason::VelocityLimit {
                axis,
                velocity_deg_s,
                limit_deg_s,
            } => write!(
                f,
                "velocity limit: axis {axis} at {velocity_deg_s:.3} deg/s, limit {limit_deg_s:.3} deg/s"
            ),
            Reason::BrakingDistance {
                axis,
                stop_deg,
                limit_deg,
            } => write!(
                f,
                "braking distance: axis {axis} would stop at {stop_deg:.3} deg, beyond the limit {limit_deg:.3} deg"
            ),
            Reason::FollowingError {
                axis,
                error_deg,
                band_deg,
            } => write!(
                f,
                "following error: axis {axis} is {error_deg:.3} deg away from its commanded position, band {band_deg:.3} deg"
            ),
            Reason::Overload {
                axis,
                current_a,
                limit_a,
            } => write!(
                f,
                "overload: axis {axis} cannot hold with its derated current of {limit_a:.2} A (its motor is hot, i2t; current {current_a:.2} A): the drives of the axes with a brake are powered off and the brakes hold the arm; send hold once the motor has cooled"
            ),
            Reason::CalibrationFailed { axis, cause } => match cause {
                CalibrationFailure::NoStop { searched_deg } => write!(
                    f,
                    "calibration of axis {axis} failed: no mechanical stop found within {searched_deg:.1} deg; the arm holds where it is"
                ),
                CalibrationFailure::NoEdge { searched_deg } => write!(
                    f,
                    "calibration of axis {axis} failed: no light-barrier edge found within {searched_deg:.1} deg; the arm holds where it is"
                ),
                CalibrationFailure::DriveLost => write!(
                    f,
                    "calibration of axis {axis} failed: its drive stopped answering"
                ),
                CalibrationFailure::Inconsistent {
                    first_deg,
                    second_deg,
                    tolerance_deg,
                } => write!(
                    f,
                    "calibration of axis {axis} failed: its reference was found at {first_deg:.3} deg (the configured position), then at {second_deg:.3} deg by the next approach, more than the tolerance {tolerance_deg:.3} deg apart (a contact in free air, or a stop that gives way); the arm holds where it is, its previous calibration is kept"
                ),
                CalibrationFailure::Implausible {
                    found_deg,
                    configured_deg,
                    tolerance_deg,
                } => write!(
                    f,
                    "calibration of axis {axis} failed: its reference was found at {found_deg:.3} deg by its previous calibration, configured at {configured_deg:.3} deg, more than the tolerance {tolerance_deg:.3} deg apart (an obstacle in the way now or during the previous calibration, or the stop is not where the configuration says); the arm holds where it is, and axis {axis} is no longer calibrated: one of the two calibrations is wrong; remove what may be in the way and calibrate again"
                ),
                CalibrationFailure::Blocked { lag_deg, bound_deg } => write!(
                    f,
                    "calibration of axis {axis} failed: it stayed {lag_deg:.3} deg behind its search target, more than the {bound_deg:.3} deg allowed, without a contact seen (an obstacle holds it, or it cannot move: derated current); the arm holds where it is, its previous calibration is kept"
                ),
            },
            Reason::Aborted => {
                f.write_str("aborted (superseded by another command or a mode change)")
            }
            Reason::Busy { remaining_s } => write!(
                f,
                "a motion is in progress ({remaining_s:.3} s left); wait until it ends, or send `hold` to stop it"
            ),
            Reason::PvtPoint {
                axis,
                point,
                quantity,
                value,
                limit,
            } => {
                let (what, unit) = (quantity.name(), quantity.unit());
                write!(
                    f,
                    "point {point}: axis {axis} {what} {} {unit} exceeds the limit {} {unit}; nothing was queued",
                    Num(value),
                    Num(limit)
                )
            }
            Reason::Unreachable {
                axis,
                target_deg,
                min_deg,
                max_deg,
            } => write!(
                f,
                "axis {axis}: target {} deg is not allowed; expected {}",
                Num(target_deg),
                Arg::TargetPosition.expected(min_deg, max_deg)
            ),
            Reason::NotOwner { owner } => write!(
                f,
                "another client (id {owner:#x}) controls the arm; only `hold` and state reads are open to others until it releases control or disconnects"
            ),
            Reason::ShuttingDown => f.write_str(
                "the MCM is shutting down: the arm is being stopped and its drives disabled",
            ),
        }
    }
}

/// The move a `move_all` planned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveAllPlan {
    /// Peak velocity of each axis [deg/s].
    pub velocities_deg_s: [f64; NUM_AXES],
    /// The axis that needs the longest (it sets the pace of the others).
    pub longest: Axis,
    /// Time from now to arrival [s].
    pub duration_s: f64,
}

/// What the core says about itself in answer to `info`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InfoReply {
    pub num_axes: u32,
    /// Cycle period [s].
    pub period_s: f64,
}

/// What a command that succeeded answers: most say only "done" ([`Done::Ack`]); `info` and
/// `move_all` carry figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Done {
    Ack,
    Info(InfoReply),
    MoveAll(MoveAllPlan),
}

/// How the core answered a request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome {
    /// Done (or accepted, for commands that start a motion).
    Done(Done),
    /// Refused; nothing changed.
    Refused(Reason),
    /// Accepted, but failed while running (e.g. a calibration that found no stop).
    Failed(Reason),
}

/// The answer to one request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Response {
    pub client_id: u64,
    pub request_id: u64,
    /// The kind of the request answered.
    pub kind: CommandKind,
    pub outcome: Outcome,
}

impl Response {
    /// The wire form (`seq` 0: the reply ring numbers it).
    pub fn encode(&self) -> Reply {
        let mut r = Reply {
            client_id: self.client_id,
            request_id: self.request_id,
            kind: self.kind.to_wire(),
            ..Reply::default()
        };
        let reason = match self.outcome {
            Outcome::Done(done) => {
                r.status = ReplyStatus::Ok.to_wire();
                match done {
                    Done::Ack => {}
                    Done::Info(i) => {
                        r.values[0] = f64::from(i.num_axes);
                        r.values[1] = i.period_s;
                    }
                    Done::MoveAll(p) => {
                        r.values[..NUM_AXES].copy_from_slice(&p.velocities_deg_s);
                        r.values[NUM_AXES] = f64::from(p.longest.number());
                        r.values[NUM_AXES + 1] = p.duration_s;
                    }
                }
                return r;
            }
            Outcome::Refused(reason) => {
                r.status = ReplyStatus::Rejected.to_wire();
                reason
            }
            Outcome::Failed(reason) => {
                r.status = ReplyStatus::Failed.to_wire();
                reason
            }
        };
        let w = reason.to_wire();
        r.code = w.code.to_wire();
        r.axis = w.axis;
        r.values[..4].copy_from_slice(&w.values);
        r
    }

    /// The typed answer a wire reply stands for.
    pub fn decode(r: &Reply) -> Result<Response, DecodeError> {
        let kind = CommandKind::try_from(r.kind).map_err(|_| DecodeError::UnknownKind(r.kind))?;
        let status = ReplyStatus::try_from(r.status).map_err(|e| DecodeError::Unknown {
            what: e.what,
            value: e.value,
        })?;
        let reason = || {
            let v = &r.values;
            Reason::from_wire(r.code, r.axis, &[v[0], v[1], v[2], v[3]])
        };
        let outcome = match status {
            ReplyStatus::Ok => Outcome::Done(match kind {
                CommandKind::Info => Done::Info(InfoReply {
                    num_axes: r.values[0] as u32,
                    period_s: r.values[1],
                }),
                CommandKind::MoveAll => {
                    let v = &r.values;
                    let longest = v[NUM_AXES];
                    let longest = (longest.fract() == 0.0 && (1.0..=6.0).contains(&longest))
                        .then(|| Axis::new(longest as u8))
                        .flatten()
                        .ok_or(DecodeError::Mismatch {
                            kind,
                            problem: "the longest axis is not 1 to 6",
                        })?;
                    let mut velocities_deg_s = [0.0; NUM_AXES];
                    velocities_deg_s.copy_from_slice(&v[..NUM_AXES]);
                    Done::MoveAll(MoveAllPlan {
                        velocities_deg_s,
                        longest,
                        duration_s: v[NUM_AXES + 1],
                    })
                }
                _ => Done::Ack,
            }),
            ReplyStatus::Rejected => Outcome::Refused(reason()?),
            ReplyStatus::Failed => Outcome::Failed(reason()?),
        };
        Ok(Response {
            client_id: r.client_id,
            request_id: r.request_id,
            kind,
            outcome,
        })
    }
}

/// The wire reply refusing a sample that did not decode: the sample's own (possibly unknown)
/// kind and ids, status `REJECTED`, and the fault as `OutOfRange` naming the value and the
/// allowed bounds (an unknown kind as its number against the known range); a value of a
/// protocol argument out of its range ([`crate::ranges`]) as [`Reason::InvalidArgument`].
pub fn refuse_undecodable(sample: &CommandSample, e: &DecodeError) -> Reply {
    if let DecodeError::Invalid {
        field,
        value,
        allowed,
        ..
    } = *e
        && let Some(arg) = Arg::by_name(field.name)
        && !matches!(allowed, crate::command::Allowed::Finite)
    {
        let (min, max) = allowed.bounds();
        let axis = field.axis();
        return refusal_reply(
            sample,
            Reason::InvalidArgument(ArgRefusal {
                arg,
                axis,
                value,
                min,
                max,
            }),
        );
    }
    let (axis, value, (min, max)) = match *e {
        DecodeError::Invalid {
            field,
            value,
            allowed,
            ..
        } => (field.axis(), value, allowed.bounds()),
        DecodeError::UnknownKind(kind) => (
            None,
            f64::from(kind),
            (
                f64::from(CommandKind::ALL[0].to_wire()),
                f64::from(CommandKind::ALL[CommandKind::ALL.len() - 1].to_wire()),
            ),
        ),
        DecodeError::Unknown { value, .. } => (None, f64::from(value), (0.0, 0.0)),
        DecodeError::Mismatch { .. } => (None, 0.0, (0.0, 0.0)),
    };
    refusal_reply(
        sample,
        Reason::OutOfRange {
            axis,
            value,
            min,
            max,
        },
    )
}

fn refusal_reply(sample: &CommandSample, reason: Reason) -> Reply {
    let w = reason.to_wire();
    let mut r = Reply {
        client_id: sample.client_id,
        request_id: sample.request_id,
        kind: sample.kind,
        status: ReplyStatus::Rejected.to_wire(),
        code: w.code.to_wire(),
        axis: w.axis,
        ..Reply::default()
    };
    r.values[..4].copy_from_slice(&w.values);
    r
}

/// A safety violation or drive error, as the core reports it to every client once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SafetyError {
    /// Increments with every new error (1, 2, ...).
    pub seq: u64,
    /// Cycle in which it tripped.
    pub cycle: u64,
    /// `CLOCK_REALTIME` of that cycle [ns since the Unix epoch].
    pub unix_ns: u64,
    /// The check that tripped and its figures.
    pub reason: Reason,
}

impl SafetyError {
    /// The wire record.
    pub fn encode(&self) -> ErrorRecord {
        let w = self.reason.to_wire();
        ErrorRecord {
            seq: self.seq,
            cycle: self.cycle,
            unix_ns: self.unix_ns,
            code: w.code.to_wire(),
            axis: w.axis,
            values: w.values,
        }
    }

    /// The error a wire record stands for; `Ok(None)` for the empty record (`seq` 0: no error
    /// since start).
    pub fn decode(e: &ErrorRecord) -> Result<Option<SafetyError>, DecodeError> {
        if e.seq == 0 {
            return Ok(None);
        }
        Ok(Some(SafetyError {
            seq: e.seq,
            cycle: e.cycle,
            unix_ns: e.unix_ns,
            reason: Reason::from_wire(e.code, e.axis, &e.values)?,
        }))
    }
}

mod words;
pub use words::OutcomeWords;

#[cfg(test)]
mod tests;
