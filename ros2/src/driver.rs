//! Executing trajectories on the core: goals of `follow_joint_trajectory` and messages of
//! `joint_trajectory` become the PVT stream of [`crate::stream`].
//!
//! One trajectory runs at a time. A new one preempts the running one where its queued points
//! end (the old goal ends `CANCELED`, "preempted"). The driver is called once per state (cycle)
//! by the arm loop; it never waits: commands go out with [`ShmClient::submit`] and their replies
//! are looked for in later cycles.
//!
//! How a trajectory ends:
//! - `SUCCEEDED` when the plan's time has passed its end and the measured positions and
//!   velocities are within the goal tolerances;
//! - `ABORTED` with `GOAL_TOLERANCE_VIOLATED` when they are not within the goal time tolerance
//!   after the end; with `PATH_TOLERANCE_VIOLATED` when the measured positions leave the path
//!   tolerance during the motion, and when the MCM stops the arm (a safety error, a `hold` from
//!   another client, the stream running dry), with the MCM's words; with `INVALID_GOAL` or
//!   `INVALID_JOINTS` for a trajectory that cannot run (and the MCM's words when the core
//!   refused it: not calibrated, not the owner, limits);
//! - `CANCELED` on a cancel request (the arm makes the controlled stop of `hold`) or when a new
//!   goal preempts it.

use crate::msgs::builtin::Time;
use crate::msgs::control::{
    FollowJointTrajectoryFeedback, FollowJointTrajectoryGoal, FollowJointTrajectoryResult,
    error_code,
};
use crate::msgs::std_msgs::Header;
use crate::msgs::trajectory::{JointTrajectory, JointTrajectoryPoint};
use crate::stream::Stream;
use crate::trajectory::{Joints, Plan, StartState, ToleranceDefaults, Tolerances};
use mcm_client::shm::{ShmClient, Submitted};
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Pvt, PvtChunk, PvtPoint, Request};
use mcm_shared::mode::Mode;
use mcm_shared::sample::{
    PVT_POINTS_PER_COMMAND, STATE_ALL_CALIBRATED, STATE_PVT_STARVED, StateSample,
};
use ros2_client::action::GoalEndStatus;
use std::collections::VecDeque;

/// Where a trajectory came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin<G> {
    /// A goal of the action server, by its id.
    Goal(G),
    /// A message of the `joint_trajectory` topic.
    Topic,
}

/// What the arm loop passes on to the action server.
#[derive(Debug)]
pub enum Event<G> {
    Feedback(G, Box<FollowJointTrajectoryFeedback>),
    Finished(G, GoalEndStatus, FollowJointTrajectoryResult),
    /// A `joint_trajectory` message ended (there is nobody to tell but the log).
    TopicEnded(GoalEndStatus, String),
}

/// The driver's settings.
#[derive(Debug, Clone)]
pub struct DriverOptions {
    /// Spacing of the PVT points [s] (the `pvt` command's `dt`).
    pub dt: f64,
    /// How far the node queues points ahead of the arm [s]: a new goal takes over this late.
    pub lead_s: f64,
    /// Feedback every this many cycles.
    pub feedback_every: u64,
    pub tolerances: ToleranceDefaults,
}

struct Active<G> {
    origin: Origin<G>,
    plan: Plan,
    tol: Tolerances,
    /// The plan's t = 0 on the stream's time [s].
    begin_s: f64,
    /// Next plan point to send.
    next_k: usize,
    accepted_cycle: u64,
    first_queued_cycle: Option<u64>,
    last_feedback_cycle: u64,
}

struct InFlight {
    sub: Submitted,
    sent_ns: u64,
}

/// Executes one trajectory at a time (see the module docs).
pub struct Driver<G> {
    opts: DriverOptions,
    joints: Joints,
    stream: Stream,
    active: Option<Active<G>>,
    /// `pvt` (enter PVT mode) sent, reply not read yet.
    entering: Option<(Submitted, u64)>,
    in_flight: VecDeque<InFlight>,
    /// Results to pass on.
    events: Vec<Event<G>>,
    /// Cycles from the newest trajectory's acceptance to the cycle that queued its first points.
    last_start_latency: Option<u64>,
}

/// Longest wait for a reply before the driver gives the trajectory up [ns].
const REPLY_WITHIN_NS: u64 = 2_000_000_000;

