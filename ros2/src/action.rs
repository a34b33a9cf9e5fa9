//! The `follow_joint_trajectory` action server, on its own thread (ros2-client's action server
//! is async): it accepts goals and cancel requests and hands them to the arm loop, and passes
//! the arm loop's feedback (in the served distribution's layout) and results back to the
//! clients.
//!
//! Every goal is accepted and handed on while the node holds fewer than [`MAX_GOALS`]; one that
//! cannot run ends at once `ABORTED` with its error code and the reason in `error_string`. A
//! goal that comes when [`MAX_GOALS`] are held is rejected (a ROS rejection carries no words:
//! the reason goes to stderr, once per run of rejections), so a burst of goals costs a bounded
//! amount of memory and every goal of it is answered.

use crate::distro::RosDistro;
use crate::driver::Event;
use crate::motion::ToArm;
use crate::msgs::control::{
    FeedbackOnWire, FollowJointTrajectoryGoal, FollowJointTrajectoryResult,
};
use futures::channel::mpsc::UnboundedReceiver;
use futures::stream::FuturesUnordered;
use futures::{FutureExt, StreamExt};
use ros2_client::action::{ExecutingGoalHandle, GoalEndStatus, GoalId};
use ros2_client::dds::AsyncActionServer;
use std::collections::BTreeMap;
use std::sync::mpsc::Sender;
use std::time::Duration;

/// The action server's type.
pub type Server =
    AsyncActionServer<FollowJointTrajectoryGoal, FollowJointTrajectoryResult, FeedbackOnWire>;
type Handle = ExecutingGoalHandle<FollowJointTrajectoryGoal>;

/// How long a finished goal's result waits for the client to ask for it.
const RESULT_KEPT: Duration = Duration::from_secs(60);

/// Most goals the node holds at once: running, handed to the arm loop, or ended with a result
/// its client has not fetched yet (for at most [`RESULT_KEPT`]). More are rejected.
pub const MAX_GOALS: usize = 100;

/// History depth of the goal service: how many goal requests DDS keeps before the node reads
/// them, and how many answers it keeps until their clients acknowledge them. RustDDS keeps
/// that many received goals (at least 64) even once read, without their data (patched,
/// vendor/rustdds/MCM-PATCHES.md); it is sized by the goals held, not by the largest burst: a
/// burst is read as it comes, its goals beyond [`MAX_GOALS`] rejected at once.
pub const GOAL_REQUESTS_DEPTH: usize = MAX_GOALS;

/// History depth of the result and cancel services (requests of a few bytes): a result request
/// for each goal held comes as soon as it is accepted and waits until the goal ends, so these
/// keep many times [`MAX_GOALS`] (RustDDS keeps at most 64 samples of a topic when the depth is
/// smaller, or `KEEP_ALL`).
pub const REQUESTS_DEPTH: usize = 1024;
const _: () = assert!(
    REQUESTS_DEPTH >= 2 * MAX_GOALS,
    "a result request for each goal held, and as many again"
);

/// Counts a run of rejected goals, for a log line at its first and at its end.
#[derive(Debug, Default)]
pub struct Rejections {
    run: u64,
}

impl Rejections {
    /// A goal rejected with `held` goals held: the reason, for the first of a run.
    pub fn rejected(&mut self, held: usize) -> Option<String> {
        self.run += 1;
        (self.run == 1).then(|| {
            format!(
                "goal rejected: the node holds {held} goals (running, or ended with a result not \
                 fetched yet); allowed: at most {MAX_GOALS} (docs/ros2.md, limits); more \
                 rejections follow until one of them ends"
            )
        })
    }

    /// A goal accepted: how many were rejected before it, when any were.
    pub fn accepted(&mut self) -> Option<String> {
        let run = std::mem::take(&mut self.run);
        (run > 0).then(|| format!("accepting goals again after rejecting {run}"))
    }
}

/// Serve the peers of `distro` until the arm loop ends (its event channel closes).
pub async fn serve(
    server: Server,
    distro: RosDistro,
    to_arm: Sender<ToArm<GoalId>>,
    mut from_arm: UnboundedReceiver<Event<GoalId>>,
) {
    let mut running: BTreeMap<GoalId, Handle> = BTreeMap::new();
    let mut results = FuturesUnordered::new();
    let mut rejections = Rejections::default();
    loop {
        futures::select! {
            new = server.receive_new_goal().fuse() => {
                let Ok(new) = new else { continue };
                let held = running.len() + results.len();
                if held >= MAX_GOALS {
                    if let Some(why) = rejections.rejected(held) {
                        eprintln!("mcm-ros2: {why}");
                    }
                    let _ = server.reject_goal(new).await;
                    continue;
                }
                if let Some(again) = rejections.accepted() {
                    eprintln!("mcm-ros2: {again}");
                }
                let Some(goal) = server.get_new_goal(new.clone()) else { continue };
                if crate::trajectory::check_size(&goal).is_err() {
                    // The arm loop refuses it; what receiving it took is free now.
                    crate::allocator::give_back();
                }
                let id = new.goal_id();
                let Ok(accepted) = server.accept_goal(new).await else { continue };
                let Ok(executing) = server.start_executing_goal(accepted).await else { continue };
                running.insert(id, executing);
                if to_arm.send(ToArm::Goal(id, Box::new(goal))).is_err() {
                    return;
                }
            }
            cancel = server.receive_cancel_request().fuse() => {
                let Ok(cancel) = cancel else { continue };
                let ids: Vec<GoalId> = cancel.goals().filter(|g| running.contains_key(g)).collect();
                let _ = server.respond_to_cancel_requests(&cancel, ids.iter().copied()).await;
                for id in ids {
                    if to_arm.send(ToArm::Cancel(id)).is_err() {
                        return;
                    }
                }
            }
            ev = from_arm.next() => match ev {
                Some(Event::Feedback(id, fb)) => {
                    if let Some(h) = running.get(&id) {
                        let fb = FeedbackOnWire { distro, feedback: *fb };
                        let _ = server.publish_feedback(h.clone(), fb).await;
                    }
                }
                Some(Event::Finished(id, status, result)) => {
                    if let Some(h) = running.remove(&id) {
                        results.push(send_result(&server, h, status, result));
                    }
                }
                Some(Event::TopicEnded(..)) => {}
                None => return,
            },
            () = results.select_next_some() => {}
        }
    }
}

/// Send a goal's result once its client asks for it (at most [`RESULT_KEPT`]). Waits in
/// slices of a second: a result request read by another goal's wait is kept by the server
/// and found by the next slice. A result nobody asked for is dropped with its goal (the server
/// keeps every goal until its end).
async fn send_result(
    server: &Server,
    h: Handle,
    status: GoalEndStatus,
    result: FollowJointTrajectoryResult,
) {
    let slices = RESULT_KEPT.as_secs();
    for _ in 0..slices {
        let send = server
            .send_result_response(h.clone(), status, result.clone())
            .fuse();
        let timer = futures_timer::Delay::new(Duration::from_secs(1)).fuse();
        futures::pin_mut!(send, timer);
        futures::select! {
            _ = send => return,
            () = timer => {}
        }
    }
    let _ = server.abort_executing_goal(h).await;
}

#[cfg(test)]
mod tests;
