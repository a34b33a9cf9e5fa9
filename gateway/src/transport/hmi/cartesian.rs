//! The HMI's Cartesian words, for people: positions in millimetres, orientations as roll,
//! pitch and yaw in degrees (fixed axes X, Y, Z, the URDF's `rpy`:
//! [`mcm_kinematics::quaternion_from_rpy_deg`]). The protocol takes metres and unit
//! quaternions; the words are converted here, once, into its commands:
//!
//! - `pose`: the TCP in the base frame and the active tool (from the newest state; nothing is
//!   sent).
//! - `tool`: the active tool; `tool X Y Z ROLL PITCH YAW [mass=KG] [com=X,Y,Z]` sets its TCP
//!   (in the flange frame) with `set_tool`, keeping the active load unless `mass` or `com` is
//!   given (a point mass then; the other of the two kept).
//! - `moveto X Y Z ROLL PITCH YAW [vf=F]`: `move_to_pose` (a joint move to the solution nearest
//!   the present position).
//! - `movel X Y Z [ROLL PITCH YAW] [v=MM_S]`: `move_linear` (the TCP on a straight line; the
//!   orientation kept when not typed; the speed in mm/s).
//!
//! Runs in the gateway's async tasks, never in the real-time cycle.

use super::words::{Form, Line, LineError, Token};
use crate::command::cartesian::active_tool;
use mcm_kinematics::{quaternion_from_rpy_deg, rpy_deg_from_quaternion};
use mcm_shared::config::RobotConfig;
use mcm_shared::protocol::{self, Command, Pose};
use mcm_shared::ranges::{Arg, Num};
use mcm_shared::sample::{STATE_CARTESIAN, StateSample};
use mcm_shared::tool::{Tcp, Tool, ToolError};
use serde_json::{Map, Value};
use std::fmt::Write;

/// Millimetres per metre.
const MM: f64 = 1000.0;

/// The words after `moveto`, in its usage line.
pub const MOVETO_USAGE: &str = "usage: `moveto X Y Z ROLL PITCH YAW [vf=F]` (mm and deg, base frame), e.g. `moveto 400 0 500 180 0 0 vf=0.3`";
/// The words after `movel`, in its usage line.
pub const MOVEL_USAGE: &str = "usage: `movel X Y Z [ROLL PITCH YAW] [v=MM_S]` (mm and deg, base frame; speed in mm/s), e.g. `movel 400 0 500 180 0 0 v=100`";
/// The words after `tool`, in its usage line.
pub const TOOL_USAGE: &str = "usage: `tool` shows the tool; `tool X Y Z ROLL PITCH YAW [mass=KG] [com=X,Y,Z]` sets its TCP (mm and deg, flange frame) and load (com in mm), e.g. `tool 0 0 150 0 0 90 mass=1.2 com=0,0,60`";

/// What `help pose`, `help tool`, `help moveto` and `help movel` add: the units and the
/// convention.
pub const HELP: &str = "\
Positions in millimetres, angles in degrees. Roll, pitch and yaw turn about the fixed axes
x, then y, then z (the URDF's rpy: R = Rz(yaw) Ry(pitch) Rx(roll)). `pose`, `moveto` and
`movel` use the base frame (the TCP of the active tool); `tool` the flange frame. `movel`
keeps the TCP's orientation when no roll, pitch and yaw are typed; its speed v= is in mm/s.
Without mass= and com= `tool` keeps the active load; with either the load becomes a point
mass (the other value kept). The protocol's set_tool, inverse_kinematics, move_to_pose and
move_linear take metres and quaternions [x, y, z, w].
examples:
  pose
  moveto 400 0 500 180 0 0 vf=0.3
  movel 400 0 400 v=100
  movel 400 0 500 180 0 0 v=50
  tool 0 0 150 0 0 90
  tool 0 0 150 0 0 90 mass=1.2 com=0,0,60
";

/// A pose as people type it: position [mm], roll, pitch, yaw [deg].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseWords {
    pub position_mm: [f64; 3],
    pub rpy_deg: [f64; 3],
}

