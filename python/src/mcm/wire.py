"""Requests into :class:`~mcm.layout.CommandSample` and replies out of
:class:`~mcm.layout.Reply`: the Python port of ``Request::encode`` (``shared/src/command.rs``)
and ``Response::decode`` (``shared/src/reply.rs``). Where each argument goes, the values some
travel as and the defaults come from :mod:`mcm.encoding`, generated from the Rust contract.
Standard library only; the core checks every sample again and refuses a malformed one naming
the field."""

import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Union

from . import codes
from . import encoding as enc
from .errors import CommandError
from .layout import (
    CALIBRATE_FLAG_FORCE_STOP,
    IDENTIFY_FLAG_APPLY,
    NUM_AXES,
    PVT_FLAG_LAST,
    PVT_POINTS_PER_COMMAND,
    SIM_FLAG_POWER_CYCLE,
    TORQUE_FLAG_NO_GRAVITY,
    CommandSample,
    Reply,
)
from .types import MoveAllResult, MoveLinearResult, PayloadResult, PvtPoint

Value = Union[float, Sequence[float]]


def _six(values: Sequence[float], name: str) -> List[float]:
    v = [float(x) for x in values]
    if len(v) != NUM_AXES or not all(math.isfinite(x) for x in v):
        raise ValueError("%s: expected six finite numbers, got %r" % (name, list(values)))
    return v


def three(values: Sequence[float], name: str) -> List[float]:
    """A Cartesian vector's three finite numbers (``name`` for the error)."""
    v = [float(x) for x in values]
    if len(v) != 3 or not all(math.isfinite(x) for x in v):
        raise ValueError("%s: expected three finite numbers, got %r" % (name, list(values)))
    return v


def _axis(n: int, name: str) -> float:
    if not (isinstance(n, int) and 1 <= n <= NUM_AXES):
        raise ValueError("%s = %r is not allowed; expected an axis number from 1 to 6" % (name, n))
    return float(n)


def _timeout(timeout: Optional[float]) -> float:
    """A mode's ``timeout`` as it travels: None or negative is no timeout; 0 is refused."""
    t = enc.NO_TIMEOUT if timeout is None or timeout < 0 else float(timeout)
    if t == 0.0 or not math.isfinite(t):
        raise ValueError("timeout = %r is not allowed; expected a finite number other than 0" % timeout)
    return t


def sample(kind: str, flags: int = 0, args: Sequence[float] = ()) -> CommandSample:
    """A command sample of ``kind`` (ids 0, for the sender to stamp)."""
    s = CommandSample()
    s.kind = codes.KINDS[kind]
    s.flags = flags
    for i, a in enumerate(args):
        s.args[i] = a
    return s


def _put(s: CommandSample, kind: str, name: str, value: Value) -> None:
    """Argument ``name`` of ``kind`` into its place (``encoding.ARGS``)."""
    at = enc.ARGS[kind][name]
    values = [value] if isinstance(value, (int, float)) else list(value)
    for i, v in enumerate(values):
        s.args[at + i] = float(v)


def command(kind: str, flags: int = 0, **args: Value) -> CommandSample:
    """A command sample of ``kind`` with its arguments by protocol name, each in its place."""
    s = sample(kind, flags)
    for name, value in args.items():
        _put(s, kind, name, value)
    return s


def calibrate(
    which: Union[str, int] = enc.DEFAULT_WHICH,
    elbow_direction: int = 1,
    wrist_direction: int = 1,
    force_mechanical_stop: bool = False,
) -> CommandSample:
    """``calibrate``: which is ALL, ELBOW, WRIST or an axis 1..6."""
    code = enc.CALIBRATE_WHICH.get(which) if isinstance(which, str) else _axis(which, "which")
    if code is None:
        raise ValueError(
            "which = %r is not allowed; expected %s or 1 to 6" % (which, ", ".join(enc.CALIBRATE_WHICH))
        )
    for name, d in (("elbow_direction", elbow_direction), ("wrist_direction", wrist_direction)):
        if d not in enc.DIRECTIONS:
            raise ValueError("%s = %r is not allowed; expected 1 or -1" % (name, d))
    return command(
        "calibrate",
        CALIBRATE_FLAG_FORCE_STOP if force_mechanical_stop else 0,
        which=code,
        elbow_direction=elbow_direction,
        wrist_direction=wrist_direction,
    )


def identify_payload(apply: bool = False) -> CommandSample:
    """``identify_payload``; with ``apply`` the estimate becomes the tool's load."""
    return command("identify_payload", IDENTIFY_FLAG_APPLY if apply else 0)


def torque_control(
    timeout: Optional[float] = enc.DEFAULT_MODE_TIMEOUT, gravity_compensation: bool = True
) -> CommandSample:
    """``torque_control``; ``timeout`` None or negative: no timeout."""
    flags = 0 if gravity_compensation else TORQUE_FLAG_NO_GRAVITY
    return command("torque_control", flags, timeout=_timeout(timeout))


