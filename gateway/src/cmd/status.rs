//! `status`: request the status result; `"detail": true` adds hardware status and per-axis data.

use crate::args::{Args, CommandError};
use serde_json::Value;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Status {
    pub detail: bool,
}

impl Status {
    pub fn parse(arguments: Option<&Value>) -> Result<Self, CommandError> {
        let args = Args::new("status", arguments, &["detail"])?;
        Ok(Self {
            detail: args.boolean("detail")?.unwrap_or(false),
        })
    }
}