impl PoseWords {
    /// The protocol's pose: metres and a unit quaternion.
    pub fn pose(&self) -> Pose {
        Pose {
            position: self.position_mm.map(|x| x / MM),
            orientation: quaternion_from_rpy_deg(self.rpy_deg),
        }
    }
}

/// `tool X Y Z ROLL PITCH YAW [mass=KG] [com=X,Y,Z]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToolEdit {
    /// The TCP in the flange frame.
    pub tcp: PoseWords,
    pub mass_kg: Option<f64>,
    pub com_mm: Option<[f64; 3]>,
}

impl ToolEdit {
    /// The tool `set_tool` is to set: the TCP typed, the load of `active` unless `mass` or
    /// `com` was given (then a point mass of that mass at that centre, the other taken from
    /// `active`).
    pub fn tool(&self, active: &Tool) -> Result<Tool, ToolError> {
        let pose = self.tcp.pose();
        let tcp = Tcp {
            position: pose.position,
            orientation: pose.orientation,
        };
        if self.mass_kg.is_none() && self.com_mm.is_none() {
            return Tool::new(
                tcp,
                active.mass,
                active.center_of_mass,
                Some(active.inertia),
            );
        }
        let mass = self.mass_kg.unwrap_or(active.mass);
        let com = self
            .com_mm
            .map_or(active.center_of_mass, |c| c.map(|x| x / MM));
        Tool::new(tcp, mass, com, None)
    }
}

fn session_error(command: &'static str, what: String) -> LineError {
    LineError::Session { command, what }
}

/// A finite number, or the error naming it.
fn number(command: &'static str, name: &str, w: &str, usage: &str) -> Result<f64, LineError> {
    w.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| {
            session_error(
                command,
                format!("{command}: {name} = {w} is not a number; {usage}"),
            )
        })
}

/// The numbers at the start of a pose's words, and the named words after them.
struct PoseNumbers<'a> {
    position_mm: [f64; 3],
    /// Absent when only X Y Z were typed.
    rpy_deg: Option<[f64; 3]>,
    rest: &'a [Token],
}

/// The plain numbers at the start of `tokens` (X Y Z, then ROLL PITCH YAW) and the named words
/// after them; `rpy_optional`: three numbers (no orientation) are allowed too.
fn pose_numbers<'a>(
    command: &'static str,
    tokens: &'a [Token],
    usage: &str,
    rpy_optional: bool,
) -> Result<PoseNumbers<'a>, LineError> {
    const NAMES: [&str; 6] = ["X", "Y", "Z", "ROLL", "PITCH", "YAW"];
    let plain = tokens
        .iter()
        .take_while(|t| t.name.is_none() && t.form == Form::Plain)
        .count();
    if plain != NAMES.len() && !(rpy_optional && plain == 3) {
        let needs = if rpy_optional {
            "3 numbers X Y Z or 6 X Y Z ROLL PITCH YAW"
        } else {
            "6 numbers X Y Z ROLL PITCH YAW"
        };
        return Err(session_error(
            command,
            format!("{command}: needs {needs}, got {plain}; {usage}"),
        ));
    }
    let mut v = [0.0; 6];
    for (i, t) in tokens[..plain].iter().enumerate() {
        v[i] = number(command, NAMES[i], &t.value, usage)?;
    }
    Ok(PoseNumbers {
        position_mm: [v[0], v[1], v[2]],
        rpy_deg: (plain == 6).then_some([v[3], v[4], v[5]]),
        rest: &tokens[plain..],
    })
}

/// The six plain numbers at the start of `tokens` (X Y Z ROLL PITCH YAW) and the named words
/// after them.
fn pose_words<'a>(
    command: &'static str,
    tokens: &'a [Token],
    usage: &str,
) -> Result<(PoseWords, &'a [Token]), LineError> {
    let n = pose_numbers(command, tokens, usage, false)?;
    let words = PoseWords {
        position_mm: n.position_mm,
        rpy_deg: n.rpy_deg.unwrap_or_default(),
    };
    Ok((words, n.rest))
}

