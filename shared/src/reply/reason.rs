//! Every reason the real-time core gives, defined once in `reasons!` below: its fields, where
//! each travels in the wire form ([`WireReason`]: the axis, or a slot of the four figures), its
//! code ([`RejectCode`], named in [`crate::error_code`]) and its words. `Reason`,
//! `Reason::to_wire`, `Reason::from_wire` and `Display` are derived from that one entry, so a
//! new reason (or safety check) is one entry there and one row in the table of error codes;
//! the compiler refuses a code without a reason.
//!
//! Encoding, decoding and `Reason::code` never allocate (used inside the cycle); `Display` is
//! not.

use crate::NUM_AXES;
use crate::command::{Axis, DecodeError};
use crate::error_code::ErrorCode;
use crate::mode::{CommandKind, Mode, RejectCode};
use crate::ranges::{Arg, ArgRefusal, Num};
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

/// One of the arm's singularities, in a [`LineFault`] (`Display`: its words).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Singularity {
    /// Axes 4 and 6 aligned (measured in degrees).
    Wrist,
    /// The arm stretched or folded (measured in degrees).
    Elbow,
    /// The wrist centre on axis 1 (measured in metres).
    Shoulder,
}

impl Singularity {
    /// The unit of its measure: degrees, or metres for the shoulder.
    pub fn unit(self) -> &'static str {
        match self {
            Singularity::Wrist | Singularity::Elbow => "deg",
            Singularity::Shoulder => "m",
        }
    }
}

impl fmt::Display for Singularity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Singularity::Wrist => "wrist singularity (axes 4 and 6 aligned)",
            Singularity::Elbow => "elbow singularity (the arm stretched or folded)",
            Singularity::Shoulder => "shoulder singularity (the wrist centre on axis 1)",
        })
    }
}

/// Where and why the straight line of a `move_linear` cannot be followed: `fraction` is the
/// share of the path from the start (0) to the target (1) where the planner found it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LineFault {
    /// No configuration of the start's branch puts the TCP there (beyond the reach).
    NoSolution { fraction: f64 },
    /// The path comes within `value` of a singularity whose margin is `margin` (its unit).
    Singular {
        fraction: f64,
        singularity: Singularity,
        value: f64,
        margin: f64,
    },
    /// The reason's axis would jump by `step_deg` where its rate allows at most `allowed_deg`.
    JointJump {
        fraction: f64,
        step_deg: f64,
        allowed_deg: f64,
    },
    /// The reason's axis would be at `value_deg`, beyond its reachable range's end `limit_deg`.
    OutOfRange {
        fraction: f64,
        value_deg: f64,
        limit_deg: f64,
    },
}

/// The first number of a [`LineFault`]'s kind in the last slot: above every argument code
/// (`u8`) of an [`Reason::InvalidArgument`] and never 0, so the faults of a line share the
/// codes `unreachable` and `out_of_range` with the joint moves' reasons and stay told apart.
const LINE_FAULT_BASE: f64 = 256.0;

impl LineFault {
    /// The share of the path where it was found.
    pub fn fraction(&self) -> f64 {
        match *self {
            LineFault::NoSolution { fraction }
            | LineFault::Singular { fraction, .. }
            | LineFault::JointJump { fraction, .. }
            | LineFault::OutOfRange { fraction, .. } => fraction,
        }
    }
}

/// Four slots from `at`: the fraction, two figures, then the kind from [`LINE_FAULT_BASE`].
impl Field for LineFault {
    fn put(self, w: &mut WireReason, at: usize) {
        let (kind, x, y) = match self {
            LineFault::NoSolution { .. } => (1.0, 0.0, 0.0),
            LineFault::Singular {
                singularity,
                value,
                margin,
                ..
            } => {
                let k = match singularity {
                    Singularity::Wrist => 2.0,
                    Singularity::Elbow => 3.0,
                    Singularity::Shoulder => 4.0,
                };
                (k, value, margin)
            }
            LineFault::JointJump {
                step_deg,
                allowed_deg,
                ..
            } => (5.0, step_deg, allowed_deg),
            LineFault::OutOfRange {
                value_deg,
                limit_deg,
                ..
            } => (6.0, value_deg, limit_deg),
        };
        let v = [self.fraction(), x, y, LINE_FAULT_BASE + kind];
        w.values[at..at + 4].copy_from_slice(&v);
    }
    fn take(w: &WireReason, at: usize, _: &'static str) -> Result<Self, DecodeError> {
        let [fraction, x, y] = [w.values[at], w.values[at + 1], w.values[at + 2]];
        let singular = |singularity| LineFault::Singular {
            fraction,
            singularity,
            value: x,
            margin: y,
        };
        let kind = whole(w.values[at + 3] - LINE_FAULT_BASE, "line fault")?;
        Ok(match kind {
            1 => LineFault::NoSolution { fraction },
            2 => singular(Singularity::Wrist),
            3 => singular(Singularity::Elbow),
            4 => singular(Singularity::Shoulder),
            5 => LineFault::JointJump {
                fraction,
                step_deg: x,
                allowed_deg: y,
            },
            6 => LineFault::OutOfRange {
                fraction,
                value_deg: x,
                limit_deg: y,
            },
            n => {
                return Err(DecodeError::Unknown {
                    what: "line fault",
                    value: n,
                });
            }
        })
    }
}

