//! The typed command contract: one request type per command, and the one place that turns it
//! into a [`CommandSample`] and back.
//!
//! Every sender (the gateway, a co-located controller, a test) builds a [`Request`] and calls
//! [`Request::encode`]; the real-time core calls [`Request::decode`] on every sample it
//! receives. Nothing outside this module reads or writes `CommandSample::args` by position.
//! Decoding validates every value (co-located controllers publish samples directly), so the
//! core only ever sees well-formed requests; a bad sample is a [`DecodeError`] that names the
//! field, the value and what is allowed. Limits that depend on the robot's configuration
//! (joint ranges, torque limits) are checked by the core, not here.
//!
//! Values are in the user's units (degrees, degrees/s, newton-metres, seconds); the core
//! converts them to SI where it takes them in.
//!
//! Encoding and decoding never allocate, so both may run inside the real-time cycle.
//!
//! ```
//! use mcm_shared::command::{Axis, MoveAxis, Request};
//! let req = Request::MoveAxis(MoveAxis {
//!     axis: Axis::new(2).unwrap(),
//!     target_deg: 30.0,
//!     velocity_factor: 0.5,
//! });
//! let mut sample = req.encode();
//! sample.client_id = 7; // the sender stamps its ids
//! assert_eq!(Request::decode(&sample), Ok(req));
//! ```
//!
//! A long `pvt_points` batch travels as several samples ([`PvtChunk::batch`]); the core queues
//! the batch when the chunk marked `last` arrives.

use crate::NUM_AXES;
use crate::mode::CommandKind;
use crate::ranges::{Arg, Num};
use crate::sample::{
    CALIBRATE_FLAG_FORCE_STOP, COMMAND_ARGS, CommandSample, IDENTIFY_FLAG_APPLY, PVT_FLAG_LAST,
    PVT_POINTS_PER_COMMAND, SIM_FLAG_POWER_CYCLE, TORQUE_FLAG_NO_GRAVITY,
};
use crate::tool::{Tcp, Tool, ToolError};
use core::fmt;

/// `CommandSample::flags` of `PvtPoints`: bits 0..7 hold the number of points in the sample.
const PVT_COUNT_MASK: u32 = 0xFF;
/// `CommandSample::flags` of `Sim`: bit n says `args[n]` is present (bit 5 covers all six
/// external torques in `args[5..11]`, bit 6 the true tool's mass and centre of mass in
/// `args[11..15]`).
const SIM_FIELDS: u32 = 0b111_1111;
/// Where a `sim` sample carries the true tool: its mass, then its centre of mass.
const SIM_TRUE_TOOL: usize = 11;
/// Arguments a PVT point takes in a sample: six positions, then six velocities.
const PVT_POINT_ARGS: usize = 2 * NUM_AXES;

const _: () = assert!(PVT_POINTS_PER_COMMAND * PVT_POINT_ARGS <= COMMAND_ARGS);
const _: () = assert!(PVT_POINTS_PER_COMMAND as u32 <= PVT_COUNT_MASK);

/// One axis of the arm, numbered 1 to 6 as the protocol does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Axis(u8);

impl Axis {
    /// Every axis, in order.
    pub const ALL: [Axis; NUM_AXES] = [Axis(1), Axis(2), Axis(3), Axis(4), Axis(5), Axis(6)];

    /// The axis with this number (1 to 6).
    pub const fn new(number: u8) -> Option<Axis> {
        if number >= 1 && number as usize <= NUM_AXES {
            Some(Axis(number))
        } else {
            None
        }
    }

    /// The axis at this 0-based index (0 to 5).
    pub const fn from_index(index: usize) -> Option<Axis> {
        if index < NUM_AXES {
            Some(Axis(index as u8 + 1))
        } else {
            None
        }
    }

    /// The protocol's number, 1 to 6.
    pub const fn number(self) -> u8 {
        self.0
    }

    /// The 0-based index into per-axis arrays.
    pub const fn index(self) -> usize {
        self.0 as usize - 1
    }

    /// The axis from a wire value where 0 means "none".
    pub(crate) fn from_wire(value: u32) -> Result<Option<Axis>, u32> {
        match value {
            0 => Ok(None),
            n => u8::try_from(n).ok().and_then(Axis::new).map(Some).ok_or(n),
        }
    }

    /// The wire value of an optional axis (0 for none).
    pub(crate) fn to_wire(axis: Option<Axis>) -> u32 {
        axis.map_or(0, |a| u32::from(a.0))
    }
}

impl fmt::Display for Axis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// Which axes a calibration covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    All,
    /// Axes 1 to 3.
    Elbow,
    /// Axes 4 to 6.
    Wrist,
    Axis(Axis),
}

impl Which {
    /// Whether the calibration covers `axis`.
    pub fn contains(self, axis: Axis) -> bool {
        match self {
            Which::All => true,
            Which::Elbow => axis.number() <= 3,
            Which::Wrist => axis.number() >= 4,
            Which::Axis(a) => a == axis,
        }
    }

