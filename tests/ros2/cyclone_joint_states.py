"""Read the MCM node's /joint_states with a second DDS implementation, Cyclone DDS (its Python
binding, no ROS): the node's RustDDS and a DDS that is neither it nor Fast DDS agree on the
wire (discovery, the topic and type names ROS 2 uses, CDR). Run by tests/end_to_end/ros2.rs.

    python cyclone_joint_states.py --domain N [--namespace /] [--count 20]

Prints `ok cyclone_joint_states ...` and the last message's positions as `at: name=deg ...`;
exits 1 saying what did not come. Every wait is bounded.
"""

import argparse
import math
import sys
import time
from dataclasses import dataclass

import cyclonedds.idl.annotations as annotate
from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import float64, int32, sequence, uint32
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration


# ROS 2's messages as DDS types: the name ROS 2 gives them on the wire (`pkg::msg::dds_::T_`),
# final (not appendable) structs, fields in the order of their .msg files.
@dataclass
@annotate.final
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32
    nanosec: uint32


@dataclass
@annotate.final
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Time
    frame_id: str


@dataclass
@annotate.final
class JointState(IdlStruct, typename="sensor_msgs::msg::dds_::JointState_"):
    header: Header
    name: sequence[str]
    position: sequence[float64]
    velocity: sequence[float64]
    effort: sequence[float64]


p = argparse.ArgumentParser()
p.add_argument("--domain", type=int, required=True)
p.add_argument("--namespace", default="/")
p.add_argument("--count", type=int, default=20)
p.add_argument("--timeout", type=float, default=20.0)
args = p.parse_args()

participant = DomainParticipant(args.domain)
# ROS 2 topics are DDS topics prefixed `rt/`.
topic = Topic(participant, "rt" + args.namespace.rstrip("/") + "/joint_states", JointState)
reader = DataReader(participant, topic, qos=Qos(Policy.Reliability.Reliable(duration(seconds=1)),
                                                Policy.History.KeepLast(100)))
got = []
end = time.monotonic() + args.timeout
while len(got) < args.count:
    if time.monotonic() > end:
        print(f"FAILED: {len(got)} of {args.count} joint states within {args.timeout} s", flush=True)
        sys.exit(1)
    got.extend(reader.take(N=100))
    time.sleep(0.02)
stamps = [m.header.stamp.sec + m.header.stamp.nanosec * 1e-9 for m in got]
if any(b <= a for a, b in zip(stamps, stamps[1:])):
    print(f"FAILED: stamps not increasing: {stamps}", flush=True)
    sys.exit(1)
m = got[-1]
if not (len(m.name) == len(m.position) == len(m.velocity) == len(m.effort)):
    print(f"FAILED: vector lengths differ in {m}", flush=True)
    sys.exit(1)
print(f"ok cyclone_joint_states messages={len(got)} span_s={stamps[-1] - stamps[0]:.3f}", flush=True)
print("at: " + " ".join(f"{n}={math.degrees(q):.4f}" for n, q in zip(m.name, m.position)) + " deg",
      flush=True)