/// The wire form of a reason: its code, axis (0: none) and figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WireReason {
    pub code: RejectCode,
    pub axis: u32,
    pub values: [f64; 4],
}

/// Where a field of a reason travels: `@ axis` (the wire form's axis) or `@ i` (its figures
/// from slot `i` on); `what` names the figure in a [`DecodeError`].
trait Field: Sized {
    fn put(self, w: &mut WireReason, at: usize);
    fn take(w: &WireReason, at: usize, what: &'static str) -> Result<Self, DecodeError>;
}

/// The slot of `@ axis`: the wire form's `axis`, not a figure.
const AXIS: usize = usize::MAX;

/// A figure that must be a whole number (a count, a code) within `u32`.
fn whole(x: f64, what: &'static str) -> Result<u32, DecodeError> {
    if x.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&x) {
        Ok(x as u32)
    } else {
        Err(DecodeError::Unknown {
            what,
            value: x as u32,
        })
    }
}

impl Field for f64 {
    fn put(self, w: &mut WireReason, at: usize) {
        w.values[at] = self;
    }
    fn take(w: &WireReason, at: usize, _: &'static str) -> Result<f64, DecodeError> {
        Ok(w.values[at])
    }
}

impl Field for u32 {
    fn put(self, w: &mut WireReason, at: usize) {
        w.values[at] = f64::from(self);
    }
    fn take(w: &WireReason, at: usize, what: &'static str) -> Result<u32, DecodeError> {
        whole(w.values[at], what)
    }
}

impl Field for u16 {
    fn put(self, w: &mut WireReason, at: usize) {
        w.values[at] = f64::from(self);
    }
    fn take(w: &WireReason, at: usize, what: &'static str) -> Result<u16, DecodeError> {
        let x = w.values[at];
        u16::try_from(whole(x, what)?).map_err(|_| DecodeError::Unknown {
            what,
            value: x as u32,
        })
    }
}

/// A set of axes (bit `i`: axis `i + 1`), the only `u8` of a reason.
impl Field for u8 {
    fn put(self, w: &mut WireReason, at: usize) {
        w.values[at] = f64::from(self);
    }
    fn take(w: &WireReason, at: usize, what: &'static str) -> Result<u8, DecodeError> {
        let x = w.values[at];
        u8::try_from(whole(x, what)?)
            .ok()
            .filter(|m| *m < 1 << NUM_AXES)
            .ok_or(DecodeError::Unknown {
                what,
                value: x as u32,
            })
    }
}

/// A client id: it does not fit an f64's 53-bit mantissa, so it travels as two halves (slots
/// `at` and `at + 1`).
impl Field for u64 {
    fn put(self, w: &mut WireReason, at: usize) {
        w.values[at] = (self >> 32) as f64;
        w.values[at + 1] = (self & 0xFFFF_FFFF) as f64;
    }
    fn take(w: &WireReason, at: usize, _: &'static str) -> Result<u64, DecodeError> {
        let high = whole(w.values[at], "owner (high half)")?;
        let low = whole(w.values[at + 1], "owner (low half)")?;
        Ok((u64::from(high) << 32) | u64::from(low))
    }
}

impl Field for Mode {
    fn put(self, w: &mut WireReason, at: usize) {
        w.values[at] = f64::from(self.to_wire());
    }
    fn take(w: &WireReason, at: usize, what: &'static str) -> Result<Mode, DecodeError> {
        Mode::try_from(whole(w.values[at], what)?).map_err(|e| DecodeError::Unknown {
            what: e.what,
            value: e.value,
        })
    }
}

