//! The arm loop: the node's one shared-memory client of the core, on its own thread.
//!
//! Each cycle it reads the core's state (woken by the core's event), publishes
//! `/joint_states`, answers the services, takes `joint_trajectory` messages and the action
//! server's goals and cancels, and drives the running trajectory ([`crate::driver`]). It never
//! waits for a command's reply: commands are submitted and their replies read in later cycles,
//! so a `calibrate` that takes a minute does not stop the joint states. The core does not wait
//! for it either: a late node only misses states (counted in `/diagnostics`).

use crate::convert::{DiagnosticsContext, JointStates, diagnostics};
use crate::dds_threads::{DdsEnded, DdsThreads};
use crate::driver::{Driver, Event, Origin};
use crate::msgs::builtin::Time;
use crate::msgs::control::{FollowJointTrajectoryGoal, error_code};
use crate::msgs::diagnostic::DiagnosticArray;
use crate::msgs::sensor::JointState;
use crate::msgs::std_srvs::{TriggerRequest, TriggerResponse};
use crate::msgs::trajectory::JointTrajectory;
use futures::channel::mpsc::UnboundedSender;
use mcm_client::shm::{ShmClient, ShmEvent, Submitted, WaitError};
use mcm_shared::busload::BusLoad;
use mcm_shared::command::{Calibrate, Request};
use mcm_shared::protocol::core_reply_within;
use mcm_shared::reply::SafetyError;
use ros2_client::RmwRequestId;
use ros2_client::action::GoalEndStatus;
use ros2_client::dds::{Publisher, Server, Subscription};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError};
use std::time::{Duration, Instant};

/// What the action server passes to the arm loop.
#[derive(Debug)]
pub enum ToArm<G> {
    Goal(G, Box<FollowJointTrajectoryGoal>),
    Cancel(G),
}

/// The services of the node (`std_srvs/Trigger`), in [`Services::ALL`] order.
pub struct Services {
    pub servers: Vec<(ServiceKind, Server<TriggerRequest, TriggerResponse>)>,
}

/// Which service.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ServiceKind {
    Hold,
    Calibrate,
    Release,
    TakeControl,
    ReleaseControl,
}

impl ServiceKind {
    pub const ALL: [ServiceKind; 5] = [
        ServiceKind::Hold,
        ServiceKind::Calibrate,
        ServiceKind::Release,
        ServiceKind::TakeControl,
        ServiceKind::ReleaseControl,
    ];

    /// The service's name (under the node's namespace).
    pub fn name(self) -> &'static str {
        match self {
            ServiceKind::Hold => "hold",
            ServiceKind::Calibrate => "calibrate",
            ServiceKind::Release => "release",
            ServiceKind::TakeControl => "take_control",
            ServiceKind::ReleaseControl => "release_control",
        }
    }

    fn request(self) -> Request {
        match self {
            ServiceKind::Hold => Request::Hold,
            ServiceKind::Calibrate => Request::Calibrate(Calibrate::default()),
            ServiceKind::Release => Request::Release,
            ServiceKind::TakeControl => Request::TakeControl,
            ServiceKind::ReleaseControl => Request::ReleaseControl,
        }
    }

    fn done(self) -> &'static str {
        match self {
            ServiceKind::Hold => "the arm holds (HOLD)",
            ServiceKind::Calibrate => "calibrated; the arm holds (HOLD)",
            ServiceKind::Release => "the arm is in RELEASE (movable by hand)",
            ServiceKind::TakeControl => "this node controls the arm's motion",
            ServiceKind::ReleaseControl => "this node no longer controls the arm's motion",
        }
    }
}

struct Call {
    kind: ServiceKind,
    server: usize,
    req_id: RmwRequestId,
    sub: Submitted,
    deadline: Instant,
}