    fn code(self) -> f64 {
        match self {
            Which::All => 0.0,
            Which::Axis(a) => f64::from(a.number()),
            Which::Elbow => 7.0,
            Which::Wrist => 8.0,
        }
    }

    fn from_code(x: f64) -> Option<Which> {
        match x {
            0.0 => Some(Which::All),
            7.0 => Some(Which::Elbow),
            8.0 => Some(Which::Wrist),
            _ if x.fract() == 0.0 && (1.0..=6.0).contains(&x) => {
                Axis::new(x as u8).map(Which::Axis)
            }
            _ => None,
        }
    }
}

/// The direction a calibration searches in (the manual's `elbow_direction`/`wrist_direction`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Direction {
    /// `1`: the default direction.
    #[default]
    Positive,
    /// `-1`: the reverse direction.
    Negative,
}

impl Direction {
    /// `1.0` or `-1.0`.
    pub fn sign(self) -> f64 {
        match self {
            Direction::Positive => 1.0,
            Direction::Negative => -1.0,
        }
    }

    fn from_sign(x: f64) -> Option<Direction> {
        match x {
            1.0 => Some(Direction::Positive),
            -1.0 => Some(Direction::Negative),
            _ => None,
        }
    }
}

/// `calibrate`: home the axes against their mechanical stops or light barriers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Calibrate {
    pub which: Which,
    pub elbow_direction: Direction,
    pub wrist_direction: Direction,
    /// Use the mechanical stops even where light barriers exist.
    pub force_mechanical_stop: bool,
}

impl Default for Calibrate {
    /// The protocol's defaults: every axis ([`crate::protocol::DEFAULT_WHICH`]), the default
    /// directions, light barriers where there are some.
    fn default() -> Self {
        Calibrate {
            which: crate::protocol::DEFAULT_WHICH,
            elbow_direction: Direction::default(),
            wrist_direction: Direction::default(),
            force_mechanical_stop: false,
        }
    }
}

/// `torque_control`: enter TORQUE_CONTROL.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorqueControl {
    /// Fall back to HOLD when no `set_torques` came for this long [s]; `None`: never.
    pub timeout_s: Option<f64>,
    /// Add the gravity compensation to the torques given.
    pub gravity_compensation: bool,
}

/// `velocity_control`: enter VELOCITY_CONTROL.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityControl {
    /// Stop (controlled, to HOLD) when no `set_velocities` came for this long [s]; `None`:
    /// never.
    pub timeout_s: Option<f64>,
}

/// `set_velocities`: the joint velocities in VELOCITY_CONTROL, each within its axis's maximum
/// velocity (checked by the core, which knows the configuration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetVelocities {
    /// [deg/s]
    pub velocities_deg_s: [f64; NUM_AXES],
}

/// The frame a Cartesian velocity's axes are those of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CartesianFrame {
    /// The base frame (DH frame 0, z up along axis 1).
    #[default]
    Base,
    /// The TCP frame as it is in each cycle (the active tool's TCP).
    Tool,
}

impl CartesianFrame {
    /// Every frame, the default first.
    pub const ALL: [CartesianFrame; 2] = [CartesianFrame::Base, CartesianFrame::Tool];

    /// The protocol's name: `base` or `tool`.
    pub const fn as_str(self) -> &'static str {
        match self {
            CartesianFrame::Base => "base",
            CartesianFrame::Tool => "tool",
        }
    }

    /// The frame of the protocol's name.
    pub fn from_name(name: &str) -> Option<CartesianFrame> {
        Self::ALL.into_iter().find(|f| f.as_str() == name)
    }

    /// The value the frame travels as in a sample.
    pub const fn code(self) -> f64 {
        match self {
            CartesianFrame::Base => 0.0,
            CartesianFrame::Tool => 1.0,
        }
    }

    /// The frame a sample's (or a binding's) value stands for.
    pub fn from_code(x: f64) -> Option<CartesianFrame> {
        Self::ALL.into_iter().find(|f| f.code() == x)
    }
}

/// `set_cartesian_velocity`: the TCP's velocity in VELOCITY_CONTROL, each component within its
/// fixed range ([`Arg::Linear`], [`Arg::Angular`]: checked by [`Request::decode`] and the
/// gateway's parser, with the same table).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetCartesianVelocity {
    /// The TCP origin's velocity [m/s], in `frame`'s axes.
    pub linear_m_s: [f64; 3],
    /// The TCP frame's angular velocity [deg/s], in `frame`'s axes.
    pub angular_deg_s: [f64; 3],
    pub frame: CartesianFrame,
}

/// Where a `set_cartesian_velocity` sample carries its linear velocity, its angular velocity
/// and its frame.
const TWIST_ARGS: [usize; 3] = [0, 3, 6];

/// `set_tool`: the tool the arm carries from the next cycle (checked by [`Tool::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetTool {
    pub tool: Tool,
}

/// `identify_payload`: move the wrist through poses, estimate the load on the flange from the
/// holding torques, and with `apply` make the estimate the tool's load.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IdentifyPayload {
    pub apply: bool,
}

