//! The wake-up thread: it owns its own iceoryx2 node and a listener on the core's state event
//! (`mcm/<i>/state-ready`, notified by mcm-rt after each new state) and turns every
//! notification into a [`Wake::State`] on the channel the bridge thread blocks on. Listener
//! ports are not `Send`, hence a thread of their own.
//!
//! While the event service does not exist it retries every [`OPEN_RETRY`]; `live` tells the
//! bridge whether wake-ups come (when not, the bridge falls back to a bounded poll). Quiet for
//! longer than [`SILENT_AFTER`] (the core stopped or restarted), it drops the listener and opens
//! the service again, so a restarted core's new service is picked up.

use super::Wake;
use iceoryx2::prelude::*;
use mcm_shared::service::{STATE_EVENT_ID, ServiceNames};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Sender;
use std::time::{Duration, Instant};

/// Time between two attempts to open the event service.
const OPEN_RETRY: Duration = Duration::from_millis(100);
/// Longest single wait on the listener (the stop flag is checked in between).
const WAIT: Duration = Duration::from_millis(100);
/// No notification for this long: reopen the service.
const SILENT_AFTER: Duration = Duration::from_millis(500);

/// Flags shared between the wake-up thread and the bridge thread.
#[derive(Default)]
pub(super) struct EventFlags {
    /// The listener is open and notifications arrive.
    pub(super) live: AtomicBool,
    /// A [`Wake::State`] is on its way and not yet taken by the bridge (wake-ups coalesce).
    pub(super) pending: AtomicBool,
    pub(super) stop: AtomicBool,
}

struct Open {
    _node: Node<ipc::Service>,
    listener: iceoryx2::port::listener::Listener<ipc::Service>,
}

fn open(names: &ServiceNames) -> Result<Open, String> {
    let node = NodeBuilder::new()
        .name(
            &NodeName::new(&names.node("mcm-gateway-wake"))
                .map_err(|e| format!("node name: {e:?}"))?,
        )
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .map_err(|e| format!("creating the node failed: {e:?}"))?;
    let service = node
        .service_builder(
            &ServiceName::new(&names.state_event()).map_err(|e| format!("service name: {e}"))?,
        )
        .event()
        .open()
        .map_err(|e| format!("opening `{}` failed: {e:?}", names.state_event()))?;
    let listener = service
        .listener_builder()
        .create()
        .map_err(|e| format!("creating a listener failed: {e:?}"))?;
    Ok(Open {
        _node: node,
        listener,
    })
}

/// Run the wake-up loop until `flags.stop` is set.
pub(super) fn run(names: ServiceNames, wake: Sender<Wake>, flags: Arc<EventFlags>) {
    let mut open_port: Option<Open> = None;
    let mut last_try: Option<Instant> = None;
    let mut last_event = Instant::now();
    while !flags.stop.load(Ordering::Relaxed) {
        let Some(port) = open_port.as_ref() else {
            if let Some(t) = last_try {
                let left = OPEN_RETRY.saturating_sub(t.elapsed());
                if !left.is_zero() {
                    // Not a synchronisation: the pace of the open retries (the stop flag is
                    // seen within one retry period).
                    std::thread::sleep(left);
                    continue;
                }
            }
            last_try = Some(Instant::now());
            if let Ok(p) = open(&names) {
                open_port = Some(p);
                last_event = Instant::now();
            }
            continue;
        };
        let mut ours = false;
        let waited = port
            .listener
            .timed_wait(|e| ours |= e.id.as_value() == STATE_EVENT_ID, WAIT);
        match waited {
            Ok(_) if ours => {
                last_event = Instant::now();
                flags.live.store(true, Ordering::Relaxed);
                if !flags.pending.swap(true, Ordering::AcqRel) && wake.send(Wake::State).is_err() {
                    return;
                }
            }
            Ok(_) if last_event.elapsed() < SILENT_AFTER => {}
            // Silent (the core stopped) or broken: open the service again.
            _ => {
                flags.live.store(false, Ordering::Relaxed);
                open_port = None;
                last_try = Some(Instant::now());
            }
        }
    }
}
