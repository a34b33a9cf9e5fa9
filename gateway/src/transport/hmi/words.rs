//! The HMI's line parser: one typed line becomes a [`Line`], i.e. a session command (`help`,
//! `watch`, `quit`, ...) or a protocol [`Command`]. Runs in the gateway's async tasks, not in
//! the real-time cycle.
//!
//! A command line is the command name followed by arguments, by position (in the order of
//! [`mcm_shared::protocol::CommandDef`]) or as `name=value` (short names such as `vf` for
//! `velocity_factor` too). Values: numbers, `true`/`false`, words; `"..."` or `'...'` quote a
//! value (a quoted value is always a string, except a quoted JSON array for `pvt_points` and
//! six-value arguments); `[...]` and `{...}` are JSON and may contain spaces. Six values
//! (`move_all`, `set_torques`) are six words, `a,b,c,d,e,f` or a JSON array; so are a pose's
//! position (three) and orientation (four). A bare boolean
//! argument name means `true` (`status detail`). The words become a JSON `arguments` object
//! that [`Command::parse`] validates, exactly as for the JSON channel. A line starting with `{`
//! is a JSON command ([`Command::from_json`]).

use mcm_shared::command::CartesianFrame;
use mcm_shared::config::RobotConfig;
use mcm_shared::protocol::CommandError;
use mcm_shared::protocol::{self, ArgDef, Command, CommandDef, Kind, command_names, suggest};
use mcm_shared::ranges::Arg;
use serde_json::{Map, Value};

/// The session's own commands (not sent to the robot).
pub const SESSION_COMMANDS: &[&str] = &[
    "help", "watch", "jog", "pose", "tool", "moveto", "movel", "clear", "quit", "exit",
];

/// One parsed line.
#[derive(Debug, Clone, PartialEq)]
pub enum Line {
    Empty,
    /// `help` or `help CMD` (also `?`, and `CMD ?`).
    Help(Option<String>),
    /// `watch` or `watch detail`.
    Watch {
        detail: bool,
    },
    /// `clear`: clear the screen.
    Clear,
    /// `jog AXIS [SPEED]` or `jog x|y|z|rx|ry|rz [SPEED] [base|tool]`: drive one axis or the
    /// TCP from the keyboard ([`super::jog`]); the speed checked.
    Jog(super::jog::Jogged),
    /// `pose`: the TCP and the tool in millimetres and degrees ([`super::cartesian`]).
    Pose,
    /// `tool`: show the active tool, or set its TCP (and load) typed in millimetres and
    /// degrees ([`super::cartesian::ToolEdit`]).
    Tool(Option<super::cartesian::ToolEdit>),
    /// `quit` or `exit`.
    Quit,
    /// A protocol command; `json` when it was typed as a JSON object.
    Command {
        cmd: Command,
        json: bool,
    },
}

/// Why a line was refused; every message says what was wrong and what is expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LineError {
    #[error("unknown command \"{name}\"{}; type `help` for the list", did_you_mean(*suggestion))]
    UnknownCommand {
        name: String,
        suggestion: Option<&'static str>,
    },
    #[error("a line starts with a command name, e.g. `status`; got `{got}`")]
    NoCommand { got: String },
    #[error("unterminated {quote} quote starting at column {column}; close it on the same line")]
    UnterminatedQuote { quote: char, column: usize },
    #[error(
        "unbalanced '{open}' starting at column {column}; a JSON value must close its brackets on the same line"
    )]
    Unbalanced { open: char, column: usize },
    #[error("{command}: unknown argument \"{argument}\"{}; allowed: {allowed}", did_you_mean(*suggestion))]
    UnknownArgument {
        command: &'static str,
        argument: String,
        suggestion: Option<&'static str>,
        allowed: String,
    },
    #[error("{command}: argument \"{argument}\" is given twice")]
    Duplicate {
        command: &'static str,
        argument: &'static str,
    },
    #[error("{command}: too many arguments: {takes}, got {got}")]
    TooMany {
        command: &'static str,
        /// What the command takes, in words.
        takes: String,
        got: usize,
    },
    #[error("{command}: \"{argument}\" needs {needs} numbers, {what}, got {got}")]
    TooFewNumbers {
        command: &'static str,
        argument: &'static str,
        needs: usize,
        /// What they are ([`Kind::numbers`]).
        what: &'static str,
        got: usize,
    },
    #[error("{command}: argument \"{argument}\" is not valid JSON ({reason})")]
    BadJson {
        command: &'static str,
        argument: &'static str,
        reason: String,
    },
    #[error("{what}")]
    Session { command: &'static str, what: String },
    /// Refused by the gateway's command parser (value, range, missing argument, ...).
    #[error("{error}")]
    Rejected {
        command: &'static str,
        error: CommandError,
    },
    /// A JSON line that is not a valid command.
    #[error("{0}")]
    Json(CommandError),
}