impl<G: Copy + PartialEq + std::fmt::Debug> Driver<G> {
    pub fn new(opts: DriverOptions, joints: Joints) -> Driver<G> {
        Driver {
            opts,
            joints,
            stream: Stream::default(),
            active: None,
            entering: None,
            in_flight: VecDeque::new(),
            events: Vec::new(),
            last_start_latency: None,
        }
    }

    /// Events since the last call.
    pub fn take_events(&mut self) -> Vec<Event<G>> {
        std::mem::take(&mut self.events)
    }

    /// The running goal, if any.
    pub fn active_goal(&self) -> Option<G> {
        match self.active.as_ref()?.origin {
            Origin::Goal(g) => Some(g),
            Origin::Topic => None,
        }
    }

    /// A new trajectory: joins the stream where it ends (or starts one) and preempts the
    /// running one; or, when it cannot run, ends at once and leaves the running one alone.
    pub fn start(
        &mut self,
        origin: Origin<G>,
        goal: &FollowJointTrajectoryGoal,
        s: &StateSample,
        client: &mut ShmClient,
    ) {
        if let Err(e) = crate::trajectory::check_size(goal) {
            return self.finish_with(origin, GoalEndStatus::Aborted, e.code(), e.to_string());
        }
        if !goal.multi_dof_trajectory.points.is_empty()
            || !goal.multi_dof_trajectory.joint_names.is_empty()
        {
            return self.finish_with(
                origin,
                GoalEndStatus::Aborted,
                error_code::INVALID_JOINTS,
                format!(
                    "the goal has a multi-DOF trajectory (joints {:?}); this arm has only the revolute joints {}",
                    &goal.multi_dof_trajectory.joint_names[..],
                    self.joints.known()
                ),
            );
        }
        let tol = match Tolerances::from_goal(goal, &self.joints, &self.opts.tolerances) {
            Ok(t) => t,
            Err(e) => {
                return self.finish_with(origin, GoalEndStatus::Aborted, e.code(), e.to_string());
            }
        };
        self.start_plan(origin, &goal.trajectory, tol, s, client);
    }

    /// A `joint_trajectory` message: a trajectory with the default tolerances; an empty one
    /// stops the arm (as ros2_control's controller does).
    pub fn start_topic(&mut self, traj: &JointTrajectory, s: &StateSample, client: &mut ShmClient) {
        if traj.points.is_empty() {
            if let Some(old) = self.active.take() {
                self.finish_with(
                    old.origin,
                    GoalEndStatus::Canceled,
                    error_code::SUCCESSFUL,
                    "stopped by an empty joint_trajectory message".to_string(),
                );
            }
            return self.stop(s, client);
        }
        let goal = FollowJointTrajectoryGoal {
            trajectory: traj.clone(),
            ..Default::default()
        };
        self.start(Origin::Topic, &goal, s, client);
    }

    fn start_plan(
        &mut self,
        origin: Origin<G>,
        traj: &JointTrajectory,
        tol: Tolerances,
        s: &StateSample,
        client: &mut ShmClient,
    ) {
        let dt = self.opts.dt;
        let joined = self.stream.join(s.t_ns);
        // When the arm reaches the plan's start: where the queued points end, or (a new stream)
        // at the start itself.
        let (begin_s, start, ahead_s) = match joined {
            Some((begin, position, velocity)) => (
                begin,
                StartState { position, velocity },
                self.stream.ahead_s(s.t_ns),
            ),
            None => (
                0.0,
                StartState {
                    position: crate::convert::rad6(&s.commanded_position),
                    velocity: [0.0; NUM_AXES],
                },
                0.0,
            ),
        };
        let plan = match Plan::new(
            traj,
            &self.joints,
            start,
            Time::now().plus_secs(ahead_s),
            dt,
        ) {
            Ok(p) => p,
            Err(e) => {
                return self.finish_with(origin, GoalEndStatus::Aborted, e.code(), e.to_string());
            }
        };
        let end = plan.final_state();
        if let Some(i) = (0..NUM_AXES).find(|&i| end.velocity[i].abs() > 1e-9) {
            return self.finish_with(
                origin,
                GoalEndStatus::Aborted,
                error_code::INVALID_GOAL,
                format!(
                    "the trajectory ends moving: joint {} has velocity {:.6} rad/s at its last point; allowed: 0 (a trajectory ends at rest)",
                    self.joints.name(i),
                    end.velocity[i]
                ),
            );
        }
        // It runs: the running one ends here.
        if let Some(old) = self.active.take() {
            self.finish_with(
                old.origin,
                GoalEndStatus::Canceled,
                error_code::SUCCESSFUL,
                "preempted by a newer trajectory".to_string(),
            );
        }
        if joined.is_none() {
            self.stream.end();
        }
        if !self.stream.is_alive() && s.mode != Mode::Pvt.to_wire() && self.entering.is_none() {
            match client.submit(&Request::Pvt(Pvt { dt_s: dt })) {
                Ok(sub) => self.entering = Some((sub, s.t_ns)),
                Err(e) => {
                    return self.finish_with(
                        origin,
                        GoalEndStatus::Aborted,
                        error_code::INVALID_GOAL,
                        format!("cannot send `pvt` to the MCM: {e}"),
                    );
                }
            }
        }
        self.active = Some(Active {
            origin,
            plan,
            tol,
            begin_s,
            next_k: 0,
            accepted_cycle: s.seq,
            first_queued_cycle: None,
            last_feedback_cycle: s.seq,
        });
        self.feed(s, client);
    }

