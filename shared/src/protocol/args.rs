//! Typed access to a command's `arguments` object, with errors that name the command, the
//! argument, the value received and what is allowed.

use super::json::{json_kind, shown};
use super::spec::CommandDef;
use crate::command::Axis;
use crate::config::RobotConfig;
use crate::error_code::ErrorCode;
use crate::ranges::{Arg, Num, Shape};
use crate::reply::Reason;
use serde_json::{Map, Value};

/// Why a command line was refused before it reached the robot.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CommandError {
    #[error("invalid input: {0}")]
    Framing(String),
    #[error("invalid JSON ({0})")]
    Json(String),
    #[error("duplicate key \"{key}\" in one JSON object; each key may appear only once")]
    DuplicateKey { key: String },
    #[error(
        "a command needs a \"command\" field with the command name, e.g. {{\"command\":\"status\"}}"
    )]
    MissingCommand,
    #[error("\"command\" must be a string, got a JSON {got}")]
    CommandNotString { got: &'static str },
    #[error("unknown command \"{name}\"{}; known commands: {known}", suggestion.as_ref().map(|s| format!(" (did you mean \"{s}\"?)")).unwrap_or_default())]
    UnknownCommand {
        name: String,
        suggestion: Option<&'static str>,
        known: String,
    },
    #[error(
        "{command}: unknown field \"{field}\"; a command has only \"command\" and \"arguments\""
    )]
    UnknownField {
        command: &'static str,
        field: String,
    },
    #[error("{command}: \"arguments\" must be an object, got a JSON {got}")]
    ArgumentsNotObject {
        command: &'static str,
        got: &'static str,
    },
    #[error("{command}: unknown argument \"{argument}\"; allowed: {allowed}")]
    UnknownArgument {
        command: &'static str,
        argument: String,
        allowed: String,
    },
    #[error("{command}: missing argument \"{argument}\" ({expected})")]
    Missing {
        command: &'static str,
        argument: &'static str,
        expected: String,
    },
    #[error("{command}: argument \"{argument}\" = {value} is not allowed; expected {expected}")]
    Invalid {
        command: &'static str,
        argument: String,
        value: String,
        expected: String,
    },
    /// A number of a protocol argument ([`crate::ranges`]) outside its range: worded as
    /// [`CommandError::Invalid`], with the code the real-time core gives the same value
    /// ([`Reason::argument_code`]: `unreachable` for a target position, else `out_of_range`).
    #[error("{command}: argument \"{argument}\" = {value} is not allowed; expected {expected}")]
    OutOfRange {
        command: &'static str,
        argument: String,
        value: String,
        expected: String,
        arg: Arg,
    },
    /// A tool that is not allowed ([`crate::tool::Tool::new`], the core's own check).
    #[error("{command}: {error}")]
    Tool {
        command: &'static str,
        error: crate::tool::ToolError,
    },
}

impl CommandError {
    /// Its `error_code` ([`crate::error_code`]).
    pub fn code(&self) -> ErrorCode {
        match self {
            CommandError::Framing(_)
            | CommandError::Json(_)
            | CommandError::DuplicateKey { .. } => ErrorCode::InvalidJson,
            CommandError::MissingCommand
            | CommandError::CommandNotString { .. }
            | CommandError::UnknownField { .. }
            | CommandError::ArgumentsNotObject { .. } => ErrorCode::InvalidCommand,
            CommandError::UnknownCommand { .. } => ErrorCode::UnknownCommand,
            CommandError::UnknownArgument { .. } => ErrorCode::UnknownArgument,
            CommandError::Missing { .. } => ErrorCode::MissingArgument,
            CommandError::Invalid { .. } => ErrorCode::InvalidArgument,
            CommandError::Tool { .. } => ErrorCode::OutOfRange,
            CommandError::OutOfRange { arg, .. } => Reason::argument_code(*arg)
                .error_code()
                .unwrap_or(ErrorCode::OutOfRange),
        }
    }

    /// The known command the refused line names; `None` for a line that names none.
    pub fn command(&self) -> Option<&'static str> {
        match self {
            CommandError::Framing(_)
            | CommandError::Json(_)
            | CommandError::DuplicateKey { .. }
            | CommandError::MissingCommand
            | CommandError::CommandNotString { .. }
            | CommandError::UnknownCommand { .. } => None,
            CommandError::UnknownField { command, .. }
            | CommandError::ArgumentsNotObject { command, .. }
            | CommandError::UnknownArgument { command, .. }
            | CommandError::Missing { command, .. }
            | CommandError::Invalid { command, .. }
            | CommandError::OutOfRange { command, .. }
            | CommandError::Tool { command, .. } => Some(command),
        }
    }
}