/// Where a `set_tool` sample carries the tool: TCP position, orientation, mass, centre of
/// mass, inertia.
const TOOL_ARGS: [usize; 6] = [0, 3, 7, 8, 11, 17];

/// `pvt`: enter PVT mode with this spacing of streamed points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pvt {
    /// Time between two `pvt_points` points [s], from one cycle period to [`Pvt::MAX_DT_S`]
    /// (the real-time core checks it: the range is [`crate::ranges::Arg::Dt`]'s).
    pub dt_s: f64,
}

impl Pvt {
    /// The largest point spacing [s].
    pub const MAX_DT_S: f64 = 1.0;
}

/// `move_axis`: move one axis to a target position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveAxis {
    pub axis: Axis,
    /// [deg]
    pub target_deg: f64,
    /// Share of the axis's maximum velocity and acceleration, from 0.001 to 1
    /// ([`crate::ranges::Arg::VelocityFactor`]).
    pub velocity_factor: f64,
}

/// `move_all`: move all axes to target positions, all starting and arriving together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveAll {
    /// [deg]
    pub targets_deg: [f64; NUM_AXES],
    /// Share of the maximum velocities and accelerations, from 0.001 to 1.
    pub velocity_factor: f64,
}

/// `move_linear`: the TCP on a straight line to `position`, its orientation turned on the
/// shortest arc to `orientation` (kept when `None`), at most at `velocity` [m/s] and
/// `acceleration` [m/s²] (`None`: [`MoveLinear::DEFAULT_VELOCITY_M_S`],
/// [`MoveLinear::DEFAULT_ACCELERATION_M_S2`]). Base frame, metres; the orientation
/// a unit quaternion `[x, y, z, w]` (decoding normalises one within
/// [`crate::units::UNIT_QUATERNION_TOLERANCE`] of unit norm and refuses any other).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveLinear {
    pub position: [f64; 3],
    pub orientation: Option<[f64; 4]>,
    pub velocity: Option<f64>,
    pub acceleration: Option<f64>,
}

impl MoveLinear {
    /// The TCP's speed when the request gives none [m/s].
    pub const DEFAULT_VELOCITY_M_S: f64 = 0.25;
    /// The TCP's acceleration when the request gives none [m/s²].
    pub const DEFAULT_ACCELERATION_M_S2: f64 = 1.2;
}

/// `CommandSample::flags` of `MoveLinear`: which optional arguments the sample carries.
const LINE_FLAG_ORIENTATION: u32 = 1;
const LINE_FLAG_VELOCITY: u32 = 2;
const LINE_FLAG_ACCELERATION: u32 = 4;
/// Where a `move_linear` sample carries its arguments: position, orientation, velocity,
/// acceleration.
const LINE_ARGS: [usize; 4] = [0, 3, 7, 8];

/// One point of a `pvt_points` stream.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PvtPoint {
    /// [deg]
    pub position_deg: [f64; NUM_AXES],
    /// [deg/s]
    pub velocity_deg_s: [f64; NUM_AXES],
}

/// Up to [`PVT_POINTS_PER_COMMAND`] points of a `pvt_points` batch: what one sample carries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PvtChunk {
    points: [PvtPoint; PVT_POINTS_PER_COMMAND],
    len: u8,
    /// This chunk closes the batch: the core queues the batch (whole or not at all) now.
    pub last: bool,
}

impl PvtChunk {
    /// A chunk of 1 to [`PVT_POINTS_PER_COMMAND`] points; `None` for more or fewer.
    pub fn new(points: &[PvtPoint], last: bool) -> Option<PvtChunk> {
        if points.is_empty() || points.len() > PVT_POINTS_PER_COMMAND {
            return None;
        }
        let mut chunk = PvtChunk {
            points: [PvtPoint::default(); PVT_POINTS_PER_COMMAND],
            len: points.len() as u8,
            last,
        };
        chunk.points[..points.len()].copy_from_slice(points);
        Some(chunk)
    }

    /// The points of this chunk.
    pub fn points(&self) -> &[PvtPoint] {
        &self.points[..usize::from(self.len)]
    }

    /// A whole batch as chunks, the last one marked `last`; empty for no points.
    pub fn batch(points: &[PvtPoint]) -> impl ExactSizeIterator<Item = PvtChunk> + '_ {
        let chunks = points.len().div_ceil(PVT_POINTS_PER_COMMAND);
        points
            .chunks(PVT_POINTS_PER_COMMAND)
            .enumerate()
            .map(move |(i, c)| PvtChunk::new(c, i + 1 == chunks).expect("chunks are 1..=N long"))
    }
}

/// `set_torques`: the joint torques in TORQUE_CONTROL.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetTorques {
    /// [Nm]
    pub torques_nm: [f64; NUM_AXES],
}

