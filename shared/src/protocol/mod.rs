//! # The JSON contract: every command of the protocol defined once
//!
//! The JSON protocol (port 18010), the text HMI, the ZeroMQ interface and the Rust client all
//! speak through this module. As in tokio's mini-redis, each command is one file in [`cmd`]: its
//! typed arguments, how they are read from and written to a JSON `arguments` object, the
//! typed requests that carry it to the real-time core, and its [`CommandDef`] (name, wire kind,
//! what it answers on success, its help for people). [`Command`] and [`COMMANDS`] are derived
//! from the list in `commands!` below; so are the command names, the help groups and the set of
//! commands that answer nothing on success. The typed results are in [`results`]; how long
//! the MCM may take to answer each command is in [`wait`].
//!
//! Parsing checks every value against [`crate::ranges`] (the same table the core checks
//! against) and the robot's configuration, and refuses with a [`CommandError`] that names the
//! command, the argument, the value and what is allowed.
//!
//! ```
//! use mcm_shared::command::{Axis, MoveAxis};
//! use mcm_shared::config::RobotConfig;
//! use mcm_shared::protocol::Command;
//! let cfg = RobotConfig::prob2_default();
//! let cmd = Command::from_json(
//!     r#"{"command":"move_axis","arguments":{"axis_index":2,"target_position":30}}"#,
//!     &cfg,
//! )?;
//! let Command::MoveAxis(m) = &cmd else { unreachable!() };
//! assert_eq!((m.axis, m.target_deg), (Axis::new(2).unwrap(), 30.0));
//! assert!(cmd.def().needs_control());
//! // A client writes the same command with the same code:
//! assert_eq!(Command::from_value(&cmd.to_json(), &cfg)?, cmd);
//! # Ok::<(), mcm_shared::protocol::CommandError>(())
//! ```
//!
//! Adding a command: `docs/architecture.md`, "How to add a command". Not used inside the
//! real-time cycle.

pub mod args;
pub mod cmd;
pub mod json;
pub mod pose;
pub mod results;
pub mod spec;
pub mod wait;

pub use args::{Args, CommandError};
pub use cmd::authenticate::{Authenticate, Secret};
pub use cmd::calibrate::DEFAULT_WHICH;
pub use cmd::hold::Hold;
pub use cmd::info::Info;
pub use cmd::inverse_kinematics::InverseKinematics;
pub use cmd::move_axis::DEFAULT_VELOCITY_FACTOR;
pub use cmd::move_to_pose::MoveToPose;
pub use cmd::pvt::DEFAULT_PVT_DT;
pub use cmd::pvt_points::{MAX_POINTS_PER_BATCH, PvtPoints};
pub use cmd::release::Release;
pub use cmd::release_control::ReleaseControl;
pub use cmd::sleep::Sleep;
pub use cmd::status::Status;
pub use cmd::take_control::TakeControl;
pub use cmd::torque_control::{DEFAULT_MODE_TIMEOUT, TorqueControl};
pub use cmd::velocity_control::VelocityControl;
pub use pose::Pose;
pub use spec::{ArgDef, CommandDef, Group, Kind, Success};
pub use wait::{CALIBRATION_TIMEOUT, IDENTIFY_PAYLOAD_TIMEOUT, REPLY_TIMEOUT, core_reply_within};

use crate::command::{
    Calibrate, IdentifyPayload, MoveAll, MoveAxis, MoveLinear, Pvt, Request, SetCartesianVelocity,
    SetTool, SetTorques, SetVelocities, SimCommand,
};
use crate::config::RobotConfig;
use json::json_kind;
use serde_json::{Map, Value};

/// Longest command the MCM takes (64 KiB): a JSON object, from `{` to its `}`, of this many
/// bytes is read; one byte more closes the connection (`docs/protocol.md`). A client keeps its
/// command lines within it.
pub const MAX_COMMAND_BYTES: usize = 64 * 1024;

/// One command of the protocol: its definition, and its values read from and written to JSON.
/// Each type in [`cmd`] implements it; [`Command`] dispatches to them.
pub trait Definition: Sized {
    /// Everything about the command that is not its values.
    const DEF: CommandDef;

