"""The MCM's ROS 2 node under abuse, with real ROS 2 (rclpy, Fast DDS), run by tests/end_to_end/ros2.rs.

    python abuse_checks.py stop_continue --json 127.0.0.1:PORT --until FILE
    python abuse_checks.py refused_goal --json 127.0.0.1:PORT
    python abuse_checks.py big_goals --count N --points P
    python abuse_checks.py burst --count N [--within S] [--json 127.0.0.1:PORT --holds H]
    python abuse_checks.py holds --json 127.0.0.1:PORT --holds H

`stop_continue` calibrates, prints `calibrated`, then sends goals one after the other until FILE
exists (the test stops and continues the node meanwhile): every goal must be answered and end
with a result. `refused_goal` checks that a goal refused because a JSON client controls the arm
leaves that client's move alone. `big_goals` prints `ready`, then sends N goals of P points each
one after the other (no calibration: the node refuses them for their size), printing `goal I` as
each ends; the test reads the node's memory meanwhile. `burst` calibrates, then sends N goals at
once from a client that keeps all its requests (rclpy's default history of 10 drops most of a
burst before the node sees it): every goal must be answered, and every accepted one end with a
result; with `--json` it also times H `hold`s of a JSON client (`holds`, in a process of its
own, send to reply) before the burst and from its start. Each check prints
`ok <name> <figures>`; the first failure raises (exit 1) with what was expected and what came.
Every wait is bounded.
"""

import argparse
import math
import os
import subprocess
import sys
import time

from action_msgs.msg import GoalStatus

from node_checks import WAIT, Arm, Failure, Json, expect, ok, start, wait_for, wait_future, wait_online_and_calibrate

STATUS = {GoalStatus.STATUS_SUCCEEDED: "succeeded", GoalStatus.STATUS_ABORTED: "aborted",
          GoalStatus.STATUS_CANCELED: "canceled"}


def stop_continue(args, arm, json_client):
    """Goals back and forth on the base joint until the test is done stopping the node."""
    print("calibrated", flush=True)
    q0 = arm.position()
    ends = {}
    n = 0
    while not os.path.exists(args.until):
        target = [q0[0] + (0.3 if n % 2 == 0 else 0.0)] + q0[1:]
        h = wait_future(arm.action.send_goal_async(arm.goal([(1.0, target, [0.0] * 6)])),
                        f"the answer to goal {n}")
        expect(h.accepted, f"goal {n} was rejected")
        r = wait_future(h.get_result_async(), f"the result of goal {n}")
        name = STATUS.get(r.status, str(r.status))
        ends[name] = ends.get(name, 0) + 1
        n += 1
    expect(n > 0, "no goal ran while the node was stopped and continued")
    ok("stop_continue", goals=n, **ends)


def refused_goal(args, arm, json_client):
    """After the node drove and let go, a JSON client takes control and moves; a goal sent then is
    refused, and the JSON client's move goes on to its target."""
    q0 = arm.position()
    h = arm.send(arm.goal([(1.0, [q0[0] + 0.1] + q0[1:], [0.0] * 6)]))
    status, res = arm.result(h)
    expect(status == GoalStatus.STATUS_SUCCEEDED, f"the node's own goal: {status} {res.error_string!r}")
    r = arm.call("release_control")
    expect(r.success, f"release_control service: {r.message}")
    r = json_client.request("take_control")
    expect(r.get("error_status") == "OK", f"take_control by the JSON client: {r}")
    start_deg = math.degrees(json_client.truth()[0][0])
    target_deg = start_deg + 40.0
    r = json_client.request("pvt")
    expect(r.get("operating_mode") == "PVT", f"pvt by the JSON client: {r}")
    r = json_client.request("move_axis", axis_index=1, target_position=target_deg, velocity_factor=0.2)
    expect(r.get("error_status") == "OK", f"move_axis by the JSON client: {r}")
    h = arm.send(arm.goal([(1.0, arm.position(), [0.0] * 6)]))
    status, res = arm.result(h)
    expect(status == GoalStatus.STATUS_ABORTED and "controls the arm" in res.error_string,
           f"goal while a JSON client controls and moves the arm: {status} {res.error_string!r}")
    moved_at_refusal = math.degrees(json_client.truth()[0][0]) - start_deg
    expect(moved_at_refusal < 35.0, f"the move was nearly over ({moved_at_refusal:.1f} deg) when the goal was refused")

    def at_rest():
        q, v = json_client.truth()
        return (q, v) if max(abs(x) for x in v) < 1e-3 else None
    q, _ = wait_for(at_rest, "the JSON client's move at rest", timeout=60, step=0.05)
    reached = math.degrees(q[0])
    expect(abs(reached - target_deg) < 0.2,
           f"the JSON client's move to {target_deg:.1f} deg stopped at {reached:.1f} deg "
           f"({reached - start_deg:.1f} of 40 deg): the refused goal changed something")
    json_client.request("release_control")
    ok("refused_goal", moved_at_refusal_deg=f"{moved_at_refusal:.1f}", reached_deg=f"{reached:.2f}")


