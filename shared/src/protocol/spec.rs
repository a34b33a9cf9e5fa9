//! What is known of each command apart from its values: its name, the wire kind that carries it,
//! what it answers on success, and its description for people (arguments in positional order,
//! their kinds, short names, defaults and units, the modes that accept it). The HMI's line
//! parser uses the arguments to turn words into a JSON `arguments` object, `help` explains the
//! command from it, and [`super::Args`] accepts exactly the arguments listed. Not used inside the
//! real-time cycle.

use super::results::Answer;
use crate::mode::CommandKind;

/// What a command answers on success.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Success {
    /// `{"result_type":"generic","error_status":"OK"}`.
    Ok,
    /// A `status` result.
    Status,
    /// Nothing: a refusal comes as an ERROR later (`set_torques`, `set_velocities`,
    /// `set_cartesian_velocity`).
    Nothing,
    /// The `initialization` result (`info`).
    Initialization,
    /// The `move_all` result.
    MoveAll,
    /// The `move_linear` result.
    MoveLinear,
    /// The `sim` result.
    Sim,
    /// The `inverse_kinematics` result.
    InverseKinematics,
    /// The `payload` result (`identify_payload`).
    Payload,
}

impl Success {
    /// The `result_type` of the answer ([`Answer::result_type`]); `None` for
    /// [`Success::Nothing`].
    pub const fn result_type(self) -> Option<&'static str> {
        match self {
            Success::Ok => Some("generic"),
            Success::Status => Some("status"),
            Success::Nothing => None,
            Success::Initialization => Some("initialization"),
            Success::MoveAll => Some("move_all"),
            Success::MoveLinear => Some("move_linear"),
            Success::Sim => Some("sim"),
            Success::InverseKinematics => Some("inverse_kinematics"),
            Success::Payload => Some("payload"),
        }
    }

    /// Whether `answer` is what a command answers on success: a `generic` OK for
    /// [`Success::Ok`], a result of the type [`Success::result_type`] names otherwise (a
    /// command that answers [`Success::Nothing`] is answered by no result).
    pub fn answers(self, answer: &Answer) -> bool {
        match (self, answer) {
            (Success::Ok, Answer::Generic(g)) => g.is_ok(),
            (Success::Nothing, _) => false,
            (s, a) => s.result_type() == Some(a.result_type()),
        }
    }
}

/// The groups of `help`, in the order it lists them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    EveryMode,
    Control,
    OffAndHold,
    ModeChange,
    Pvt,
    TorqueControl,
    VelocityControl,
    Tool,
}

impl Group {
    /// Every group, in the order `help` lists them.
    pub const ALL: [Group; 8] = [
        Group::EveryMode,
        Group::Control,
        Group::OffAndHold,
        Group::ModeChange,
        Group::Pvt,
        Group::TorqueControl,
        Group::VelocityControl,
        Group::Tool,
    ];

    /// The heading `help` gives the group.
    pub const fn title(self) -> &'static str {
        match self {
            Group::EveryMode => "In every mode",
            Group::Control => "Control of the arm (one client at a time)",
            Group::OffAndHold => "In OFF and HOLD",
            Group::ModeChange => "In HOLD (all axes calibrated): change the mode",
            Group::Pvt => "In PVT",
            Group::TorqueControl => "In TORQUE_CONTROL",
            Group::VelocityControl => "In VELOCITY_CONTROL",
            Group::Tool => "In HOLD, or PVT at standstill: the tool",
        }
    }
}

/// How the words of an argument become a JSON value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Number,
    /// An axis number 1..6.
    Axis,
    /// `true`/`false` (also `on`/`off`, `yes`/`no`, `1`/`0`); the bare name means `true`.
    Bool,
    /// Six numbers, one per axis: six words, `a,b,c,d,e,f`, or a JSON array.
    Six,
    /// A Cartesian position: three numbers [m] (`x,y,z`), written as [`Kind::Six`] is.
    Position,
    /// A Cartesian vector (a velocity): three numbers `x,y,z`, written as [`Kind::Six`] is.
    Vector,
    /// An orientation: the four numbers of a unit quaternion (`x,y,z,w`), written as
    /// [`Kind::Six`] is.
    Orientation,
    /// `ALL`, `ELBOW`, `WRIST` or an axis number.
    Which,
    /// `1` or `-1`.
    Direction,
    /// A JSON array of PVT points (bracketed or quoted).
    Points,
    /// A word taken as text, whatever it looks like (the shared secret).
    Text,
    /// A JSON object or array of numbers (bracketed or quoted), e.g. a tool's `tcp`.
    Json,
}

impl Kind {
    /// A placeholder for usage lines.
    pub fn placeholder(self) -> &'static str {
        match self {
            Kind::Number => "X",
            Kind::Axis => "1..6",
            Kind::Bool => "true|false",
            Kind::Six => "a,b,c,d,e,f",
            Kind::Position | Kind::Vector => "x,y,z",
            Kind::Orientation => "x,y,z,w",
            Kind::Which => "ALL|ELBOW|WRIST|1..6",
            Kind::Direction => "1|-1",
            Kind::Points => "[...]",
            Kind::Text => "TEXT",
            Kind::Json => "{...}",
        }
    }

    /// For a kind of several numbers ([`Kind::Six`], [`Kind::Position`], [`Kind::Vector`],
    /// [`Kind::Orientation`]): how many, and what they are in words; `None` for the others.
    pub const fn numbers(self) -> Option<(usize, &'static str)> {
        match self {
            Kind::Six => Some((6, "one per axis")),
            Kind::Position => Some((3, "x, y, z in metres")),
            Kind::Vector => Some((3, "x, y, z")),
            Kind::Orientation => Some((4, "a quaternion x, y, z, w")),
            Kind::Number
            | Kind::Axis
            | Kind::Bool
            | Kind::Which
            | Kind::Direction
            | Kind::Points
            | Kind::Text
            | Kind::Json => None,
        }
    }
}

