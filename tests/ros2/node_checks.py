"""Checks of the MCM's ROS 2 node with real ROS 2 (rclpy, Fast DDS), run by tests/end_to_end/ros2.rs.

    python node_checks.py single --json 127.0.0.1:PORT [--namespace /] [--prefix ""]
    python node_checks.py remote --namespaces /left,/right --prefixes left_,right_ --move /right

`single` runs every check against one simulated arm whose JSON port it may use for the
simulation's ground truth (`sim`) and to play another client. `remote` runs on another "host"
(network namespace) with DDS only: two arms, one moved. Each check prints `ok <name> <figures>`;
the first failure raises (exit 1) with what was expected and what came. Every wait is bounded.
"""

import argparse
import json
import math
import socket
import sys
import threading
import time
import xml.etree.ElementTree as ET

import rclpy
from rclpy.action import ActionClient
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from builtin_interfaces.msg import Duration
from control_msgs.action import FollowJointTrajectory
from control_msgs.msg import JointTolerance
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from std_srvs.srv import Trigger
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
from action_msgs.msg import GoalStatus

WAIT = 20.0  # longest single wait [s]
AXES = ["base", "shoulder", "elbow", "forearm", "wrist", "flange"]


class Failure(Exception):
    pass


def expect(cond, what):
    if not cond:
        raise Failure(what)


def ok(name, **figures):
    words = " ".join(f"{k}={v}" for k, v in figures.items())
    print(f"ok {name} {words}".rstrip(), flush=True)


def wait_for(pred, what, timeout=WAIT, step=0.01):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        v = pred()
        if v:
            return v
        time.sleep(step)
    raise Failure(f"{what}: not within {timeout} s")


def wait_future(fut, what, timeout=WAIT):
    wait_for(fut.done, what, timeout)
    return fut.result()


def level(status):
    """A DiagnosticStatus's level: a ROS `byte`, which rclpy gives as a one-byte `bytes`."""
    lv = status.level
    return lv[0] if isinstance(lv, (bytes, bytearray)) else int(lv)


def dur(s):
    return Duration(sec=int(math.floor(s)), nanosec=int(round((s - math.floor(s)) * 1e9)))


class Json:
    """The MCM's JSON protocol (one line per command and reply), as another client."""

    def __init__(self, addr):
        host, port = addr.rsplit(":", 1)
        self.sock = socket.create_connection((host, int(port)), timeout=WAIT)
        self.file = self.sock.makefile("rw", encoding="utf-8", newline="\n")

    def request(self, command, **arguments):
        msg = {"command": command}
        if arguments:
            msg["arguments"] = arguments
        self.file.write(json.dumps(msg) + "\n")
        self.file.flush()
        while True:
            line = self.file.readline()
            expect(line, f"the JSON connection closed waiting for `{command}`")
            reply = json.loads(line)
            # Spontaneous errors (a `check`) are not replies.
            if reply.get("check") is None:
                return reply

    def truth(self):
        r = self.request("sim")
        expect(r.get("result_type") == "sim", f"`sim` answered {r}")
        return [math.radians(x) for x in r["true_position"]], [math.radians(x) for x in r["true_velocity"]]

    def status(self):
        return self.request("status", detail=True)


