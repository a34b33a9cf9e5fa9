//! `calibrate`: home the axes against their mechanical stops or light barriers.

use super::sample;
use crate::args::{Args, CommandError};
use mcm_shared::mode::CommandKind;
use mcm_shared::sample::{CALIBRATE_FLAG_FORCE_STOP, CommandSample};
use serde_json::Value;

/// Which axes to calibrate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    All,
    /// Axes 1-3.
    Elbow,
    /// Axes 4-6.
    Wrist,
    /// One axis, 1..=6.
    Axis(u8),
}

impl Which {
    /// The wire code of `CommandSample::args[0]`.
    pub fn code(self) -> f64 {
        match self {
            Which::All => 0.0,
            Which::Axis(n) => f64::from(n),
            Which::Elbow => 7.0,
            Which::Wrist => 8.0,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibrate {
    pub which: Which,
    pub elbow_direction: i8,
    pub wrist_direction: i8,
    pub force_mechanical_stop: bool,
}

impl Calibrate {
    pub fn parse(arguments: Option<&Value>) -> Result<Self, CommandError> {
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
                n => match n.parse::<u8>() {
                    Ok(a @ 1..=6) => Which::Axis(a),
                    _ => return Err(args.invalid("which", v, expected)),
                },
            },
            Some(v) => match v.as_u64() {
                Some(a @ 1..=6) => Which::Axis(a as u8),
                _ => return Err(args.invalid("which", v, expected)),
            },
        };
        let direction = |name: &'static str| -> Result<i8, CommandError> {
            match args.raw(name) {
                None => Ok(1),
                Some(v) => match v.as_i64() {
                    Some(1) => Ok(1),
                    Some(-1) => Ok(-1),
                    _ => Err(args.invalid(name, v, "1 or -1")),
                },
            }
        };
        Ok(Self {
            which,
            elbow_direction: direction("elbow_direction")?,
            wrist_direction: direction("wrist_direction")?,
            force_mechanical_stop: args.boolean("force_mechanical_stop")?.unwrap_or(false),
        })
    }

    pub fn sample(&self) -> CommandSample {
        let mut s = sample(CommandKind::Calibrate);
        s.args[0] = self.which.code();
        s.args[1] = f64::from(self.elbow_direction);
        s.args[2] = f64::from(self.wrist_direction);
        if self.force_mechanical_stop {
            s.flags |= CALIBRATE_FLAG_FORCE_STOP;
        }
        s
    }
}
