//! `calibrate`: home the axes against their mechanical stops or light barriers. Answers OK when
//! the calibration has finished (HOLD), or the reason it failed.

use super::prelude::*;
use crate::command::{Axis, Calibrate, Direction, Which};

/// `which` when none is given: every axis.
pub const DEFAULT_WHICH: Which = Which::All;

const WHICH_EXPECTED: &str = "\"ALL\", \"ELBOW\", \"WRIST\" or an axis number from 1 to 6";

/// An axis number given as a JSON number (`3`, also `3.0`, as `axis_index` takes it: the same
/// check) or as a string (`"3"`).
fn axis_of(v: &Value) -> Option<Axis> {
    let n = match v {
        Value::String(s) => s.trim().parse::<f64>().ok()?,
        _ => v.as_f64()?,
    };
    let arg = Arg::AxisIndex;
    arg.accepts(n, arg.fixed_bounds())
        .then(|| Axis::new(n as u8))
        .flatten()
}

fn which_of(v: &Value) -> Option<Which> {
    if let Value::String(s) = v {
        match s.to_ascii_uppercase().as_str() {
            "ALL" => return Some(Which::All),
            "ELBOW" => return Some(Which::Elbow),
            "WRIST" => return Some(Which::Wrist),
            _ => {}
        }
    }
    axis_of(v).map(Which::Axis)
}

fn which_value(w: Which) -> Value {
    match w {
        Which::All => "ALL".into(),
        Which::Elbow => "ELBOW".into(),
        Which::Wrist => "WRIST".into(),
        Which::Axis(a) => a.number().into(),
    }
}

fn direction(args: &Args<'_>, name: &'static str) -> Result<Direction, CommandError> {
    match args.raw(name) {
        None => Ok(Direction::Positive),
        Some(v) => match v.as_f64() {
            Some(1.0) => Ok(Direction::Positive),
            Some(-1.0) => Ok(Direction::Negative),
            _ => Err(args.invalid(name, v, "1 or -1")),
        },
    }
}

impl Definition for Calibrate {
    const DEF: CommandDef = CommandDef {
        name: "calibrate",
        kind: Some(CommandKind::Calibrate),
        sends: None,
        success: Success::Ok,
        group: Group::OffAndHold,
        ok_words: " - calibration finished",
        summary: "home the axes against their mechanical stops or light barriers",
        args: &[
            arg(
                "which",
                "",
                Kind::Which,
                true,
                "ALL",
                "ALL, ELBOW (axes 1-3), WRIST (axes 4-6) or one axis 1..6",
            ),
            arg(
                "elbow_direction",
                "elbow",
                Kind::Direction,
                false,
                "1",
                "1 or -1; -1 reverses the search direction of axis 3",
            ),
            arg(
                "wrist_direction",
                "wrist",
                Kind::Direction,
                false,
                "1",
                "1 or -1; -1 reverses the search direction of axes 4-6",
            ),
            arg(
                "force_mechanical_stop",
                "force",
                Kind::Bool,
                false,
                "false",
                "use the mechanical stops even where light barriers exist",
            ),
        ],
        modes: "OFF and HOLD (the mode is CALIBRATION while it runs)",
        how: "`hold` first",
        reply: "OK when calibration has finished (HOLD), or the reason it failed (ERROR)",
        examples: &["calibrate", "calibrate which=WRIST", "calibrate 3 force"],
        notes: "Needed after every power-up, before any motion. Until then positions are raw \
                encoder positions. Ctrl-C stops waiting for the answer, not the calibration.",
    };

    /// All arguments optional: every axis, default directions.
    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        let which = match args.raw("which") {
            None => DEFAULT_WHICH,
            Some(v) => which_of(v).ok_or_else(|| args.invalid("which", v, WHICH_EXPECTED))?,
        };
        Ok(Calibrate {
            which,
            elbow_direction: direction(args, "elbow_direction")?,
            wrist_direction: direction(args, "wrist_direction")?,
            force_mechanical_stop: args.boolean("force_mechanical_stop")?.unwrap_or(false),
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("which".into(), which_value(self.which));
        m.insert(
            "elbow_direction".into(),
            (self.elbow_direction.sign() as i8).into(),
        );
        m.insert(
            "wrist_direction".into(),
            (self.wrist_direction.sign() as i8).into(),
        );
        m.insert(
            "force_mechanical_stop".into(),
            self.force_mechanical_stop.into(),
        );
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::Calibrate(*self)]
    }
}
