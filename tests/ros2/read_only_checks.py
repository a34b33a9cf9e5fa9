"""A node started with --ros2-read-only, seen by real ROS 2 (rclpy, Fast DDS); run by
tests/end_to_end/ros2_read_only.rs against a calibrated arm that nobody controls.

    python read_only_checks.py --json 127.0.0.1:PORT [--node mcm] [--namespace /]

It reads the joint states; finds in the ROS graph that the node offers them, the robot
description and the diagnostics, and no action server, no service and no `joint_trajectory`
subscription; publishes a `JointTrajectory` on `joint_trajectory` and checks that the arm's true
position (the simulation's `sim`) does not change over two seconds of the robot's cycles; and
that the node holds no control (a JSON client takes it). Each check prints
`ok <name> <figures>`; the first failure raises (exit 1) with what was expected and what came.
Every wait is bounded.
"""

import argparse
import sys

import rclpy.action

from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from node_checks import Arm, Failure, Json, dur, expect, ok, start, wait_for

# What a read-only node publishes, by topic name and type.
PUBLISHED = {"joint_states": "sensor_msgs/msg/JointState",
             "robot_description": "std_msgs/msg/String",
             "/diagnostics": "diagnostic_msgs/msg/DiagnosticArray"}


def full(ns, name):
    return name if name.startswith("/") else f"{ns.rstrip('/')}/{name}"


def check(args):
    node, close = start("mcm_read_only_checks")
    arm = Arm(node, args.namespace, "")
    json_client = Json(args.json)
    ns = args.namespace

    # The joint states come, with the arm's joint names, matching the truth.
    m = wait_for(arm.latest, "/joint_states")
    expect(list(m.name) == arm.names, f"joint names {list(m.name)}, expected {arm.names}")
    q_true, _ = json_client.truth()
    err = max(abs(a - b) for a, b in zip(arm.position(), q_true))
    expect(err < 0.01, f"joint_states positions differ from the truth {q_true} by {err} rad")
    wait_for(lambda: arm.description, "/robot_description (transient local)")
    ok("joint_states", max_error_rad=f"{err:.2e}")

    # The ROS graph, by node (this script's own clients of the services and the action are in
    # the graph too, under its own node): once the node's publishers are known (the node
    # announced its entities), what it offers is exact.
    def publishers():
        got = dict(node.get_publisher_names_and_types_by_node(args.node, ns))
        want = {full(ns, t): [ty] for t, ty in PUBLISHED.items()}
        return got if all(got.get(t) == ty for t, ty in want.items()) else None
    pubs = wait_for(publishers, f"the publishers {sorted(PUBLISHED)} of node {args.node} in the ROS graph")
    def offered():
        services = node.get_service_names_and_types_by_node(args.node, ns)
        expect(services == [], f"a read-only node offers no service; it offers {services}")
        subs = [t for t, _ in node.get_subscriber_names_and_types_by_node(args.node, ns)]
        expect(full(ns, "joint_trajectory") not in subs, f"the node subscribes {subs}")
        servers = rclpy.action.get_action_server_names_and_types_by_node(node, args.node, ns)
        expect(servers == [], f"a read-only node offers no action server; it offers {servers}")
        return subs, services, servers
    subs, services, servers = offered()
    ok("graph", publishers=",".join(sorted(pubs)), subscriptions=",".join(subs) or "none",
       services=len(services), action_servers=len(servers))

    # The action client finds no server.
    expect(not arm.action.wait_for_server(timeout_sec=3.0),
           "an rclpy action client found the follow_joint_trajectory server")
    ok("no_action_server")

    # A trajectory published on joint_trajectory moves nothing: nobody reads it.
    q0, _ = json_client.truth()
    target = [q0[0] + 0.3] + q0[1:]
    msg = JointTrajectory(joint_names=arm.names,
                          points=[JointTrajectoryPoint(positions=target, velocities=[0.0] * 6,
                                                       time_from_start=dur(1.0))])
    cycle = lambda: json_client.status()["detail"]["cycle"]
    c0 = cycle()
    # Published every 100 of the robot's cycles (a subscriber that DDS matches late gets one
    # too) for 400, then checked 400 cycles later (the trajectory lasts 200).
    sent = 0
    while (c := cycle()) < c0 + 400:
        arm.topic.publish(msg)
        sent += 1
        wait_for(lambda: cycle() >= c + 100, "100 cycles", step=0.05)
    c1 = cycle()
    wait_for(lambda: cycle() >= c1 + 400, "400 cycles", step=0.05)
    q1, v1 = json_client.truth()
    moved = max(abs(a - b) for a, b in zip(q0, q1))
    expect(moved < 1e-3 and max(abs(v) for v in v1) < 1e-3,
           f"the arm moved after a joint_trajectory message: {q0} -> {q1} rad, velocity {v1}")
    matched = arm.topic.get_subscription_count()
    expect(matched == 0, f"{matched} subscribers of joint_trajectory")
    ok("joint_trajectory_ignored", messages=sent, moved_rad=f"{moved:.1e}", cycles=cycle() - c0)

    # Seconds later, discovery long finished (a service's endpoints may be announced after
    # the publishers the first look waited for): still nothing that moves the arm.
    subs, services, servers = offered()
    ok("graph_later", subscriptions=",".join(subs) or "none", services=len(services),
       action_servers=len(servers))

    # The diagnostics say the node is read-only.
    d = wait_for(arm.my_diagnostics, "/diagnostics")
    values = dict((kv.key, kv.value) for kv in d.values)
    expect(values.get("motion interface") == "none (--ros2-read-only)",
           f"diagnostics' motion interface: {values.get('motion interface')!r}")
    ok("diagnostics_read_only", owner=repr(values.get("owner")))
    close()


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--json", required=True)
    p.add_argument("--node", default="mcm")
    p.add_argument("--namespace", default="/")
    args = p.parse_args()
    try:
        check(args)
    except Failure as e:
        print(f"FAILED: {e}", flush=True)
        sys.exit(1)


if __name__ == "__main__":
    main()
