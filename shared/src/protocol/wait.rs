//! How long the MCM may take to answer a command: the one bound the gateway waits for the
//! real-time core's reply, and that the clients (TCP and shared memory) add their margin to.
//! Not used inside the real-time cycle.

use super::Command;
use crate::mode::CommandKind;
use std::time::Duration;

/// Longest wait for the real-time core's reply to a command other than `calibrate` and
/// `identify_payload`: after it
/// the gateway says the outcome is unknown.
pub const REPLY_TIMEOUT: Duration = Duration::from_secs(5);

/// Longest wait for a calibration to finish.
pub const CALIBRATION_TIMEOUT: Duration = Duration::from_secs(600);

/// Longest wait for `identify_payload` to answer: the procedure takes under 30 s of robot
/// time; twice that leaves room for a core that runs late.
pub const IDENTIFY_PAYLOAD_TIMEOUT: Duration = Duration::from_secs(60);

/// The longest the real-time core takes to reply to a request of `kind`.
pub const fn core_reply_within(kind: CommandKind) -> Duration {
    match kind {
        CommandKind::Calibrate => CALIBRATION_TIMEOUT,
        CommandKind::IdentifyPayload => IDENTIFY_PAYLOAD_TIMEOUT,
        _ => REPLY_TIMEOUT,
    }
}

impl Command {
    /// The longest the MCM takes to answer this command: the real-time core's bound for its
    /// reply ([`core_reply_within`]), `sleep`'s duration, [`REPLY_TIMEOUT`] for what the
    /// gateway answers itself. A client waits this long plus its own margin for the way.
    pub fn reply_within(&self) -> Duration {
        match (self, self.def().kind) {
            (Command::Sleep(s), _) => s.duration,
            (_, Some(kind)) => core_reply_within(kind),
            (_, None) => REPLY_TIMEOUT,
        }
    }

    /// How much longer than [`REPLY_TIMEOUT`] the MCM may take to answer this command (0 for
    /// most): what a client adds to the wait it uses for every command.
    pub fn extra_reply_time(&self) -> Duration {
        self.reply_within().saturating_sub(REPLY_TIMEOUT)
    }
}

#[cfg(test)]
mod tests;
