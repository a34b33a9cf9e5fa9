"""Print the arm's joint names and positions from /joint_states a few times, then exit.

    cargo run --release -- --ros2            # in one terminal: the MCM with its ROS 2 node
    python3 examples/ros2/joint_states.py    # in another (README.md: what it needs)
"""

import math

import rclpy
from rclpy.node import Node
from sensor_msgs.msg import JointState

from _common import name, parser, spin_for, spin_until

p = parser(__doc__.splitlines()[0])
p.add_argument("--count", type=int, default=3, help="messages to print (default %(default)s)")
p.add_argument("--every", type=float, default=0.5, help="seconds between them (default %(default)s)")
args = p.parse_args()

rclpy.init()
node = Node("joint_states_example")
latest = []
# The node publishes one message per control cycle (200 Hz); a depth of 10 is plenty here.
node.create_subscription(JointState, name(args.namespace, "joint_states"), latest.append, 10)

for i in range(args.count):
    latest.clear()
    m = spin_until(node, lambda: latest[-1] if latest else None, "a /joint_states message", args.timeout)
    stamp = m.header.stamp.sec + m.header.stamp.nanosec * 1e-9
    print(f"joint_states {i + 1}/{args.count} (stamp {stamp:.3f} s):")
    for joint, q in zip(m.name, m.position):
        # Positions are in radians (ROS's unit); degrees for the reader.
        print(f"  {joint:12s} {q:+.4f} rad  {math.degrees(q):+9.3f} deg")
    if i + 1 < args.count:
        spin_for(node, args.every)  # spinning: the subscription keeps up meanwhile

node.destroy_node()
rclpy.shutdown()
