//! The allowed range of every numeric command argument, in one table that the gateway's
//! parsing and the real-time core's checks both read, and the one wording of a value that is
//! not allowed ([`ArgRefusal`]), so a refusal reads the same whichever side gives it.
//!
//! A range is fixed ([`Bound::Fixed`]) or follows from the robot's configuration: the
//! reachable range of an axis ([`reachable_deg`]: its software limits less the safety
//! margin), its peak joint torque ([`peak_torque_nm`]), its maximum velocity
//! ([`max_velocity_deg_s`]), one cycle period. The real-time core's parameters are computed
//! with the same functions, so both sides compare with the same numbers.
//!
//! Numbers in messages are written by [`Num`]: at most 12 significant digits, with an exponent
//! outside 1e-5 to 1e15 (`1e-320`, never 320 digits).
//!
//! Adding an argument is one row of the `arguments!` table below.
//!
//! Pure, allocation-free and panic-free: the core runs the checks inside the cycle (formatting,
//! `Display`, belongs outside it).

use crate::NUM_AXES;
use crate::command::Axis;
use crate::config::RobotConfig;
use core::fmt;

/// How the value relates to its bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// A number from `min` to `max`, both included.
    Range,
    /// A whole number from `min` to `max`: an axis number.
    Axis,
    /// A number other than 0, at most `max` (a negative one means "none", said in the note).
    NonZeroUpTo,
}

/// Where the bounds come from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    Fixed(f64, f64),
    /// The axis's reachable range [deg] ([`reachable_deg`]).
    Reach,
    /// Plus or minus the axis's peak joint torque [Nm] ([`peak_torque_nm`]).
    PeakTorque,
    /// Plus or minus the axis's maximum velocity [deg/s] ([`max_velocity_deg_s`]).
    MaxVelocity,
    /// From one cycle period to this [s].
    CycleTo(f64),
}

/// One numeric argument: its protocol name, range, unit and what the range means.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArgSpec {
    pub arg: Arg,
    /// The name in the JSON `arguments` (an array's elements are `name[i]`).
    pub name: &'static str,
    pub shape: Shape,
    pub bound: Bound,
    /// `""` or the unit, e.g. `"deg"`.
    pub unit: &'static str,
    /// `""` or what the range means, shown in brackets after it.
    pub note: &'static str,
}

macro_rules! arguments {
    ($($variant:ident = $code:literal, $name:literal, $shape:ident, $bound:expr, $unit:literal, $note:literal;)*) => {
        /// A numeric argument of the protocol; its code travels in a refusal
        /// (`Reason::InvalidArgument`).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum Arg {
            $($variant = $code,)*
        }

        /// Every numeric argument of every command, one row each.
        pub const ARGS: &[ArgSpec] = &[
            $(ArgSpec {
                arg: Arg::$variant,
                name: $name,
                shape: Shape::$shape,
                bound: $bound,
                unit: $unit,
                note: $note,
            },)*
        ];
    };
}

arguments! {
    AxisIndex = 1, "axis_index", Axis, Bound::Fixed(1.0, 6.0), "", "";
    TargetPosition = 2, "target_position", Range, Bound::Reach, "deg", "the axis's reachable range: its limits less the safety margin";
    TargetPositions = 3, "target_positions", Range, Bound::Reach, "deg", "the axis's reachable range: its limits less the safety margin";
    VelocityFactor = 4, "velocity_factor", Range, Bound::Fixed(0.001, 1.0), "", "a fraction of each axis's maximum velocity";
    Dt = 5, "dt", Range, Bound::CycleTo(crate::command::Pvt::MAX_DT_S), "s", "at least one cycle";
    Timeout = 6, "timeout", NonZeroUpTo, Bound::Fixed(-f64::MAX, 3600.0), "s", "negative: no timeout";
    DtStatus = 7, "dt_status", Range, Bound::Fixed(0.0, 60.0), "s", "0: no status results";
    Torques = 8, "torques", Range, Bound::PeakTorque, "Nm", "the axis's peak joint torque";
    Duration = 9, "duration", Range, Bound::Fixed(0.0, 3600.0), "s", "";
    ExternalTorques = 10, "external_torques", Range, Bound::Fixed(-1000.0, 1000.0), "Nm", "";
    DisconnectAxis = 11, "disconnect_axis", Axis, Bound::Fixed(1.0, 6.0), "", "";
    ReconnectAxis = 12, "reconnect_axis", Axis, Bound::Fixed(1.0, 6.0), "", "";
    BlockAxis = 13, "block_axis", Axis, Bound::Fixed(1.0, 6.0), "", "";
    UnblockAxis = 14, "unblock_axis", Axis, Bound::Fixed(1.0, 6.0), "", "";
    Velocities = 15, "velocities", Range, Bound::MaxVelocity, "deg/s", "the axis's maximum velocity";
    Linear = 16, "linear", Range, Bound::Fixed(-1.0, 1.0), "m/s", "each component of the TCP's velocity";
    Angular = 17, "angular", Range, Bound::Fixed(-180.0, 180.0), "deg/s", "each component of the TCP's angular velocity";
    LinearVelocity = 18, "velocity", Range, Bound::Fixed(0.001, 1.0), "m/s", "the TCP's speed on the line";
    LinearAcceleration = 19, "acceleration", Range, Bound::Fixed(0.01, 10.0), "m/s^2", "the TCP's acceleration on the line";
}