    /// The command from its `arguments` (their names already checked against `DEF.args`),
    /// every value checked; `cfg` gives the ranges that depend on the robot.
    fn parse(args: &Args<'_>, cfg: &RobotConfig) -> Result<Self, CommandError>;

    /// The `arguments` object that [`Definition::parse`] reads back as `self` (empty: none).
    fn arguments(&self) -> Map<String, Value> {
        Map::new()
    }

    /// The typed requests that carry it to the real-time core: one, or the chunks of a
    /// `pvt_points` batch; none for what the gateway executes itself.
    fn requests(&self) -> Vec<Request>;
}

macro_rules! commands {
    ($($(#[$doc:meta])* $variant:ident($ty:ty),)*) => {
        /// One parsed, validated command of the protocol.
        #[derive(Debug, Clone, PartialEq)]
        pub enum Command {
            $($(#[$doc])* $variant($ty),)*
        }

        /// Every command, in the order `help` and the "known commands" list give them.
        pub const COMMANDS: &[&CommandDef] = &[$(&<$ty as Definition>::DEF,)*];

        impl Command {
            /// Its definition.
            pub fn def(&self) -> &'static CommandDef {
                match self {
                    $(Command::$variant(_) => &<$ty as Definition>::DEF,)*
                }
            }

            /// Parse the `arguments` of the command `def` (one of [`COMMANDS`]).
            pub fn parse(
                def: &'static CommandDef,
                arguments: Option<&Value>,
                cfg: &RobotConfig,
            ) -> Result<Command, CommandError> {
                let args = Args::new(def, arguments)?;
                $(
                    if def.name == <$ty as Definition>::DEF.name {
                        return <$ty as Definition>::parse(&args, cfg).map(Command::$variant);
                    }
                )*
                Err(unknown_command(def.name))
            }

            /// The `arguments` object of this command (empty: none).
            pub fn arguments(&self) -> Map<String, Value> {
                match self {
                    $(Command::$variant(c) => c.arguments(),)*
                }
            }

            /// The typed requests that carry this command to the real-time core.
            pub fn requests(&self) -> Vec<Request> {
                match self {
                    $(Command::$variant(c) => c.requests(),)*
                }
            }
        }

        $(
            impl From<$ty> for Command {
                fn from(c: $ty) -> Command {
                    Command::$variant(c)
                }
            }
        )*
    };
}

commands! {
    Status(Status),
    Info(Info),
    Hold(Hold),
    Calibrate(Calibrate),
    Release(Release),
    TorqueControl(TorqueControl),
    SetTorques(SetTorques),
    VelocityControl(VelocityControl),
    SetVelocities(SetVelocities),
    SetCartesianVelocity(SetCartesianVelocity),
    Pvt(Pvt),
    MoveAxis(MoveAxis),
    MoveAll(MoveAll),
    MoveToPose(MoveToPose),
    MoveLinear(MoveLinear),
    PvtPoints(PvtPoints),
    Sleep(Sleep),
    Sim(SimCommand),
    TakeControl(TakeControl),
    ReleaseControl(ReleaseControl),
    Authenticate(Authenticate),
    InverseKinematics(InverseKinematics),
    SetTool(SetTool),
    IdentifyPayload(IdentifyPayload),
}

/// The command called `name` (any case).
pub fn find(name: &str) -> Option<&'static CommandDef> {
    COMMANDS
        .iter()
        .copied()
        .find(|c| c.name.eq_ignore_ascii_case(name))
}

/// Every command name, in the order of [`COMMANDS`].
pub fn command_names() -> impl Iterator<Item = &'static str> {
    COMMANDS.iter().map(|c| c.name)
}

impl Command {
    /// Parse one JSON text (a complete object from the framing layer); a key repeated in any
    /// object is refused.
    pub fn from_json(text: &str, cfg: &RobotConfig) -> Result<Command, CommandError> {
        let value = json::parse(text).map_err(|e| match e {
            json::ParseError::Syntax(s) => CommandError::Json(s),
            json::ParseError::DuplicateKey { key } => CommandError::DuplicateKey { key },
        })?;
        Self::from_value(&value, cfg)
    }

    /// Parse one JSON value.
    pub fn from_value(value: &Value, cfg: &RobotConfig) -> Result<Command, CommandError> {
        let obj = value.as_object().ok_or_else(|| {
            CommandError::Framing(format!(
                "expected a JSON object, got a JSON {}",
                json_kind(value)
            ))
        })?;
        let name = match obj.get("command") {
            None => return Err(CommandError::MissingCommand),
            Some(Value::String(s)) => s.as_str(),
            Some(other) => {
                return Err(CommandError::CommandNotString {
                    got: json_kind(other),
                });
            }
        };
        let def = COMMANDS
            .iter()
            .copied()
            .find(|d| d.name == name)
            .ok_or_else(|| unknown_command(name))?;
        if let Some(field) = obj.keys().find(|k| *k != "command" && *k != "arguments") {
            return Err(CommandError::UnknownField {
                command: def.name,
                field: field.clone(),
            });
        }
        Self::parse(def, obj.get("arguments"), cfg)
    }

    /// The protocol name.
    pub fn name(&self) -> &'static str {
        self.def().name
    }

    /// The command as a client sends it: `{"command": name, "arguments": {...}}` (without
    /// `arguments` when it has none). [`Command::from_value`] reads it back as `self`.
    pub fn to_json(&self) -> Value {
        let mut obj = Map::new();
        obj.insert("command".into(), Value::from(self.name()));
        let args = self.arguments();
        if !args.is_empty() {
            obj.insert("arguments".into(), Value::Object(args));
        }
        Value::Object(obj)
    }
}

fn unknown_command(name: &str) -> CommandError {
    CommandError::UnknownCommand {
        name: name.chars().take(40).collect(),
        suggestion: suggest(name, COMMANDS.iter().map(|c| c.name)),
        known: command_names().collect::<Vec<_>>().join(", "),
    }
}

/// The closest of `candidates` to `word` when it is a plausible typo (edit distance <= 2, or
/// a unique prefix of at least 3 letters).
pub fn suggest(
    word: &str,
    candidates: impl IntoIterator<Item = &'static str>,
) -> Option<&'static str> {
    let word = word.to_ascii_lowercase();
    let candidates: Vec<&'static str> = candidates.into_iter().collect();
    let best = candidates
        .iter()
        .map(|c| (edit_distance(&word, c), *c))
        .min_by_key(|(d, _)| *d)?;
    if best.0 <= 2 && best.0 < word.len() {
        return Some(best.1);
    }
    let prefixed: Vec<_> = candidates
        .iter()
        .filter(|c| word.len() >= 3 && c.starts_with(&word))
        .collect();
    (prefixed.len() == 1).then(|| *prefixed[0])
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            let cost = usize::from(ca != *cb);
            cur[j + 1] = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests;
