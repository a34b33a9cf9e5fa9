//! The commands of the JSON protocol, one file each: parsing and validation of the arguments
//! into the typed requests of [`mcm_shared::command`], which the bridge encodes for the
//! real-time core. The gateway keeps its own types only for what it does itself (`status`'s
//! `detail`, `torque_control`'s and `velocity_control`'s `dt_status`, `sleep`, `authenticate`, a whole `pvt_points`
//! batch).
//!
//! The text HMI parses its words into the same [`Command`] type, so both channels share one
//! execution path.

pub mod authenticate;
mod calibrate;
pub mod info;
mod modes;
pub mod move_all;
mod move_axis;
mod pvt_points;
mod release_control;
mod set_torques;
mod set_velocities;
pub mod sim;
mod sleep;
mod status;
mod take_control;
mod velocity_control;

pub use authenticate::Secret;
pub use modes::TorqueControl;
pub use pvt_points::PvtPoints;
pub use sleep::Sleep;
pub use status::Status;
pub use velocity_control::VelocityControl;

use crate::args::CommandError;
use crate::framing::json_kind;
use mcm_shared::command::{
    Calibrate, MoveAll, MoveAxis, Pvt, PvtChunk, Request, SetTorques, SetVelocities, SimCommand,
};
use mcm_shared::config::RobotConfig;
use serde_json::Value;

/// Every command name of the protocol, in the order `help` lists them.
pub const COMMAND_NAMES: &[&str] = &[
    "status",
    "info",
    "hold",
    "calibrate",
    "release",
    "torque_control",
    "set_torques",
    "velocity_control",
    "set_velocities",
    "pvt",
    "move_axis",
    "move_all",
    "pvt_points",
    "sleep",
    "sim",
    "take_control",
    "release_control",
    "authenticate",
];

/// The default `velocity_factor` of the manual.
pub const DEFAULT_VELOCITY_FACTOR: f64 = 0.33333;

/// One parsed, validated command.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    Status(Status),
    Info,
    Hold,
    Calibrate(Calibrate),
    Release,
    TorqueControl(TorqueControl),
    SetTorques(SetTorques),
    VelocityControl(VelocityControl),
    SetVelocities(SetVelocities),
    Pvt(Pvt),
    MoveAxis(MoveAxis),
    MoveAll(MoveAll),
    PvtPoints(PvtPoints),
    Sleep(Sleep),
    Sim(SimCommand),
    TakeControl,
    ReleaseControl,
    Authenticate(Secret),
}