/// `sim`: a fault to inject into the simulated robot. Fields left `None`/`false` change nothing.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SimCommand {
    /// Press (`true`) or release the emergency switch.
    pub emergency_stop: Option<bool>,
    /// Pull the drive's cable.
    pub disconnect_axis: Option<Axis>,
    /// Plug it back in.
    pub reconnect_axis: Option<Axis>,
    /// Put an immovable obstacle in the way of the joint, where it is now.
    pub block_axis: Option<Axis>,
    pub unblock_axis: Option<Axis>,
    /// Joint-side torques of a hand pushing on the joints [Nm], until set back to zeros.
    pub external_torques_nm: Option<[f64; NUM_AXES]>,
    /// Switch the drives' power off and on (they lose their calibration).
    pub power_cycle: bool,
    /// The load the simulated arm really carries (its mass and centre of mass; the TCP and
    /// inertia of a [`Tool`] made by [`SimCommand::true_tool`]), whatever `set_tool` says.
    pub true_tool: Option<Tool>,
}

impl SimCommand {
    /// The true load of `true_tool`: `mass` [kg] at `center_of_mass` [m, flange frame], checked
    /// as a tool's load is ([`Tool::new`]).
    pub fn true_tool(mass: f64, center_of_mass: [f64; 3]) -> Result<Tool, ToolError> {
        Tool::new(Tcp::FLANGE, mass, center_of_mass, None)
    }
}

/// A command to the real-time core, typed.
// A `pvt_points` chunk makes this 392 bytes; boxing it would allocate inside the cycle, and
// requests are decoded one at a time on the stack.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Request {
    Status,
    Hold,
    Info,
    Calibrate(Calibrate),
    Release,
    TorqueControl(TorqueControl),
    Pvt(Pvt),
    MoveAxis(MoveAxis),
    MoveAll(MoveAll),
    PvtPoints(PvtChunk),
    SetTorques(SetTorques),
    Sim(SimCommand),
    /// Take control of the arm's motion (refused while another client controls it).
    TakeControl,
    /// Give up control (refused when another client controls it).
    ReleaseControl,
    /// The sending client is gone: sent by the gateway when a connection closes, and by a
    /// shared-memory client when it stops.
    ClientGone,
    VelocityControl(VelocityControl),
    SetVelocities(SetVelocities),
    SetTool(SetTool),
    IdentifyPayload(IdentifyPayload),
    SetCartesianVelocity(SetCartesianVelocity),
    MoveLinear(MoveLinear),
}

/// What a value may be, in a [`DecodeError`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Allowed {
    /// From `min` to `max`, both included.
    Range { min: f64, max: f64 },
    /// A number other than 0 from `min` to `max` (negative: none).
    NonZeroUpTo { min: f64, max: f64 },
    /// Any finite number.
    Finite,
    /// One of the listed values (as words).
    OneOf(&'static str),
}

impl Allowed {
    /// The bounds to report in a refusal (`OutOfRange` carries a min and a max).
    pub fn bounds(self) -> (f64, f64) {
        match self {
            Allowed::Range { min, max } | Allowed::NonZeroUpTo { min, max } => (min, max),
            Allowed::Finite | Allowed::OneOf(_) => (f64::MIN, f64::MAX),
        }
    }
}

impl fmt::Display for Allowed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Allowed::Range { min, max } => write!(f, "from {} to {}", Num(*min), Num(*max)),
            Allowed::NonZeroUpTo { max, .. } => write!(f, "other than 0, at most {}", Num(*max)),
            Allowed::Finite => f.write_str("a finite number"),
            Allowed::OneOf(words) => f.write_str(words),
        }
    }
}

/// A sample (or a reply, or an error record) that is not a well-formed message of this MCM
/// version. Says which field was wrong, its value and what is allowed.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum DecodeError {
    #[error(
        "command kind {0} is not known to this MCM version (known: {first} to {last})",
        first = CommandKind::ALL[0].to_wire(),
        last = CommandKind::ALL[CommandKind::ALL.len() - 1].to_wire()
    )]
    UnknownKind(u32),
    #[error("{kind}: {field} = {} is not allowed; allowed: {allowed}", Num(*value))]
    Invalid {
        kind: CommandKind,
        field: Field,
        value: f64,
        allowed: Allowed,
    },
    #[error("{what} {value} is not known to this MCM version")]
    Unknown { what: &'static str, value: u32 },
    #[error("reply to {kind}: {problem}")]
    Mismatch {
        kind: CommandKind,
        problem: &'static str,
    },
}

/// A field of a sample, named as the protocol names it; `index` is the 0-based element of an
/// array argument (`target_positions[2]`), or the point of a `pvt_points` chunk.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    pub name: &'static str,
    pub index: Option<u8>,
}

impl Field {
    const fn named(name: &'static str) -> Field {
        Field { name, index: None }
    }

    const fn at(name: &'static str, index: usize) -> Field {
        Field {
            name,
            index: Some(index as u8),
        }
    }

