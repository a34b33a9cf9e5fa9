//! `release_control`: give up control of the arm's motion. What this connection drove (a
//! move, a PVT stream, RELEASE, TORQUE_CONTROL, a calibration) ends in HOLD with the
//! controlled stop. OK when nobody controls the arm; refused (`not_owner`) when another
//! client does. No arguments.

use crate::args::{Args, CommandError};
use serde_json::Value;

pub fn parse(arguments: Option<&Value>) -> Result<(), CommandError> {
    Args::new("release_control", arguments, &[]).map(|_| ())
}
