//! `sleep`: delay this connection's next command; other connections are not delayed.
//! Executed by the gateway itself.

use crate::args::{Args, CommandError};
use serde_json::Value;
use std::time::Duration;

/// Longest sleep accepted [s].
pub const MAX_SLEEP_S: f64 = 3600.0;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sleep {
    pub duration: Duration,
}

impl Sleep {
    pub fn parse(arguments: Option<&Value>) -> Result<Self, CommandError> {
        let args = Args::new("sleep", arguments, &["duration"])?;
        let s = args.required_number("duration", 0.0, MAX_SLEEP_S, " s")?;
        Ok(Self {
            duration: Duration::from_secs_f64(s),
        })
    }
}