class Arm:
    """One MCM node's interfaces, seen from rclpy."""

    def __init__(self, node, namespace, prefix):
        ns = namespace.rstrip("/")
        self.node = node
        self.names = [prefix + a for a in AXES]
        self.lock = threading.Lock()
        self.states = []  # (receive monotonic, msg)
        self.diagnostics = []
        self.description = None
        node.create_subscription(JointState, f"{ns}/joint_states", self._state, 100)
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                             reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST)
        node.create_subscription(String, f"{ns}/robot_description", self._description, latched)
        node.create_subscription(DiagnosticArray, "/diagnostics", self._diag, 10)
        self.services = {n: node.create_client(Trigger, f"{ns}/{n}")
                         for n in ["hold", "calibrate", "release", "take_control", "release_control"]}
        self.action = ActionClient(node, FollowJointTrajectory, f"{ns}/follow_joint_trajectory")
        self.topic = node.create_publisher(JointTrajectory, f"{ns}/joint_trajectory", 10)
        self.hardware = None

    def _state(self, m):
        with self.lock:
            self.states.append((time.monotonic(), m))
            if len(self.states) > 20000:
                del self.states[:10000]

    def _description(self, m):
        self.description = m.data

    def _diag(self, m):
        with self.lock:
            self.diagnostics.append(m)
            del self.diagnostics[:-50]

    def latest(self):
        with self.lock:
            return self.states[-1][1] if self.states else None

    def position(self):
        m = wait_for(self.latest, "a joint state")
        return list(m.position)

    def my_diagnostics(self):
        """The newest DiagnosticStatus of this arm (its hardware id names the instance)."""
        with self.lock:
            for arr in reversed(self.diagnostics):
                for s in arr.status:
                    if self.hardware is None or s.hardware_id == self.hardware:
                        return s
        return None

    def call(self, name, timeout=WAIT):
        cli = self.services[name]
        expect(cli.wait_for_service(timeout_sec=WAIT), f"service {name} not available")
        return wait_future(cli.call_async(Trigger.Request()), f"service {name}", timeout)

    def goal(self, points, names=None, path_tol=None, goal_tol=None, goal_time=0.0):
        g = FollowJointTrajectory.Goal()
        g.trajectory.joint_names = names or self.names
        for t, q, v in points:
            p = JointTrajectoryPoint(positions=list(q), time_from_start=dur(t))
            if v is not None:
                p.velocities = list(v)
            g.trajectory.points.append(p)
        g.path_tolerance = path_tol or []
        g.goal_tolerance = goal_tol or []
        g.goal_time_tolerance = dur(goal_time)
        return g

    def send(self, goal, feedback=None):
        expect(self.action.wait_for_server(timeout_sec=WAIT), "the follow_joint_trajectory action server")
        handle = wait_future(self.action.send_goal_async(goal, feedback_callback=feedback), "goal response")
        expect(handle.accepted, "the goal was rejected (the node accepts every goal and ends bad ones with a code)")
        return handle

    def wait_feedback(self, handle, feedback, n, what):
        """Wait for more than `n` messages in `feedback`, the running goal `handle`'s; a failure
        says how many came and how the goal ended, if it did."""
        end = time.monotonic() + WAIT
        while len(feedback) <= n:
            if time.monotonic() > end:
                r = handle.get_result_async()
                try:
                    wait_for(r.done, "the goal's result", timeout=5)
                    how = f"the goal ended: status {r.result().status} {r.result().result.error_string!r}"
                except Failure:
                    how = "the goal has no result within 5 s more"
                raise Failure(f"{what}: {len(feedback)} feedback messages within {WAIT} s, wanted more "
                              f"than {n}; {how}")
            time.sleep(0.01)

    def result(self, handle, timeout=WAIT):
        r = wait_future(handle.get_result_async(), "goal result", timeout)
        return r.status, r.result


def start(name):
    """rclpy with a node `name` spun on a thread of its own; returns the node and a function that
    stops the spinning, joins the thread and shuts rclpy down in that order (a thread of the
    middleware still running at interpreter exit aborts the process)."""
    rclpy.init()
    node = Node(name)
    ex = SingleThreadedExecutor()
    ex.add_node(node)
    spinner = threading.Thread(target=ex.spin, daemon=True)
    spinner.start()

    def close():
        ex.shutdown(timeout_sec=WAIT)
        spinner.join(timeout=WAIT)
        node.destroy_node()
        rclpy.shutdown()
    return node, close


def wait_online_and_calibrate(arm):
    def online():
        d = arm.my_diagnostics()
        return d and dict((kv.key, kv.value) for kv in d.values).get("drives online") == "6/6"
    wait_for(online, "diagnostics saying all 6 drives are online", timeout=30)
    t0 = time.monotonic()
    r = arm.call("calibrate", timeout=120)
    expect(r.success, f"calibrate service: {r.message}")
    ok("calibrate_service", seconds=f"{time.monotonic() - t0:.1f}", message=repr(r.message))


