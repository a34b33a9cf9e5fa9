"""Wire codes shared with the Rust core (``shared/src/mode.rs``): operating modes, command
kinds, reply statuses and reject codes, and the words the core's refusals use
(``shared/src/reply.rs``, ``Reason``'s ``Display``)."""

from decimal import Decimal
from typing import Dict, Optional, Sequence, Tuple

#: Operating modes by wire value.
MODES: Dict[int, str] = {
    0: "OFF",
    1: "ERROR",
    2: "HOLD",
    3: "RELEASE",
    4: "TORQUE_CONTROL",
    5: "PVT",
    6: "CALIBRATION",
    7: "VELOCITY_CONTROL",
}

#: Command kinds by protocol name (``CommandSample.kind``).
KINDS: Dict[str, int] = {
    "status": 1,
    "hold": 2,
    "info": 3,
    "calibrate": 4,
    "release": 5,
    "torque_control": 6,
    "pvt": 7,
    "move_axis": 8,
    "move_all": 9,
    "pvt_points": 10,
    "set_torques": 11,
    "sim": 12,
    "take_control": 13,
    "release_control": 14,
    "client_gone": 15,
    "velocity_control": 16,
    "set_velocities": 17,
}
KIND_NAMES: Dict[int, str] = {v: k for k, v in KINDS.items()}

#: Commands only the client that controls the arm may send (``CommandKind::needs_control``).
NEEDS_CONTROL = frozenset(
    [
        "calibrate",
        "release",
        "torque_control",
        "pvt",
        "move_axis",
        "move_all",
        "pvt_points",
        "set_torques",
        "velocity_control",
        "set_velocities",
    ]
)

#: ``Reply.status`` values.
REPLY_OK = 0
REPLY_REJECTED = 1
REPLY_FAILED = 2

#: Reject codes by wire value (``RejectCode``); also the ``check`` of a safety error.
REJECT_CODES: Dict[int, str] = {
    0: "none",
    1: "wrong_mode",
    2: "not_calibrated",
    3: "emergency_stop",
    4: "drive_disconnected",
    5: "drive_fault",
    6: "out_of_range",
    7: "not_available",
    8: "not_simulated",
    9: "queue_full",
    10: "position_limit",
    11: "velocity_limit",
    12: "braking_distance",
    13: "following_error",
    14: "calibration_failed",
    15: "aborted",
    16: "busy",
    17: "pvt_point",
    18: "unreachable",
    19: "not_owner",
    20: "shutting_down",
}

_PVT_QUANTITY = {1: ("position", "deg"), 2: ("velocity", "deg/s"), 3: ("acceleration", "deg/s^2")}


def num(x: float) -> str:
    """A number as the MCM writes it in messages (``mcm_shared::ranges::Num``): at most 12
    significant digits, an exponent below 1e-5 and from 1e15 on (``1e-320``), ``0`` for zero."""
    x = float(x)
    if x == 0.0:
        return "0"
    if x != x:
        return "NaN"
    if x in (float("inf"), float("-inf")):
        return "inf" if x > 0 else "-inf"
    y = float("%.11e" % x)
    d = Decimal(repr(y))
    if 1e-5 <= abs(y) < 1e15:
        out = format(d, "f")
        if "." in out:
            out = out.rstrip("0").rstrip(".")
        return out
    sign, digits, exponent = d.as_tuple()
    text = "".join(str(k) for k in digits).rstrip("0") or "0"
    exp = int(exponent) + len(digits) - 1
    mantissa = text[0] + ("." + text[1:] if len(text) > 1 else "")
    return "%s%se%d" % ("-" if sign else "", mantissa, exp)


def _g(x: float) -> str:
    """A number as Rust's ``{}`` prints an f64 (``1`` for 1.0, ``0.5``)."""
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e16 else repr(float(x))