/// The `arguments` of one command.
pub struct Args<'a> {
    command: &'static str,
    map: Option<&'a Map<String, Value>>,
}

impl<'a> Args<'a> {
    /// The `arguments` of the command `def`, their names checked against `def.args`.
    pub fn new(
        def: &'static CommandDef,
        arguments: Option<&'a Value>,
    ) -> Result<Self, CommandError> {
        let command = def.name;
        let map = match arguments {
            None | Some(Value::Null) => None,
            Some(Value::Object(m)) => Some(m),
            Some(other) => {
                return Err(CommandError::ArgumentsNotObject {
                    command,
                    got: json_kind(other),
                });
            }
        };
        if let Some(m) = map {
            for key in m.keys() {
                if !def.arg_list().any(|a| a == key) {
                    return Err(CommandError::UnknownArgument {
                        command,
                        argument: key.clone(),
                        allowed: if def.args.is_empty() {
                            "none (this command takes no arguments)".to_string()
                        } else {
                            def.arg_list().collect::<Vec<_>>().join(", ")
                        },
                    });
                }
            }
        }
        Ok(Self { command, map })
    }

    pub fn command(&self) -> &'static str {
        self.command
    }

    fn get(&self, name: &str) -> Option<&'a Value> {
        self.map.and_then(|m| m.get(name)).filter(|v| !v.is_null())
    }

    /// An error for argument `name` holding `value`.
    pub fn invalid(&self, name: &str, value: &Value, expected: impl Into<String>) -> CommandError {
        CommandError::Invalid {
            command: self.command,
            argument: name.to_string(),
            value: shown(value),
            expected: expected.into(),
        }
    }

    /// An error for a value that is not a JSON value (e.g. computed).
    pub fn invalid_value(
        &self,
        name: &str,
        value: impl ToString,
        expected: impl Into<String>,
    ) -> CommandError {
        CommandError::Invalid {
            command: self.command,
            argument: name.to_string(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }

    /// An error for the required argument `name`, not given; `expected` says what it holds.
    pub fn missing(&self, name: &'static str, expected: &str) -> CommandError {
        CommandError::Missing {
            command: self.command,
            argument: name,
            expected: expected.to_string(),
        }
    }

    /// An optional number of the protocol argument `arg` within `bounds`, refused in the words
    /// of [`crate::ranges`] (the real-time core's words for the same value).
    pub fn ranged(&self, arg: Arg, bounds: (f64, f64)) -> Result<Option<f64>, CommandError> {
        let name = arg.name();
        let Some(v) = self.get(name) else {
            return Ok(None);
        };
        ranged_value(self, arg, name, v, bounds).map(Some)
    }

    /// A required number of the protocol argument `arg` within `bounds`.
    pub fn required_ranged(&self, arg: Arg, bounds: (f64, f64)) -> Result<f64, CommandError> {
        self.ranged(arg, bounds)?
            .ok_or_else(|| self.missing(arg.name(), &arg.expected(bounds.0, bounds.1).to_string()))
    }

    /// An optional array of `N` numbers of the argument `arg`, element `i` within the range
    /// of the table for index `i` ([`Arg::bounds`] with `cfg`: axis `i + 1`'s for a per-axis
    /// argument, the fixed range for a Cartesian vector).
    pub fn ranged_array<const N: usize>(
        &self,
        arg: Arg,
        cfg: &RobotConfig,
    ) -> Result<Option<[f64; N]>, CommandError> {
        let name = arg.name();
        let Some(v) = self.get(name) else {
            return Ok(None);
        };
        let arr = v
            .as_array()
            .filter(|a| a.len() == N)
            .ok_or_else(|| self.invalid(name, v, array_expected(N, arg, cfg)))?;
        let mut out = [0.0; N];
        for (i, x) in arr.iter().enumerate() {
            let bounds = arg.bounds(cfg, Some(i));
            out[i] = ranged_value(self, arg, &format!("{name}[{i}]"), x, bounds)?;
        }
        Ok(Some(out))
    }

    /// A required array of `N` numbers of the argument `arg` ([`Args::ranged_array`]).
    pub fn required_ranged_array<const N: usize>(
        &self,
        arg: Arg,
        cfg: &RobotConfig,
    ) -> Result<[f64; N], CommandError> {
        self.ranged_array(arg, cfg)?
            .ok_or_else(|| self.missing(arg.name(), &array_expected(N, arg, cfg)))
    }

    /// An optional boolean; `0` and `1` are accepted too (the manual writes `<bool>` as 1).
    pub fn boolean(&self, name: &'static str) -> Result<Option<bool>, CommandError> {
        let Some(v) = self.get(name) else {
            return Ok(None);
        };
        match v {
            Value::Bool(b) => Ok(Some(*b)),
            Value::Number(n) if n.as_f64() == Some(0.0) => Ok(Some(false)),
            Value::Number(n) if n.as_f64() == Some(1.0) => Ok(Some(true)),
            _ => Err(self.invalid(name, v, "true, false, 1 or 0")),
        }
    }

    /// An optional axis number 1..=6 of the axis argument `arg` ([`Shape::Axis`] in
    /// [`crate::ranges`]).
    pub fn axis(&self, arg: Arg) -> Result<Option<Axis>, CommandError> {
        debug_assert_eq!(arg.spec().shape, Shape::Axis, "{arg:?} is no axis argument");
        let name = arg.name();
        let Some(v) = self.get(name) else {
            return Ok(None);
        };
        let n = ranged_value(self, arg, name, v, arg.fixed_bounds())?;
        // Accepted within the axis range: a whole number from 1 to 6.
        Axis::new(n as u8)
            .map(Some)
            .ok_or_else(|| self.invalid(name, v, arg.expected(1.0, 6.0).to_string()))
    }

    /// A required axis number 1..=6 of the axis argument `arg`.
    pub fn required_axis(&self, arg: Arg) -> Result<Axis, CommandError> {
        let (lo, hi) = arg.fixed_bounds();
        self.axis(arg)?
            .ok_or_else(|| self.missing(arg.name(), &arg.expected(lo, hi).to_string()))
    }

    /// The raw value of an argument.
    pub fn raw(&self, name: &'static str) -> Option<&'a Value> {
        self.get(name)
    }
}

/// What an array of `n` numbers of the argument `arg` must hold (the range of its first
/// element shown).
fn array_expected(n: usize, arg: Arg, cfg: &RobotConfig) -> String {
    let (lo, hi) = arg.bounds(cfg, Some(0));
    format!("an array of {n} numbers, each {}", arg.expected(lo, hi))
}

/// The number `v` of the argument `arg` (shown as `name`: an array's element is `name[i]`)
/// within `bounds`. A number is shown as [`Num`] writes it, as the core shows it.
fn ranged_value(
    args: &Args<'_>,
    arg: Arg,
    name: &str,
    v: &Value,
    bounds: (f64, f64),
) -> Result<f64, CommandError> {
    let expected = || arg.expected(bounds.0, bounds.1).to_string();
    let Some(x) = v.as_f64() else {
        return Err(args.invalid(name, v, expected()));
    };
    if arg.accepts(x, bounds) {
        Ok(x)
    } else {
        Err(CommandError::OutOfRange {
            command: args.command,
            argument: name.to_string(),
            value: Num(x).to_string(),
            expected: expected(),
            arg,
        })
    }
}

/// Six finite numbers from `v` (`what` says what they are, for the refusal); their ranges are
/// the caller's to check.
pub fn six_numbers(
    args: &Args<'_>,
    name: &str,
    v: &Value,
    what: &str,
) -> Result<[f64; 6], CommandError> {
    numbers(args, name, v, what)
}

/// `N` finite numbers from `v` (`what` says what they are, for the refusal); their ranges are
/// the caller's to check.
pub fn numbers<const N: usize>(
    args: &Args<'_>,
    name: &str,
    v: &Value,
    what: &str,
) -> Result<[f64; N], CommandError> {
    let arr = v
        .as_array()
        .filter(|a| a.len() == N)
        .ok_or_else(|| args.invalid(name, v, format!("an array of {N} {what}")))?;
    let mut out = [0.0; N];
    for (i, x) in arr.iter().enumerate() {
        out[i] = x.as_f64().filter(|n| n.is_finite()).ok_or_else(|| {
            args.invalid(&format!("{name}[{i}]"), x, format!("a number ({what})"))
        })?;
    }
    Ok(out)
}