    /// The axis this field concerns, for array fields indexed by axis (and the element of a
    /// Cartesian vector, carried the same way: [`Arg::per_axis_array`]).
    pub fn axis(self) -> Option<Axis> {
        match self.name {
            "target_positions" | "torques" | "external_torques" | "velocities" | "linear"
            | "angular" => self.index.and_then(|i| Axis::from_index(usize::from(i))),
            _ => None,
        }
    }
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.index {
            Some(i) => write!(f, "{}[{i}]", self.name),
            None => f.write_str(self.name),
        }
    }
}

struct Decoder<'a> {
    kind: CommandKind,
    s: &'a CommandSample,
}

impl Decoder<'_> {
    fn invalid(&self, field: Field, value: f64, allowed: Allowed) -> DecodeError {
        DecodeError::Invalid {
            kind: self.kind,
            field,
            value,
            allowed,
        }
    }

    fn flags(&self, allowed_bits: u32) -> Result<(), DecodeError> {
        let extra = self.s.flags & !allowed_bits;
        if extra == 0 {
            Ok(())
        } else {
            Err(self.invalid(
                Field::named("flags"),
                f64::from(extra),
                Allowed::OneOf("no flag bits beyond those of the command"),
            ))
        }
    }

    fn finite(&self, field: Field, x: f64) -> Result<f64, DecodeError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.invalid(field, x, Allowed::Finite))
        }
    }

    /// `N` finite numbers from `args[at..]` (`name[i]`).
    fn finite_array<const N: usize>(
        &self,
        name: &'static str,
        at: usize,
    ) -> Result<[f64; N], DecodeError> {
        let mut v = [0.0; N];
        for (i, x) in v.iter_mut().enumerate() {
            *x = self.finite(Field::at(name, i), self.s.args[at + i])?;
        }
        Ok(v)
    }

    fn axis(&self, field: Field, x: f64) -> Result<Axis, DecodeError> {
        if x.fract() == 0.0 && (1.0..=NUM_AXES as f64).contains(&x) {
            Ok(Axis(x as u8))
        } else {
            Err(self.invalid(
                field,
                x,
                Allowed::Range {
                    min: 1.0,
                    max: NUM_AXES as f64,
                },
            ))
        }
    }

    /// A value of an argument with a fixed range in [`crate::ranges`] (`field` names the
    /// element of an array argument).
    fn ranged(&self, arg: Arg, field: Field, x: f64) -> Result<f64, DecodeError> {
        let (min, max) = arg.fixed_bounds();
        if arg.accepts(x, (min, max)) {
            return Ok(x);
        }
        let allowed = match arg.spec().shape {
            crate::ranges::Shape::NonZeroUpTo => Allowed::NonZeroUpTo { min, max },
            _ => Allowed::Range { min, max },
        };
        Err(self.invalid(field, x, allowed))
    }

    /// `N` numbers from `args[at..]` of the fixed-range argument `arg` (`name[i]`).
    fn ranged_array<const N: usize>(
        &self,
        arg: Arg,
        name: &'static str,
        at: usize,
    ) -> Result<[f64; N], DecodeError> {
        let mut v = [0.0; N];
        for (i, x) in v.iter_mut().enumerate() {
            *x = self.ranged(arg, Field::at(name, i), self.s.args[at + i])?;
        }
        Ok(v)
    }

    /// A tool that [`Tool::new`] refused, as the field, the value and what is allowed.
    fn tool(&self, e: ToolError) -> DecodeError {
        let f = e.field();
        let allowed = match e {
            ToolError::Mass { .. } => {
                let (min, max) = e.bounds();
                Allowed::Range { min, max }
            }
            ToolError::NotFinite { .. } => Allowed::Finite,
            _ => Allowed::OneOf(e.allowed()),
        };
        self.invalid(
            Field {
                name: f.name,
                index: f.index,
            },
            e.value(),
            allowed,
        )
    }

    fn velocity_factor(&self, x: f64) -> Result<f64, DecodeError> {
        self.ranged(Arg::VelocityFactor, Field::named("velocity_factor"), x)
    }
}

impl Request {
    /// The command kind, as it travels in `CommandSample::kind`.
    pub fn kind(&self) -> CommandKind {
        match self {
            Request::Status => CommandKind::Status,
            Request::Hold => CommandKind::Hold,
            Request::Info => CommandKind::Info,
            Request::Calibrate(_) => CommandKind::Calibrate,
            Request::Release => CommandKind::Release,
            Request::TorqueControl(_) => CommandKind::TorqueControl,
            Request::Pvt(_) => CommandKind::Pvt,
            Request::MoveAxis(_) => CommandKind::MoveAxis,
            Request::MoveAll(_) => CommandKind::MoveAll,
            Request::PvtPoints(_) => CommandKind::PvtPoints,
            Request::SetTorques(_) => CommandKind::SetTorques,
            Request::Sim(_) => CommandKind::Sim,
            Request::TakeControl => CommandKind::TakeControl,
            Request::ReleaseControl => CommandKind::ReleaseControl,
            Request::ClientGone => CommandKind::ClientGone,
            Request::VelocityControl(_) => CommandKind::VelocityControl,
            Request::SetVelocities(_) => CommandKind::SetVelocities,
            Request::SetTool(_) => CommandKind::SetTool,
            Request::IdentifyPayload(_) => CommandKind::IdentifyPayload,
            Request::SetCartesianVelocity(_) => CommandKind::SetCartesianVelocity,
            Request::MoveLinear(_) => CommandKind::MoveLinear,
        }
    }