# The numeric arguments of the protocol (``mcm_shared::ranges::ARGS``): wire code -> (name,
# shape, unit, note, one element per axis). An argument refusal carries the code in its fourth
# value; the layout check compares the words with the Rust ones for every row.
ARGS: Dict[int, Tuple[str, str, str, str, bool]] = {
    1: ("axis_index", "axis", "", "", False),
    2: ("target_position", "range", "deg", "the axis's reachable range: its limits less the safety margin", False),
    3: ("target_positions", "range", "deg", "the axis's reachable range: its limits less the safety margin", True),
    4: ("velocity_factor", "range", "", "a fraction of each axis's maximum velocity", False),
    5: ("dt", "range", "s", "at least one cycle", False),
    6: ("timeout", "nonzero_up_to", "s", "negative: no timeout", False),
    7: ("dt_status", "range", "s", "0: no status results", False),
    8: ("torques", "range", "Nm", "the axis's peak joint torque", True),
    9: ("duration", "range", "s", "", False),
    10: ("external_torques", "range", "Nm", "", True),
    11: ("disconnect_axis", "axis", "", "", False),
    12: ("reconnect_axis", "axis", "", "", False),
    13: ("block_axis", "axis", "", "", False),
    14: ("unblock_axis", "axis", "", "", False),
    15: ("velocities", "range", "deg/s", "the axis's maximum velocity", True),
}


def argument_text(arg: int, axis: int, value: float, lo: float, hi: float) -> str:
    """The words of an argument refusal (``ArgRefusal``'s), as gateway and core give them."""
    name, shape, unit, note, per_axis = ARGS.get(arg, ("argument %d" % arg, "range", "", "", False))
    label = '"%s[%d]"' % (name, axis - 1) if per_axis and axis else '"%s"' % name
    if shape == "axis":
        expected = "an axis number from %s to %s" % (num(lo), num(hi))
    elif shape == "nonzero_up_to":
        expected = "a number other than 0, at most %s" % num(hi)
    else:
        expected = "a number from %s to %s" % (num(lo), num(hi))
    if unit:
        expected += " " + unit
    if note:
        expected += " (%s)" % note
    return "argument %s = %s is not allowed; expected %s" % (label, num(value), expected)


def reason_text(code: int, axis: int, v: Sequence[float]) -> str:
    """The words for a refusal, failure or safety trip, as the core's ``Reason`` gives them."""
    name = REJECT_CODES.get(code)
    if name == "wrong_mode":
        return "not allowed in mode %s" % MODES.get(int(v[0]), "?")
    if name == "not_calibrated":
        return "axis %d is not calibrated; run `calibrate` first" % axis
    if name == "emergency_stop":
        return "the emergency stop is pressed; release it, then send `hold`"
    if name == "drive_disconnected":
        lost = (int(v[0]) & ~(1 << (axis - 1))) | (1 << (axis - 1)) if axis else 0
        axes = [str(i + 1) for i in range(6) if lost & (1 << i)]
        if len(axes) <= 1:
            return "the drive of axis %d does not answer on the bus" % axis
        return "the drives of axes %s and %s do not answer on the bus" % (
            ", ".join(axes[:-1]),
            axes[-1],
        )
    if name == "drive_fault":
        if axis:
            return "the drive of axis %d is in fault (error code 0x%04X)" % (axis, int(v[0]))
        return "a drive is in fault (error code 0x%04X)" % int(v[0])
    if name == "out_of_range" and int(v[3]) != 0:
        return argument_text(int(v[3]), axis, v[0], v[1], v[2])
    if name == "out_of_range":
        prefix = "axis %d: " % axis if axis else ""
        return "%svalue %s is outside the allowed range [%s, %s]" % (
            prefix,
            _g(v[0]),
            _g(v[1]),
            _g(v[2]),
        )
    if name == "not_available":
        return "not available yet in this MCM version"
    if name == "not_simulated":
        return "only available when the simulated robot is running"
    if name == "queue_full":
        return "queue full: %d points offered, %d places free; nothing was queued" % (
            int(v[0]),
            int(v[1]),
        )
    if name == "position_limit":
        return "position limit: axis %d at %.3f deg, limit %.3f deg" % (axis, v[0], v[1])
    if name == "velocity_limit":
        return "velocity limit: axis %d at %.3f deg/s, limit %.3f deg/s" % (axis, v[0], v[1])
    if name == "braking_distance":
        return "braking distance: axis %d would stop at %.3f deg, beyond the limit %.3f deg" % (
            axis,
            v[0],
            v[1],
        )
    if name == "following_error":
        return (
            "following error: axis %d is %.3f deg away from its commanded position, "
            "band %.3f deg" % (axis, v[0], v[1])
        )
    if name == "calibration_failed":
        cause = int(v[0])
        if cause == 1:
            what = "no mechanical stop found within %.1f deg; the arm holds where it is" % v[1]
        elif cause == 2:
            what = "no light-barrier edge found within %.1f deg; the arm holds where it is" % v[1]
        elif cause == 4:
            what = (
                "its reference was found at %.3f deg (the configured position), then at %.3f "
                "deg by the next approach, more than the tolerance %.3f deg apart (a contact in "
                "free air, or a stop that gives way); the arm holds where it is, its previous "
                "calibration is kept" % (v[1], v[2], v[3])
            )
            return "calibration of axis %d failed: %s" % (axis, what)
        elif cause == 5:
            what = (
                "its reference was found at %.3f deg by its previous calibration, configured "
                "at %.3f deg, more than the tolerance %.3f deg apart (an obstacle in the way, or "
                "the stop is not where the configuration says); the arm holds where it is, its "
                "previous calibration is kept" % (v[1], v[2], v[3])
            )
            return "calibration of axis %d failed: %s" % (axis, what)
        else:
            what = "its drive stopped answering"
        return "calibration of axis %d failed: %s" % (axis, what)
    if name == "aborted":
        return "aborted (superseded by another command or a mode change)"
    if name == "busy":
        return (
            "a motion is in progress (%.3f s left); wait until it ends, or send `hold` to stop it"
            % v[0]
        )
    if name == "pvt_point":
        what, unit = _PVT_QUANTITY.get(int(v[1]), ("value", ""))
        return "point %d: axis %d %s %s %s exceeds the limit %s %s; nothing was queued" % (
            int(v[0]),
            axis,
            what,
            num(v[2]),
            unit,
            num(v[3]),
            unit,
        )
    if name == "unreachable":
        return (
            "axis %d: target %s deg is not allowed; expected a number from %s to %s deg "
            "(the axis's reachable range: its limits less the safety margin)"
            % (axis, num(v[0]), num(v[1]), num(v[2]))
        )
    if name == "not_owner":
        owner = (int(v[0]) << 32) | int(v[1])
        return (
            "another client (id %#x) controls the arm; only `hold` and state reads are open to "
            "others until it releases control or disconnects" % owner
        )
    if name == "shutting_down":
        return "the MCM is shutting down: the arm is being stopped and its drives disabled"
    return "reason code %d is not known to this client version" % code