/// The value of the named word `t` (after the numbers), `name` being one of `names`.
fn named<'a>(
    command: &'static str,
    t: &'a Token,
    names: &[&str],
    usage: &str,
) -> Result<(&'a str, &'a str), LineError> {
    match &t.name {
        Some(n) if names.contains(&n.as_str()) => Ok((n.as_str(), t.value.as_str())),
        _ => Err(session_error(
            command,
            format!(
                "{command}: unexpected `{}` after the numbers; {usage}",
                t.value.chars().take(40).collect::<String>()
            ),
        )),
    }
}

/// `moveto X Y Z ROLL PITCH YAW [vf=F]`: the `move_to_pose` command, checked by the protocol's
/// own parser (the velocity factor's range, the pose).
pub fn parse_moveto(tokens: &[Token], cfg: &RobotConfig) -> Result<Line, LineError> {
    let (words, rest) = pose_words("moveto", tokens, MOVETO_USAGE)?;
    let mut args = Map::new();
    words.pose().insert_into(&mut args);
    for t in rest {
        let (_, v) = named("moveto", t, &["vf", "velocity_factor"], MOVETO_USAGE)?;
        let vf = number("moveto", "vf", v, MOVETO_USAGE)?;
        args.insert("velocity_factor".into(), vf.into());
    }
    protocol_command("move_to_pose", args, cfg)
}

/// The protocol's command `name` of the JSON `args`, checked by the protocol's own parser.
fn protocol_command(
    name: &str,
    args: Map<String, Value>,
    cfg: &RobotConfig,
) -> Result<Line, LineError> {
    let spec = protocol::find(name).expect("the HMI's Cartesian words send protocol commands");
    Command::parse(spec, Some(&Value::Object(args)), cfg)
        .map(|cmd| Line::Command { cmd, json: false })
        .map_err(|error| LineError::Rejected {
            command: spec.name,
            error,
        })
}

/// `movel X Y Z [ROLL PITCH YAW] [v=MM_S]`: the `move_linear` command (metres, the quaternion
/// of the roll, pitch and yaw typed, the speed in m/s), checked by the protocol's own parser.
/// The speed is checked here, against the protocol's range in mm/s, so its refusal speaks the
/// unit it was typed in.
pub fn parse_movel(tokens: &[Token], cfg: &RobotConfig) -> Result<Line, LineError> {
    let PoseNumbers {
        position_mm,
        rpy_deg,
        rest,
    } = pose_numbers("movel", tokens, MOVEL_USAGE, true)?;
    let mut args = Map::new();
    args.insert(
        "position".into(),
        position_mm.map(|x| x / MM).to_vec().into(),
    );
    if let Some(rpy) = rpy_deg {
        args.insert(
            "orientation".into(),
            quaternion_from_rpy_deg(rpy).to_vec().into(),
        );
    }
    for t in rest {
        let (_, v) = named("movel", t, &["v", "speed", "velocity"], MOVEL_USAGE)?;
        let speed = number("movel", "speed", v, MOVEL_USAGE)?;
        let (lo, hi) = Arg::LinearVelocity.fixed_bounds();
        if !Arg::LinearVelocity.accepts(speed / MM, (lo, hi)) {
            return Err(session_error(
                "movel",
                format!(
                    "movel: speed = {} mm/s is not allowed; expected a number from {} to {} mm/s \
                     (the TCP's speed on the line); {MOVEL_USAGE}",
                    Num(speed),
                    Num(lo * MM),
                    Num(hi * MM)
                ),
            ));
        }
        args.insert("velocity".into(), (speed / MM).into());
    }
    protocol_command("move_linear", args, cfg)
}

