"""Requests into :class:`~mcm.layout.CommandSample` and replies out of
:class:`~mcm.layout.Reply`: the Python port of ``Request::encode`` (``shared/src/command.rs``)
and ``Response::decode`` (``shared/src/reply.rs``). Standard library only; the core checks
every sample again and refuses a malformed one naming the field."""

import math
from dataclasses import dataclass
from typing import List, Optional, Sequence, Union

from . import codes
from .errors import CommandError
from .layout import (
    CALIBRATE_FLAG_FORCE_STOP,
    NUM_AXES,
    PVT_FLAG_LAST,
    PVT_POINTS_PER_COMMAND,
    SIM_FLAG_POWER_CYCLE,
    TORQUE_FLAG_NO_GRAVITY,
    CommandSample,
    Reply,
)
from .types import MoveAllResult, PvtPoint

_WHICH = {"ALL": 0.0, "ELBOW": 7.0, "WRIST": 8.0}


def _six(values: Sequence[float], name: str) -> List[float]:
    v = [float(x) for x in values]
    if len(v) != NUM_AXES or not all(math.isfinite(x) for x in v):
        raise ValueError("%s: expected six finite numbers, got %r" % (name, list(values)))
    return v


def _axis(n: int, name: str) -> float:
    if not (isinstance(n, int) and 1 <= n <= NUM_AXES):
        raise ValueError("%s = %r is not allowed; expected an axis number from 1 to 6" % (name, n))
    return float(n)


def sample(kind: str, flags: int = 0, args: Sequence[float] = ()) -> CommandSample:
    """A command sample of ``kind`` (ids 0, for the sender to stamp)."""
    s = CommandSample()
    s.kind = codes.KINDS[kind]
    s.flags = flags
    for i, a in enumerate(args):
        s.args[i] = a
    return s


def calibrate(
    which: Union[str, int] = "ALL",
    elbow_direction: int = 1,
    wrist_direction: int = 1,
    force_mechanical_stop: bool = False,
) -> CommandSample:
    """``calibrate``: which is ALL, ELBOW, WRIST or an axis 1..6."""
    code = _WHICH.get(which) if isinstance(which, str) else _axis(which, "which")
    if code is None:
        raise ValueError("which = %r is not allowed; expected ALL, ELBOW, WRIST or 1 to 6" % which)
    for name, d in (("elbow_direction", elbow_direction), ("wrist_direction", wrist_direction)):
        if d not in (1, -1):
            raise ValueError("%s = %r is not allowed; expected 1 or -1" % (name, d))
    flags = CALIBRATE_FLAG_FORCE_STOP if force_mechanical_stop else 0
    return sample("calibrate", flags, [code, float(elbow_direction), float(wrist_direction)])


def torque_control(timeout: Optional[float] = 1.0, gravity_compensation: bool = True) -> CommandSample:
    """``torque_control``; ``timeout`` None or negative: no timeout."""
    t = -1.0 if timeout is None or timeout < 0 else float(timeout)
    if t == 0.0:
        raise ValueError("timeout = 0 is not allowed; expected a finite number other than 0")
    return sample("torque_control", 0 if gravity_compensation else TORQUE_FLAG_NO_GRAVITY, [t])


def velocity_control(timeout: Optional[float] = 1.0) -> CommandSample:
    """``velocity_control``; ``timeout`` None or negative: no timeout."""
    t = -1.0 if timeout is None or timeout < 0 else float(timeout)
    if t == 0.0 or not math.isfinite(t):
        raise ValueError("timeout = %r is not allowed; expected a finite number other than 0" % timeout)
    return sample("velocity_control", 0, [t])


def set_velocities(velocities: Sequence[float]) -> CommandSample:
    """``set_velocities`` [deg/s] (the core checks each against its axis's maximum)."""
    return sample("set_velocities", 0, _six(velocities, "velocities"))


def pvt(dt: float = 0.01) -> CommandSample:
    """``pvt`` with point spacing ``dt`` [s]."""
    return sample("pvt", 0, [float(dt)])


def move_axis(axis_index: int, target_position: float, velocity_factor: float = 0.33333) -> CommandSample:
    """``move_axis``."""
    return sample(
        "move_axis", 0, [_axis(axis_index, "axis_index"), float(target_position), float(velocity_factor)]
    )


def move_all(target_positions: Sequence[float], velocity_factor: float = 0.33333) -> CommandSample:
    """``move_all``."""
    return sample("move_all", 0, _six(target_positions, "target_positions") + [float(velocity_factor)])


def set_torques(torques: Sequence[float]) -> CommandSample:
    """``set_torques`` [Nm]."""
    return sample("set_torques", 0, _six(torques, "torques"))


def pvt_chunks(points: Sequence[PvtPoint]) -> List[CommandSample]:
    """A ``pvt_points`` batch as samples of up to four points, the last marked."""
    if not points:
        raise ValueError("pvt_points: expected 1 to 1000 points, got none")
    out = []
    for at in range(0, len(points), PVT_POINTS_PER_COMMAND):
        chunk = points[at : at + PVT_POINTS_PER_COMMAND]
        last = at + PVT_POINTS_PER_COMMAND >= len(points)
        args: List[float] = []
        for p in chunk:
            args += _six(p.position, "points.position") + _six(p.velocity, "points.velocity")
        out.append(sample("pvt_points", len(chunk) | (PVT_FLAG_LAST if last else 0), args))
    return out


def sim(
    emergency_stop: Optional[bool] = None,
    disconnect_axis: Optional[int] = None,
    reconnect_axis: Optional[int] = None,
    block_axis: Optional[int] = None,
    unblock_axis: Optional[int] = None,
    external_torques: Optional[Sequence[float]] = None,
    power_cycle: bool = False,
) -> CommandSample:
    """``sim``: fields left None change nothing."""
    s = sample("sim")
    if emergency_stop is not None:
        s.args[0] = 1.0 if emergency_stop else 0.0
        s.flags |= 1
    for bit, (name, axis) in enumerate(
        (
            ("disconnect_axis", disconnect_axis),
            ("reconnect_axis", reconnect_axis),
            ("block_axis", block_axis),
            ("unblock_axis", unblock_axis),
        ),
        start=1,
    ):
        if axis is not None:
            s.args[bit] = _axis(axis, name)
            s.flags |= 1 << bit
    if external_torques is not None:
        for i, t in enumerate(_six(external_torques, "external_torques")):
            s.args[5 + i] = t
        s.flags |= 1 << 5
    if power_cycle:
        s.flags |= SIM_FLAG_POWER_CYCLE
    return s


@dataclass
class Answer:
    """A decoded reply: the command answered, the cycle (``StateSample.seq``) that gave it,
    and for ``info``/``move_all`` their figures."""

    command: str
    request_id: int
    cycle: int
    move_all: Optional[MoveAllResult] = None
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
            a.move_all = MoveAllResult(v[:NUM_AXES], int(v[NUM_AXES]), v[NUM_AXES + 1])
        elif command == "info":
            a.num_axes, a.period_s = int(v[0]), v[1]
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
