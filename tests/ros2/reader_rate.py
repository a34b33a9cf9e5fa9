"""A /joint_states subscriber (rclpy, reliable, the default QoS) that says what it receives,
judged on the robot's clock: tests/end_to_end/ros2.rs runs two, stops one (SIGSTOP) and reads the other.

    python reader_rate.py --period 0.005 --window 2 --seconds 30

Every `--window` seconds it prints `window received=N cycles=M`: the messages received in the
window, and the cycles their stamps span (the stamps are the cycles' times, one period apart):
a reader that gets every state has N = M + 1. It prints `ready` after its first message.
"""

import argparse
import time

import rclpy
from rclpy.node import Node
from sensor_msgs.msg import JointState


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--period", type=float, required=True)
    p.add_argument("--window", type=float, default=2.0)
    p.add_argument("--seconds", type=float, default=30.0)
    args = p.parse_args()
    rclpy.init()
    node = Node("reader_rate")
    stamps = []
    node.create_subscription(
        JointState, "/joint_states",
        lambda m: stamps.append(m.header.stamp.sec + m.header.stamp.nanosec * 1e-9), 100)
    end = time.monotonic() + args.seconds
    while not stamps:
        if time.monotonic() > end:
            raise SystemExit("no joint state within the time given")
        rclpy.spin_once(node, timeout_sec=0.05)
    print("ready", flush=True)
    stamps.clear()
    next_report = time.monotonic() + args.window
    while time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.01)
        if time.monotonic() >= next_report:
            got = list(stamps)
            stamps.clear()
            cycles = round((max(got) - min(got)) / args.period) if len(got) > 1 else 0
            print(f"window received={len(got)} cycles={cycles}", flush=True)
            next_report += args.window
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