def big_goals(args, arm):
    """Oversize goals, each answered and ended with the limit's words."""
    from control_msgs.action import FollowJointTrajectory
    from trajectory_msgs.msg import JointTrajectoryPoint
    from node_checks import dur
    goal = FollowJointTrajectory.Goal()
    goal.trajectory.joint_names = arm.names
    q = [0.0] * 6
    goal.trajectory.points = [JointTrajectoryPoint(positions=q, velocities=q, time_from_start=dur(0.005 * (i + 1)))
                              for i in range(args.points)]
    print("ready", flush=True)
    words = None
    for i in range(args.count):
        h = wait_future(arm.action.send_goal_async(goal), f"the answer to big goal {i}", timeout=60)
        expect(h.accepted, f"big goal {i} was rejected without a reason")
        r = wait_future(h.get_result_async(), f"the result of big goal {i}", timeout=60)
        expect(r.status == GoalStatus.STATUS_ABORTED and r.result.error_code == FollowJointTrajectory.Result.INVALID_GOAL
               and "points" in r.result.error_string,
               f"big goal {i}: status {r.status}, code {r.result.error_code}, {r.result.error_string!r}")
        words = r.result.error_string
        print(f"goal {i}", flush=True)
    ok("big_goals", goals=args.count, points=args.points, error_string=repr(words))


def keep_all_client(node):
    """An action client whose services keep every request and reply: a burst's requests all go out,
    and every answer is kept until read (the client's choice; docs/ros2.md)."""
    from control_msgs.action import FollowJointTrajectory
    from rclpy.action import ActionClient
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    keep_all = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                          durability=DurabilityPolicy.VOLATILE)
    return ActionClient(node, FollowJointTrajectory, "/follow_joint_trajectory",
                        goal_service_qos_profile=keep_all, result_service_qos_profile=keep_all,
                        cancel_service_qos_profile=keep_all)


def holds(args):
    """`hold`s of a JSON client, one at a time (a process of its own: the burst's client does not
    delay it): their round trips, send to reply."""
    json_client = Json(args.json)
    times = []
    for _ in range(args.holds):
        t = time.monotonic()
        r = json_client.request("hold")
        times.append((time.monotonic() - t) * 1000.0)
        expect(r.get("operating_mode") == "HOLD", f"hold by the JSON client: {r}")
    times.sort()
    ok("holds", holds=len(times), p50_ms=f"{times[len(times) // 2]:.2f}",
       p99_ms=f"{times[min(len(times) - 1, int(0.99 * len(times)))]:.2f}", max_ms=f"{times[-1]:.2f}")


def timed_holds(args):
    """Start `holds` in a process of its own."""
    return subprocess.Popen([sys.executable, __file__, "holds", "--json", args.json, "--holds", str(args.holds)],
                            stdout=subprocess.PIPE, text=True)


def holds_line(proc, when):
    """Wait for the `holds` process and print its figures as `ok holds_<when> ...`."""
    try:
        out, _ = proc.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise Failure(f"the holds {when} were not done within 120 s")
    lines = [l for l in out.splitlines() if l.startswith("ok holds")]
    expect(proc.returncode == 0 and lines, f"the holds {when}: {out!r}")
    print(lines[0].replace("ok holds", f"ok holds_{when}"), flush=True)


def burst(args, arm, action):
    """N goals sent at once, each holding the arm where it is: every one answered (accepted or
    rejected), every accepted one ends with a result."""
    q0 = arm.position()
    goal = arm.goal([(0.5, q0, [0.0] * 6)])
    if args.json:
        holds_line(timed_holds(args), "idle")
        during = timed_holds(args)
    t0 = time.monotonic()
    sent = [action.send_goal_async(goal) for _ in range(args.count)]
    sent_s = time.monotonic() - t0
    answered = lambda: sum(1 for f in sent if f.done())
    try:
        wait_for(lambda: answered() == args.count, "an answer to every goal", timeout=args.within)
    except Failure:
        raise Failure(f"{answered()} of {args.count} goals answered within {args.within} s")
    answered_s = time.monotonic() - t0
    accepted = [f.result() for f in sent if f.result().accepted]
    results = [h.get_result_async() for h in accepted]
    got = lambda: sum(1 for f in results if f.done())
    try:
        wait_for(lambda: got() == len(results), "a result for every accepted goal", timeout=args.within)
    except Failure:
        raise Failure(f"{got()} of {len(results)} accepted goals ended with a result within {args.within} s")
    if args.json:
        holds_line(during, "during_burst")
    ends = {}
    for f in results:
        name = STATUS.get(f.result().status, str(f.result().status))
        ends[name] = ends.get(name, 0) + 1
    ok("burst", goals=args.count, sent_s=f"{sent_s:.2f}", accepted=len(accepted),
       rejected=args.count - len(accepted), answered_s=f"{answered_s:.2f}",
       results_s=f"{time.monotonic() - t0:.2f}", **ends)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("check", choices=["stop_continue", "refused_goal", "big_goals", "burst", "holds"])
    p.add_argument("--json")
    p.add_argument("--until")
    p.add_argument("--count", type=int, default=10)
    p.add_argument("--points", type=int, default=100000)
    p.add_argument("--within", type=float, default=60.0)
    p.add_argument("--holds", type=int, default=200)
    args = p.parse_args()
    if args.check == "holds":
        try:
            holds(args)
        except Failure as e:
            print(f"FAILED: {e}", flush=True)
            sys.exit(1)
        return
    node, close = start("mcm_abuse_checks")
    failed = False
    try:
        arm = Arm(node, "/", "")
        expect(arm.action.wait_for_server(timeout_sec=WAIT), "the follow_joint_trajectory action server")
        if args.check == "big_goals":
            big_goals(args, arm)
        elif args.check == "burst":
            action = keep_all_client(node)
            expect(action.wait_for_server(timeout_sec=WAIT), "the follow_joint_trajectory action server (keeping all)")
            wait_online_and_calibrate(arm)
            burst(args, arm, action)
        else:
            json_client = Json(args.json)
            wait_online_and_calibrate(arm)
            {"stop_continue": stop_continue, "refused_goal": refused_goal}[args.check](args, arm, json_client)
    except Failure as e:
        print(f"FAILED: {e}", flush=True)
        failed = True
    close()
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