def velocity_control(timeout: Optional[float] = enc.DEFAULT_MODE_TIMEOUT) -> CommandSample:
    """``velocity_control``; ``timeout`` None or negative: no timeout."""
    return command("velocity_control", timeout=_timeout(timeout))


def set_velocities(velocities: Sequence[float]) -> CommandSample:
    """``set_velocities`` [deg/s] (the core checks each against its axis's maximum)."""
    return command("set_velocities", velocities=_six(velocities, "velocities"))


def set_cartesian_velocity(
    linear: Sequence[float], angular: Sequence[float], frame: str = "base"
) -> CommandSample:
    """``set_cartesian_velocity``: the TCP's ``linear`` [m/s] and ``angular`` [deg/s] velocity
    in the axes of ``frame`` (``base`` or ``tool``); the core checks each component's range."""
    code = enc.CARTESIAN_FRAMES.get(frame)
    if code is None:
        raise ValueError(
            "frame = %r is not allowed; expected %s" % (frame, " or ".join(enc.CARTESIAN_FRAMES))
        )
    return command(
        "set_cartesian_velocity",
        linear=three(linear, "linear"),
        angular=three(angular, "angular"),
        frame=code,
    )


def set_tool(
    tcp: Dict[str, Sequence[float]],
    mass: float,
    center_of_mass: Sequence[float],
    inertia: Optional[Sequence[float]] = None,
) -> CommandSample:
    """``set_tool``: ``tcp`` ``{"position": [3 m], "orientation": [x, y, z, w]}`` in the flange
    frame, ``mass`` [kg], ``center_of_mass`` [m], ``inertia`` ``[ixx, iyy, izz, ixy, ixz, iyz]``
    [kg m²] (None: a point mass). The core checks the values as the gateway does."""
    position, orientation = list(tcp["position"]), list(tcp["orientation"])
    if len(position) != 3 or len(orientation) != 4 or len(center_of_mass) != 3:
        raise ValueError("set_tool: tcp.position and center_of_mass take 3 numbers, tcp.orientation 4")
    moments = [0.0] * 6 if inertia is None else list(inertia)
    if len(moments) != 6:
        raise ValueError("set_tool: inertia takes 6 numbers, got %d" % len(moments))
    return command(
        "set_tool",
        tcp=position + orientation,
        mass=mass,
        center_of_mass=center_of_mass,
        inertia=moments,
    )


def pvt(dt: float = enc.DEFAULT_PVT_DT) -> CommandSample:
    """``pvt`` with point spacing ``dt`` [s]."""
    return command("pvt", dt=float(dt))


def move_axis(
    axis_index: int, target_position: float, velocity_factor: float = enc.DEFAULT_VELOCITY_FACTOR
) -> CommandSample:
    """``move_axis``."""
    return command(
        "move_axis",
        axis_index=_axis(axis_index, "axis_index"),
        target_position=float(target_position),
        velocity_factor=float(velocity_factor),
    )


def move_all(
    target_positions: Sequence[float], velocity_factor: float = enc.DEFAULT_VELOCITY_FACTOR
) -> CommandSample:
    """``move_all``."""
    return command(
        "move_all",
        target_positions=_six(target_positions, "target_positions"),
        velocity_factor=float(velocity_factor),
    )


def move_linear(
    position: Sequence[float],
    orientation: Optional[Sequence[float]] = None,
    velocity: Optional[float] = None,
    acceleration: Optional[float] = None,
) -> CommandSample:
    """``move_linear``: ``position`` [m], ``orientation`` a unit quaternion x, y, z, w (None:
    kept), ``velocity`` [m/s], ``acceleration`` [m/s²] (None: the core's defaults). The core
    checks the values as the gateway does."""
    if len(position) != 3 or (orientation is not None and len(orientation) != 4):
        raise ValueError("move_linear: position takes 3 numbers, orientation 4")
    given: Dict[str, Value] = {"position": [float(x) for x in position]}
    flags = 0
    if orientation is not None:
        given["orientation"] = [float(x) for x in orientation]
        flags |= enc.MOVE_LINEAR_FLAGS["orientation"]
    for name, x in (("velocity", velocity), ("acceleration", acceleration)):
        if x is not None:
            given[name] = float(x)
            flags |= enc.MOVE_LINEAR_FLAGS[name]
    return command("move_linear", flags, **given)


def set_torques(torques: Sequence[float]) -> CommandSample:
    """``set_torques`` [Nm]."""
    return command("set_torques", torques=_six(torques, "torques"))


