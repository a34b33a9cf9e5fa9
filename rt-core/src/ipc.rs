//! The iceoryx2 edge of the real-time core: the state blackboard it writes and the command
//! service it drains.
//!
//! Set-up ([`RtIpc::create`]) runs once before the cycle. Inside the cycle, [`RtIpc::drain`]
//! (`Subscriber::receive`) and [`RtIpc::publish`] (blackboard `update_with_copy`) neither block
//! nor allocate in steady state. When a peer opens or closes the command service, the next
//! `receive` sets the connection up inside that call (iceoryx2 0.10: about ten small allocations
//! and 0.1 to 0.3 ms); peers therefore join at start-up, not per command. State goes through a
//! blackboard precisely because readers joining or leaving never touch the writer.
//!
//! The real-time core *creates* both services with the QoS of [`mcm_shared::service`]; anything
//! else opens them.

use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::port::writer::EntryHandleMut;
use iceoryx2::prelude::*;
use iceoryx2::service::builder::blackboard::BlackboardCreateError;
use mcm_shared::sample::{CommandSample, StateSample};
use mcm_shared::service::{
    COMMAND_BUFFER, COMMAND_MAX_PUBLISHERS, STATE_KEY, STATE_MAX_READERS, ServiceNames,
};

/// Setting up the IPC services failed.
#[derive(Debug, thiserror::Error)]
pub enum IpcSetupError {
    #[error("iceoryx2 {what} `{name}` failed: {reason}")]
    Iceoryx {
        what: &'static str,
        name: String,
        reason: String,
    },
    #[error(
        "the services of instance `{instance}` exist already: another mcm-rt runs with this instance name ({reason})"
    )]
    InstanceInUse { instance: String, reason: String },
}

fn iox(what: &'static str, name: &str, e: impl std::fmt::Debug) -> IpcSetupError {
    IpcSetupError::Iceoryx {
        what,
        name: name.to_string(),
        reason: format!("{e:?}"),
    }
}

/// Receiving commands failed inside the cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("command service receive failed: {0}")]
pub struct ReceiveError(&'static str);

/// The real-time core's IPC ports. Not `Send`: create it on the cycle thread.
pub struct RtIpc {
    _node: Node<ipc::Service>,
    state: EntryHandleMut<ipc::Service, u32, StateSample>,
    commands: Subscriber<ipc::Service, CommandSample, ()>,
}

impl RtIpc {
    /// Create the node and both services of `names`.
    pub fn create(names: &ServiceNames) -> Result<Self, IpcSetupError> {
        // iceoryx2 warns about its own defaults (no config file); IOX2_LOG_LEVEL overrides.
        set_log_level_from_env_or(LogLevel::Error);
        let node_name = names.node("mcm-rt");
        let node = NodeBuilder::new()
            .name(
                &node_name
                    .as_str()
                    .try_into()
                    .map_err(|e| iox("node name", &node_name, e))?,
            )
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<ipc::Service>()
            .map_err(|e| iox("node", &node_name, e))?;

        // A restarted mcm-rt finds its services still open by the gateway or controllers:
        // it creates them when they are missing and opens them otherwise. A second live
        // mcm-rt of the same instance is refused when it asks for the single writer.
        let state_name = names.state();
        let service_name: ServiceName = state_name
            .as_str()
            .try_into()
            .map_err(|e| iox("service name", &state_name, e))?;
        let state_service = match node
            .service_builder(&service_name)
            .blackboard_creator::<u32>()
            .max_readers(STATE_MAX_READERS)
            .add::<StateSample>(STATE_KEY, StateSample::default())
            .create()
        {
            Ok(s) => s,
            Err(BlackboardCreateError::AlreadyExists) => node
                .service_builder(&service_name)
                .blackboard_opener::<u32>()
                .max_readers(STATE_MAX_READERS)
                .open()
                .map_err(|e| iox("blackboard open", &state_name, e))?,
            Err(e) => return Err(iox("blackboard", &state_name, e)),
        };
        let writer =
            state_service
                .writer_builder()
                .create()
                .map_err(|e| IpcSetupError::InstanceInUse {
                    instance: names.instance().to_string(),
                    reason: format!("{state_name}: writer: {e:?}"),
                })?;
        let state = writer
            .entry::<StateSample>(&STATE_KEY)
            .map_err(|e| iox("blackboard entry", &state_name, e))?;

        let command_name = names.command();
        let command_service = node
            .service_builder(
                &command_name
                    .as_str()
                    .try_into()
                    .map_err(|e| iox("service name", &command_name, e))?,
            )
            .publish_subscribe::<CommandSample>()
            .max_publishers(COMMAND_MAX_PUBLISHERS)
            .max_subscribers(1)
            .subscriber_max_buffer_size(COMMAND_BUFFER)
            .history_size(0)
            .enable_safe_overflow(true)
            .open_or_create()
            .map_err(|e| iox("publish-subscribe service", &command_name, e))?;
        let commands = command_service
            .subscriber_builder()
            .buffer_size(COMMAND_BUFFER)
            .create()
            .map_err(|e| IpcSetupError::InstanceInUse {
                instance: names.instance().to_string(),
                reason: format!("{command_name}: subscriber: {e:?}"),
            })?;

        Ok(Self {
            _node: node,
            state,
            commands,
        })
    }

    /// Move up to `buf.len()` pending commands into `buf`; returns how many. Commands beyond
    /// that stay queued for the next cycle.
    pub fn drain(&mut self, buf: &mut [CommandSample]) -> Result<usize, ReceiveError> {
        let mut n = 0;
        while n < buf.len() {
            match self.commands.receive() {
                Ok(Some(sample)) => {
                    buf[n] = *sample;
                    n += 1;
                }
                Ok(None) => break,
                Err(_) => return Err(ReceiveError("iceoryx2 subscriber error")),
            }
        }
        Ok(n)
    }

    /// Publish the state of this cycle.
    pub fn publish(&self, state: &StateSample) {
        self.state.update_with_copy(*state);
    }
}