    /// Cancel the goal `g` if it runs: the controlled stop of `hold`, and `CANCELED`.
    pub fn cancel(&mut self, g: G, s: &StateSample, client: &mut ShmClient) -> bool {
        if self.active_goal() != Some(g) {
            return false;
        }
        let a = self.active.take().expect("active_goal is Some");
        self.finish_with(
            a.origin,
            GoalEndStatus::Canceled,
            error_code::SUCCESSFUL,
            "canceled: the arm made the controlled stop of `hold` and holds".to_string(),
        );
        self.stop(s, client);
        true
    }

    /// End the running trajectory (if any) as `ABORTED` with these words: the arm was stopped
    /// by something else (the hold service, a safety error).
    pub fn abort(&mut self, client: &mut ShmClient, code: i32, why: String) {
        if let Some(a) = self.active.take() {
            self.finish_with(a.origin, GoalEndStatus::Aborted, code, why);
        }
        self.stream.end();
        self.forget_in_flight(client);
    }

    /// Stop what the node drives (`hold`) and forget the stream. Only while the node controls
    /// the arm: otherwise its motion commands were refused and the motion (if any) is another
    /// client's, which a refused goal must not change (`hold` is open to every client).
    fn stop(&mut self, s: &StateSample, client: &mut ShmClient) {
        // The reply is not waited for: `hold` is never refused for lack of control, and the
        // state shows HOLD in the next cycle.
        if s.owner_client_id == client.client_id() {
            let _ = client.submit(&Request::Hold).map(|sub| client.forget(&sub));
        }
        self.stream.end();
        self.forget_in_flight(client);
    }

    fn forget_in_flight(&mut self, client: &mut ShmClient) {
        for f in &self.in_flight {
            client.forget(&f.sub);
        }
        if let Some((sub, _)) = self.entering.take() {
            client.forget(&sub);
        }
        self.in_flight.clear();
        self.entering = None;
    }

    fn finish_with(&mut self, origin: Origin<G>, status: GoalEndStatus, code: i32, why: String) {
        let result = FollowJointTrajectoryResult {
            error_code: code,
            error_string: why.clone(),
        };
        self.events.push(match origin {
            Origin::Goal(g) => Event::Finished(g, status, result),
            Origin::Topic => Event::TopicEnded(status, why),
        });
    }