def check_single(args):
    node, close = start("mcm_checks")
    arm = Arm(node, args.namespace, args.prefix)
    json_client = Json(args.json)
    other = Json(args.json)

    # /robot_description: the URDF, latched.
    wait_for(lambda: arm.description, "/robot_description (transient local)")
    robot = ET.fromstring(arm.description)
    joints = {j.get("name"): j for j in robot.iter("joint") if j.get("type") == "revolute"}
    expect(sorted(joints) == sorted(arm.names), f"URDF joints {sorted(joints)}, expected {arm.names}")
    ok("robot_description", bytes=len(arm.description), joints=len(joints))

    # /joint_states: names, radians matching the truth, one per cycle.
    wait_for(arm.latest, "/joint_states")
    c0 = json_client.status()["detail"]["cycle"]
    with arm.lock:
        n0 = len(arm.states)
    wait_for(lambda: json_client.status()["detail"]["cycle"] >= c0 + 400, "400 cycles", step=0.05)
    c1 = json_client.status()["detail"]["cycle"]
    with arm.lock:
        n1 = len(arm.states)
        m = arm.states[-1][1]
    expect(list(m.name) == arm.names, f"joint names {list(m.name)}, expected {arm.names}")
    expect(len(m.position) == 6 and len(m.velocity) == 6 and len(m.effort) == 6, f"vector lengths in {m}")
    got, cycles = n1 - n0, c1 - c0
    # Counted against the robot's cycle counter; the benchmark measures the rate exactly.
    expect(got >= 0.8 * cycles, f"{got} joint states in {cycles} cycles")
    ok("joint_states", messages=got, cycles=cycles)

    # A goal before calibration ends with the core's reason.
    h = arm.send(arm.goal([(1.0, [0.1] * 6, None)]))
    status, res = arm.result(h)
    expect(status == GoalStatus.STATUS_ABORTED and res.error_code == FollowJointTrajectory.Result.INVALID_GOAL
           and "calibrat" in res.error_string,
           f"uncalibrated goal: status {status}, code {res.error_code}, {res.error_string!r}")
    ok("goal_before_calibration", error_string=repr(res.error_string))

    wait_online_and_calibrate(arm)
    d = wait_for(lambda: (lambda s: s if s and level(s) == 0 else None)(arm.my_diagnostics()),
                 "diagnostics at level OK after calibration")
    values = dict((kv.key, kv.value) for kv in d.values)
    for key in ["mode", "owner", "last error", "wake-up latency p99 [us]", "bus load [%]"]:
        expect(key in values, f"diagnostics lack {key!r}: {values}")
    ok("diagnostics", level=level(d), mode=values["mode"], bus_load=values["bus load [%]"])

    # Calibrated, the measured positions are the joint angles: radians matching the truth.
    q_true, _ = json_client.truth()
    q = arm.position()
    err = max(abs(a - b) for a, b in zip(q, q_true))
    expect(err < 0.01, f"joint_states positions {q} differ from the truth {q_true} by {err} rad")
    ok("joint_states_truth", max_error_rad=f"{err:.2e}")

    # Invalid goals get their codes.
    names = list(reversed(arm.names))
    h = arm.send(arm.goal([(1.0, [0.0] * 6, None)], names=names[:5] + ["elbow_x"]))
    status, unknown = arm.result(h)
    expect(unknown.error_code == FollowJointTrajectory.Result.INVALID_JOINTS and "elbow_x" in unknown.error_string,
           f"unknown joint: code {unknown.error_code} {unknown.error_string!r}")
    h = arm.send(arm.goal([(1.0, [0.0] * 6, None), (0.5, [0.1] * 6, None)]))
    status, res = arm.result(h)
    expect(res.error_code == FollowJointTrajectory.Result.INVALID_GOAL, f"times going back: {res.error_code} {res.error_string!r}")
    ok("invalid_goals", unknown_joint=repr(unknown.error_string), times=repr(res.error_string))

    # A goal in shuffled joint order, followed on the truth.
    q0 = arm.position()
    target = [q0[0] + 0.4, q0[1] - 0.2, q0[2] + 0.3, q0[3] + 0.3, q0[4] - 0.3, q0[5] + 0.5]
    order = [3, 0, 5, 1, 4, 2]
    shuffled = [arm.names[i] for i in order]
    mid = [(a + b) / 2 for a, b in zip(q0, target)]
    pts = [(0.0, q0, [0.0] * 6), (1.2, mid, None), (2.4, target, [0.0] * 6)]
    pts = [(t, [q[i] for i in order], None if v is None else [v[i] for i in order]) for t, q, v in pts]
    feedback = []
    errors = []

    def on_feedback(fb):
        f = fb.feedback
        feedback.append((time.monotonic(), f))

    h = arm.send(arm.goal(pts, names=shuffled), on_feedback)
    result = h.get_result_async()
    deadline = time.monotonic() + WAIT
    while not result.done():
        expect(time.monotonic() < deadline, f"no result of the goal within {WAIT} s")
        if feedback:
            f = feedback[-1][1]
            q_true, _ = json_client.truth()
            des = dict(zip(f.joint_names, f.desired.positions))
            errors.append(max(abs(des[n] - q_true[i]) for i, n in enumerate(arm.names)))
        time.sleep(0.02)
    status, res = result.result().status, result.result().result
    expect(status == GoalStatus.STATUS_SUCCEEDED and res.error_code == 0, f"goal: status {status} {res.error_code} {res.error_string!r}")
    q_true, _ = json_client.truth()
    final = max(abs(q_true[i] - target[i]) for i in range(6))
    expect(final < 0.01, f"final truth {q_true} vs target {target}: {final} rad")
    fb_times = [f.desired.time_from_start.sec + f.desired.time_from_start.nanosec * 1e-9 for _, f in feedback]
    expect(fb_times, "no feedback of the goal came (none this rclpy's control_msgs decodes)")
    span = max(fb_times) - min(fb_times)
    rate = (len(fb_times) - 1) / span if span > 0 else 0
    expect(rate >= 10, f"feedback at {rate:.1f} per second of trajectory time")
    # The truth lags the desired path by the drives' following error and by the time between
    # the feedback and the `sim` reply (at most a few cycles at up to ~0.5 rad/s).
    worst = max(errors) if errors else float("nan")
    expect(errors and worst < 0.05, f"truth vs desired during the goal: worst {worst} rad over {len(errors)} samples")
    # Every feedback decoded whole, up to the goal's end: nothing multi-DOF (the node sends
    # none; the feedback of another distribution's layout decodes as garbage there, or not at all).
    last = pts[-1][0]
    expect(max(fb_times) > last - 0.2, f"feedback up to the goal's end at {last} s: the last at {max(fb_times):.3f} s")
    garbled = [f for _, f in feedback if f.multi_dof_joint_names or f.multi_dof_desired.transforms
               or f.multi_dof_actual.transforms or f.multi_dof_error.transforms]
    expect(not garbled, f"{len(garbled)} of {len(feedback)} feedback messages have multi-DOF entries: {garbled[:1]}")
    # control_msgs 6.x (Kilted) has the point being executed, `index`: from the first of the
    # goal's 3 points past the middle one, never going back; 5.x (Jazzy) has no such field.
    indices = [f.index for _, f in feedback] if hasattr(feedback[0][1], "index") else None
    if indices is not None:
        expect(indices == sorted(indices) and indices[0] == 0 and 1 <= indices[-1] <= len(pts) - 1,
               f"feedback index from 0 to 1 or {len(pts) - 1}, never going back: {indices}")
    ok("follow_joint_trajectory", final_error_rad=f"{final:.2e}", feedback_per_s=f"{rate:.0f}",
       worst_tracking_rad=f"{worst:.4f}", samples=len(errors),
       feedback_index="absent" if indices is None else f"{indices[0]}..{indices[-1]}")

    # Cancel: a controlled stop, then HOLD.
    q0 = arm.position()
    far = [q0[0] - 1.0] + q0[1:]
    feedback.clear()
    h = arm.send(arm.goal([(4.0, far, [0.0] * 6)]), on_feedback)
    arm.wait_feedback(h, feedback, 20, "feedback before the cancel")
    wait_future(h.cancel_goal_async(), "cancel response")
    status, res = arm.result(h)
    expect(status == GoalStatus.STATUS_CANCELED, f"canceled goal: status {status} {res.error_string!r}")
    wait_for(lambda: json_client.status()["operating_mode"] == "HOLD", "HOLD after the cancel")
    wait_for(lambda: max(abs(v) for v in json_client.truth()[1]) < 1e-3, "the arm at rest after the cancel")
    q = arm.position()
    expect(abs(q[0] - far[0]) > 0.2, f"the arm went on to the canceled target: {q}")
    ok("cancel", stopped_at_rad=f"{q[0]:.3f}")

    # Preemption: a second goal takes over from the first, without a jump.
    q0 = arm.position()
    a_target = [q0[0] + 0.8] + q0[1:]
    b_target = [q0[0] + 0.2, q0[1] + 0.2] + q0[2:]
    feedback.clear()
    ha = arm.send(arm.goal([(3.0, a_target, [0.0] * 6)]), on_feedback)
    arm.wait_feedback(ha, feedback, 30, "the first goal under way")
    samples = []
    stop_sampling = threading.Event()

    def sample():
        while not stop_sampling.is_set():
            _, v = json_client.truth()
            samples.append((time.monotonic(), v))
    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    # A goal that cannot run ends at once and leaves the running one alone.
    bad = arm.send(arm.goal([(1.0, a_target, None)], names=arm.names[:5] + ["nope"]))
    status, res = arm.result(bad)
    expect(res.error_code == FollowJointTrajectory.Result.INVALID_JOINTS, f"invalid goal during a goal: {res.error_code}")
    expect(ha.status == GoalStatus.STATUS_EXECUTING, f"an invalid goal ended the running one (status {ha.status})")
    wait_for(lambda: len(samples) >= 20, "truth samples before the switch")
    hb = arm.send(arm.goal([(2.0, b_target, [0.0] * 6)]))
    status_a, res_a = arm.result(ha)
    status_b, res_b = arm.result(hb)
    stop_sampling.set()
    sampler.join(timeout=WAIT)
    expect(status_a == GoalStatus.STATUS_CANCELED and "preempted" in res_a.error_string,
           f"preempted goal: status {status_a} {res_a.error_string!r}")
    expect(status_b == GoalStatus.STATUS_SUCCEEDED, f"preempting goal: status {status_b} {res_b.error_string!r}")
    # No jump: the truth's velocity never changes faster than the axes can accelerate.
    worst = 0.0
    for (t0, v0), (t1, v1) in zip(samples, samples[1:]):
        if t1 - t0 > 1e-3:
            worst = max(worst, max(abs(b - a) for a, b in zip(v0, v1)) / (t1 - t0))
    q_true, _ = json_client.truth()
    final = max(abs(q_true[i] - b_target[i]) for i in range(6))
    expect(final < 0.01, f"after the preemption the truth {q_true} is not at {b_target}")
    expect(worst < args.max_accel, f"velocity changed at {worst:.2f} rad/s^2 (allowed {args.max_accel})")
    ok("preempt", samples=len(samples), worst_accel_rad_s2=f"{worst:.2f}", final_error_rad=f"{final:.2e}")

    # Another client's hold stops a goal at once; then that client holds control.
    q0 = arm.position()
    feedback.clear()
    h = arm.send(arm.goal([(4.0, [q0[0] + 1.0] + q0[1:], [0.0] * 6)]), on_feedback)
    arm.wait_feedback(h, feedback, 20, "feedback before the other client's hold")
    expect(other.request("hold").get("operating_mode") == "HOLD", "hold from the JSON client")
    status, res = arm.result(h)
    expect(status == GoalStatus.STATUS_ABORTED, f"goal after another client's hold: {status} {res.error_string!r}")
    ok("hold_from_json_client", error_string=repr(res.error_string))
    # The node keeps control after its goals (as a controller does) until it is told to let go.
    r = other.request("take_control")
    expect(r.get("error_status") == "ERROR" and "shared-memory client" in r.get("error_message", "")
           and "of mcm-ros2 (pid" in r.get("error_message", ""),
           f"take_control while the node holds control: {r}")
    r = arm.call("release_control")
    expect(r.success, f"release_control service: {r.message}")
    r = other.request("take_control")
    expect(r.get("error_status") == "OK", f"take_control by the JSON client: {r}")
    h = arm.send(arm.goal([(1.0, arm.position(), [0.0] * 6)]))
    status, res = arm.result(h)
    expect(status == GoalStatus.STATUS_ABORTED and "controls the arm" in res.error_string
           and "client of the gateway" in res.error_string,
           f"goal while a JSON client controls the arm: {status} {res.error_string!r}")
    ok("not_owner", error_string=repr(res.error_string))
    other.request("release_control")

    # The streaming topic: a trajectory message moves the arm too.
    q0 = arm.position()
    target = [q0[0] - 0.3] + q0[1:]
    msg = JointTrajectory(joint_names=arm.names,
                          points=[JointTrajectoryPoint(positions=target, velocities=[0.0] * 6, time_from_start=dur(1.0))])
    arm.topic.publish(msg)
    wait_for(lambda: abs(json_client.truth()[0][0] - target[0]) < 0.01, "the arm at the joint_trajectory target")
    ok("joint_trajectory_topic")

    # A safety error of the core (the emergency stop) ends a running goal at once, with the
    # core's words, and shows in /diagnostics at level ERROR.
    q0 = arm.position()
    feedback.clear()
    h = arm.send(arm.goal([(4.0, [q0[0] + 1.0] + q0[1:], [0.0] * 6)]), on_feedback)
    arm.wait_feedback(h, feedback, 20, "feedback before the emergency stop")
    r = other.request("sim", emergency_stop=True)
    expect(r.get("emergency_stop") is True, f"sim emergency_stop: {r}")
    status, res = arm.result(h)
    expect(status == GoalStatus.STATUS_ABORTED and res.error_string.startswith("the MCM stopped the arm:"),
           f"goal during an emergency stop: {status} {res.error_string!r}")
    words = res.error_string.removeprefix("the MCM stopped the arm: ")
    d = wait_for(lambda: (lambda s: s if s and level(s) == 2 and words in s.message else None)(arm.my_diagnostics()),
                 f"diagnostics at level ERROR saying {words!r}", timeout=5)
    ok("safety_error", error_string=repr(res.error_string), diagnostics=repr(d.message))
    other.request("sim", emergency_stop=False)
    wait_for(lambda: other.request("hold").get("operating_mode") == "HOLD", "HOLD after the emergency stop", step=0.2)

    r = arm.call("hold")
    expect(r.success, f"hold service: {r.message}")
    r = arm.call("release_control")
    expect(r.success, f"release_control service: {r.message}")
    ok("services", hold=repr(r.message))
    close()