fn did_you_mean(s: Option<&'static str>) -> String {
    s.map(|s| format!(" (did you mean \"{s}\"?)"))
        .unwrap_or_default()
}

impl LineError {
    /// The protocol command the error is about, when it is one (for a usage hint).
    /// Its `error_code` (the HMI shows it in brackets): the code of the same mistake in a JSON
    /// command where there is one.
    pub fn code(&self) -> mcm_shared::error_code::ErrorCode {
        use mcm_shared::error_code::ErrorCode;
        match self {
            LineError::UnknownCommand { .. } => ErrorCode::UnknownCommand,
            LineError::NoCommand { .. }
            | LineError::UnterminatedQuote { .. }
            | LineError::Unbalanced { .. } => ErrorCode::InvalidCommand,
            LineError::UnknownArgument { .. } => ErrorCode::UnknownArgument,
            LineError::Duplicate { .. }
            | LineError::TooMany { .. }
            | LineError::TooFewNumbers { .. }
            | LineError::BadJson { .. }
            | LineError::Session { .. } => ErrorCode::InvalidArgument,
            LineError::Rejected { error, .. } | LineError::Json(error) => error.code(),
        }
    }

    pub fn command(&self) -> Option<&'static CommandDef> {
        match self {
            LineError::UnknownArgument { command, .. }
            | LineError::Duplicate { command, .. }
            | LineError::TooMany { command, .. }
            | LineError::TooFewNumbers { command, .. }
            | LineError::BadJson { command, .. }
            | LineError::Rejected { command, .. } => protocol::find(command),
            _ => None,
        }
    }
}

/// How a token was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    Plain,
    /// Contains a quoted part: always a string.
    Quoted,
    /// Exactly one `[...]` or `{...}` group: JSON.
    Bracketed,
}

/// One word of a line, split at its first unquoted `=` when it has a name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Token {
    pub name: Option<String>,
    pub value: String,
    pub form: Form,
}

/// Split a line into tokens.
pub fn tokenize(line: &str) -> Result<Vec<Token>, LineError> {
    let mut tokens = Vec::new();
    let mut chars = line.char_indices().peekable();
    loop {
        while chars.next_if(|(_, c)| c.is_whitespace()).is_some() {}
        if chars.peek().is_none() {
            return Ok(tokens);
        }
        let mut tok = Token {
            name: None,
            value: String::new(),
            form: Form::Plain,
        };
        let (mut plain, mut quoted, mut bracketed) = (false, false, false);
        while let Some(&(pos, c)) = chars.peek() {
            if c.is_whitespace() {
                break;
            }
            chars.next();
            match c {
                '"' | '\'' => {
                    quoted = true;
                    let mut escape = false;
                    loop {
                        let Some((_, q)) = chars.next() else {
                            return Err(LineError::UnterminatedQuote {
                                quote: c,
                                column: line[..pos].chars().count() + 1,
                            });
                        };
                        match q {
                            _ if escape => {
                                if q != '"' && q != '\\' {
                                    tok.value.push('\\');
                                }
                                tok.value.push(q);
                                escape = false;
                            }
                            '\\' if c == '"' => escape = true,
                            _ if q == c => break,
                            _ => tok.value.push(q),
                        }
                    }
                }
                '[' | '{' if tok.value.is_empty() && !quoted => {
                    bracketed = true;
                    tok.value.push(c);
                    let (mut depth, mut in_string, mut escape) = (1usize, false, false);
                    while depth > 0 {
                        let Some((_, b)) = chars.next() else {
                            return Err(LineError::Unbalanced {
                                open: c,
                                column: line[..pos].chars().count() + 1,
                            });
                        };
                        tok.value.push(b);
                        if in_string {
                            match b {
                                _ if escape => escape = false,
                                '\\' => escape = true,
                                '"' => in_string = false,
                                _ => {}
                            }
                            continue;
                        }
                        match b {
                            '"' => in_string = true,
                            '[' | '{' => depth += 1,
                            ']' | '}' => depth -= 1,
                            _ => {}
                        }
                    }
                }
                '=' if tok.name.is_none()
                    && plain
                    && !quoted
                    && !bracketed
                    && is_name(&tok.value) =>
                {
                    tok.name = Some(std::mem::take(&mut tok.value));
                    plain = false;
                }
                _ => {
                    tok.value.push(c);
                    plain = true;
                }
            }
        }
        tok.form = if quoted {
            Form::Quoted
        } else if bracketed && !plain {
            Form::Bracketed
        } else {
            Form::Plain
        };
        tokens.push(tok);
    }
}

