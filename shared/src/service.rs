//! iceoryx2 service names and their quality of service.
//!
//! Every service name starts with `mcm/<instance>/`, so several MCMs (or parallel tests) can
//! share one machine. The real-time core *creates* every service with the QoS below; every
//! other participant only *opens* them (and retries while they do not exist yet).
//!
//! | service | pattern | payload | writer | readers |
//! | --- | --- | --- | --- | --- |
//! | `mcm/<i>/state` | blackboard, key [`STATE_KEY`] | [`StateSample`](crate::sample::StateSample) | mcm-rt, once per cycle | gateway, controllers |
//! | `mcm/<i>/state` | same blackboard, keys 1 to [`REPLY_BLOCKS`](crate::sample::REPLY_BLOCKS) | [`ReplyBlock`](crate::sample::ReplyBlock) | mcm-rt, before the state that counts the replies | gateway, controllers |
//! | `mcm/<i>/state-ready` | event, id [`STATE_EVENT_ID`] | - | mcm-rt, after each cycle's work | gateway, controllers (wait for the next state) |
//! | `mcm/<i>/command` | publish-subscribe | [`CommandSample`](crate::sample::CommandSample) | gateway, controllers | mcm-rt, drained every cycle |
//!
//! Reply `n` is in the block [`reply_location`](crate::sample::reply_location) names; a reader
//! keeps the last `n` it has seen and reads up to the state's `reply_head`.
//!
//! [`ServiceNames`] hands out each name as text (for messages) and as iceoryx2's
//! `ServiceName` (`*_service`), the one conversion every participant (the core, the gateway,
//! the clients, the tests) uses; an instance name that [`ServiceNames::new`] accepts always
//! makes names iceoryx2 accepts, so the conversion cannot fail.

use core::fmt;
use iceoryx2::prelude::ServiceName;

/// The blackboard key of the state entry.
pub const STATE_KEY: u32 = 0;
/// Most publishers the command service accepts (gateway plus co-located controllers).
pub const COMMAND_MAX_PUBLISHERS: usize = 8;
/// Commands the real-time core serves per cycle at most (the rest wait for the next cycle).
pub const COMMANDS_PER_CYCLE: usize = 8;
/// Commands buffered for the real-time core between two cycles. Publishers must keep fewer
/// than this many unanswered (the gateway keeps at most half of it in flight).
pub const COMMAND_BUFFER: usize = 64;
/// Most readers of the state blackboard.
pub const STATE_MAX_READERS: usize = 16;
/// Most listeners of the state event (the gateway and co-located controllers).
pub const STATE_EVENT_MAX_LISTENERS: usize = 16;
/// The event id mcm-rt notifies after publishing a new state.
pub const STATE_EVENT_ID: usize = 1;
/// Commands the real-time core keeps received but not yet served: every publisher's whole
/// buffer, so that draining the command service every cycle never overflows it.
pub const COMMAND_BACKLOG: usize = COMMAND_MAX_PUBLISHERS * COMMAND_BUFFER;

/// An instance name is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "instance name {name:?} is not allowed: use 1 to 32 characters from a-z, A-Z, 0-9, '-' and '_'"
)]
pub struct InvalidInstanceName {
    pub name: String,
}

/// Where the simulated robot of `instance` waits while its `mcm-rt` restarts: the file
/// `mcm-sim-<instance>.state` in the temporary directory, written when the real-time loop
/// stops and resumed from (then deleted) at the next start of the same instance.
pub fn sim_state_path(instance: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("mcm-sim-{instance}.state"))
}

/// Longest instance name [characters].
const MAX_INSTANCE: usize = 32;

/// One of an instance's service names as iceoryx2's: `mcm/`, an instance name of 1 to
/// [`MAX_INSTANCE`] characters from `a-z A-Z 0-9 - _`, and a fixed suffix, which iceoryx2
/// always accepts (non-empty ASCII, far within its length limit; a test tries the extremes).
fn iceoryx2_name(name: &str) -> ServiceName {
    match ServiceName::new(name) {
        Ok(n) => n,
        Err(e) => unreachable!("the service name `{name}` of a valid instance is refused: {e}"),
    }
}

/// The service names of one MCM instance.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ServiceNames {
    instance: String,
}

impl ServiceNames {
    /// The instance used when none is given.
    pub const DEFAULT_INSTANCE: &'static str = "default";

    pub fn new(instance: &str) -> Result<Self, InvalidInstanceName> {
        let ok = (1..=MAX_INSTANCE).contains(&instance.len())
            && instance
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_');
        if ok {
            Ok(Self {
                instance: instance.to_string(),
            })
        } else {
            Err(InvalidInstanceName {
                name: instance.to_string(),
            })
        }
    }

    pub fn instance(&self) -> &str {
        &self.instance
    }

    /// The state blackboard.
    pub fn state(&self) -> String {
        format!("mcm/{}/state", self.instance)
    }

    /// The event service mcm-rt notifies after each new state.
    pub fn state_event(&self) -> String {
        format!("mcm/{}/state-ready", self.instance)
    }

    /// The command publish-subscribe service.
    pub fn command(&self) -> String {
        format!("mcm/{}/command", self.instance)
    }

    /// [`ServiceNames::state`] as iceoryx2's service name.
    pub fn state_service(&self) -> ServiceName {
        iceoryx2_name(&self.state())
    }

    /// [`ServiceNames::state_event`] as iceoryx2's service name.
    pub fn state_event_service(&self) -> ServiceName {
        iceoryx2_name(&self.state_event())
    }

    /// [`ServiceNames::command`] as iceoryx2's service name.
    pub fn command_service(&self) -> ServiceName {
        iceoryx2_name(&self.command())
    }

    /// Node name of a participant, e.g. `mcm-rt.robot1`.
    pub fn node(&self, role: &str) -> String {
        format!("{role}.{}", self.instance)
    }
}

impl fmt::Display for ServiceNames {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.instance)
    }
}

#[cfg(test)]
mod tests;
