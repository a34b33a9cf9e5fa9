"""Typed results of the MCM protocol (``docs/protocol.md``, "Results"). Each keeps the whole
JSON object in ``raw``, so fields added by later MCM versions stay reachable."""

from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence

Six = List[float]


def _six(v: Any, name: str) -> Six:
    if not isinstance(v, list) or len(v) != 6:
        from .errors import ProtocolError

        raise ProtocolError("expected six numbers in %r, got %r" % (name, v))
    return [float(x) for x in v]


@dataclass
class AxisStates:
    """The manual's ``axis_states``: per axis, the time [s], position [deg], velocity [deg/s],
    acceleration [deg/s^2] and motor current [A]."""

    time: Six
    position: Six
    velocity: Six
    acceleration: Six
    current: Six

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "AxisStates":
        return cls(
            **{k: _six(v.get(k), k) for k in ("time", "position", "velocity", "acceleration", "current")}
        )


def _floats(v: Any, n: int, name: str) -> List[float]:
    if not isinstance(v, list) or len(v) != n:
        from .errors import ProtocolError

        raise ProtocolError("expected %d numbers in %r, got %r" % (n, name, v))
    return [float(x) for x in v]


@dataclass
class CartesianState:
    """``cartesian_state`` of a status: the TCP in the base frame, from the same axis values as
    ``axis_states`` (``docs/cartesian.md``): position [m], orientation a unit quaternion
    ``[x, y, z, w]`` (``w >= 0``), linear velocity [m/s], angular velocity [deg/s]."""

    position: List[float]
    orientation: List[float]
    linear_velocity: List[float]
    angular_velocity: List[float]

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "CartesianState":
        return cls(
            position=_floats(v.get("position"), 3, "position"),
            orientation=_floats(v.get("orientation"), 4, "orientation"),
            linear_velocity=_floats(v.get("linear_velocity"), 3, "linear_velocity"),
            angular_velocity=_floats(v.get("angular_velocity"), 3, "angular_velocity"),
        )


@dataclass
class StatusDetail:
    """The ``detail`` object of ``status`` with ``detail: true``."""

    cycle: int
    calibrated: List[bool]
    all_calibrated: bool
    measured_position: Six
    commanded_position: Six
    following_error: Six
    i2t: Six
    drive_online: List[bool]
    drive_enabled: List[bool]
    drive_fault: List[bool]
    emergency_stop: bool
    pvt_queue: Dict[str, Any]
    timing: Dict[str, Any]
    control: Optional[Dict[str, Any]]
    raw: Dict[str, Any] = field(repr=False)
    #: The active tool, as ``set_tool`` takes it: ``tcp`` ``{"position", "orientation"}``,
    #: ``mass``, ``center_of_mass``, ``inertia``.
    tool: Dict[str, Any] = field(default_factory=dict)

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "StatusDetail":
        return cls(
            cycle=int(v.get("cycle", 0)),
            calibrated=list(v.get("calibrated", [])),
            all_calibrated=bool(v.get("all_calibrated", False)),
            measured_position=list(v.get("measured_position", [])),
            commanded_position=list(v.get("commanded_position", [])),
            following_error=list(v.get("following_error", [])),
            i2t=list(v.get("i2t", [])),
            drive_online=list(v.get("drive_online", [])),
            drive_enabled=list(v.get("drive_enabled", [])),
            drive_fault=list(v.get("drive_fault", [])),
            emergency_stop=bool(v.get("emergency_stop", False)),
            pvt_queue=dict(v.get("pvt_queue", {})),
            timing=dict(v.get("timing", {})),
            control=v.get("control"),
            raw=v,
            tool=dict(v.get("tool", {})),
        )