    /// One cycle: read replies, check the motion, send feedback, queue points, end the goal.
    /// `velocity` is the measured joint velocity [rad/s] (the arm loop's estimate).
    pub fn step(&mut self, s: &StateSample, velocity: &[f64; NUM_AXES], client: &mut ShmClient) {
        if !self.replies(s, client) {
            return;
        }
        let Some(a) = self.active.as_ref() else {
            // Nothing runs: a stream whose points are all consumed is over.
            if self.stream.is_alive()
                && self.stream.ahead_s(s.t_ns) <= 0.0
                && self.in_flight.is_empty()
            {
                self.stream.end();
            }
            return;
        };
        if self.entering.is_some() {
            return;
        }
        if a.first_queued_cycle.is_none() || self.stream.origin_ns().is_none() {
            return self.feed(s, client);
        }
        if s.mode != Mode::Pvt.to_wire() {
            return self.abort(client, error_code::PATH_TOLERANCE_VIOLATED, left_pvt(s));
        }
        if s.flags & STATE_PVT_STARVED != 0 {
            return self.abort(client, error_code::PATH_TOLERANCE_VIOLATED,
                "the MCM stopped the trajectory: its PVT queue ran dry (the node fell behind the arm); the arm decelerated to a stop".to_string(),
            );
        }
        let t = self.stream.elapsed_s(s.t_ns) - a.begin_s;
        let actual = crate::convert::rad6(&s.measured_position);
        let duration = a.plan.duration();
        if (0.0..=duration).contains(&t)
            && let Err(v) = a.tol.check_path(&a.plan.sample(t), &actual, velocity)
        {
            let why = format!("path tolerance violated at t = {t:.3} s: {v}");
            self.stop(s, client);
            return self.abort(client, error_code::PATH_TOLERANCE_VIOLATED, why);
        }
        let all_sent = a.next_k == a.plan.point_count();
        let goal_check = (all_sent && t >= duration)
            .then(|| a.tol.check_goal(&a.plan.final_state(), &actual, velocity));
        let goal_time = a.tol.goal_time();
        if s.seq >= a.last_feedback_cycle + self.opts.feedback_every {
            self.feedback(s, t);
        }
        match goal_check {
            None => self.feed(s, client),
            Some(Ok(())) => {
                let a = self.active.take().expect("active");
                self.finish_with(
                    a.origin,
                    GoalEndStatus::Succeeded,
                    error_code::SUCCESSFUL,
                    String::new(),
                );
            }
            Some(Err(v)) if t > duration + goal_time => {
                let why = format!(
                    "goal tolerance violated {:.3} s after the trajectory's end: {v}",
                    t - duration
                );
                self.stop(s, client);
                self.abort(client, error_code::GOAL_TOLERANCE_VIOLATED, why);
            }
            Some(Err(_)) => {}
        }
    }

    /// Read the replies that came; `false` when the trajectory ended here.
    fn replies(&mut self, s: &StateSample, client: &mut ShmClient) -> bool {
        if let Some((sub, sent)) = self.entering {
            match client.take_reply(&sub) {
                Some(Ok(_)) => self.entering = None,
                Some(Err(e)) => {
                    self.entering = None;
                    let hint = refusal_hint(s, client.client_id());
                    self.abort(
                        client,
                        error_code::INVALID_GOAL,
                        format!("the MCM refused the trajectory: {e}{hint}"),
                    );
                    return false;
                }
                None if s.t_ns.saturating_sub(sent) > REPLY_WITHIN_NS => {
                    client.forget(&sub);
                    self.entering = None;
                    self.abort(
                        client,
                        error_code::INVALID_GOAL,
                        "the MCM did not answer `pvt` within 2 s".to_string(),
                    );
                    return false;
                }
                None => {}
            }
        }
        while let Some(f) = self.in_flight.front() {
            match client.take_reply(&f.sub) {
                Some(Ok(_)) => {
                    self.in_flight.pop_front();
                    self.stream.started(s.t_ns, s.timing.period_ns);
                    if let Some(a) = self.active.as_mut()
                        && a.first_queued_cycle.is_none()
                    {
                        a.first_queued_cycle = Some(s.seq);
                        self.last_start_latency = Some(s.seq - a.accepted_cycle);
                    }
                }
                Some(Err(e)) => {
                    let first = self
                        .active
                        .as_ref()
                        .is_some_and(|a| a.first_queued_cycle.is_none());
                    let why = if s.mode != Mode::Pvt.to_wire() && !first {
                        left_pvt(s)
                    } else {
                        format!(
                            "the MCM refused the trajectory's points: {e}{}",
                            refusal_hint(s, client.client_id())
                        )
                    };
                    let code = if first {
                        error_code::INVALID_GOAL
                    } else {
                        error_code::PATH_TOLERANCE_VIOLATED
                    };
                    self.stop(s, client);
                    self.abort(client, code, why);
                    return false;
                }
                None if s.t_ns.saturating_sub(f.sent_ns) > REPLY_WITHIN_NS => {
                    self.stop(s, client);
                    self.abort(
                        client,
                        error_code::PATH_TOLERANCE_VIOLATED,
                        "the MCM did not answer `pvt_points` within 2 s".to_string(),
                    );
                    return false;
                }
                None => break,
            }
        }
        true
    }