    /// The sample that carries this request; `client_id` and `request_id` are 0 for the
    /// sender to stamp.
    pub fn encode(&self) -> CommandSample {
        let mut s = CommandSample {
            kind: self.kind().to_wire(),
            ..CommandSample::default()
        };
        let a = &mut s.args;
        match self {
            Request::Status
            | Request::Hold
            | Request::Info
            | Request::Release
            | Request::TakeControl
            | Request::ReleaseControl
            | Request::ClientGone => {}
            Request::Calibrate(c) => {
                a[0] = c.which.code();
                a[1] = c.elbow_direction.sign();
                a[2] = c.wrist_direction.sign();
                if c.force_mechanical_stop {
                    s.flags |= CALIBRATE_FLAG_FORCE_STOP;
                }
            }
            Request::TorqueControl(t) => {
                a[0] = t.timeout_s.unwrap_or(-1.0);
                if !t.gravity_compensation {
                    s.flags |= TORQUE_FLAG_NO_GRAVITY;
                }
            }
            Request::Pvt(p) => a[0] = p.dt_s,
            Request::MoveAxis(m) => {
                a[0] = f64::from(m.axis.number());
                a[1] = m.target_deg;
                a[2] = m.velocity_factor;
            }
            Request::MoveAll(m) => {
                a[..NUM_AXES].copy_from_slice(&m.targets_deg);
                a[NUM_AXES] = m.velocity_factor;
            }
            Request::PvtPoints(c) => {
                for (j, p) in c.points().iter().enumerate() {
                    let at = j * PVT_POINT_ARGS;
                    a[at..at + NUM_AXES].copy_from_slice(&p.position_deg);
                    a[at + NUM_AXES..at + PVT_POINT_ARGS].copy_from_slice(&p.velocity_deg_s);
                }
                s.flags = u32::from(c.len) | if c.last { PVT_FLAG_LAST } else { 0 };
            }
            Request::SetTorques(t) => a[..NUM_AXES].copy_from_slice(&t.torques_nm),
            Request::VelocityControl(v) => a[0] = v.timeout_s.unwrap_or(-1.0),
            Request::SetVelocities(v) => a[..NUM_AXES].copy_from_slice(&v.velocities_deg_s),
            Request::SetTool(SetTool { tool: t }) => {
                let [p, o, m, c, i, end] = TOOL_ARGS;
                a[p..o].copy_from_slice(&t.tcp.position);
                a[o..m].copy_from_slice(&t.tcp.orientation);
                a[m] = t.mass;
                a[c..i].copy_from_slice(&t.center_of_mass);
                a[i..end].copy_from_slice(&t.inertia);
            }
            Request::IdentifyPayload(i) => {
                if i.apply {
                    s.flags |= IDENTIFY_FLAG_APPLY;
                }
            }
            Request::SetCartesianVelocity(v) => {
                let [l, w, f] = TWIST_ARGS;
                a[l..l + 3].copy_from_slice(&v.linear_m_s);
                a[w..w + 3].copy_from_slice(&v.angular_deg_s);
                a[f] = v.frame.code();
            }
            Request::MoveLinear(m) => {
                let [p, o, v, acc] = LINE_ARGS;
                a[p..o].copy_from_slice(&m.position);
                if let Some(q) = m.orientation {
                    a[o..v].copy_from_slice(&q);
                    s.flags |= LINE_FLAG_ORIENTATION;
                }
                if let Some(x) = m.velocity {
                    a[v] = x;
                    s.flags |= LINE_FLAG_VELOCITY;
                }
                if let Some(x) = m.acceleration {
                    a[acc] = x;
                    s.flags |= LINE_FLAG_ACCELERATION;
                }
            }
            Request::Sim(c) => {
                let mut set = |bit: usize, value: f64| {
                    a[bit] = value;
                    s.flags |= 1 << bit;
                };
                if let Some(e) = c.emergency_stop {
                    set(0, f64::from(u8::from(e)));
                }
                for (bit, axis) in [
                    (1, c.disconnect_axis),
                    (2, c.reconnect_axis),
                    (3, c.block_axis),
                    (4, c.unblock_axis),
                ] {
                    if let Some(axis) = axis {
                        set(bit, f64::from(axis.number()));
                    }
                }
                if let Some(t) = c.external_torques_nm {
                    a[5..5 + NUM_AXES].copy_from_slice(&t);
                    s.flags |= 1 << 5;
                }
                if let Some(t) = c.true_tool {
                    a[SIM_TRUE_TOOL] = t.mass;
                    a[SIM_TRUE_TOOL + 1..SIM_TRUE_TOOL + 4].copy_from_slice(&t.center_of_mass);
                    s.flags |= 1 << 6;
                }
                if c.power_cycle {
                    s.flags |= SIM_FLAG_POWER_CYCLE;
                }
            }
        }
        s
    }

