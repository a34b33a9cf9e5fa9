"""Shared pieces of the ROS 2 examples (not an example itself)."""

import argparse
import time

import rclpy


def parser(description: str) -> argparse.ArgumentParser:
    """The options every example takes."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--namespace", default="/",
                   help="ROS namespace of the MCM's node, e.g. /left (default %(default)s)")
    p.add_argument("--timeout", type=float, default=20.0,
                   help="longest wait for the node [s] (default %(default)s)")
    return p


def name(namespace: str, base: str) -> str:
    """`base` under `namespace`: name("/", "joint_states") is "/joint_states"."""
    return namespace.rstrip("/") + "/" + base


def spin_until(node, done, what: str, timeout: float):
    """Spin `node` until `done()` returns something true (returned); exit saying `what` did not
    come within `timeout` seconds."""
    end = time.monotonic() + timeout
    while True:
        value = done()
        if value:
            return value
        if time.monotonic() > end:
            raise SystemExit(f"{what}: nothing within {timeout} s (is `mcm --ros2` running, "
                             "in the same ROS_DOMAIN_ID?)")
        rclpy.spin_once(node, timeout_sec=0.05)


def spin_for(node, seconds: float):
    """Spin `node` for `seconds` (its callbacks keep running meanwhile)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=min(0.05, max(0.0, end - time.monotonic())))
