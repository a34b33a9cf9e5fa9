//! The arm loop: the node's one shared-memory client of the core, on its own thread.
//!
//! Each cycle it reads the core's state (woken by the core's event), publishes
//! `/joint_states`, and serves the motion interface ([`crate::motion`]: services, goals,
//! `joint_trajectory`, the running trajectory) unless the node is read-only
//! ([`crate::access`]), which then never sends the core a command. The core does not wait for
//! it: a late node only misses states (counted in `/diagnostics`).

use crate::access::Access;
use crate::convert::{DiagnosticsContext, JointStates, diagnostics};
use crate::dds_threads::{DdsEnded, DdsThreads};
use crate::motion::Motion;
use crate::msgs::builtin::Time;
use crate::msgs::diagnostic::DiagnosticArray;
use crate::msgs::sensor::JointState;
use mcm_client::shm::{ShmClient, ShmEvent, WaitError};
use mcm_shared::busload::BusLoad;
use mcm_shared::reply::SafetyError;
use ros2_client::dds::Publisher;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Everything the arm loop uses.
pub struct Arm<G> {
    pub client: ShmClient,
    pub joint_states: JointStates,
    pub joint_state_pub: Publisher<JointState>,
    pub diagnostics_pub: Publisher<DiagnosticArray>,
    /// The motion interface; `None` for a read-only node.
    pub motion: Option<Motion<G>>,
    pub hardware_id: String,
    pub bus: BusLoad,
    /// Diagnostics every this many cycles (and at once on a safety error).
    pub diagnostics_every: u64,
    /// DDS's threads, checked with the diagnostics.
    pub dds: DdsThreads,
}

/// Why the arm loop ended.
#[derive(Debug, thiserror::Error)]
pub enum ArmError {
    #[error("the MCM's state stopped coming: {0}")]
    State(#[from] WaitError),
    #[error(transparent)]
    Dds(#[from] DdsEnded),
}

impl<G: Copy + PartialEq + std::fmt::Debug> Arm<G> {
    /// Run until `stop` is set, or the core is gone (an error).
    pub fn run(mut self, stop: &AtomicBool) -> Result<(), ArmError> {
        let mut last_error: Option<SafetyError> = None;
        let mut last_diagnostics = 0u64;
        let mut stale_since: Option<Instant> = None;
        let mut not_sent = 0u64;
        while !stop.load(Ordering::Relaxed) {
            let s = match self.client.wait_state_timeout(Duration::from_millis(200)) {
                Ok(s) => {
                    stale_since = None;
                    s
                }
                Err(WaitError::Timeout { .. }) => {
                    // The core publishes every cycle; a pause this long means it stopped. The
                    // node goes on waiting (the launcher ends it with the MCM) for 5 s.
                    let since = *stale_since.get_or_insert_with(Instant::now);
                    if since.elapsed() > Duration::from_secs(5) {
                        return Err(WaitError::Timeout {
                            waited: since.elapsed(),
                            last_seq: self.client.latest().seq,
                        }
                        .into());
                    }
                    continue;
                }
                // Stopping anyway: a wait that fails then is no error.
                Err(_) if stop.load(Ordering::Relaxed) => break,
                Err(e) => return Err(e.into()),
            };
            let stamp = cycle_stamp(s.t_ns);
            let v = self.joint_states.velocity(&s);
            if self
                .joint_state_pub
                .publish(self.joint_states.message(&s, v, stamp))
                .is_err()
            {
                // A reader that does not acknowledge filled the send window: this state is
                // not sent (counted in /diagnostics) rather than the loop waiting.
                not_sent += 1;
            }

            let mut error_now = false;
            while let Some(ev) = self.client.next_event() {
                match ev {
                    ShmEvent::SafetyError(e) => {
                        if let Some(m) = self.motion.as_mut() {
                            m.stopped_by_core(
                                &mut self.client,
                                format!("the MCM stopped the arm: {e}"),
                            );
                        }
                        last_error = Some(e);
                        error_now = true;
                    }
                    ShmEvent::UnreadableSafetyError(e) => {
                        if let Some(m) = self.motion.as_mut() {
                            m.stopped_by_core(
                                &mut self.client,
                                format!(
                                    "the MCM stopped the arm with an error this node cannot read ({e})"
                                ),
                            );
                        }
                        error_now = true;
                    }
                    ShmEvent::Refused(_) => {}
                }
            }

            if let Some(m) = self.motion.as_mut()
                && m.cycle(&s, &v, &mut self.client).is_break()
            {
                return Ok(());
            }

            if error_now || s.seq >= last_diagnostics + self.diagnostics_every {
                last_diagnostics = s.seq;
                self.dds.check()?;
                let cx = DiagnosticsContext {
                    hardware_id: &self.hardware_id,
                    own_client_id: self.client.client_id(),
                    last_error: last_error.as_ref(),
                    bus: &self.bus,
                    missed_states: self.client.missed_states(),
                    not_sent,
                    start_latency_cycles: self
                        .motion
                        .as_ref()
                        .and_then(Motion::start_latency_cycles),
                    access: Access::from_read_only(self.motion.is_none()),
                };
                let _ = self.diagnostics_pub.publish(diagnostics(&s, &cx, stamp));
            }
        }
        Ok(())
    }
}

/// The ROS time (`CLOCK_REALTIME`) of the cycle that started at `t_ns` (`CLOCK_MONOTONIC`):
/// the joint states are stamped with the cycle that measured them, not with the moment they
/// were sent.
fn cycle_stamp(t_ns: u64) -> Time {
    let age_ns = mcm_client::monotonic_ns().saturating_sub(t_ns);
    Time::from_nanos(Time::now().as_nanos() - age_ns as i64)
}