impl Field for Axis {
    fn put(self, w: &mut WireReason, _: usize) {
        w.axis = Axis::to_wire(Some(self));
    }
    fn take(w: &WireReason, _: usize, _: &'static str) -> Result<Axis, DecodeError> {
        <Option<Axis> as Field>::take(w, AXIS, "axis")?.ok_or(DecodeError::Unknown {
            what: "axis (missing) of reason",
            value: w.code.to_wire(),
        })
    }
}

impl Field for Option<Axis> {
    fn put(self, w: &mut WireReason, _: usize) {
        w.axis = Axis::to_wire(self);
    }
    fn take(w: &WireReason, _: usize, _: &'static str) -> Result<Option<Axis>, DecodeError> {
        Axis::from_wire(w.axis).map_err(|value| DecodeError::Unknown {
            what: "axis",
            value,
        })
    }
}

impl Field for PvtQuantity {
    fn put(self, w: &mut WireReason, at: usize) {
        w.values[at] = match self {
            PvtQuantity::Position => 1.0,
            PvtQuantity::Velocity => 2.0,
            PvtQuantity::Acceleration => 3.0,
        };
    }
    fn take(w: &WireReason, at: usize, _: &'static str) -> Result<PvtQuantity, DecodeError> {
        match whole(w.values[at], "PVT quantity")? {
            1 => Ok(PvtQuantity::Position),
            2 => Ok(PvtQuantity::Velocity),
            3 => Ok(PvtQuantity::Acceleration),
            n => Err(DecodeError::Unknown {
                what: "PVT quantity",
                value: n,
            }),
        }
    }
}

/// Four slots from `at`: which failure, then its figures.
impl Field for CalibrationFailure {
    fn put(self, w: &mut WireReason, at: usize) {
        let v = match self {
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
            CalibrationFailure::Blocked { lag_deg, bound_deg } => [6.0, lag_deg, bound_deg, 0.0],
        };
        w.values[at..at + 4].copy_from_slice(&v);
    }
    fn take(w: &WireReason, at: usize, _: &'static str) -> Result<Self, DecodeError> {
        let [v1, v2, v3] = [w.values[at + 1], w.values[at + 2], w.values[at + 3]];
        Ok(match whole(w.values[at], "calibration failure")? {
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
        })
    }
}

/// The axis, and four slots from `at`: the value, its bounds and the argument's code (never 0,
/// which tells an [`Reason::OutOfRange`] apart).
impl Field for ArgRefusal {
    fn put(self, w: &mut WireReason, at: usize) {
        w.axis = Axis::to_wire(self.axis);
        let v = [self.value, self.min, self.max, f64::from(self.arg as u8)];
        w.values[at..at + 4].copy_from_slice(&v);
    }
    fn take(w: &WireReason, at: usize, _: &'static str) -> Result<Self, DecodeError> {
        let code = whole(w.values[at + 3], "argument code")?;
        Ok(ArgRefusal {
            arg: Arg::from_code(code).ok_or(DecodeError::Unknown {
                what: "argument code",
                value: code,
            })?,
            axis: <Option<Axis> as Field>::take(w, AXIS, "axis")?,
            value: w.values[at],
            min: w.values[at + 1],
            max: w.values[at + 2],
        })
    }
}

macro_rules! slot {
    (axis) => {
        AXIS
    };
    ($i:literal) => {
        $i
    };
}

macro_rules! what {
    ($field:ident) => {
        stringify!($field)
    };
    ($field:ident $what:literal) => {
        $what
    };
}