@dataclass
class Status:
    """A ``status`` result: the operating mode and the axis states, the TCP's
    :class:`CartesianState` once every axis is calibrated (``None`` before), and with ``detail``
    also ``hardware_status`` and :class:`StatusDetail`."""

    operating_mode: str
    axis_states: AxisStates
    cartesian_state: Optional[CartesianState] = None
    hardware_status: Optional[str] = None
    detail: Optional[StatusDetail] = None
    raw: Dict[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "Status":
        d = v.get("detail")
        c = v.get("cartesian_state")
        return cls(
            operating_mode=str(v.get("operating_mode")),
            axis_states=AxisStates.from_json(v.get("axis_states", {})),
            cartesian_state=CartesianState.from_json(c) if isinstance(c, dict) else None,
            hardware_status=v.get("hardware_status"),
            detail=StatusDetail.from_json(d) if isinstance(d, dict) else None,
            raw=v,
        )


@dataclass
class MoveAllResult:
    """A ``move_all`` result: the peak velocity of each axis [deg/s], the axis (1-based) that
    would take longest on its own, and the time to the target [s]."""

    velocities: Six
    longest: int
    max_time_to_target: float
    raw: Dict[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "MoveAllResult":
        return cls(
            velocities=_six(v.get("velocities"), "velocities"),
            longest=int(v["longest"]),
            max_time_to_target=float(v["max_time_to_target"]),
            raw=v,
        )


@dataclass
class PayloadResult:
    """A ``payload`` result (``identify_payload``): the load's ``mass`` [kg], its
    ``center_of_mass`` [m] in the flange frame (zeros below 0.05 kg), and the ``residual`` [N m]:
    the RMS over every axis and pose of the holding torque the estimate does not explain."""

    mass: float
    center_of_mass: List[float]
    residual: float
    raw: Dict[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "PayloadResult":
        return cls(
            mass=float(v["mass"]),
            center_of_mass=[float(x) for x in v["center_of_mass"]],
            residual=float(v["residual"]),
            raw=v,
        )


@dataclass
class MoveLinearResult:
    """A ``move_linear`` result: the time to the target [s] and each axis's position there
    [deg]."""

    duration: float
    joint_target: Six
    raw: Dict[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "MoveLinearResult":
        return cls(
            duration=float(v["duration"]),
            joint_target=_six(v.get("joint_target"), "joint_target"),
            raw=v,
        )


@dataclass
class InverseKinematicsResult:
    """An ``inverse_kinematics`` result: every joint configuration [deg] that puts the TCP at
    the pose, each within the axis limits, the nearest to the seed first."""

    solutions: List[Six]
    raw: Dict[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "InverseKinematicsResult":
        solutions = v.get("solutions")
        if not isinstance(solutions, list):
            from .errors import ProtocolError

            raise ProtocolError("expected a list of solutions in 'solutions', got %r" % (solutions,))
        return cls(solutions=[_six(q, "solutions") for q in solutions], raw=v)


@dataclass
class AxisInfo:
    """One axis of an ``info`` result: its limits."""

    axis: int
    name: str
    min_position: float
    max_position: float
    max_velocity: float
    max_acceleration: float
    max_torque: float
    light_barrier: bool


@dataclass
class Info:
    """An ``info`` (``initialization``) result."""

    num_axes: int
    version: str
    robot: str
    cycle_time: float
    simulated: bool
    axes: List[AxisInfo]
    raw: Dict[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "Info":
        names = AxisInfo.__dataclass_fields__.keys()
        return cls(
            num_axes=int(v["num_axes"]),
            version=str(v.get("version")),
            robot=str(v.get("robot")),
            cycle_time=float(v["cycle_time"]),
            simulated=bool(v.get("simulated", False)),
            axes=[AxisInfo(**{k: a[k] for k in names}) for a in v.get("axes", [])],
            raw=v,
        )


@dataclass
class SimResult:
    """A ``sim`` result: the simulation's ground truth."""

    true_position: Six
    true_velocity: Six
    emergency_stop: bool
    raw: Dict[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "SimResult":
        return cls(
            true_position=_six(v.get("true_position"), "true_position"),
            true_velocity=_six(v.get("true_velocity"), "true_velocity"),
            emergency_stop=bool(v.get("emergency_stop", False)),
            raw=v,
        )


@dataclass
class PvtPoint:
    """One point of a ``pvt_points`` stream: positions [deg] and velocities [deg/s]."""

    position: Sequence[float]
    velocity: Sequence[float]

    def to_json(self) -> Dict[str, List[float]]:
        return {"position": [float(x) for x in self.position], "velocity": [float(x) for x in self.velocity]}


@dataclass
class Velocities:
    """Six joint velocities [deg/s]: what a control callback returns in VELOCITY_CONTROL
    (sent as ``set_velocities``; a plain sequence of six numbers is sent as torques)."""

    velocities: Sequence[float]


@dataclass
class SafetyErrorEvent:
    """A spontaneous ERROR: a safety check tripped (``check``, ``axis``, the flight-recorder
    file), the MCM shutting down, or a connection notice (``check`` None)."""

    message: str
    check: Optional[str] = None
    axis: Optional[int] = None
    flight_recorder: Optional[str] = None
    raw: Dict[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def from_json(cls, v: Dict[str, Any]) -> "SafetyErrorEvent":
        return cls(
            message=str(v.get("error_message", "")),
            check=v.get("check"),
            axis=v.get("axis"),
            flight_recorder=v.get("flight_recorder"),
            raw=v,
        )


@dataclass
class StatusEvent:
    """A spontaneous status of a torque or velocity session (every ``dt_status``, and once
    when the mode falls back to HOLD)."""

    status: Status


@dataclass
class CommandErrorEvent:
    """An ERROR of a command that has no result on success (``set_torques``,
    ``set_velocities``), delivered when it arrives."""

    command: str
    message: str
    #: Its ``error_code`` (:class:`mcm.codes.ErrorCode`); None for a code this version does
    #: not know.
    code: Optional[str] = None
    #: How it ended, the result's ``outcome`` (:class:`mcm.codes.Outcome`: ``"refused"``,
    #: ``"invalid"``, ...).
    outcome: str = "invalid"
