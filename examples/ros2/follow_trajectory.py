"""Move the arm through 3 points with the follow_joint_trajectory action, printing feedback
and the result; calibrates the arm first when it is not calibrated.

    cargo run --release -- --ros2                 # in one terminal: the MCM with its ROS 2 node
    python3 examples/ros2/follow_trajectory.py    # in another (README.md: what it needs)

The points are relative to where the arm stands: out by --offset degrees on every joint, back
halfway, starting and ending at rest (velocity 0).
"""

import math

import rclpy
from builtin_interfaces.msg import Duration
from control_msgs.action import FollowJointTrajectory
from rclpy.action import ActionClient
from rclpy.node import Node
from sensor_msgs.msg import JointState
from std_srvs.srv import Trigger
from trajectory_msgs.msg import JointTrajectoryPoint

from _common import name, parser, spin_until

p = parser(__doc__.splitlines()[0])
p.add_argument("--offset", type=float, default=10.0, help="how far out [deg] (default %(default)s)")
p.add_argument("--duration", type=float, default=3.0, help="trajectory time [s] (default %(default)s)")
p.add_argument("--feedback-every", type=float, default=0.5,
               help="seconds between printed feedback (default %(default)s; the node sends it at 50 Hz)")
args = p.parse_args()
Result = FollowJointTrajectory.Result
CODES = {Result.SUCCESSFUL: "SUCCESSFUL", Result.INVALID_GOAL: "INVALID_GOAL",
         Result.INVALID_JOINTS: "INVALID_JOINTS", Result.OLD_HEADER_TIMESTAMP: "OLD_HEADER_TIMESTAMP",
         Result.PATH_TOLERANCE_VIOLATED: "PATH_TOLERANCE_VIOLATED",
         Result.GOAL_TOLERANCE_VIOLATED: "GOAL_TOLERANCE_VIOLATED"}

rclpy.init()
node = Node("follow_trajectory_example")
states = []
node.create_subscription(JointState, name(args.namespace, "joint_states"),
                         lambda m: states.__setitem__(slice(None), [m]), 10)
action = ActionClient(node, FollowJointTrajectory, name(args.namespace, "follow_joint_trajectory"))
calibrate = node.create_client(Trigger, name(args.namespace, "calibrate"))


def wait(future, what, timeout=args.timeout):
    return spin_until(node, lambda: future.done() and future, what, timeout).result()


def current():
    """The newest joint state: its names and positions [rad]."""
    states.clear()
    m = spin_until(node, lambda: states[0] if states else None, "a /joint_states message", args.timeout)
    return list(m.name), list(m.position)


def seconds(t):
    return Duration(sec=int(t), nanosec=int(round((t - int(t)) * 1e9)))


def goal():
    """3 points from where the arm stands: there at rest, out by the offset, back halfway at rest."""
    names, q0 = current()
    d = math.radians(args.offset)
    out = [q + d for q in q0]
    target = [q + d / 2 for q in q0]
    g = FollowJointTrajectory.Goal()
    g.trajectory.joint_names = names
    g.trajectory.points = [
        JointTrajectoryPoint(positions=q0, velocities=[0.0] * len(names), time_from_start=seconds(0.0)),
        # No velocity given: the node plans one through this point.
        JointTrajectoryPoint(positions=out, time_from_start=seconds(args.duration / 2)),
        JointTrajectoryPoint(positions=target, velocities=[0.0] * len(names),
                             time_from_start=seconds(args.duration)),
    ]
    print("target: " + " ".join(f"{n}={math.degrees(q):.4f}" for n, q in zip(names, target)) + " deg")
    return g, names, target


last_print = [-1e9]


def on_feedback(msg):
    f = msg.feedback
    t = f.desired.time_from_start.sec + f.desired.time_from_start.nanosec * 1e-9
    if t - last_print[0] >= args.feedback_every:
        last_print[0] = t
        worst = max((abs(e) for e in f.error.positions), default=0.0)
        # The point being executed: control_msgs 6.x (Kilted, Lyrical) only, not Jazzy's 5.x.
        point = f"point {f.index}, " if hasattr(f, "index") else ""
        print(f"  feedback t={t:.2f} s: {point}largest error {math.degrees(worst):.3f} deg")


def run(g):
    """Send the goal, print its feedback; returns the result."""
    handle = wait(action.send_goal_async(g, feedback_callback=on_feedback), "the goal's acceptance")
    if not handle.accepted:
        raise SystemExit("the goal was rejected")
    # The goal's own time, plus the wait for a start, is how long the result may take.
    r = wait(handle.get_result_async(), "the goal's result", args.duration + args.timeout)
    return r.result


if not action.wait_for_server(timeout_sec=args.timeout):
    raise SystemExit(f"no follow_joint_trajectory action server under {args.namespace} within "
                     f"{args.timeout} s (is `mcm --ros2` running, in the same ROS_DOMAIN_ID?)")
g, names, target = goal()
result = run(g)
if result.error_code == Result.INVALID_GOAL and "not calibrated" in result.error_string:
    # The node names the reason; the calibrate service homes every axis (about 12 s simulated).
    print(f"not calibrated ({result.error_string}); calling calibrate ...", flush=True)
    if not calibrate.wait_for_service(timeout_sec=args.timeout):
        raise SystemExit("no calibrate service")
    r = wait(calibrate.call_async(Trigger.Request()), "calibrate", 120)
    print(f"calibrate: success={r.success} ({r.message})")
    if not r.success:
        raise SystemExit(1)
    g, names, target = goal()  # calibrating moved the arm: plan from where it stands now
    result = run(g)
code = CODES.get(result.error_code, str(result.error_code))
print(f"result: error_code {result.error_code} ({code}), error_string {result.error_string!r}")
_, q = current()
print("at: " + " ".join(f"{n}={math.degrees(x):.4f}" for n, x in zip(names, q)) + " deg")

node.destroy_node()
rclpy.shutdown()
raise SystemExit(0 if result.error_code == Result.SUCCESSFUL else 1)
