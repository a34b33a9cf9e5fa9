"""Proof that the ROS 2 test venv works: two rclpy processes on one ROS domain.

    selfcheck.py server TAG     action server + JointState publisher, until stdin closes
    selfcheck.py client TAG     action client + JointState subscriber; exit 0 when all held

`server` serves `/selfcheck_TAG/follow_joint_trajectory`
(control_msgs/action/FollowJointTrajectory, the type built by build-interfaces.sh): it accepts
every goal, "executes" a trajectory over its points' time_from_start, publishing feedback
(desired = the current point, its index), and returns error_code SUCCESSFUL with an
error_string naming what it got, or aborts with INVALID_GOAL for a trajectory without points.
It publishes sensor_msgs/JointState on `/selfcheck_TAG/joint_states` at 100 Hz. It prints
`READY` once its entities exist and, when stdin closes, `SERVED goals=N` and exits.

`client` sends a goal of 2 points and checks its feedback and result, sends an empty one and
checks that it aborts with INVALID_GOAL, checks 20 JointState messages, and prints
`SELFCHECK OK` (or raises). Both load the type support of every other interface the MCM's
node speaks (std_msgs/String, diagnostic_msgs/DiagnosticArray, std_srvs/Trigger,
trajectory_msgs/JointTrajectory). TAG keeps two runs on one machine apart. Every wait is
bounded.
"""

import sys
import threading
import time

import rclpy
from builtin_interfaces.msg import Duration
from control_msgs.action import FollowJointTrajectory
from diagnostic_msgs.msg import DiagnosticArray
from rclpy.action import ActionClient, ActionServer
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.type_support import check_for_type_support
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from std_srvs.srv import Trigger
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

JOINTS = [f"joint_{i}" for i in range(1, 7)]
WAIT = 20.0  # seconds, for any one wait
SERVER_LIFETIME = 120.0  # the server exits by itself after this, should stdin never close
Result = FollowJointTrajectory.Result


def seconds(d):
    return d.sec + d.nanosec * 1e-9


def server(tag):
    node = rclpy.create_node(f"selfcheck_server_{tag}")
    group = ReentrantCallbackGroup()
    goals = []

    def execute(goal_handle):
        traj = goal_handle.request.trajectory
        goals.append(len(traj.points))
        print(f"GOAL points={len(traj.points)} joints={','.join(traj.joint_names)}", flush=True)
        if not traj.points:
            goal_handle.abort()
            return Result(error_code=Result.INVALID_GOAL, error_string="no points")
        start = time.monotonic()
        end = seconds(traj.points[-1].time_from_start)
        while True:
            t = time.monotonic() - start
            index = next(
                (i for i, p in enumerate(traj.points) if seconds(p.time_from_start) >= t),
                len(traj.points) - 1,
            )
            fb = FollowJointTrajectory.Feedback()
            fb.header.stamp = node.get_clock().now().to_msg()
            fb.joint_names = traj.joint_names
            fb.desired = traj.points[index]
            fb.actual = traj.points[index]
            fb.index = index
            goal_handle.publish_feedback(fb)
            if t >= end:
                break
            time.sleep(0.01)  # the pace of the simulated execution, not a synchronisation
        goal_handle.succeed()
        last = list(traj.points[-1].positions)
        return Result(
            error_code=Result.SUCCESSFUL,
            error_string=f"{len(traj.points)} points, last {last}",
        )

    action = ActionServer(
        node,
        FollowJointTrajectory,
        f"/selfcheck_{tag}/follow_joint_trajectory",
        execute,
        callback_group=group,
    )
    pub = node.create_publisher(JointState, f"/selfcheck_{tag}/joint_states", 10)
    published = [0]

    def tick():
        msg = JointState()
        msg.header.stamp = node.get_clock().now().to_msg()
        msg.name = JOINTS
        msg.position = [published[0] * 0.001 + i for i in range(6)]
        pub.publish(msg)
        published[0] += 1

    timer = node.create_timer(0.01, tick, callback_group=group)
    executor = MultiThreadedExecutor(num_threads=2)
    executor.add_node(node)
    stdin_closed = threading.Event()
    threading.Thread(
        target=lambda: (sys.stdin.read(), stdin_closed.set()), daemon=True
    ).start()
    print("READY", flush=True)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    stdin_closed.wait(SERVER_LIFETIME)
    # Stop the executor and wait for its thread before destroying what it spins: destroying
    # entities under a spinning executor, or exiting with its thread still in rclpy's C++
    # code, aborted the process at exit now and then ("terminate called without an active
    # exception", SIGABRT).
    executor.shutdown(timeout_sec=WAIT)
    spinner.join(WAIT)
    node.destroy_timer(timer)
    action.destroy()
    node.destroy_node()
    print(f"SERVED goals={len(goals)} joint_states={published[0]}", flush=True)


