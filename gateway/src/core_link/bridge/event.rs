//! The core's state event (`mcm/<i>/state-ready`, notified by mcm-rt after each new state), as
//! the bridge thread listens to it: the listener is one of the thread's own ports, and its
//! file descriptor is polled together with the doorbell (`wait.rs`), so a new state wakes the
//! bridge thread directly.
//!
//! While the event service does not exist the bridge retries every [`OPEN_RETRY`]. Quiet for
//! longer than [`SILENT_AFTER`] (the core stopped or restarted), the listener is dropped and the
//! service opened again, so a restarted core's new service is picked up.

use iceoryx2::port::listener::{Listener, ListenerWaitError};
use iceoryx2::prelude::*;
use mcm_client::shm::OpenError;
use mcm_client::shm::ports::{open_node, open_state_event};
use mcm_shared::service::{STATE_EVENT_ID, ServiceNames};
use std::os::fd::RawFd;
use std::time::{Duration, Instant};

/// Time between two attempts to open the event service.
pub(super) const OPEN_RETRY: Duration = Duration::from_millis(100);
/// No notification for this long: reopen the service.
const SILENT_AFTER: Duration = Duration::from_millis(500);

struct Open {
    listener: Listener<ipc::Service>,
    // Dropped after the listener made through it.
    _node: Node<ipc::Service>,
}

fn open(names: &ServiceNames) -> Result<Open, OpenError> {
    let node = open_node(names, "mcm-gateway-wake")?;
    let listener = open_state_event(&node, names)?;
    Ok(Open {
        listener,
        _node: node,
    })
}

/// The bridge thread's listener on the core's state event, opened (and reopened) as needed.
pub(super) struct StateEvent {
    names: ServiceNames,
    port: Option<Open>,
    last_try: Option<Instant>,
    last_event: Instant,
    /// Notifications arrive (the bridge need not poll the state).
    live: bool,
}

impl StateEvent {
    pub(super) fn new(names: ServiceNames) -> StateEvent {
        StateEvent {
            names,
            port: None,
            last_try: None,
            last_event: Instant::now(),
            live: false,
        }
    }

    /// Whether notifications arrive.
    pub(super) fn live(&self) -> bool {
        self.live
    }

    /// Open the service when closed and the last attempt is [`OPEN_RETRY`] ago; drop it when
    /// it has been silent for [`SILENT_AFTER`].
    pub(super) fn maintain(&mut self) {
        if self.port.is_some() {
            if self.last_event.elapsed() > SILENT_AFTER {
                self.close();
            }
            return;
        }
        if self.last_try.is_some_and(|t| t.elapsed() < OPEN_RETRY) {
            return;
        }
        self.last_try = Some(Instant::now());
        if let Ok(p) = open(&self.names) {
            self.port = Some(p);
            self.last_event = Instant::now();
        }
    }

    /// Drop the listener; the next [`StateEvent::maintain`] after [`OPEN_RETRY`] opens it again.
    fn close(&mut self) {
        self.port = None;
        self.live = false;
        self.last_try = Some(Instant::now());
    }

    /// The listener's descriptor to poll, when open. Valid until the next
    /// [`StateEvent::maintain`] or [`StateEvent::drain`] (either may close the port): the
    /// bridge polls it right away and never keeps it.
    pub(super) fn fd(&self) -> Option<RawFd> {
        self.port.as_ref().map(|p| {
            // SAFETY: the value is only passed to the `poll(2)` that follows at once, while the
            // listener (which owns and alone closes the descriptor) is alive and unchanged.
            unsafe { p.listener.file_descriptor().native_handle() }
        })
    }

    /// Take every pending notification (without blocking); one that says a new state is
    /// published marks the event live.
    pub(super) fn drain(&mut self) {
        let Some(port) = self.port.as_ref() else {
            return;
        };
        let mut ours = false;
        match port
            .listener
            .try_wait(|e| ours |= e.id.as_value() == STATE_EVENT_ID)
        {
            Ok(_) if ours => {
                self.last_event = Instant::now();
                self.live = true;
            }
            // Cut short by a signal: what is pending stays readable for the next poll.
            Ok(_) | Err(ListenerWaitError::InterruptSignal) => {}
            Err(_) => {
                self.close();
            }
        }
    }
}
