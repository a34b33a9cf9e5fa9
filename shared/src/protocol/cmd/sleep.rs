//! `sleep`: delay this connection's next command; other connections are not delayed. Executed
//! by the gateway itself.

use super::prelude::*;
use std::time::Duration;

/// `sleep`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sleep {
    pub duration: Duration,
}

impl Definition for Sleep {
    const DEF: CommandDef = CommandDef {
        name: "sleep",
        kind: None,
        sends: None,
        success: Success::Ok,
        group: Group::EveryMode,
        ok_words: "",
        summary: "wait before the next command of this session",
        args: &[arg(
            "duration",
            "",
            Kind::Number,
            true,
            "",
            "seconds, 0 to 3600",
        )],
        modes: "every mode",
        how: "",
        reply: "OK when the time has passed (Ctrl-C stops waiting)",
        examples: &["sleep 1.5"],
        notes: "Other sessions are not delayed.",
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        let s = args.required_ranged(Arg::Duration, Arg::Duration.fixed_bounds())?;
        Ok(Sleep {
            duration: Duration::from_secs_f64(s),
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("duration".into(), self.duration.as_secs_f64().into());
        m
    }

    fn requests(&self) -> Vec<Request> {
        Vec::new()
    }
}