/// The range a target of `axis0` (0-based) may lie in [deg]: the software limits less the
/// safety margin (`safety.limit_margin_deg`). Whatever is outside would trip the braking check.
pub fn reachable_deg(cfg: &RobotConfig, axis0: usize) -> (f64, f64) {
    let a = &cfg.axes[axis0];
    let margin = cfg.safety.limit_margin_deg;
    (a.min_deg + margin, a.max_deg - margin)
}

/// The peak joint torque of `axis0` (0-based) [Nm]: its drive's current limit through the gear.
pub fn peak_torque_nm(cfg: &RobotConfig, axis0: usize) -> f64 {
    let a = &cfg.axes[axis0];
    a.max_current_a * a.torque_per_amp()
}

/// The maximum velocity of `axis0` (0-based) [deg/s] (`max_velocity_deg_s` of its axis).
pub fn max_velocity_deg_s(cfg: &RobotConfig, axis0: usize) -> f64 {
    cfg.axes[axis0].max_velocity_deg_s
}

impl Arg {
    /// The table row of this argument.
    pub fn spec(self) -> &'static ArgSpec {
        // Every variant has exactly one row (checked by a test); the fallback is never taken.
        ARGS.iter().find(|s| s.arg == self).unwrap_or(&ARGS[0])
    }

    /// The argument with this protocol name.
    pub fn by_name(name: &str) -> Option<Arg> {
        ARGS.iter().find(|s| s.name == name).map(|s| s.arg)
    }

    /// The argument with this wire code.
    pub fn from_code(code: u32) -> Option<Arg> {
        ARGS.iter().find(|s| s.arg as u32 == code).map(|s| s.arg)
    }

    pub fn name(self) -> &'static str {
        self.spec().name
    }

    /// The bounds for `axis0` (the axis the value belongs to, for per-axis ranges; axis 1
    /// when none is given) with the configuration `cfg`: a handful of arithmetic, so callers
    /// compute it when they check a value and keep no table of their own.
    pub fn bounds(self, cfg: &RobotConfig, axis0: Option<usize>) -> (f64, f64) {
        let i = axis0.unwrap_or(0).min(NUM_AXES - 1);
        match self.spec().bound {
            Bound::Fixed(min, max) => (min, max),
            Bound::Reach => reachable_deg(cfg, i),
            Bound::PeakTorque => {
                let peak = peak_torque_nm(cfg, i);
                (-peak, peak)
            }
            Bound::MaxVelocity => {
                let max = max_velocity_deg_s(cfg, i);
                (-max, max)
            }
            Bound::CycleTo(max) => (cfg.cycle_period_s(), max),
        }
    }

    /// The bounds of an argument with a fixed range; `(-inf, inf)` for one whose range comes
    /// from the configuration (use [`Arg::bounds`]).
    pub fn fixed_bounds(self) -> (f64, f64) {
        match self.spec().bound {
            Bound::Fixed(min, max) => (min, max),
            _ => (f64::NEG_INFINITY, f64::INFINITY),
        }
    }

    /// Whether `x` is allowed within `(min, max)`.
    pub fn accepts(self, x: f64, (min, max): (f64, f64)) -> bool {
        let within = x.is_finite() && x >= min && x <= max;
        match self.spec().shape {
            Shape::Range => within,
            Shape::Axis => within && x.fract() == 0.0,
            Shape::NonZeroUpTo => within && x != 0.0,
        }
    }

    /// `x` if allowed within `bounds`, else the refusal (`axis`: the axis the value belongs
    /// to; for an array argument it names the element).
    pub fn check(self, x: f64, bounds: (f64, f64), axis: Option<Axis>) -> Result<f64, ArgRefusal> {
        if self.accepts(x, bounds) {
            Ok(x)
        } else {
            Err(ArgRefusal {
                arg: self,
                axis,
                value: x,
                min: bounds.0,
                max: bounds.1,
            })
        }
    }

    /// Whether the argument is an array whose refusal names the element: one element per
    /// axis, or a Cartesian vector (`linear`, `angular`: the element's index carried as the
    /// axis of that number).
    pub fn per_axis_array(self) -> bool {
        matches!(
            self,
            Arg::TargetPositions
                | Arg::Torques
                | Arg::ExternalTorques
                | Arg::Velocities
                | Arg::Linear
                | Arg::Angular
        )
    }

    /// What is allowed, in words: `a number from -169 to 169 deg (...)`.
    pub fn expected(self, min: f64, max: f64) -> Expected {
        Expected {
            spec: self.spec(),
            min,
            max,
        }
    }
}

