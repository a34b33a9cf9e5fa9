"""ctypes mirrors of the MCM's shared-memory samples (``shared/src/sample.rs``).

iceoryx2 compares only a type's name, size and alignment when a peer opens a service, never
its fields, so these structures are pinned to the Rust layouts by a test
(``tests/end_to_end/python_layout.rs`` runs ``python/tests/test_layout.py`` against the sizes and field
offsets the Rust compiler computed). Any layout change in Rust bumps the version in the type
name (``mcm.StateSample.v7``), and this module must follow.

This module needs only the standard library.
"""

import ctypes
from typing import Dict, Optional, Tuple, Type

NUM_AXES = 6
#: Arguments in one command sample.
COMMAND_ARGS = 64
#: PVT points carried by one ``pvt_points`` command sample.
PVT_POINTS_PER_COMMAND = 4
#: Replies in one ReplyBlock.
REPLY_BLOCK = 16
#: Reply blocks the state blackboard keeps (keys 1 to REPLY_BLOCKS).
REPLY_BLOCKS = 512
#: Values carried by one reply.
REPLY_VALUES = 8
#: The blackboard key of the state entry.
STATE_KEY = 0
#: The event id mcm-rt notifies on ``mcm/<instance>/state-ready`` after each new state.
STATE_EVENT_ID = 1
#: Commands a publisher may keep unanswered in the core's buffer (keep well below).
COMMAND_BUFFER = 64

#: ``CommandSample.flags`` of ``pvt_points``: this sample closes its batch.
PVT_FLAG_LAST = 1 << 8
#: ``CommandSample.flags`` of ``torque_control``: torques are not added to the gravity
#: compensation.
TORQUE_FLAG_NO_GRAVITY = 1
#: ``CommandSample.flags`` of ``calibrate``: use mechanical stops even where light barriers exist.
CALIBRATE_FLAG_FORCE_STOP = 1
#: ``CommandSample.flags`` of ``identify_payload``: the estimate becomes the tool's load.
IDENTIFY_FLAG_APPLY = 1
#: ``CommandSample.flags`` of ``sim``: power cycle the drives.
SIM_FLAG_POWER_CYCLE = 1 << 11

#: ``StateSample.flags`` bits.
STATE_ESTOP = 1
STATE_SIMULATED = 1 << 1
STATE_ALL_CALIBRATED = 1 << 2
STATE_PVT_STARVED = 1 << 3
STATE_NOT_REALTIME = 1 << 4
STATE_SIM_ESTOP = 1 << 5
STATE_SHUTTING_DOWN = 1 << 6
#: ``StateSample.cartesian`` holds the TCP's state (every axis calibrated); zeros when clear.
STATE_CARTESIAN = 1 << 7

#: ``StateSample.axis_flags`` bits.
AXIS_CALIBRATED = 1
AXIS_ONLINE = 1 << 1
AXIS_ENABLED = 1 << 2
AXIS_FAULT = 1 << 3
AXIS_I2T_DERATED = 1 << 4

_F6 = ctypes.c_double * NUM_AXES


class CommandSample(ctypes.Structure):
    """A command to the real-time core (Rust ``mcm_shared::sample::CommandSample``)."""

    _fields_ = [
        ("client_id", ctypes.c_uint64),
        ("request_id", ctypes.c_uint64),
        ("kind", ctypes.c_uint32),
        ("flags", ctypes.c_uint32),
        ("args", ctypes.c_double * COMMAND_ARGS),
    ]

    @staticmethod
    def type_name() -> str:
        """The iceoryx2 type name, equal to the Rust ``#[type_name]``."""
        return "mcm.CommandSample.v1"


class Reply(ctypes.Structure):
    """The answer to one command, kept in a ReplyBlock."""

    _fields_ = [
        ("seq", ctypes.c_uint64),
        ("client_id", ctypes.c_uint64),
        ("request_id", ctypes.c_uint64),
        ("cycle", ctypes.c_uint64),
        ("kind", ctypes.c_uint32),
        ("status", ctypes.c_uint32),
        ("code", ctypes.c_uint32),
        ("axis", ctypes.c_uint32),
        ("values", ctypes.c_double * REPLY_VALUES),
    ]


class ErrorRecord(ctypes.Structure):
    """The latest safety violation (or drive error)."""

    _fields_ = [
        ("seq", ctypes.c_uint64),
        ("cycle", ctypes.c_uint64),
        ("unix_ns", ctypes.c_uint64),
        ("code", ctypes.c_uint32),
        ("axis", ctypes.c_uint32),
        ("values", ctypes.c_double * 4),
    ]


class LatencyFigures(ctypes.Structure):
    """Percentiles of the cycle's wake-up latency [ns]."""

    _fields_ = [
        ("p50_ns", ctypes.c_uint64),
        ("p99_ns", ctypes.c_uint64),
        ("p99_9_ns", ctypes.c_uint64),
        ("p99_99_ns", ctypes.c_uint64),
        ("max_ns", ctypes.c_uint64),
        ("cycles", ctypes.c_uint64),
    ]


