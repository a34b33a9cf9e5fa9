//! iceoryx2 service names and their quality of service.
//!
//! Every service name starts with `mcm/<instance>/`, so several MCMs (or parallel tests) can
//! share one machine. The real-time core *creates* every service with the QoS below; every
//! other participant only *opens* them (and retries while they do not exist yet).
//!
//! | service | pattern | payload | writer | readers |
//! | --- | --- | --- | --- | --- |
//! | `mcm/<i>/state` | blackboard, key [`STATE_KEY`] | [`StateSample`](crate::sample::StateSample) | mcm-rt, once per cycle | gateway, controllers |
//! | `mcm/<i>/command` | publish-subscribe | [`CommandSample`](crate::sample::CommandSample) | gateway, controllers | mcm-rt, drained every cycle |

use core::fmt;

/// The blackboard key of the state entry.
pub const STATE_KEY: u32 = 0;
/// Most publishers the command service accepts (gateway plus co-located controllers).
pub const COMMAND_MAX_PUBLISHERS: usize = 8;
/// Commands the real-time core serves per cycle at most (the rest wait for the next cycle).
/// Each produces a reply (a command may also end an earlier one, e.g. `hold` answers an aborted
/// calibration too), and the state's reply ring keeps the last [`crate::sample::REPLY_RING`]:
/// a reader must look at every cycle's state to be sure to see every reply.
pub const COMMANDS_PER_CYCLE: usize = crate::sample::REPLY_RING / 2;
/// Commands buffered for the real-time core between two cycles. Publishers must keep fewer
/// than this many unanswered (the gateway keeps at most half of it in flight).
pub const COMMAND_BUFFER: usize = 64;
/// Most readers of the state blackboard.
pub const STATE_MAX_READERS: usize = 16;

/// An instance name is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "instance name {name:?} is not allowed: use 1 to 32 characters from a-z, A-Z, 0-9, '-' and '_'"
)]
pub struct InvalidInstanceName {
    pub name: String,
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
        let ok = (1..=32).contains(&instance.len())
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

    /// The command publish-subscribe service.
    pub fn command(&self) -> String {
        format!("mcm/{}/command", self.instance)
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
mod tests {
    use super::*;

    #[test]
    fn names_derive_from_instance() {
        let n = ServiceNames::new("test-42_a").unwrap();
        assert_eq!(n.state(), "mcm/test-42_a/state");
        assert_eq!(n.command(), "mcm/test-42_a/command");
        assert_eq!(n.node("mcm-rt"), "mcm-rt.test-42_a");
        assert_eq!(n.instance(), "test-42_a");
        assert_eq!(n.to_string(), "test-42_a");
    }

    #[test]
    fn default_and_longest_instance_names_are_accepted() {
        let d = ServiceNames::new(ServiceNames::DEFAULT_INSTANCE).unwrap();
        assert_eq!(d.state(), "mcm/default/state");
        let longest = "x".repeat(32);
        assert_eq!(ServiceNames::new(&longest).unwrap().instance(), longest);
    }

    #[test]
    fn bad_instance_names_are_refused() {
        for bad in ["", "a/b", "with space", "é", &"x".repeat(33)] {
            let err = ServiceNames::new(bad).unwrap_err();
            assert_eq!(err.name, bad);
            assert_eq!(
                err.to_string(),
                format!(
                    "instance name {bad:?} is not allowed: use 1 to 32 characters from a-z, \
                     A-Z, 0-9, '-' and '_'"
                ),
            );
        }
    }
}
