"""Print the MCM's DiagnosticStatus from /diagnostics once: level, message and its values.

    cargo run --release -- --ros2            # in one terminal: the MCM with its ROS 2 node
    python3 examples/ros2/diagnostics.py     # in another (README.md: what it needs)

/diagnostics is one topic for the whole ROS graph (it has no namespace): every MCM node
publishes its status there, about once a second, named "mcm: <robot> (MCM instance <name>)".
With several MCMs, --instance picks one.
"""

import argparse

import rclpy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.node import Node

from _common import spin_until


p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--instance", help="only the MCM with this instance name (default: the first MCM heard)")
p.add_argument("--timeout", type=float, default=20.0, help="longest wait [s] (default %(default)s)")
args = p.parse_args()


def level(status):
    """A ROS `byte` field comes to rclpy as a one-byte `bytes`."""
    lv = status.level
    return lv[0] if isinstance(lv, (bytes, bytearray)) else int(lv)


LEVELS = {level(DiagnosticStatus(level=lv)): word for lv, word in [
    (DiagnosticStatus.OK, "OK"), (DiagnosticStatus.WARN, "WARN"),
    (DiagnosticStatus.ERROR, "ERROR"), (DiagnosticStatus.STALE, "STALE")]}


def is_ours(status):
    if not status.name.startswith("mcm: "):
        return False  # another component's status
    return args.instance is None or status.hardware_id.endswith(f"(MCM instance {args.instance})")


rclpy.init()
node = Node("diagnostics_example")
found = []
node.create_subscription(DiagnosticArray, "/diagnostics",
                         lambda arr: found.extend(s for s in arr.status if is_ours(s)), 10)
s = spin_until(node, lambda: found[0] if found else None, "an MCM's DiagnosticStatus", args.timeout)
lv = level(s)
print(f"{s.name}: level {lv} ({LEVELS.get(lv, '?')}): {s.message}")
print(f"  hardware_id: {s.hardware_id}")
for kv in s.values:
    print(f"  {kv.key}: {kv.value}")

node.destroy_node()
rclpy.shutdown()