    /// The request a sample carries, every value checked. Never allocates or panics, whatever
    /// the sample holds.
    pub fn decode(s: &CommandSample) -> Result<Request, DecodeError> {
        let kind = CommandKind::try_from(s.kind).map_err(|_| DecodeError::UnknownKind(s.kind))?;
        let d = Decoder { kind, s };
        let a = &s.args;
        Ok(match kind {
            CommandKind::Status
            | CommandKind::Hold
            | CommandKind::Info
            | CommandKind::Release
            | CommandKind::TakeControl
            | CommandKind::ReleaseControl
            | CommandKind::ClientGone => {
                d.flags(0)?;
                match kind {
                    CommandKind::Status => Request::Status,
                    CommandKind::Hold => Request::Hold,
                    CommandKind::Info => Request::Info,
                    CommandKind::TakeControl => Request::TakeControl,
                    CommandKind::ReleaseControl => Request::ReleaseControl,
                    CommandKind::ClientGone => Request::ClientGone,
                    _ => Request::Release,
                }
            }
            CommandKind::Calibrate => {
                d.flags(CALIBRATE_FLAG_FORCE_STOP)?;
                let which = Which::from_code(a[0]).ok_or_else(|| {
                    d.invalid(
                        Field::named("which"),
                        a[0],
                        Allowed::OneOf("0 (ALL), 1 to 6 (one axis), 7 (ELBOW) or 8 (WRIST)"),
                    )
                })?;
                let dir = |name, x| {
                    Direction::from_sign(x)
                        .ok_or_else(|| d.invalid(Field::named(name), x, Allowed::OneOf("1 or -1")))
                };
                Request::Calibrate(Calibrate {
                    which,
                    elbow_direction: dir("elbow_direction", a[1])?,
                    wrist_direction: dir("wrist_direction", a[2])?,
                    force_mechanical_stop: s.flags & CALIBRATE_FLAG_FORCE_STOP != 0,
                })
            }
            CommandKind::TorqueControl => {
                d.flags(TORQUE_FLAG_NO_GRAVITY)?;
                let t = d.ranged(Arg::Timeout, Field::named("timeout"), a[0])?;
                Request::TorqueControl(TorqueControl {
                    timeout_s: (t > 0.0).then_some(t),
                    gravity_compensation: s.flags & TORQUE_FLAG_NO_GRAVITY == 0,
                })
            }
            CommandKind::VelocityControl => {
                d.flags(0)?;
                // The same `timeout` as `torque_control`'s ([`Arg::Timeout`]).
                let t = d.ranged(Arg::Timeout, Field::named("timeout"), a[0])?;
                Request::VelocityControl(VelocityControl {
                    timeout_s: (t > 0.0).then_some(t),
                })
            }
            CommandKind::SetVelocities => {
                d.flags(0)?;
                Request::SetVelocities(SetVelocities {
                    velocities_deg_s: d.finite_array("velocities", 0)?,
                })
            }
            CommandKind::SetTool => {
                d.flags(0)?;
                let [p, o, m, c, i, end] = TOOL_ARGS;
                let tcp = Tcp {
                    position: [a[p], a[p + 1], a[p + 2]],
                    orientation: [a[o], a[o + 1], a[o + 2], a[o + 3]],
                };
                let mut inertia = [0.0; 6];
                inertia.copy_from_slice(&a[i..end]);
                let tool = Tool::new(tcp, a[m], [a[c], a[c + 1], a[c + 2]], Some(inertia))
                    .map_err(|e| d.tool(e))?;
                Request::SetTool(SetTool { tool })
            }
            CommandKind::IdentifyPayload => {
                d.flags(IDENTIFY_FLAG_APPLY)?;
                Request::IdentifyPayload(IdentifyPayload {
                    apply: s.flags & IDENTIFY_FLAG_APPLY != 0,
                })
            }
            CommandKind::SetCartesianVelocity => {
                d.flags(0)?;
                let [l, w, f] = TWIST_ARGS;
                let frame = CartesianFrame::from_code(a[f]).ok_or_else(|| {
                    d.invalid(
                        Field::named("frame"),
                        a[f],
                        Allowed::OneOf("0 (base) or 1 (tool)"),
                    )
                })?;
                Request::SetCartesianVelocity(SetCartesianVelocity {
                    linear_m_s: d.ranged_array(Arg::Linear, "linear", l)?,
                    angular_deg_s: d.ranged_array(Arg::Angular, "angular", w)?,
                    frame,
                })
            }
            CommandKind::MoveLinear => {
                d.flags(LINE_FLAG_ORIENTATION | LINE_FLAG_VELOCITY | LINE_FLAG_ACCELERATION)?;
                let [p, o, v, acc] = LINE_ARGS;
                let position = d.finite_array("position", p)?;
                let orientation = if s.flags & LINE_FLAG_ORIENTATION != 0 {
                    let q = d.finite_array("orientation", o)?;
                    Some(crate::units::unit_quaternion(q).map_err(|norm| {
                        d.invalid(
                            Field::named("orientation (its norm)"),
                            norm,
                            Allowed::OneOf("a unit quaternion [x, y, z, w] (norm 1)"),
                        )
                    })?)
                } else {
                    None
                };
                let optional = |flag: u32, arg: Arg, x: f64| {
                    (s.flags & flag != 0)
                        .then(|| d.ranged(arg, Field::named(arg.name()), x))
                        .transpose()
                };
                Request::MoveLinear(MoveLinear {
                    position,
                    orientation,
                    velocity: optional(LINE_FLAG_VELOCITY, Arg::LinearVelocity, a[v])?,
                    acceleration: optional(
                        LINE_FLAG_ACCELERATION,
                        Arg::LinearAcceleration,
                        a[acc],
                    )?,
                })
            }
            CommandKind::Pvt => {
                d.flags(0)?;
                // Its range starts at one cycle period: the core checks it (`crate::ranges`).
                Request::Pvt(Pvt {
                    dt_s: d.finite(Field::named("dt"), a[0])?,
                })
            }
            CommandKind::MoveAxis => {
                d.flags(0)?;
                Request::MoveAxis(MoveAxis {
                    axis: d.axis(Field::named("axis_index"), a[0])?,
                    target_deg: d.finite(Field::named("target_position"), a[1])?,
                    velocity_factor: d.velocity_factor(a[2])?,
                })
            }
            CommandKind::MoveAll => {
                d.flags(0)?;
                Request::MoveAll(MoveAll {
                    targets_deg: d.finite_array("target_positions", 0)?,
                    velocity_factor: d.velocity_factor(a[NUM_AXES])?,
                })
            }
            CommandKind::PvtPoints => {
                d.flags(PVT_COUNT_MASK | PVT_FLAG_LAST)?;
                let count = (s.flags & PVT_COUNT_MASK) as usize;
                if count == 0 || count > PVT_POINTS_PER_COMMAND {
                    return Err(d.invalid(
                        Field::named("points in the sample"),
                        count as f64,
                        Allowed::Range {
                            min: 1.0,
                            max: PVT_POINTS_PER_COMMAND as f64,
                        },
                    ));
                }
                let mut points = [PvtPoint::default(); PVT_POINTS_PER_COMMAND];
                for (j, p) in points.iter_mut().enumerate().take(count) {
                    let at = j * PVT_POINT_ARGS;
                    for i in 0..NUM_AXES {
                        p.position_deg[i] = d.finite(Field::at("points.position", j), a[at + i])?;
                        p.velocity_deg_s[i] =
                            d.finite(Field::at("points.velocity", j), a[at + NUM_AXES + i])?;
                    }
                }
                Request::PvtPoints(PvtChunk {
                    points,
                    len: count as u8,
                    last: s.flags & PVT_FLAG_LAST != 0,
                })
            }
            CommandKind::SetTorques => {
                d.flags(0)?;
                Request::SetTorques(SetTorques {
                    torques_nm: d.finite_array("torques", 0)?,
                })
            }
            CommandKind::Sim => {
                d.flags(SIM_FIELDS | SIM_FLAG_POWER_CYCLE)?;
                let has = |bit: usize| s.flags & (1 << bit) != 0;
                let axis = |bit: usize, name| -> Result<Option<Axis>, DecodeError> {
                    if has(bit) {
                        d.axis(Field::named(name), a[bit]).map(Some)
                    } else {
                        Ok(None)
                    }
                };
                let emergency_stop = if has(0) {
                    match a[0] {
                        0.0 => Some(false),
                        1.0 => Some(true),
                        x => {
                            return Err(d.invalid(
                                Field::named("emergency_stop"),
                                x,
                                Allowed::OneOf("0 (released) or 1 (pressed)"),
                            ));
                        }
                    }
                } else {
                    None
                };
                Request::Sim(SimCommand {
                    emergency_stop,
                    disconnect_axis: axis(1, "disconnect_axis")?,
                    reconnect_axis: axis(2, "reconnect_axis")?,
                    block_axis: axis(3, "block_axis")?,
                    unblock_axis: axis(4, "unblock_axis")?,
                    external_torques_nm: if has(5) {
                        let mut t = [0.0; NUM_AXES];
                        for (i, x) in t.iter_mut().enumerate() {
                            let field = Field::at("external_torques", i);
                            *x = d.ranged(Arg::ExternalTorques, field, a[5 + i])?;
                        }
                        Some(t)
                    } else {
                        None
                    },
                    power_cycle: s.flags & SIM_FLAG_POWER_CYCLE != 0,
                    true_tool: if has(6) {
                        let at = SIM_TRUE_TOOL;
                        let com = [a[at + 1], a[at + 2], a[at + 3]];
                        let tool = SimCommand::true_tool(a[at], com).map_err(|e| d.tool(e))?;
                        Some(tool)
                    } else {
                        None
                    },
                })
            }
        })
    }
}

#[cfg(test)]
mod tests;
