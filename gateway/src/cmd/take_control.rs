//! `take_control`: make this connection the one that controls the arm's motion. Refused
//! (`not_owner`, naming the owner) while another client controls it; OK when this connection
//! already does. Subject to the access rules (`crate::access`): allowed network, and the shared
//! secret when one is configured. No arguments.

use crate::args::{Args, CommandError};
use serde_json::Value;

pub fn parse(arguments: Option<&Value>) -> Result<(), CommandError> {
    Args::new("take_control", arguments, &[]).map(|_| ())
}