def wait_future(node, future, what):
    rclpy.spin_until_future_complete(node, future, timeout_sec=WAIT)
    if not future.done():
        raise TimeoutError(f"{what}: nothing within {WAIT} s")
    return future.result()


def client(tag):
    node = rclpy.create_node(f"selfcheck_client_{tag}")
    states = []
    node.create_subscription(
        JointState, f"/selfcheck_{tag}/joint_states", states.append, 10
    )
    action = ActionClient(node, FollowJointTrajectory, f"/selfcheck_{tag}/follow_joint_trajectory")
    if not action.wait_for_server(timeout_sec=WAIT):
        raise TimeoutError(f"no FollowJointTrajectory server within {WAIT} s")

    goal = FollowJointTrajectory.Goal()
    goal.trajectory.joint_names = JOINTS
    for k, t in enumerate((0.2, 0.4)):
        p = JointTrajectoryPoint()
        p.positions = [0.1 * (k + 1) * (i + 1) for i in range(6)]
        p.velocities = [0.0] * 6
        p.time_from_start = Duration(sec=0, nanosec=int(t * 1e9))
        goal.trajectory.points.append(p)
    goal.goal_time_tolerance = Duration(sec=0, nanosec=100_000_000)
    feedback = []
    handle = wait_future(
        node,
        action.send_goal_async(goal, feedback_callback=lambda f: feedback.append(f.feedback)),
        "the goal's acceptance",
    )
    assert handle.accepted, "the 2-point goal was rejected"
    result = wait_future(node, handle.get_result_async(), "the 2-point goal's result")
    want = f"2 points, last {list(goal.trajectory.points[-1].positions)}"
    assert result.result.error_code == Result.SUCCESSFUL, result
    assert result.result.error_string == want, (result.result.error_string, want)
    indices = sorted({f.index for f in feedback})
    assert indices == [0, 1], f"feedback indices {indices} of {len(feedback)} messages"
    assert all(f.joint_names == JOINTS for f in feedback), feedback[0]
    last = [f for f in feedback if f.index == 1][-1]
    assert list(last.desired.positions) == list(goal.trajectory.points[1].positions), last

    handle = wait_future(
        node, action.send_goal_async(FollowJointTrajectory.Goal()), "the empty goal's acceptance"
    )
    assert handle.accepted, "the empty goal was rejected"
    empty = wait_future(node, handle.get_result_async(), "the empty goal's result")
    assert empty.result.error_code == Result.INVALID_GOAL, empty

    deadline = time.monotonic() + WAIT
    while len(states) < 20 and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
    assert len(states) >= 20, f"{len(states)} JointState messages within {WAIT} s"
    assert all(list(s.name) == JOINTS for s in states), states[0]
    firsts = [s.position[0] for s in states]
    assert firsts == sorted(firsts), f"JointState out of order: {firsts}"
    print(
        f"SELFCHECK OK feedback={len(feedback)} result={result.result.error_string!r} "
        f"empty_goal={empty.result.error_code} joint_states={len(states)}",
        flush=True,
    )
    node.destroy_node()


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("server", "client"):
        sys.exit(f"usage: {sys.argv[0]} server|client TAG")
    for t in (FollowJointTrajectory, JointState, String, DiagnosticArray, Trigger, JointTrajectory):
        check_for_type_support(t)
    rclpy.init()
    try:
        (server if sys.argv[1] == "server" else client)(sys.argv[2])
    finally:
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