fn is_name(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_alphabetic())
        && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// `jog AXIS [SPEED]`: an axis number and an optional speed [deg/s]; or `jog DIRECTION
/// [SPEED] [base|tool]`: a direction of the TCP (`x y z rx ry rz`), an optional speed (mm/s
/// along, deg/s about) and frame (plain words).
fn parse_jog(rest: &[Token], cfg: &RobotConfig) -> Result<Line, LineError> {
    use super::jog::{self, Jogged, TcpDirection, TcpJog};
    let usage = "usage: `jog AXIS [SPEED]` (deg/s) or `jog x|y|z|rx|ry|rz [SPEED] [base|tool]` \
                 (mm/s along, deg/s about an axis of the frame), e.g. `jog 2 20` or `jog z 50 tool`";
    let words: Option<Vec<&str>> = rest
        .iter()
        .map(|t| (t.form == Form::Plain && t.name.is_none()).then_some(t.value.as_str()))
        .collect();
    let Some((first, more)) = words.as_deref().and_then(<[&str]>::split_first) else {
        return Err(session_error("jog", usage));
    };
    let speed_of = |s: &str| {
        s.parse::<f64>().map_err(|_| {
            session_error("jog", &format!("jog: speed = {s} is not a number; {usage}"))
        })
    };
    if let Some(direction) = TcpDirection::from_word(first) {
        let (speed, frame) = match more {
            [] => (None, None),
            [f] if CartesianFrame::from_name(&f.to_ascii_lowercase()).is_some() => (None, Some(*f)),
            [s] => (Some(*s), None),
            [s, f] => (Some(*s), Some(*f)),
            _ => return Err(session_error("jog", usage)),
        };
        let frame = match frame {
            None => CartesianFrame::default(),
            Some(f) => CartesianFrame::from_name(&f.to_ascii_lowercase()).ok_or_else(|| {
                session_error(
                    "jog",
                    &format!("jog: frame = {f} is not allowed; expected base or tool; {usage}"),
                )
            })?,
        };
        let mut tcp = TcpJog {
            direction,
            frame,
            linear_mm_s: jog::DEFAULT_TCP_SPEED_MM_S,
            angular_deg_s: jog::DEFAULT_TCP_TURN_DEG_S,
        };
        if let Some(s) = speed {
            let v = jog::check_tcp_speed(direction, speed_of(s)?)
                .map_err(|e| session_error("jog", &e))?;
            match direction {
                TcpDirection::Along(_) => tcp.linear_mm_s = v,
                TcpDirection::About(_) => tcp.angular_deg_s = v,
            }
        }
        return Ok(Line::Jog(Jogged::Tcp(tcp)));
    }
    let speed = match more {
        [] => None,
        [s] => Some(*s),
        _ => return Err(session_error("jog", usage)),
    };
    let axis = first
        .parse::<u8>()
        .ok()
        .and_then(mcm_shared::command::Axis::new)
        .ok_or_else(|| {
            let (lo, hi) = Arg::AxisIndex.fixed_bounds();
            let expected = Arg::AxisIndex.expected(lo, hi);
            session_error(
                "jog",
                &format!(
                    "jog: axis = {first} is not allowed; expected {expected}, or a direction of \
                     the TCP: x, y, z, rx, ry, rz; {usage}"
                ),
            )
        })?;
    let speed = match speed {
        None => jog::default_speed(cfg, axis),
        Some(s) => {
            jog::check_speed(cfg, axis, speed_of(s)?).map_err(|e| session_error("jog", &e))?
        }
    };
    Ok(Line::Jog(Jogged::Axis { axis, speed }))
}