def check_remote(args):
    """From another host: both arms' joint states; one arm moved; the other stays."""
    node, close = start("mcm_remote_checks")
    arms = {}
    for ns, prefix in zip(args.namespaces.split(","), args.prefixes.split(",")):
        arms[ns] = Arm(node, ns, prefix)
        arms[ns].hardware = None
    for ns, arm in arms.items():
        m = wait_for(arm.latest, f"{ns}/joint_states from the other host", timeout=30)
        expect(list(m.name) == arm.names, f"{ns}: names {list(m.name)}")
        wait_for(lambda: arm.description, f"{ns}/robot_description")
        expect(all(n in arm.description for n in arm.names), f"{ns}: URDF lacks the prefixed joint names")
        ok("remote_joint_states", namespace=ns, names=",".join(m.name))
    moved, still = arms[args.move], [a for ns, a in arms.items() if ns != args.move]
    r = moved.call("calibrate", timeout=120)
    expect(r.success, f"{args.move}/calibrate: {r.message}")
    before = [a.position() for a in still]
    q0 = moved.position()
    target = [q0[0] + 0.3] + q0[1:]
    status, res = moved.result(moved.send(moved.goal([(1.5, target, [0.0] * 6)])))
    expect(status == GoalStatus.STATUS_SUCCEEDED, f"{args.move}: goal {status} {res.error_string!r}")
    q = moved.position()
    expect(abs(q[0] - target[0]) < 0.01, f"{args.move}: at {q}, target {target}")
    for a, b in zip(still, before):
        after = a.position()
        expect(max(abs(x - y) for x, y in zip(after, b)) < 1e-3, f"the other arm moved: {b} -> {after}")
    ok("remote_goal", namespace=args.move)
    close()


def main():
    p = argparse.ArgumentParser()
    p.add_argument("mode", choices=["single", "remote"])
    p.add_argument("--json")
    p.add_argument("--namespace", default="/")
    p.add_argument("--prefix", default="")
    p.add_argument("--namespaces")
    p.add_argument("--prefixes")
    p.add_argument("--move")
    p.add_argument("--max-accel", type=float, default=10.0)
    args = p.parse_args()
    try:
        (check_single if args.mode == "single" else check_remote)(args)
    except Failure as e:
        print(f"FAILED: {e}", flush=True)
        sys.exit(1)


if __name__ == "__main__":
    main()