/// What an argument allows, in words ([`Arg::expected`]).
#[derive(Debug, Clone, Copy)]
pub struct Expected {
    spec: &'static ArgSpec,
    min: f64,
    max: f64,
}

impl fmt::Display for Expected {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (min, max) = (Num(self.min), Num(self.max));
        match self.spec.shape {
            Shape::Range => write!(f, "a number from {min} to {max}")?,
            Shape::Axis => write!(f, "an axis number from {min} to {max}")?,
            Shape::NonZeroUpTo => write!(f, "a number other than 0, at most {max}")?,
        }
        if !self.spec.unit.is_empty() {
            write!(f, " {}", self.spec.unit)?;
        }
        if !self.spec.note.is_empty() {
            write!(f, " ({})", self.spec.note)?;
        }
        Ok(())
    }
}

/// A value that is not allowed, with the bounds it was checked against. `Display`:
/// `argument "torques[1]" = 200 is not allowed; expected a number from -129.6 to 129.6 Nm (...)`;
/// the gateway prefixes the command (`set_torques: ...`), whichever side refused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArgRefusal {
    pub arg: Arg,
    /// The axis the value belongs to (names the element of a per-axis array).
    pub axis: Option<Axis>,
    pub value: f64,
    pub min: f64,
    pub max: f64,
}

impl fmt::Display for ArgRefusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = self.arg.name();
        match self.axis {
            Some(a) if self.arg.per_axis_array() => {
                write!(f, "argument \"{name}[{}]\"", a.index())?
            }
            _ => write!(f, "argument \"{name}\"")?,
        }
        write!(
            f,
            " = {} is not allowed; expected {}",
            Num(self.value),
            self.arg.expected(self.min, self.max)
        )
    }
}

/// A number for a message: at most 12 significant digits (so `169.00000000000003`, the
/// degrees of a value that went through radians, reads `169`), with an exponent below 1e-5
/// and from 1e15 on (`1e-320`, `1.79769313486e308`); `0` for both zeros.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if x == 0.0 {
            return f.write_str("0");
        }
        if !x.is_finite() {
            return write!(f, "{x}");
        }
        // Round to 12 significant digits: the nearest double to the 12-digit decimal, which
        // the shortest round-trip form below then writes with at most 12 digits.
        let mut buf = Buf::default();
        let y = match fmt::Write::write_fmt(&mut buf, format_args!("{x:.11e}")) {
            Ok(()) => buf.as_str().parse::<f64>().unwrap_or(x),
            Err(_) => x,
        };
        if (1e-5..1e15).contains(&y.abs()) {
            write!(f, "{y}")
        } else {
            write!(f, "{y:e}")
        }
    }
}

/// A small stack buffer to format into without allocating.
struct Buf {
    bytes: [u8; 40],
    len: usize,
}

impl Default for Buf {
    fn default() -> Self {
        Buf {
            bytes: [0; 40],
            len: 0,
        }
    }
}

impl Buf {
    fn as_str(&self) -> &str {
        core::str::from_utf8(&self.bytes[..self.len]).unwrap_or("")
    }
}

impl fmt::Write for Buf {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let end = self.len + s.len();
        if end > self.bytes.len() {
            return Err(fmt::Error);
        }
        self.bytes[self.len..end].copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

#[cfg(test)]
mod tests;