/// One argument of a command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ArgDef {
    /// The protocol name.
    pub name: &'static str,
    /// A short name accepted in `name=value` ("" for none).
    pub alias: &'static str,
    pub kind: Kind,
    /// May be given by position (in the order of `CommandSpec::args`).
    pub positional: bool,
    /// The default, for people ("" = required).
    pub default: &'static str,
    /// What it is, with its unit and range.
    pub help: &'static str,
}

/// One command of the protocol: everything about it that is not the values of one instance.
/// Each command module in [`super::cmd`] holds its `DEF`; [`super::COMMANDS`] lists them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandDef {
    /// The protocol name.
    pub name: &'static str,
    /// The wire kind that carries it to the real-time core; `None` for the commands the
    /// gateway executes itself (`sleep`, `authenticate`).
    pub kind: Option<CommandKind>,
    /// For a command the gateway executes itself (`kind` is `None`): the kind of the request
    /// it sends the core to do it (`move_to_pose` sends a `move_all`), whose rule on control of
    /// the arm it follows; `None` for every other command.
    pub sends: Option<CommandKind>,
    /// What it answers on success.
    pub success: Success,
    /// The group `help` lists it in.
    pub group: Group,
    /// Words the HMI adds after `OK` ("" for none), e.g. " - points queued".
    pub ok_words: &'static str,
    pub summary: &'static str,
    pub args: &'static [ArgDef],
    /// The modes that accept the command.
    pub modes: &'static str,
    /// How to get into such a mode ("" when every mode accepts it).
    pub how: &'static str,
    /// What the command answers.
    pub reply: &'static str,
    pub examples: &'static [&'static str],
    /// Anything else worth knowing ("" for nothing).
    pub notes: &'static str,
}

impl CommandDef {
    /// The argument called `name` (protocol name or short name, any case).
    pub fn arg(&self, name: &str) -> Option<&'static ArgDef> {
        let args: &'static [ArgDef] = self.args;
        args.iter().find(|a| {
            a.name.eq_ignore_ascii_case(name)
                || (!a.alias.is_empty() && a.alias.eq_ignore_ascii_case(name))
        })
    }

    /// Every argument name and short name (for "did you mean").
    pub fn arg_names(&self) -> Vec<&'static str> {
        let args: &'static [ArgDef] = self.args;
        args.iter()
            .flat_map(|a| [a.name, a.alias])
            .filter(|n| !n.is_empty())
            .collect()
    }

    /// Whether only the client that controls the arm may send it
    /// ([`CommandKind::needs_control`] of its kind, or of the kind it [`CommandDef::sends`]).
    pub const fn needs_control(&self) -> bool {
        match (self.kind, self.sends) {
            (Some(k), _) | (None, Some(k)) => k.needs_control(),
            (None, None) => false,
        }
    }

    /// Every argument name, in order (what `arguments` may hold).
    pub fn arg_list(&self) -> impl Iterator<Item = &'static str> {
        let args: &'static [ArgDef] = self.args;
        args.iter().map(|a| a.name)
    }

    /// The arguments that may be given by position.
    pub fn positional(&self) -> Vec<&'static ArgDef> {
        let args: &'static [ArgDef] = self.args;
        args.iter().filter(|a| a.positional).collect()
    }

    /// One usage line, e.g. `move_axis <axis_index> <target_position> [velocity_factor]`.
    pub fn usage(&self) -> String {
        let mut s = self.name.to_string();
        for a in self.args {
            s.push(' ');
            match (a.positional, a.default.is_empty()) {
                (true, true) if a.kind.numbers().is_some() => {
                    let n = a.kind.numbers().map_or(0, |(n, _)| n);
                    s.push_str(&format!("<{} x{n}>", a.name))
                }
                (true, true) => s.push_str(&format!("<{}>", a.name)),
                (true, false) => s.push_str(&format!("[{}]", a.name)),
                (false, _) => s.push_str(&format!("[{}={}]", a.name, a.kind.placeholder())),
            }
        }
        s
    }
}

pub(crate) const fn arg(
    name: &'static str,
    alias: &'static str,
    kind: Kind,
    positional: bool,
    default: &'static str,
    help: &'static str,
) -> ArgDef {
    ArgDef {
        name,
        alias,
        kind,
        positional,
        default,
        help,
    }
}

pub(crate) const VELOCITY_FACTOR: ArgDef = arg(
    "velocity_factor",
    "vf",
    Kind::Number,
    true,
    "0.33333",
    "fraction of each axis's maximum velocity, from 0.001 to 1",
);

/// `dt_status` of `torque_control` and `velocity_control`.
pub(crate) const DT_STATUS: ArgDef = arg(
    "dt_status",
    "",
    Kind::Number,
    true,
    "0",
    "interval of spontaneous status results [s], 0 to 60 (JSON channel only)",
);

pub(crate) const IN_HOLD: &str = "HOLD, with every axis calibrated";
pub(crate) const TO_HOLD: &str = "`hold` first (and `calibrate` if an axis is not calibrated)";
pub(crate) const TO_PVT: &str = "enter PVT mode first: `hold`, then `pvt`";