/// Each entry: the variant with its fields (`name @ where: type`, optionally `as "what"` for a
/// decode error), `= code` (with a guard on the figures `v` when two variants share a code),
/// and its words (`|f| ...`, the fields bound by name).
macro_rules! reasons {
    ($(
        $(#[$doc:meta])*
        $variant:ident $({ $($field:ident @ $at:tt : $ty:ty $(as $what:literal)?),* $(,)? })?
            = $code:ident $(if |$v:ident| $guard:expr)?,
            |$f:ident| $words:expr;
    )*) => {
        /// Why a command was refused or failed, or which safety check tripped, with its
        /// figures. `Display` gives the words for a person: what was wrong, the value, and
        /// what is allowed.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub enum Reason {
            $($(#[$doc])* $variant $({ $($field: $ty),* })?,)*
        }

        impl Reason {
            /// The wire form.
            pub fn to_wire(&self) -> WireReason {
                match *self {
                    $(Reason::$variant $({ $($field),* })? => {
                        #[allow(unused_mut)]
                        let mut w = WireReason {
                            code: RejectCode::$code,
                            axis: 0,
                            values: [0.0; 4],
                        };
                        $($(Field::put($field, &mut w, slot!($at));)*)?
                        w
                    })*
                }
            }

            /// The reason a wire code, axis and figures stand for. `RejectCode::None` is no
            /// reason; an axis or a figure this version does not know is a [`DecodeError`]
            /// naming it.
            pub fn from_wire(
                code: u32,
                axis: u32,
                values: &[f64; 4],
            ) -> Result<Reason, DecodeError> {
                let code = RejectCode::try_from(code).map_err(|e| DecodeError::Unknown {
                    what: e.what,
                    value: e.value,
                })?;
                let w = WireReason {
                    code,
                    axis,
                    values: *values,
                };
                <Option<Axis> as Field>::take(&w, AXIS, "axis")?;
                Ok(match code {
                    $(RejectCode::$code $(if { let $v = &w.values; $guard })? => Reason::$variant $({
                        $($field: Field::take(&w, slot!($at), what!($field $($what)?))?),*
                    })?,)*
                    RejectCode::None => {
                        return Err(DecodeError::Unknown {
                            what: "reason (none given) of a refusal",
                            value: 0,
                        });
                    }
                })
            }
        }

        impl fmt::Display for Reason {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                match *self {
                    $(Reason::$variant $({ $($field),* })? => {
                        let $f: &mut fmt::Formatter<'_> = f;
                        $words
                    })*
                }
            }
        }
    };
}

reasons! {
    /// Not allowed in the current mode.
    WrongMode { mode @ 0: Mode } = WrongMode,
        |f| write!(f, "not allowed in mode {mode}");
    NotCalibrated { axis @ axis: Axis } = NotCalibrated,
        |f| write!(f, "axis {axis} is not calibrated; run `calibrate` first");
    /// The emergency stop is pressed.
    EmergencyStop = EmergencyStop,
        |f| f.write_str("the emergency stop is pressed; release it, then send `hold`");
    /// The drive does not answer on the bus. `also`: bit `i` set for every further axis
    /// (index `i`) whose drive was lost in the same cycle, e.g. by a power cycle (0: only
    /// `axis`).
    DriveDisconnected { axis @ axis: Axis, also @ 0: u8 as "axes also lost" } = DriveDisconnected,
        |f| drives_lost(f, axis, also);
    /// A drive is in fault (`axis` unknown when the drive could not be told apart).
    DriveFault { axis @ axis: Option<Axis>, code @ 0: u16 as "drive error code" } = DriveFault,
        |f| match axis {
            Some(axis) => write!(f, "the drive of axis {axis} is in fault (error code 0x{code:04X})"),
            None => write!(f, "a drive is in fault (error code 0x{code:04X})"),
        };
    /// A value outside its allowed range (`axis`: the axis it belongs to, if any).
    OutOfRange {
        axis @ axis: Option<Axis>,
        value @ 0: f64,
        min @ 1: f64,
        max @ 2: f64,
    } = OutOfRange if |v| v[3] == 0.0,
        |f| out_of_range(f, axis, value, min, max);
    /// An axis would leave its reachable range on the straight line of a `move_linear`.
    LineOutOfRange { axis @ axis: Axis, fault @ 0: LineFault } = OutOfRange if |v| v[3] > LINE_FAULT_BASE,
        |f| line_fault(f, Some(axis), fault);
    /// An argument of the protocol ([`crate::ranges`]) outside its range: on the wire an
    /// `out_of_range` that carries the argument's code, worded exactly as the gateway words
    /// the same value.
    InvalidArgument { refusal @ 0: ArgRefusal } = OutOfRange,
        |f| write!(f, "{refusal}");
    /// The command exists in the manual but this build does not implement it yet.
    NotAvailable = NotAvailable,
        |f| f.write_str("not available yet in this MCM version");
    /// The command needs the simulated robot.
    NotSimulated = NotSimulated,
        |f| f.write_str("only available when the simulated robot is running");
    /// The PVT queue cannot take the batch; nothing was queued.
    QueueFull { offered @ 0: u32 as "points offered", free @ 1: u32 as "free places" } = QueueFull,
        |f| write!(f, "queue full: {offered} points offered, {free} places free; nothing was queued");
    PositionLimit { axis @ axis: Axis, position_deg @ 0: f64, limit_deg @ 1: f64 } = PositionLimit,
        |f| write!(f, "position limit: axis {axis} at {position_deg:.3} deg, limit {limit_deg:.3} deg");
    VelocityLimit { axis @ axis: Axis, velocity_deg_s @ 0: f64, limit_deg_s @ 1: f64 } = VelocityLimit,
        |f| write!(f, "velocity limit: axis {axis} at {velocity_deg_s:.3} deg/s, limit {limit_deg_s:.3} deg/s");
    BrakingDistance { axis @ axis: Axis, stop_deg @ 0: f64, limit_deg @ 1: f64 } = BrakingDistance,
        |f| write!(f, "braking distance: axis {axis} would stop at {stop_deg:.3} deg, beyond the limit {limit_deg:.3} deg");
    FollowingError { axis @ axis: Axis, error_deg @ 0: f64, band_deg @ 1: f64 } = FollowingError,
        |f| write!(f, "following error: axis {axis} is {error_deg:.3} deg away from its commanded position, band {band_deg:.3} deg");
    CalibrationFailed { axis @ axis: Axis, cause @ 0: CalibrationFailure } = CalibrationFailed,
        |f| calibration_failed(f, axis, cause);
    /// Superseded by another command or a mode change before it finished.
    Aborted = Aborted,
        |f| f.write_str("aborted (superseded by another command or a mode change)");
    /// A motion is in progress.
    Busy { remaining_s @ 0: f64 } = Busy,
        |f| write!(f, "a motion is in progress ({remaining_s:.3} s left); wait until it ends, or send `hold` to stop it");
    /// A PVT point (1-based `point`) breaks a limit; nothing was queued.
    PvtPoint {
        axis @ axis: Axis,
        point @ 0: u32 as "PVT point number",
        quantity @ 1: PvtQuantity,
        value @ 2: f64,
        limit @ 3: f64,
    } = PvtPoint,
        |f| {
            let (what, unit) = (quantity.name(), quantity.unit());
            write!(
                f,
                "point {point}: axis {axis} {what} {} {unit} exceeds the limit {} {unit}; nothing was queued",
                Num(value),
                Num(limit)
            )
        };
    /// The straight line of a `move_linear` leaves what the arm can follow (its reach, a
    /// singularity's margin, a continuous motion of an axis).
    LineUnreachable { axis @ axis: Option<Axis>, fault @ 0: LineFault } = Unreachable if |v| v[3] > LINE_FAULT_BASE,
        |f| line_fault(f, axis, fault);
    /// The target is outside the reachable range (the limits less the safety margin).
    Unreachable {
        axis @ axis: Axis,
        target_deg @ 0: f64,
        min_deg @ 1: f64,
        max_deg @ 2: f64,
    } = Unreachable,
        |f| write!(
            f,
            "axis {axis}: target {} deg is not allowed; expected {}",
            Num(target_deg),
            Arg::TargetPosition.expected(min_deg, max_deg)
        );
    /// Another client controls the arm's motion: `owner` is its client id. The gateway names
    /// the owner in its words (peer address or client name).
    NotOwner { owner @ 0: u64 } = NotOwner,
        |f| write!(f, "another client (id {owner:#x}) controls the arm; only `hold` and state reads are open to others until it releases control or disconnects");
    /// The MCM is shutting down: the arm is being stopped and its drives disabled.
    ShuttingDown = ShuttingDown,
        |f| f.write_str("the MCM is shutting down: the arm is being stopped and its drives disabled");
    /// An axis derated by i2t (its motor hot) needs more than its derated current to hold
    /// where it is: its current stood at the derated limit `limit_a` (it was `current_a`).
    /// The drives are powered off, so that the holding brakes hold the arm while the motor
    /// cools.
    Overload { axis @ axis: Axis, current_a @ 0: f64, limit_a @ 1: f64 } = Overload,
        |f| write!(f, "overload: axis {axis} cannot hold with its derated current of {limit_a:.2} A (its motor is hot, i2t; current {current_a:.2} A): the drives of the axes with a brake are powered off and the brakes hold the arm; send hold once the motor has cooled");
    /// `identify_payload`: from this pose the poses it would measure at do not tell the load's
    /// mass and centre of mass apart; `condition` is the condition number of their
    /// column-scaled regressor (`f64::MAX` for none at all), `limit` the largest allowed.
    NotIdentifiable { condition @ 0: f64, limit @ 1: f64 } = NotIdentifiable,
        |f| write!(f, "the load cannot be identified from this pose: the poses within the reachable range do not tell its mass and centre of mass apart (condition number {}, at most {}); move the arm away from its limits and from the upright pose", Num(condition), Num(limit));
}

/// The words of [`Reason::DriveDisconnected`]: one axis, or the list of every axis lost.
fn drives_lost(f: &mut fmt::Formatter<'_>, axis: Axis, also: u8) -> fmt::Result {
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

/// The words of [`Reason::LineUnreachable`] and [`Reason::LineOutOfRange`]: where on the
/// path, what, the value and what is allowed.
fn line_fault(f: &mut fmt::Formatter<'_>, axis: Option<Axis>, fault: LineFault) -> fmt::Result {
    let at = Num(fault.fraction() * 100.0);
    let axis = |f: &mut fmt::Formatter<'_>| match axis {
        Some(a) => write!(f, "axis {a}"),
        None => f.write_str("an axis"),
    };
    match fault {
        LineFault::NoSolution { .. } => write!(
            f,
            "unreachable at {at} % of the path: no configuration of the start's \
             branch puts the TCP there; nothing moved"
        ),
        LineFault::Singular {
            singularity,
            value,
            margin,
            ..
        } => {
            let unit = singularity.unit();
            write!(
                f,
                "unreachable at {at} % of the path: it comes within {} {unit} of \
                 the {singularity}; it must stay at least {} {unit} away; nothing moved",
                Num(value),
                Num(margin)
            )
        }
        LineFault::JointJump {
            step_deg,
            allowed_deg,
            ..
        } => {
            write!(f, "unreachable at {at} % of the path: ")?;
            axis(f)?;
            write!(
                f,
                " would jump by {} deg where its rate allows at most {} deg: the arm cannot \
                 follow the line there in the start's configuration; nothing moved",
                Num(step_deg),
                Num(allowed_deg)
            )
        }
        LineFault::OutOfRange {
            value_deg,
            limit_deg,
            ..
        } => {
            write!(f, "out of range at {at} % of the path: ")?;
            axis(f)?;
            write!(
                f,
                " would be at {} deg, beyond the end of its reachable range at {} deg; nothing \
                 moved",
                Num(value_deg),
                Num(limit_deg)
            )
        }
    }
}

/// The words of [`Reason::OutOfRange`]: the range, or "a finite number" when any is allowed.
fn out_of_range(
    f: &mut fmt::Formatter<'_>,
    axis: Option<Axis>,
    value: f64,
    min: f64,
    max: f64,
) -> fmt::Result {
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

/// The words of [`Reason::CalibrationFailed`], by its cause.
fn calibration_failed(
    f: &mut fmt::Formatter<'_>,
    axis: Axis,
    cause: CalibrationFailure,
) -> fmt::Result {
    match cause {
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
    }
}

impl Reason {
    /// The code naming this reason (and the safety check, for trips).
    pub fn code(&self) -> RejectCode {
        self.to_wire().code
    }

    /// Its `error_code` ([`crate::error_code`]).
    pub fn error_code(&self) -> ErrorCode {
        // Every reason has a code other than `None` (`reasons!` names one for each).
        self.code().error_code().unwrap_or(ErrorCode::InternalError)
    }

    /// The axis it concerns, if any.
    pub fn axis(&self) -> Option<Axis> {
        Axis::from_wire(self.to_wire().axis).ok().flatten()
    }

    /// The argument refused, when this reason is a value of an argument of `kind` outside its
    /// range: an [`Reason::InvalidArgument`], or an [`Reason::Unreachable`] target of
    /// `move_axis` (`target_position`) or `move_all` (`target_positions[i]`). The gateway words
    /// these as it words its own refusal of the same value (`move_axis: argument ...`).
    pub fn argument(&self, kind: CommandKind) -> Option<ArgRefusal> {
        match *self {
            Reason::InvalidArgument { refusal } => Some(refusal),
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
}