/// Parse one line typed by a person.
pub fn parse_line(text: &str, cfg: &RobotConfig) -> Result<Line, LineError> {
    let text = text.trim();
    if text.is_empty() {
        return Ok(Line::Empty);
    }
    if text.starts_with('{') {
        return Command::from_json(text, cfg)
            .map(|cmd| Line::Command { cmd, json: true })
            .map_err(LineError::Json);
    }
    let tokens = tokenize(text)?;
    let first = &tokens[0];
    if first.name.is_some() || first.form != Form::Plain {
        return Err(LineError::NoCommand {
            got: text.chars().take(40).collect(),
        });
    }
    let word = first.value.to_ascii_lowercase();
    let rest = &tokens[1..];
    let is = |t: &Token, w: &[&str]| {
        t.form == Form::Plain
            && t.name.is_none()
            && w.contains(&t.value.to_ascii_lowercase().as_str())
    };
    match word.as_str() {
        "help" | "?" => {
            return match rest {
                [] => Ok(Line::Help(None)),
                [t] => Ok(Line::Help(Some(t.value.clone()))),
                _ => Err(session_error(
                    "help",
                    "help takes at most one word: `help` or `help CMD`",
                )),
            };
        }
        "watch" => {
            return match rest {
                [] => Ok(Line::Watch { detail: false }),
                [t] if is(t, &["detail"]) => Ok(Line::Watch { detail: true }),
                _ => Err(session_error(
                    "watch",
                    "watch takes one optional word: `watch` or `watch detail`",
                )),
            };
        }
        "jog" => return parse_jog(rest, cfg),
        "pose" => {
            return match rest {
                [] => Ok(Line::Pose),
                _ => Err(session_error(
                    "pose",
                    "pose takes no words: `pose` shows the TCP; `moveto X Y Z ROLL PITCH YAW` moves it",
                )),
            };
        }
        "tool" => return super::cartesian::parse_tool(rest),
        "moveto" => return super::cartesian::parse_moveto(rest, cfg),
        "movel" => return super::cartesian::parse_movel(rest, cfg),
        "quit" | "exit" => return Ok(Line::Quit),
        "clear" => {
            return match rest {
                [] => Ok(Line::Clear),
                _ => Err(session_error("clear", "clear takes no words: `clear`")),
            };
        }
        _ => {}
    }
    let Some(spec) = protocol::find(&word) else {
        let words = command_names().chain(SESSION_COMMANDS.iter().copied());
        return Err(LineError::UnknownCommand {
            name: first.value.chars().take(40).collect(),
            suggestion: suggest(&word, words),
        });
    };
    if let [t] = rest
        && is(t, &["?", "help"])
    {
        return Ok(Line::Help(Some(spec.name.to_string())));
    }
    let arguments = arguments(spec, rest)?;
    Command::parse(spec, Some(&arguments), cfg)
        .map(|cmd| Line::Command { cmd, json: false })
        .map_err(|error| LineError::Rejected {
            command: spec.name,
            error,
        })
}

fn session_error(command: &'static str, what: &str) -> LineError {
    LineError::Session {
        command,
        what: what.to_string(),
    }
}