    /// Queue points until the lead is reached (none while the stream's first batch waits for
    /// its reply: its start time is not known yet).
    fn feed(&mut self, s: &StateSample, client: &mut ShmClient) {
        if self.entering.is_some() || (self.stream.is_alive() && self.stream.origin_ns().is_none())
        {
            return;
        }
        let dt = self.opts.dt;
        let Some(a) = self.active.as_mut() else {
            return;
        };
        let n = a.plan.point_count();
        let mut buf = [PvtPoint::default(); PVT_POINTS_PER_COMMAND];
        while a.next_k < n && self.stream.ahead_s(s.t_ns) < self.opts.lead_s {
            let m = (n - a.next_k).min(PVT_POINTS_PER_COMMAND);
            for (j, p) in buf[..m].iter_mut().enumerate() {
                *p = a.plan.pvt_point(a.next_k + j);
            }
            let chunk = PvtChunk::new(&buf[..m], true).expect("1 to PVT_POINTS_PER_COMMAND points");
            match client.submit(&Request::PvtPoints(chunk)) {
                Ok(sub) => self.in_flight.push_back(InFlight {
                    sub,
                    sent_ns: s.t_ns,
                }),
                Err(e) => {
                    let why = format!("cannot send `pvt_points` to the MCM: {e}");
                    self.stop(s, client);
                    return self.abort(client, error_code::PATH_TOLERANCE_VIOLATED, why);
                }
            }
            a.next_k += m;
            let last = a.plan.sample((a.next_k) as f64 * dt);
            self.stream.sent(m, dt, last.position, last.velocity);
            if self.stream.origin_ns().is_none() {
                // The first batch of a new stream: its start is known with its reply.
                break;
            }
        }
    }

    fn feedback(&mut self, s: &StateSample, t: f64) {
        let Some(a) = self.active.as_mut() else {
            return;
        };
        a.last_feedback_cycle = s.seq;
        let Origin::Goal(g) = a.origin else { return };
        let d = a.plan.sample(t);
        let actual_q = crate::convert::rad6(&s.measured_position);
        let point = |p: [f64; NUM_AXES],
                     v: Option<[f64; NUM_AXES]>,
                     acc: Option<[f64; NUM_AXES]>| JointTrajectoryPoint {
            positions: p.to_vec().into(),
            velocities: v.map(|v| v.to_vec().into()).unwrap_or_default(),
            accelerations: acc.map(|v| v.to_vec().into()).unwrap_or_default(),
            effort: Default::default(),
            time_from_start: crate::msgs::builtin::Duration::from_secs_f64(t.max(0.0)),
        };
        let error: [f64; NUM_AXES] = std::array::from_fn(|i| d.position[i] - actual_q[i]);
        let fb = FollowJointTrajectoryFeedback {
            header: Header {
                stamp: Time::now(),
                frame_id: String::new(),
            },
            joint_names: self.joints.names().to_vec(),
            desired: point(d.position, Some(d.velocity), Some(d.acceleration)),
            actual: point(actual_q, None, None),
            error: point(error, None, None),
            index: a.plan.index_at(t) as i32,
            ..Default::default()
        };
        self.events.push(Event::Feedback(g, Box::new(fb)));
    }

    /// Cycles from the newest trajectory's acceptance (the cycle whose state the arm loop read
    /// when the goal came) to the cycle that queued its first points: that cycle's reference
    /// moves toward the first point (`/diagnostics`, for the benchmark).
    pub fn last_start_latency_cycles(&self) -> Option<u64> {
        self.last_start_latency
    }
}

/// What the node knows of why the core refused a trajectory's command: not calibrated, or
/// another client controls the arm (empty when neither).
fn refusal_hint(s: &StateSample, own_client_id: u64) -> String {
    if s.flags & STATE_ALL_CALIBRATED == 0 {
        " (the arm is not calibrated: call the calibrate service first)".to_string()
    } else if s.owner_client_id != 0 && s.owner_client_id != own_client_id {
        format!(
            " (control is held by {})",
            crate::convert::owner_words(s.owner_client_id, own_client_id)
        )
    } else {
        String::new()
    }
}

/// Why a trajectory ended when the arm left PVT under it.
fn left_pvt(s: &StateSample) -> String {
    let mode = Mode::try_from(s.mode).map_or_else(|_| s.mode.to_string(), |m| m.to_string());
    format!(
        "the MCM stopped the trajectory: the arm left PVT and is in {mode} (a `hold` from a client, a safety error or a stop)"
    )
}