def pvt_chunks(points: Sequence[PvtPoint]) -> List[CommandSample]:
    """A ``pvt_points`` batch as samples of up to four points, the last marked."""
    if not 1 <= len(points) <= enc.MAX_POINTS_PER_BATCH:
        raise ValueError(
            "pvt_points: expected 1 to %d points, got %d" % (enc.MAX_POINTS_PER_BATCH, len(points))
        )
    out = []
    for at in range(0, len(points), PVT_POINTS_PER_COMMAND):
        chunk = points[at : at + PVT_POINTS_PER_COMMAND]
        last = at + PVT_POINTS_PER_COMMAND >= len(points)
        s = sample("pvt_points", len(chunk) | (PVT_FLAG_LAST if last else 0))
        for j, p in enumerate(chunk):
            for start, values in (
                (enc.PVT_POINT_POSITION, _six(p.position, "points.position")),
                (enc.PVT_POINT_VELOCITY, _six(p.velocity, "points.velocity")),
            ):
                for i, v in enumerate(values):
                    s.args[enc.PVT_POINT_ARGS * j + start + i] = v
        out.append(s)
    return out


def sim(
    emergency_stop: Optional[bool] = None,
    disconnect_axis: Optional[int] = None,
    reconnect_axis: Optional[int] = None,
    block_axis: Optional[int] = None,
    unblock_axis: Optional[int] = None,
    external_torques: Optional[Sequence[float]] = None,
    power_cycle: bool = False,
    true_tool: Optional[Dict[str, Union[float, Sequence[float]]]] = None,
) -> CommandSample:
    """``sim``: fields left None change nothing. ``true_tool`` ``{"mass": kg,
    "center_of_mass": [3 m]}`` is the load the simulated arm really carries (the core checks
    it as a tool's load)."""
    given: Dict[str, Value] = {}
    if emergency_stop is not None:
        given["emergency_stop"] = enc.EMERGENCY_STOP[bool(emergency_stop)]
    for name, axis in (
        ("disconnect_axis", disconnect_axis),
        ("reconnect_axis", reconnect_axis),
        ("block_axis", block_axis),
        ("unblock_axis", unblock_axis),
    ):
        if axis is not None:
            given[name] = _axis(axis, name)
    if external_torques is not None:
        given["external_torques"] = _six(external_torques, "external_torques")
    if true_tool is not None:
        com = list(true_tool["center_of_mass"])  # type: ignore[arg-type]
        if len(com) != 3:
            raise ValueError("sim: true_tool.center_of_mass takes 3 numbers, got %d" % len(com))
        given["true_tool"] = [float(true_tool["mass"])] + [float(c) for c in com]  # type: ignore[arg-type]
    flags = SIM_FLAG_POWER_CYCLE if power_cycle else 0
    for name in given:
        flags |= enc.SIM_FLAGS[name]
    return command("sim", flags, **given)


@dataclass
class Answer:
    """A decoded reply: the command answered, the cycle (``StateSample.seq``) that gave it,
    and for ``info``/``move_all``/``identify_payload`` their figures."""

    command: str
    request_id: int
    cycle: int
    move_all: Optional[MoveAllResult] = None
    payload: Optional[PayloadResult] = None
    move_linear: Optional[MoveLinearResult] = None
    num_axes: Optional[int] = None
    period_s: Optional[float] = None


def decode_reply(r: Reply) -> Answer:
    """The answer a reply stands for; raise :class:`CommandError` for a refusal or failure
    (its message in the gateway's words: ``<command> refused: <reason>``)."""
    command = codes.KIND_NAMES.get(r.kind, "kind %d" % r.kind)
    if r.status == codes.REPLY_OK:
        a = Answer(command, r.request_id, r.cycle)
        v = list(r.values)
        if command == "move_all":
            m = enc.MOVE_ALL_VALUES
            at = m["velocities_deg_s"]
            a.move_all = MoveAllResult(v[at : at + NUM_AXES], int(v[m["longest"]]), v[m["duration_s"]])
        elif command == "identify_payload":
            p = enc.PAYLOAD_VALUES
            at = p["center_of_mass_m"]
            a.payload = PayloadResult(v[p["mass_kg"]], v[at : at + 3], v[p["residual_nm"]])
        elif command == "move_linear":
            m = enc.MOVE_LINEAR_VALUES
            at = m["joint_target_deg"]
            a.move_linear = MoveLinearResult(v[m["duration_s"]], v[at : at + NUM_AXES])
        elif command == "info":
            i = enc.INFO_VALUES
            a.num_axes, a.period_s = int(v[i["num_axes"]]), v[i["period_s"]]
        return a
    outcome = "failed" if r.status == codes.REPLY_FAILED else "refused"
    text = codes.reason_text(r.code, r.axis, list(r.values)[:4])
    name = codes.REJECT_CODES.get(r.code, str(r.code))
    raise CommandError(
        command,
        "%s %s: %s" % (command, outcome, text),
        codes.error_code({"error_code": name}) or name,
        outcome,
    )