/// The JSON `arguments` object of the tokens after the command name.
pub fn arguments(spec: &'static CommandDef, tokens: &[Token]) -> Result<Value, LineError> {
    let mut map = Map::new();
    let insert = |map: &mut Map<String, Value>, a: &'static ArgDef, v: Value| {
        if map.insert(a.name.to_string(), v).is_some() {
            Err(LineError::Duplicate {
                command: spec.name,
                argument: a.name,
            })
        } else {
            Ok(())
        }
    };
    let positional = spec.positional();
    let mut next = 0;
    let mut i = 0;
    let mut by_position = 0;
    while i < tokens.len() {
        let t = &tokens[i];
        if let Some(name) = &t.name {
            let a = spec.arg(name).ok_or_else(|| LineError::UnknownArgument {
                command: spec.name,
                argument: name.chars().take(40).collect(),
                suggestion: suggest(name, spec.arg_names()),
                allowed: allowed(spec),
            })?;
            insert(&mut map, a, value(spec, a, t)?)?;
            i += 1;
            continue;
        }
        if t.form == Form::Plain
            && let Some(a) = spec.arg(&t.value)
            && a.kind == Kind::Bool
        {
            insert(&mut map, a, Value::Bool(true))?;
            i += 1;
            continue;
        }
        while positional
            .get(next)
            .is_some_and(|a| map.contains_key(a.name))
        {
            next += 1;
        }
        let Some(a) = positional.get(next).copied() else {
            let got = by_position + tokens[i..].iter().filter(|t| t.name.is_none()).count();
            let takes = match (positional.len(), spec.args.first()) {
                (_, None) => "it takes no arguments".to_string(),
                (0, Some(a)) => format!(
                    "it takes arguments only as name=value, e.g. {}={}",
                    a.name,
                    a.kind.placeholder()
                ),
                (n, _) => format!(
                    "it takes at most {n} by position ({})",
                    positional
                        .iter()
                        .map(|a| a.name)
                        .collect::<Vec<_>>()
                        .join(" ")
                ),
            };
            return Err(LineError::TooMany {
                command: spec.name,
                takes,
                got,
            });
        };
        next += 1;
        if let Some((needs, what)) = a.kind.numbers()
            && t.form == Form::Plain
            && !t.value.contains(',')
        {
            let mut numbers = Vec::new();
            while numbers.len() < needs
                && let Some(t) = tokens.get(i)
                && t.name.is_none()
                && t.form == Form::Plain
            {
                numbers.push(word(&t.value, Kind::Number));
                i += 1;
                by_position += 1;
            }
            if numbers.len() < needs {
                return Err(LineError::TooFewNumbers {
                    command: spec.name,
                    argument: a.name,
                    needs,
                    what,
                    got: numbers.len(),
                });
            }
            insert(&mut map, a, Value::Array(numbers))?;
            continue;
        }
        insert(&mut map, a, value(spec, a, t)?)?;
        i += 1;
        by_position += 1;
    }
    Ok(Value::Object(map))
}

fn allowed(spec: &CommandDef) -> String {
    if spec.args.is_empty() {
        return "none (this command takes no arguments)".into();
    }
    spec.args
        .iter()
        .map(|a| match a.alias {
            "" => a.name.to_string(),
            alias => format!("{} ({alias})", a.name),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The JSON value of one token for argument `a`.
fn value(spec: &CommandDef, a: &'static ArgDef, t: &Token) -> Result<Value, LineError> {
    let json = |text: &str| {
        mcm_shared::protocol::json::parse(text).map_err(|e| LineError::BadJson {
            command: spec.name,
            argument: a.name,
            reason: e.to_string(),
        })
    };
    match t.form {
        Form::Bracketed => json(&t.value),
        Form::Quoted
            if (a.kind.numbers().is_some() || matches!(a.kind, Kind::Points | Kind::Json))
                && t.value.trim_start().starts_with(['[', '{']) =>
        {
            json(&t.value)
        }
        Form::Quoted => Ok(Value::String(t.value.clone())),
        Form::Plain => Ok(word(&t.value, a.kind)),
    }
}

/// The JSON value of an unquoted word: a number, a boolean, comma-separated numbers (for a
/// kind of several numbers), or else a string (which the command parser then refuses with the allowed values).
fn word(w: &str, kind: Kind) -> Value {
    if kind == Kind::Text {
        return Value::String(w.to_string());
    }
    if kind.numbers().is_some() && w.contains(',') {
        return Value::Array(w.split(',').map(|p| word(p.trim(), Kind::Number)).collect());
    }
    match (w.to_ascii_lowercase().as_str(), kind) {
        ("true", _) | ("on" | "yes", Kind::Bool) => return Value::Bool(true),
        ("false", _) | ("off" | "no", Kind::Bool) => return Value::Bool(false),
        _ => {}
    }
    if w.starts_with(|c: char| c.is_ascii_digit() || matches!(c, '-' | '+' | '.')) {
        if let Ok(i) = w.parse::<i64>() {
            return Value::from(i);
        }
        if let Some(n) = w.parse::<f64>().ok().and_then(serde_json::Number::from_f64) {
            return Value::Number(n);
        }
    }
    Value::String(w.to_string())
}

#[cfg(test)]
mod tests;