/// `tool` (show) or `tool X Y Z ROLL PITCH YAW [mass=KG] [com=X,Y,Z]` (set).
pub fn parse_tool(tokens: &[Token]) -> Result<Line, LineError> {
    if tokens.is_empty() {
        return Ok(Line::Tool(None));
    }
    let (tcp, rest) = pose_words("tool", tokens, TOOL_USAGE)?;
    let mut edit = ToolEdit {
        tcp,
        mass_kg: None,
        com_mm: None,
    };
    for t in rest {
        match named("tool", t, &["mass", "com"], TOOL_USAGE)? {
            ("mass", v) => edit.mass_kg = Some(number("tool", "mass", v, TOOL_USAGE)?),
            (_, v) => {
                let parts: Vec<&str> = v.split(',').map(str::trim).collect();
                let [x, y, z] = parts[..] else {
                    return Err(session_error(
                        "tool",
                        format!("tool: com = {v} needs 3 numbers X,Y,Z [mm]; {TOOL_USAGE}"),
                    ));
                };
                edit.com_mm = Some([
                    number("tool", "com X", x, TOOL_USAGE)?,
                    number("tool", "com Y", y, TOOL_USAGE)?,
                    number("tool", "com Z", z, TOOL_USAGE)?,
                ]);
            }
        }
    }
    Ok(Line::Tool(Some(edit)))
}

/// Three numbers with `decimals`, each right-aligned in 10 columns.
pub(super) fn three(v: [f64; 3], decimals: usize) -> String {
    v.iter()
        .map(|x| format!("{:>10.decimals$}", x + 0.0))
        .collect::<String>()
}

/// Where the TCP is: position [mm] and roll, pitch, yaw [deg] in the base frame, the TCP's
/// speed, and the active tool; or why there is no pose.
pub fn pose_text(state: Option<&StateSample>, cfg: &RobotConfig) -> String {
    let Some(s) = state else {
        return "no pose: the real-time core publishes no state\n".into();
    };
    let mut out = String::new();
    if s.flags & STATE_CARTESIAN == 0 {
        out.push_str("no TCP pose: not every axis is calibrated (`calibrate` first)\n");
    } else {
        let c = &s.cartesian;
        let speed = c.linear_velocity.iter().map(|v| v * v).sum::<f64>().sqrt() * MM;
        let _ = writeln!(
            out,
            "TCP in the base frame:\n{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}\n{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}\n{}{}\nspeed {speed:.1} mm/s",
            "x",
            "y",
            "z",
            "roll",
            "pitch",
            "yaw",
            "mm",
            "mm",
            "mm",
            "deg",
            "deg",
            "deg",
            three(c.position.map(|x| x * MM), 2),
            three(rpy_deg_from_quaternion(c.orientation), 3),
        );
    }
    out.push_str(&tool_text(&active_tool(cfg, Some(s))));
    out.push_str(RPY_NOTE);
    out
}

/// How roll, pitch and yaw are meant, under every table that shows them.
const RPY_NOTE: &str =
    "roll, pitch, yaw: about the fixed axes x, then y, then z (the URDF's rpy)\n";

/// The active tool: its TCP in the flange frame [mm, deg] and its load.
pub fn tool_text(t: &Tool) -> String {
    let rpy = rpy_deg_from_quaternion(t.tcp.orientation);
    let inertia = if t.inertia == [0.0; 6] {
        "a point mass".to_string()
    } else {
        format!("inertia {:?} kg m^2", t.inertia)
    };
    format!(
        "tool: TCP in the flange frame at{} mm, roll pitch yaw{} deg\n      load {:.3} kg, centre of mass at{} mm, {inertia}\n",
        three(t.tcp.position.map(|x| x * MM), 2),
        three(rpy, 3),
        t.mass,
        three(t.center_of_mass.map(|x| x * MM), 2),
    )
}

/// [`tool_text`] with the note on roll, pitch and yaw.
pub fn tool_with_note(t: &Tool) -> String {
    format!("{}{RPY_NOTE}", tool_text(t))
}

#[cfg(test)]
mod tests;