class CycleTiming(ctypes.Structure):
    """Timing figures of the real-time cycle."""

    _fields_ = [
        ("period_ns", ctypes.c_uint64),
        ("overruns", ctypes.c_uint64),
        ("since_start", LatencyFigures),
        ("recent", LatencyFigures),
        ("recent_window_ns", ctypes.c_uint64),
        ("work_max_ns", ctypes.c_uint64),
        ("work_budget_ns", ctypes.c_uint64),
        ("over_budget", ctypes.c_uint64),
    ]


class BusCounters(ctypes.Structure):
    """Counters of the CAN bus and of the CANopen master since the core started (each counts
    something that should not happen)."""

    _fields_ = [
        ("bad_frames", ctypes.c_uint64),
        ("frames_dropped", ctypes.c_uint64),
        ("events_dropped", ctypes.c_uint64),
        ("bus_errors", ctypes.c_uint64),
    ]


class TcpState(ctypes.Structure):
    """The TCP's pose and velocity in the base frame (valid when ``StateSample.flags`` has
    ``STATE_CARTESIAN``): position [m], orientation a unit quaternion ``[x, y, z, w]`` with
    ``w >= 0``, linear velocity [m/s], angular velocity [deg/s]."""

    _fields_ = [
        ("position", ctypes.c_double * 3),
        ("orientation", ctypes.c_double * 4),
        ("linear_velocity", ctypes.c_double * 3),
        ("angular_velocity", ctypes.c_double * 3),
    ]


class ToolState(ctypes.Structure):
    """The active tool: the TCP in the flange frame [m, unit quaternion x, y, z, w], the mass
    [kg], the centre of mass [m] and the inertia [ixx, iyy, izz, ixy, ixz, iyz] [kg m^2] about
    it."""

    _fields_ = [
        ("tcp_position", ctypes.c_double * 3),
        ("tcp_orientation", ctypes.c_double * 4),
        ("mass", ctypes.c_double),
        ("center_of_mass", ctypes.c_double * 3),
        ("inertia", ctypes.c_double * 6),
    ]


class StateSample(ctypes.Structure):
    """The state of the arm and the controller, published once per cycle (key 0 of the state
    blackboard). Units: degrees, degrees/s, degrees/s^2, amperes; times ``CLOCK_MONOTONIC`` ns
    (Python's ``time.monotonic_ns()``)."""

    _fields_ = [
        ("seq", ctypes.c_uint64),
        ("t_ns", ctypes.c_uint64),
        ("mode", ctypes.c_uint32),
        ("flags", ctypes.c_uint32),
        ("position", _F6),
        ("velocity", _F6),
        ("acceleration", _F6),
        ("current", _F6),
        ("measured_position", _F6),
        ("commanded_position", _F6),
        ("following_error", _F6),
        ("i2t", _F6),
        ("sim_true_position", _F6),
        ("sim_true_velocity", _F6),
        ("axis_flags", ctypes.c_uint32 * NUM_AXES),
        ("pvt_queued", ctypes.c_uint32),
        ("pvt_capacity", ctypes.c_uint32),
        ("command_receive_errors", ctypes.c_uint64),
        ("timing", CycleTiming),
        ("last_error", ErrorRecord),
        ("reply_head", ctypes.c_uint64),
        ("owner_client_id", ctypes.c_uint64),
        ("bus", BusCounters),
        ("cartesian", TcpState),
        ("tool", ToolState),
    ]

    def tcp_state(self) -> Optional[TcpState]:
        """The TCP's state, or ``None`` until every axis is calibrated (``STATE_CARTESIAN``)."""
        return self.cartesian if self.flags & STATE_CARTESIAN else None

    @staticmethod
    def type_name() -> str:
        """The iceoryx2 type name, equal to the Rust ``#[type_name]``."""
        return "mcm.StateSample.v7"


class ReplyBlock(ctypes.Structure):
    """One block of replies, the value of a reply key (1 to REPLY_BLOCKS) of the blackboard."""

    _fields_ = [("replies", Reply * REPLY_BLOCK)]

    @staticmethod
    def type_name() -> str:
        """The iceoryx2 type name, equal to the Rust ``#[type_name]``."""
        return "mcm.ReplyBlock.v1"


#: Every structure, under its Rust name, for the layout check.
STRUCTS: Dict[str, Type[ctypes.Structure]] = {
    "CommandSample": CommandSample,
    "Reply": Reply,
    "ErrorRecord": ErrorRecord,
    "LatencyFigures": LatencyFigures,
    "CycleTiming": CycleTiming,
    "BusCounters": BusCounters,
    "TcpState": TcpState,
    "ToolState": ToolState,
    "StateSample": StateSample,
    "ReplyBlock": ReplyBlock,
}


def reply_location(seq: int) -> Tuple[int, int]:
    """Where reply ``seq`` (1, 2, ...) is kept: its blackboard key (1 to REPLY_BLOCKS) and its
    slot in that block (Rust ``mcm_shared::sample::reply_location``)."""
    n = (seq - 1) % (1 << 64)
    block = (n // REPLY_BLOCK) % REPLY_BLOCKS
    return block + 1, n % REPLY_BLOCK


def layout_of(cls: Type[ctypes.Structure]) -> Dict[str, object]:
    """Size, alignment and field offsets of a structure, as the layout check compares them."""
    return {
        "size": ctypes.sizeof(cls),
        "align": ctypes.alignment(cls),
        "fields": {f[0]: getattr(cls, f[0]).offset for f in cls._fields_},
    }