impl Command {
    /// Parse one JSON text (a complete object from the framing layer).
    pub fn from_json(text: &str, cfg: &RobotConfig) -> Result<Command, CommandError> {
        let value = crate::json::parse(text).map_err(|e| match e {
            crate::json::ParseError::Syntax(s) => CommandError::Json(s),
            crate::json::ParseError::DuplicateKey { key } => CommandError::DuplicateKey { key },
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
        let canonical = COMMAND_NAMES
            .iter()
            .copied()
            .find(|n| *n == name)
            .ok_or_else(|| unknown_command(name))?;
        if let Some(field) = obj.keys().find(|k| *k != "command" && *k != "arguments") {
            return Err(CommandError::UnknownField {
                command: canonical,
                field: field.clone(),
            });
        }
        Self::parse(canonical, obj.get("arguments"), cfg)
    }

    /// Parse the arguments of the command `name` (one of [`COMMAND_NAMES`]).
    pub fn parse(
        name: &'static str,
        arguments: Option<&Value>,
        cfg: &RobotConfig,
    ) -> Result<Command, CommandError> {
        use crate::args::Args;
        let no_args = |n| Args::new(n, arguments, &[]).map(|_| ());
        Ok(match name {
            "status" => Command::Status(Status::parse(arguments)?),
            "info" => {
                no_args(name)?;
                Command::Info
            }
            "hold" => {
                no_args(name)?;
                Command::Hold
            }
            "release" => {
                no_args(name)?;
                Command::Release
            }
            "calibrate" => Command::Calibrate(calibrate::parse(arguments)?),
            "torque_control" => Command::TorqueControl(TorqueControl::parse(arguments)?),
            "set_torques" => Command::SetTorques(set_torques::parse(arguments, cfg)?),
            "velocity_control" => Command::VelocityControl(VelocityControl::parse(arguments)?),
            "set_velocities" => Command::SetVelocities(set_velocities::parse(arguments, cfg)?),
            "pvt" => Command::Pvt(modes::parse_pvt(arguments, cfg)?),
            "move_axis" => Command::MoveAxis(move_axis::parse(arguments, cfg)?),
            "move_all" => Command::MoveAll(move_all::parse(arguments, cfg)?),
            "pvt_points" => Command::PvtPoints(PvtPoints::parse(arguments)?),
            "sleep" => Command::Sleep(Sleep::parse(arguments)?),
            "sim" => Command::Sim(sim::parse(arguments, cfg)?),
            "take_control" => {
                take_control::parse(arguments)?;
                Command::TakeControl
            }
            "release_control" => {
                release_control::parse(arguments)?;
                Command::ReleaseControl
            }
            "authenticate" => Command::Authenticate(authenticate::parse(arguments)?),
            other => return Err(unknown_command(other)),
        })
    }

    /// The protocol name.
    pub fn name(&self) -> &'static str {
        match self {
            Command::Status(_) => "status",
            Command::Info => "info",
            Command::Hold => "hold",
            Command::Calibrate(_) => "calibrate",
            Command::Release => "release",
            Command::TorqueControl(_) => "torque_control",
            Command::SetTorques(_) => "set_torques",
            Command::VelocityControl(_) => "velocity_control",
            Command::SetVelocities(_) => "set_velocities",
            Command::Pvt(_) => "pvt",
            Command::MoveAxis(_) => "move_axis",
            Command::MoveAll(_) => "move_all",
            Command::PvtPoints(_) => "pvt_points",
            Command::Sleep(_) => "sleep",
            Command::Sim(_) => "sim",
            Command::TakeControl => "take_control",
            Command::ReleaseControl => "release_control",
            Command::Authenticate(_) => "authenticate",
        }
    }

    /// The typed requests that carry this command to the real-time core: one, or the chunks
    /// of a `pvt_points` batch; none for commands the gateway executes itself (`sleep`).
    pub fn requests(&self) -> Vec<Request> {
        match self {
            Command::Status(_) => vec![Request::Status],
            Command::Info => vec![Request::Info],
            Command::Hold => vec![Request::Hold],
            Command::Release => vec![Request::Release],
            Command::Calibrate(c) => vec![Request::Calibrate(*c)],
            Command::TorqueControl(t) => vec![Request::TorqueControl(t.request)],
            Command::SetTorques(t) => vec![Request::SetTorques(*t)],
            Command::VelocityControl(v) => vec![Request::VelocityControl(v.request)],
            Command::SetVelocities(v) => vec![Request::SetVelocities(*v)],
            Command::Pvt(p) => vec![Request::Pvt(*p)],
            Command::MoveAxis(m) => vec![Request::MoveAxis(*m)],
            Command::MoveAll(m) => vec![Request::MoveAll(*m)],
            Command::PvtPoints(p) => PvtChunk::batch(&p.points).map(Request::PvtPoints).collect(),
            Command::Sleep(_) => Vec::new(),
            Command::Sim(s) => vec![Request::Sim(*s)],
            Command::TakeControl => vec![Request::TakeControl],
            Command::ReleaseControl => vec![Request::ReleaseControl],
            Command::Authenticate(_) => Vec::new(),
        }
    }
}

fn unknown_command(name: &str) -> CommandError {
    CommandError::UnknownCommand {
        name: name.chars().take(40).collect(),
        suggestion: suggest(name, COMMAND_NAMES),
        known: COMMAND_NAMES.join(", "),
    }
}

/// The closest of `candidates` to `word` when it is a plausible typo (edit distance <= 2, or
/// a unique prefix of at least 3 letters).
pub fn suggest(word: &str, candidates: &[&'static str]) -> Option<&'static str> {
    let word = word.to_ascii_lowercase();
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
