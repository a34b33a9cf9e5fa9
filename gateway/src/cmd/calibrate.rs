//! `calibrate`: home the axes against their mechanical stops or light barriers.

use crate::args::{Args, CommandError};
use mcm_shared::command::{Axis, Calibrate, Direction, Which};
use serde_json::Value;

/// Parse the arguments of `calibrate` (all optional: every axis, default directions).
pub fn parse(arguments: Option<&Value>) -> Result<Calibrate, CommandError> {
    let args = Args::new(
        "calibrate",
        arguments,
        &[
            "which",
            "elbow_direction",
            "wrist_direction",
            "force_mechanical_stop",
        ],
    )?;
    let expected = "\"ALL\", \"ELBOW\", \"WRIST\" or an axis number from 1 to 6";
    let which = match args.raw("which") {
        None => Which::All,
        Some(v @ Value::String(s)) => match s.to_ascii_uppercase().as_str() {
            "ALL" => Which::All,
            "ELBOW" => Which::Elbow,
            "WRIST" => Which::Wrist,
            n => match n.parse::<u8>().ok().and_then(Axis::new) {
                Some(a) => Which::Axis(a),
                None => return Err(args.invalid("which", v, expected)),
            },
        },
        Some(v) => match v
            .as_u64()
            .and_then(|n| u8::try_from(n).ok())
            .and_then(Axis::new)
        {
            Some(a) => Which::Axis(a),
            None => return Err(args.invalid("which", v, expected)),
        },
    };
    let direction = |name: &'static str| -> Result<Direction, CommandError> {
        match args.raw(name) {
            None => Ok(Direction::Positive),
            Some(v) => match v.as_i64() {
                Some(1) => Ok(Direction::Positive),
                Some(-1) => Ok(Direction::Negative),
                _ => Err(args.invalid(name, v, "1 or -1")),
            },
        }
    };
    Ok(Calibrate {
        which,
        elbow_direction: direction("elbow_direction")?,
        wrist_direction: direction("wrist_direction")?,
        force_mechanical_stop: args.boolean("force_mechanical_stop")?.unwrap_or(false),
    })
}
