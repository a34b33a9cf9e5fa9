//! The `follow_joint_trajectory` action server, on its own thread (ros2-client's action server
//! is async): it accepts goals and cancel requests and hands them to the arm loop, and passes
//! the arm loop's feedback and results back to the clients.
//!
//! Every goal is accepted and handed on; one that cannot run ends at once `ABORTED` with its
//! error code and the reason in `error_string` (a rejected goal could not say why).

use crate::arm::ToArm;
use crate::driver::Event;
use crate::msgs::control::{
    FollowJointTrajectoryFeedback, FollowJointTrajectoryGoal, FollowJointTrajectoryResult,
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
pub type Server = AsyncActionServer<
    FollowJointTrajectoryGoal,
    FollowJointTrajectoryResult,
    FollowJointTrajectoryFeedback,
>;
type Handle = ExecutingGoalHandle<FollowJointTrajectoryGoal>;

/// How long a finished goal's result waits for the client to ask for it.
const RESULT_KEPT: Duration = Duration::from_secs(60);

/// Serve until the arm loop ends (its event channel closes).
pub async fn serve(
    server: Server,
    to_arm: Sender<ToArm<GoalId>>,
    mut from_arm: UnboundedReceiver<Event<GoalId>>,
) {
    let mut running: BTreeMap<GoalId, Handle> = BTreeMap::new();
    let mut results = FuturesUnordered::new();
    loop {
        futures::select! {
            new = server.receive_new_goal().fuse() => {
                let Ok(new) = new else { continue };
                let Some(goal) = server.get_new_goal(new.clone()) else { continue };
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
                        let _ = server.publish_feedback(h.clone(), *fb).await;
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
