//! The node's motion interface, served by the arm loop ([`crate::arm`]) once per cycle: the
//! services (`hold`, `calibrate`, `release`, `take_control`, `release_control`), the action
//! server's goals and cancels, the `joint_trajectory` topic, and the running trajectory
//! ([`crate::driver`]). Everything here sends commands to the core; a node started with
//! `--ros2-read-only` ([`crate::access`]) has none of it.
//!
//! It never waits for a command's reply: commands are submitted and their replies read in later
//! cycles, so a `calibrate` that takes a minute does not stop the joint states.

use crate::driver::{Driver, Event, Origin};
use crate::msgs::control::{FollowJointTrajectoryGoal, FollowJointTrajectoryResult, error_code};
use crate::msgs::std_srvs::{TriggerRequest, TriggerResponse};
use crate::msgs::trajectory::JointTrajectory;
use futures::channel::mpsc::UnboundedSender;
use mcm_client::shm::{ShmClient, Submitted};
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Calibrate, Request};
use mcm_shared::protocol::core_reply_within;
use mcm_shared::sample::StateSample;
use ros2_client::RmwRequestId;
use ros2_client::action::GoalEndStatus;
use ros2_client::dds::{Server, Subscription};
use std::ops::ControlFlow;
use std::sync::mpsc::{Receiver, TryRecvError};
use std::time::Instant;

/// What the action server passes to the arm loop.
#[derive(Debug)]
pub enum ToArm<G> {
    Goal(G, Box<FollowJointTrajectoryGoal>),
    Cancel(G),
}

/// The services of the node (`std_srvs/Trigger`), in [`ServiceKind::ALL`] order.
pub type Services = Vec<(ServiceKind, Server<TriggerRequest, TriggerResponse>)>;

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

/// The motion interface's entities and state.
pub struct Motion<G> {
    driver: Driver<G>,
    services: Services,
    trajectory_sub: Subscription<JointTrajectory>,
    from_action: Receiver<ToArm<G>>,
    to_action: UnboundedSender<Event<G>>,
    /// Service requests sent to the core, their replies not read yet.
    calls: Vec<Call>,
}

impl<G: Copy + PartialEq + std::fmt::Debug> Motion<G> {
    pub fn new(
        driver: Driver<G>,
        services: Services,
        trajectory_sub: Subscription<JointTrajectory>,
        from_action: Receiver<ToArm<G>>,
        to_action: UnboundedSender<Event<G>>,
    ) -> Motion<G> {
        Motion {
            driver,
            services,
            trajectory_sub,
            from_action,
            to_action,
            calls: Vec::new(),
        }
    }

    /// The MCM stopped the arm (a safety error): the running trajectory ends with `why`.
    pub fn stopped_by_core(&mut self, client: &mut ShmClient, why: String) {
        self.driver
            .abort(client, error_code::PATH_TOLERANCE_VIOLATED, why);
    }

    /// [`Driver::last_start_latency_cycles`].
    pub fn start_latency_cycles(&self) -> Option<u64> {
        self.driver.last_start_latency_cycles()
    }

    /// One cycle at the state `s` (`velocity`: the measured joint velocity [rad/s]): the
    /// services, then goals and cancels, then the topic's newest message, then the running
    /// trajectory. `Break` when the action server's thread has ended.
    pub fn cycle(
        &mut self,
        s: &StateSample,
        velocity: &[f64; NUM_AXES],
        client: &mut ShmClient,
    ) -> ControlFlow<()> {
        self.services(client);
        loop {
            match self.from_action.try_recv() {
                Ok(ToArm::Goal(g, goal)) => self.driver.start(Origin::Goal(g), &goal, s, client),
                Ok(ToArm::Cancel(g)) => {
                    if !self.driver.cancel(g, s, client) {
                        let _ = self.to_action.unbounded_send(Event::Finished(
                            g,
                            GoalEndStatus::Canceled,
                            FollowJointTrajectoryResult {
                                error_code: error_code::SUCCESSFUL,
                                error_string: "canceled before it ran".to_string(),
                            },
                        ));
                    }
                }
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => return ControlFlow::Break(()),
            }
        }
        let mut newest = None;
        while let Ok(Some((t, _))) = self.trajectory_sub.take() {
            newest = Some(t);
        }
        if let Some(t) = newest {
            self.driver.start_topic(&t, s, client);
        }
        self.driver.step(s, velocity, client);
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
        ControlFlow::Continue(())
    }

    /// One request per server per cycle, sent on; the replies that came, answered.
    fn services(&mut self, client: &mut ShmClient) {
        for (i, (kind, server)) in self.services.iter().enumerate() {
            if let Ok(Some((req_id, _))) = server.receive_request() {
                let req = kind.request();
                match client.submit(&req) {
                    Ok(sub) => self.calls.push(Call {
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
                                message: format!("cannot send `{}` to the MCM: {e}", req.kind()),
                            },
                        );
                    }
                }
                if *kind == ServiceKind::Hold {
                    self.driver.abort(
                        client,
                        error_code::PATH_TOLERANCE_VIOLATED,
                        "stopped by the hold service".to_string(),
                    );
                }
            }
        }
        let servers = &self.services;
        self.calls.retain(|c| {
            let outcome = match client.take_reply(&c.sub) {
                Some(r) => r
                    .map(|_| c.kind.done().to_string())
                    .map_err(|e| e.to_string()),
                None if Instant::now() > c.deadline => {
                    client.forget(&c.sub);
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
            let _ = servers[c.server]
                .1
                .send_response(c.req_id, TriggerResponse { success, message });
            false
        });
    }
}