# Fragments of the gateway's refusal words, in the order they are tried, and the reject code
# each stands for. The JSON protocol's ERROR results carry words only (and `check` for safety
# errors); the TCP client gives the code it recognises here, or None. The layout check
# (`tests/python_layout.rs`) reads every reason's words from the core back through this table.
_CODE_FRAGMENTS: Tuple[Tuple[str, str], ...] = (
    ("no reply from the real-time core", "outcome_unknown"),
    ("safety check tripped", "safety"),
    ("is controlled by", "not_owner"),
    ("another client (id", "not_owner"),
    ("not allowed in mode", "wrong_mode"),
    ("is not calibrated", "not_calibrated"),
    ("emergency stop is pressed", "emergency_stop"),
    ("does not answer on the bus", "drive_disconnected"),
    ("do not answer on the bus", "drive_disconnected"),
    ("is in fault", "drive_fault"),
    ("position limit:", "position_limit"),
    ("velocity limit:", "velocity_limit"),
    ("braking distance:", "braking_distance"),
    ("following error:", "following_error"),
    ("queue full", "queue_full"),
    ("exceeds the limit", "pvt_point"),
    ("outside the reachable range", "unreachable"),
    (" deg is not allowed; expected a number from", "unreachable"),
    ("a motion is in progress", "busy"),
    ("calibration of axis", "calibration_failed"),
    ("aborted", "aborted"),
    ("only available when the simulated robot", "not_simulated"),
    ("not available yet", "not_available"),
    ("shutting down", "shutting_down"),
    ("outside the allowed range", "out_of_range"),
    ("is not allowed", "invalid_argument"),
    ("unknown command", "invalid_argument"),
    ("invalid JSON", "invalid_argument"),
    ("requires the shared secret", "not_authenticated"),
    ("the secret is wrong", "wrong_secret"),
    ("are not accepted from", "network"),
)


def code_from_message(message: str) -> Optional[str]:
    """The reject code an ERROR result's words stand for, or None when not recognised."""
    for fragment, code in _CODE_FRAGMENTS:
        if fragment in message:
            return code
    return None