/// Everything the arm loop uses.
pub struct Arm<G> {
    pub client: ShmClient,
    pub driver: Driver<G>,
    pub joint_states: JointStates,
    pub joint_state_pub: Publisher<JointState>,
    pub diagnostics_pub: Publisher<DiagnosticArray>,
    pub services: Services,
    pub trajectory_sub: Subscription<JointTrajectory>,
    pub from_action: Receiver<ToArm<G>>,
    pub to_action: UnboundedSender<Event<G>>,
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
        let mut calls: Vec<Call> = Vec::new();
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
                        self.driver.abort(
                            &mut self.client,
                            error_code::PATH_TOLERANCE_VIOLATED,
                            format!("the MCM stopped the arm: {e}"),
                        );
                        last_error = Some(e);
                        error_now = true;
                    }
                    ShmEvent::UnreadableSafetyError(e) => {
                        self.driver.abort(
                            &mut self.client,
                            error_code::PATH_TOLERANCE_VIOLATED,
                            format!(
                                "the MCM stopped the arm with an error this node cannot read ({e})"
                            ),
                        );
                        error_now = true;
                    }
                    ShmEvent::Refused(_) => {}
                }
            }

            // Services: one request per server per cycle.
            for (i, (kind, server)) in self.services.servers.iter().enumerate() {
                if let Ok(Some((req_id, _))) = server.receive_request() {
                    let req = kind.request();
                    match self.client.submit(&req) {
                        Ok(sub) => calls.push(Call {
                            kind: *kind,
                            server: i,
                            req_id,
                            sub,
                            deadline: Instant::now() + core_reply_within(req.kind()),
                        }),
                        Err(e) => {
                            let _ = server.send_response(
                                req_id,
                                TriggerResponse {
                                    success: false,
                                    message: format!(
                                        "cannot send `{}` to the MCM: {e}",
                                        req.kind()
                                    ),
                                },
                            );
                        }
                    }
                    if *kind == ServiceKind::Hold {
                        self.driver.abort(
                            &mut self.client,
                            error_code::PATH_TOLERANCE_VIOLATED,
                            "stopped by the hold service".to_string(),
                        );
                    }
                }
            }
            calls.retain(|c| {
                let outcome = match self.client.take_reply(&c.sub) {
                    Some(r) => r
                        .map(|_| c.kind.done().to_string())
                        .map_err(|e| e.to_string()),
                    None if Instant::now() > c.deadline => {
                        self.client.forget(&c.sub);
                        Err(format!(
                            "the MCM did not answer `{}` in time: its outcome is unknown",
                            c.sub.kind()
                        ))
                    }
                    None => return true,
                };
                let (success, message) = match outcome {
                    Ok(m) => (true, m),
                    Err(m) => (false, m),
                };
                let _ = self.services.servers[c.server]
                    .1
                    .send_response(c.req_id, TriggerResponse { success, message });
                false
            });

            // Trajectories: goals, cancels, then the topic's newest message.
            loop {
                match self.from_action.try_recv() {
                    Ok(ToArm::Goal(g, goal)) => {
                        self.driver
                            .start(Origin::Goal(g), &goal, &s, &mut self.client)
                    }
                    Ok(ToArm::Cancel(g)) => {
                        if !self.driver.cancel(g, &s, &mut self.client) {
                            let _ = self.to_action.unbounded_send(Event::Finished(
                                g,
                                GoalEndStatus::Canceled,
                                crate::msgs::control::FollowJointTrajectoryResult {
                                    error_code: error_code::SUCCESSFUL,
                                    error_string: "canceled before it ran".to_string(),
                                },
                            ));
                        }
                    }
                    Err(TryRecvError::Empty) => break,
                    Err(TryRecvError::Disconnected) => return Ok(()),
                }
            }
            let mut newest = None;
            while let Ok(Some((t, _))) = self.trajectory_sub.take() {
                newest = Some(t);
            }
            if let Some(t) = newest {
                self.driver.start_topic(&t, &s, &mut self.client);
            }
            self.driver.step(&s, &v, &mut self.client);
            for ev in self.driver.take_events() {
                match ev {
                    Event::TopicEnded(status, why) => {
                        if status != GoalEndStatus::Succeeded {
                            eprintln!("mcm-ros2: joint_trajectory message ended {status:?}: {why}");
                        }
                    }
                    ev => {
                        let _ = self.to_action.unbounded_send(ev);
                    }
                }
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
                    start_latency_cycles: self.driver.last_start_latency_cycles(),
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
