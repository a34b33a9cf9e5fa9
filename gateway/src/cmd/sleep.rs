//! `sleep`: delay this connection's next command; other connections are not delayed.
//! Executed by the gateway itself.

use crate::args::{Args, CommandError};
use mcm_shared::ranges::Arg;
use serde_json::Value;
use std::time::Duration;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sleep {
    pub duration: Duration,
}

impl Sleep {
    pub fn parse(arguments: Option<&Value>) -> Result<Self, CommandError> {
        let args = Args::new("sleep", arguments, &["duration"])?;
        let s = args.required_ranged(Arg::Duration, Arg::Duration.fixed_bounds())?;
        Ok(Self {
            duration: Duration::from_secs_f64(s),
        })
    }
}
