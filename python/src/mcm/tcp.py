"""The JSON/TCP client (port 18010), standard library only.

One :class:`Client` is one connection; its methods are the protocol's commands under their
own names (``client.move_axis(1, 30)``) and return typed results (:mod:`mcm.types`). A
refusal raises :class:`~mcm.errors.CommandError` carrying the MCM's words. Results that come
without a command (safety errors, shutdown notices, the status ticks of a torque or velocity
session, the ERROR of a ``set_torques`` or ``set_velocities``) are kept apart and read with :meth:`Client.events` or
:meth:`Client.wait_status`.

Not thread-safe: use one client per thread.

What each command answers on success comes from the protocol's own definition of it
(:mod:`mcm.codes`, generated from ``mcm_shared::protocol::COMMANDS``): its ``result_type``
(``codes.RESULT_TYPES``), or nothing at all (``codes.NO_RESULT``: the command is sent without
waiting, and a refusal comes later as an event).

Adding a command: regenerate :mod:`mcm.codes` (see its head), then add a method that calls
``_expect`` with the protocol's name and arguments (:meth:`Client.command`, checking that the
result is of the type the protocol defines for the command) and wraps the result (``_status``
for a status result; a ``generic`` OK is checked and dropped); a command that answers nothing
on success (``codes.NO_RESULT``) calls :meth:`Client.command`; a command that starts a session
with status ticks joins ``_SESSIONS``.
"""

import collections
import json
import socket
import time
from typing import Any, Callable, Deque, Dict, List, Optional, Sequence, Union

from . import codes
from . import encoding as enc
from . import wire
from .errors import CommandError, ConnectionLost, McmTimeout, OutcomeUnknown, ProtocolError
from .types import (
    CommandErrorEvent,
    Info,
    InverseKinematicsResult,
    MoveAllResult,
    PayloadResult,
    MoveLinearResult,
    PvtPoint,
    SafetyErrorEvent,
    SimResult,
    Status,
    StatusEvent,
    Velocities,
)

#: The real robot's address (manual, "Getting started") and port.
DEFAULT_HOST = "192.168.80.203"
DEFAULT_PORT = 18010

Event = Union[SafetyErrorEvent, StatusEvent, CommandErrorEvent]


def _outcome(v: Dict[str, Any]) -> str:
    """How a command ended that the MCM did not do: the ERROR result's ``outcome``
    (:class:`mcm.codes.Outcome`), never read from its words; ``"invalid"`` from an MCM too old
    to send one."""
    outcome = codes.outcome(v)
    return outcome.value if outcome is not None else codes.Outcome.INVALID.value


# Commands whose result on success is a status result.
_STATUS_RESULT = frozenset(c for c, t in codes.RESULT_TYPES.items() if t == "status")

# Commands that start a session sending status ticks to this connection, and its mode.
_SESSIONS = {"torque_control": "TORQUE_CONTROL", "velocity_control": "VELOCITY_CONTROL"}

# The longest a command may take on top of the client's timeout (`calibrate` takes about 12 s
# on the simulated arm, the gateway itself waits up to 600 s for it; `identify_payload` under
# 30 s, the gateway waits up to 60 s).
_EXTRA_TIME = {"calibrate": 600.0, "identify_payload": 60.0}


def _given(**arguments: Any) -> Optional[Dict[str, Any]]:
    """The arguments given (not None), in order, or None when there is none: the MCM applies
    its defaults to those left out."""
    given = {k: v for k, v in arguments.items() if v is not None}
    return given or None


def _is_error(v: Dict[str, Any]) -> bool:
    return v.get("result_type") == "generic" and v.get("error_status") == "ERROR"


class Client:
    """A connection to the MCM's JSON protocol.

    Args:
        host, port: where the MCM listens (the real robot's defaults).
        timeout: longest wait for a command's result [s] (``calibrate`` and ``sleep`` get
            their own duration on top).
        reconnect: when the connection is lost, connect again at the next command (the
            command whose result was lost raises; control of the arm and a torque session
            end with the old connection, see ``docs/protocol.md``).
        secret: sent with ``authenticate`` after every (re)connect, for an MCM configured
            with a shared secret.
        connect: connect now (else at the first command).
    """

    def __init__(
        self,
        host: str = DEFAULT_HOST,
        port: int = DEFAULT_PORT,
        timeout: float = 10.0,
        reconnect: bool = True,
        secret: Optional[str] = None,
        connect: bool = True,
    ) -> None:
        self.host = host
        self.port = port
        self.timeout = timeout
        self.auto_reconnect = reconnect
        self.secret = secret
        self._sock: Optional[socket.socket] = None
        self._buf = b""
        self._events: Deque[Event] = collections.deque()
        # The mode of this connection's session with status ticks (None: no session).
        self._session: Optional[str] = None
        #: How many times this client connected.
        self.connections = 0
        #: Status ticks :meth:`control` skipped because a newer one had arrived.
        self.skipped_ticks = 0
        if connect:
            self.connect()

    # -- connection -------------------------------------------------------------------------

    def connect(self) -> None:
        """Open the connection (closing an open one first)."""
        self.close()
        try:
            sock = socket.create_connection((self.host, self.port), timeout=self.timeout)
        except OSError as e:
            raise ConnectionLost(
                "cannot connect to the MCM at %s:%d: %s" % (self.host, self.port, e)
            ) from e
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._sock = sock
        self._buf = b""
        self._session = None
        self.connections += 1
        if self.secret is not None:
            self.authenticate(self.secret)

    def reconnect(self) -> None:
        """Close the connection and open a new one."""
        self.connect()

    def close(self) -> None:
        """Close the connection (the MCM then ends this connection's control of the arm)."""
        if self._sock is not None:
            try:
                self._sock.close()
            finally:
                self._sock = None

    @property
    def connected(self) -> bool:
        """Whether the connection is open (as far as this client knows)."""
        return self._sock is not None

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def _ensure(self) -> socket.socket:
        if self._sock is None:
            if not self.auto_reconnect and self.connections > 0:
                raise ConnectionLost("the connection to the MCM is closed (reconnect=False)")
            self.connect()
        assert self._sock is not None
        return self._sock

    def _lost(self, why: str) -> ConnectionLost:
        self.close()
        return ConnectionLost(
            "connection to the MCM at %s:%d lost: %s" % (self.host, self.port, why)
        )

    # -- lines ------------------------------------------------------------------------------

    def send_raw(self, data: bytes) -> None:
        """Send bytes as they are (one command is one JSON object and a newline)."""
        sock = self._ensure()
        try:
            sock.sendall(data)
        except OSError as e:
            raise self._lost(str(e)) from e

    def _read_line(self, deadline: Optional[float]) -> Optional[Dict[str, Any]]:
        """The next result line, or None when the deadline passed (None: wait forever)."""
        sock = self._ensure()
        while b"\n" not in self._buf:
            left = None if deadline is None else deadline - time.monotonic()
            if left is not None and left <= 0:
                return None
            sock.settimeout(left)
            try:
                chunk = sock.recv(65536)
            except socket.timeout:
                return None
            except OSError as e:
                raise self._lost(str(e)) from e
            if not chunk:
                raise self._lost("closed by the MCM")
            self._buf += chunk
        line, self._buf = self._buf.split(b"\n", 1)
        try:
            v = json.loads(line.decode("ascii"))
        except (UnicodeDecodeError, ValueError) as e:
            raise ProtocolError("the MCM sent a line that is not JSON: %r" % line[:200]) from e
        if not isinstance(v, dict):
            raise ProtocolError("the MCM sent a JSON value that is not an object: %r" % v)
        return v

    def _parse_buffered(self) -> None:
        """File the complete lines already received (no waiting) as events."""
        while b"\n" in self._buf:
            v = self._read_line(None)
            if v is not None and not self._spontaneous(v, None):
                raise ProtocolError("a result came without a command: %r" % v)

    def _spontaneous(self, v: Dict[str, Any], expecting: Optional[str]) -> bool:
        """File `v` as an event when it is not the result of the command `expecting`."""
        if _is_error(v):
            msg = str(v.get("error_message", ""))
            code = codes.error_code(v)
            if "check" in v or code in codes.SPONTANEOUS:
                self._events.append(SafetyErrorEvent.from_json(v))
                if "check" in v:
                    self._session = None
                return True
            # Commands without a result on success: their refusals are events.
            name = v.get("command")
            if name in codes.NO_RESULT and expecting != name:
                self._events.append(CommandErrorEvent(str(name), msg, code, _outcome(v)))
                return True
            return False
        if v.get("result_type") == "status" and self._session is not None:
            mode = v.get("operating_mode")
            session = self._session
            if mode != session:
                self._session = None
            if expecting == "status":
                return False
            if expecting in _STATUS_RESULT and mode != session:
                # `hold`/`release`/`pvt` end the session: their result is not in the mode.
                return False
            self._events.append(StatusEvent(Status.from_json(v)))
            return True
        return False

    # -- commands ---------------------------------------------------------------------------

    def command(
        self,
        command: str,
        arguments: Optional[Dict[str, Any]] = None,
        timeout: Optional[float] = None,
        expect_result: Optional[bool] = None,
    ) -> Dict[str, Any]:
        """Send one command and return its result object; raise :class:`CommandError` for an
        ERROR result. Use this for commands this client has no method for yet.

        A command that has no result on success (``codes.NO_RESULT``: ``set_torques``,
        ``set_velocities``) is sent without waiting and returns ``{}``; ``expect_result``
        overrides that (``False``: do not wait, ``True``: wait), e.g. for a command of a newer
        MCM that this client's :mod:`mcm.codes` does not know.
        """
        msg: Dict[str, Any] = {"command": command}
        if arguments:
            msg["arguments"] = arguments
        self.send_raw((json.dumps(msg, separators=(",", ":")) + "\n").encode("ascii"))
        if expect_result is None:
            expect_result = command not in codes.NO_RESULT
        if not expect_result:
            return {}
        wait = self.timeout if timeout is None else timeout
        deadline = time.monotonic() + wait + _EXTRA_TIME.get(command, 0.0)
        while True:
            v = self._read_line(deadline)
            if v is None:
                self.close()
                raise McmTimeout(
                    "no result for `%s` within %.1f s; the connection was closed (the result "
                    "would arrive out of order); the next command connects again" % (command, wait)
                )
            if self._spontaneous(v, command):
                continue
            if _is_error(v):
                message = str(v.get("error_message", ""))
                code = codes.error_code(v)
                outcome = _outcome(v)
                name = str(v.get("command", command))
                if outcome == codes.Outcome.UNKNOWN:
                    raise OutcomeUnknown(name, message, code, outcome)
                raise CommandError(name, message, code, outcome)
            if command in _SESSIONS and v.get("operating_mode") == _SESSIONS[command]:
                self._session = _SESSIONS[command]
            return v

    def _expect(self, command: str, arguments: Optional[Dict[str, Any]] = None, **kw: Any) -> Dict[str, Any]:
        """:meth:`command`, checking that the result is of the ``result_type`` the protocol
        defines for ``command`` on success (``codes.RESULT_TYPES``)."""
        expected = codes.RESULT_TYPES[command]
        if expected is None:
            raise ValueError("`%s` answers nothing on success; send it with `command`" % command)
        v = self.command(command, arguments, **kw)
        if v.get("result_type") != expected:
            raise ProtocolError("`%s` answered %r, expected a result of type \"%s\"" % (command, v, expected))
        return v

    def _status(self, command: str, arguments: Optional[Dict[str, Any]] = None) -> Status:
        return Status.from_json(self._expect(command, arguments))

    def status(self, detail: bool = False) -> Status:
        """The mode and the axis states (with ``detail``: hardware, calibration, timing...)."""
        return self._status("status", {"detail": True} if detail else None)

    def info(self) -> Info:
        """The robot, version, cycle time and each axis's limits."""
        return Info.from_json(self._expect("info"))

    def hold(self) -> Status:
        """Enter HOLD (clears errors, powers the drives; stops any motion)."""
        return self._status("hold")

    def calibrate(
        self,
        which: Union[str, int] = enc.DEFAULT_WHICH,
        elbow_direction: int = 1,
        wrist_direction: int = 1,
        force_mechanical_stop: bool = False,
    ) -> None:
        """Home the axes; returns when the calibration has finished (about 12 s simulated)."""
        self._expect(
            "calibrate",
            {
                "which": which,
                "elbow_direction": elbow_direction,
                "wrist_direction": wrist_direction,
                "force_mechanical_stop": force_mechanical_stop,
            },
        )

    def release(self) -> Status:
        """Enter RELEASE: the arm can be moved by hand."""
        return self._status("release")

    def torque_control(
        self,
        timeout: Optional[float] = None,
        dt_status: Optional[float] = None,
        gravity_compensation: Optional[bool] = None,
    ) -> Status:
        """Enter TORQUE_CONTROL. ``timeout``: longest interval between ``set_torques`` [s]
        (negative: none); ``dt_status``: interval of the status ticks [s], read them with
        :meth:`wait_status`; ``gravity_compensation``: add the model's compensation."""
        return self._status(
            "torque_control",
            _given(timeout=timeout, dt_status=dt_status, gravity_compensation=gravity_compensation),
        )

    def set_torques(self, torques: Sequence[float]) -> None:
        """Send six joint torques [Nm]. There is no result on success, so this does not wait;
        a refusal arrives later as a :class:`CommandErrorEvent`, and is raised by the next
        ``set_torques`` (or read with :meth:`events`)."""
        self._raise_refusal("set_torques")
        self.command("set_torques", {"torques": [float(t) for t in torques]})

    def velocity_control(self, timeout: Optional[float] = None, dt_status: Optional[float] = None) -> Status:
        """Enter VELOCITY_CONTROL: every axis starts at target velocity 0. ``timeout``: longest
        interval between ``set_velocities`` [s] (negative: none; the MCM's default 1 s); without
        one the arm stops in HOLD. ``dt_status``: interval of the status ticks [s], read them
        with :meth:`wait_status`."""
        return self._status("velocity_control", _given(timeout=timeout, dt_status=dt_status))

    def set_velocities(self, velocities: Sequence[float]) -> None:
        """Send six joint velocities [deg/s], each within its axis's ``max_velocity``; the arm
        ramps to them within its acceleration and jerk limits. There is no result on success,
        so this does not wait; a refusal arrives later as a :class:`CommandErrorEvent`, and is
        raised by the next ``set_velocities`` (or read with :meth:`events`)."""
        self._raise_refusal("set_velocities")
        values = [float(v) for v in velocities]
        if len(values) != 6:
            raise ValueError("set_velocities: expected six velocities, got %d" % len(values))
        self.command("set_velocities", {"velocities": values})

    def set_cartesian_velocity(
        self, linear: Sequence[float], angular: Sequence[float], frame: str = "base"
    ) -> None:
        """Send the TCP's velocity in VELOCITY_CONTROL: ``linear`` [m/s] and ``angular``
        [deg/s], three components each, in the axes of ``frame`` (``"base"`` or ``"tool"``, the
        TCP's own). The arm follows within every axis's limits, slower along the same
        direction where an axis or a singularity needs it. No result on success, as for
        :meth:`set_velocities`: a refusal arrives later as a :class:`CommandErrorEvent`, and is
        raised by the next ``set_cartesian_velocity`` (or read with :meth:`events`)."""
        self._raise_refusal("set_cartesian_velocity")
        vectors = {"linear": wire.three(linear, "linear"), "angular": wire.three(angular, "angular")}
        self.command("set_cartesian_velocity", dict(vectors, frame=frame))

    def set_tool(
        self,
        mass: float,
        center_of_mass: Sequence[float],
        tcp_position: Sequence[float] = (0.0, 0.0, 0.0),
        tcp_orientation: Sequence[float] = (0.0, 0.0, 0.0, 1.0),
        inertia: Optional[Sequence[float]] = None,
    ) -> None:
        """Set the tool the arm carries, from the next cycle (in HOLD, or PVT at standstill):
        its ``mass`` [kg], ``center_of_mass`` [m] in the flange frame, the TCP's position [m]
        and orientation (unit quaternion ``[x, y, z, w]``) in the flange frame (default: on the
        flange), and optionally its ``inertia`` ``[ixx, iyy, izz, ixy, ixz, iyz]`` [kg m²]
        about the centre of mass (default: a point mass)."""
        arguments: Dict[str, Any] = {
            "tcp": {
                "position": [float(v) for v in tcp_position],
                "orientation": [float(v) for v in tcp_orientation],
            },
            "mass": float(mass),
            "center_of_mass": [float(v) for v in center_of_mass],
        }
        if inertia is not None:
            arguments["inertia"] = [float(v) for v in inertia]
        self._expect("set_tool", arguments)

    def identify_payload(self, apply: bool = False) -> PayloadResult:
        """Estimate the load on the flange (in HOLD, at rest, calibrated): the arm moves through
        a few poses and back (under 30 s), measuring the holding torques; the result gives the
        ``mass`` [kg], ``center_of_mass`` [m] in the flange frame and the ``residual`` [N m].
        With ``apply`` the estimate becomes the tool's mass and centre of mass."""
        return PayloadResult.from_json(self._expect("identify_payload", {"apply": bool(apply)}))

    def _raise_refusal(self, command: str) -> None:
        """Raise the first queued refusal of `command` (one without a result on success)."""
        for i, e in enumerate(self._events):
            if isinstance(e, CommandErrorEvent) and e.command == command:
                del self._events[i]
                raise CommandError(command, e.message, e.code, e.outcome)

    def pvt(self, dt: Optional[float] = None) -> Status:
        """Enter PVT mode; ``dt`` is the spacing of the ``pvt_points`` points [s]."""
        return self._status("pvt", _given(dt=dt))

    def move_axis(
        self, axis_index: int, target_position: float, velocity_factor: Optional[float] = None
    ) -> None:
        """Move one axis (1..6) to a target [deg]; returns as the motion starts."""
        self._expect(
            "move_axis",
            _given(axis_index=axis_index, target_position=target_position, velocity_factor=velocity_factor),
        )

    def move_all(
        self, target_positions: Sequence[float], velocity_factor: Optional[float] = None
    ) -> MoveAllResult:
        """Move all axes to their targets [deg], starting and arriving together."""
        targets = [float(x) for x in target_positions]
        args = _given(target_positions=targets, velocity_factor=velocity_factor)
        return MoveAllResult.from_json(self._expect("move_all", args))

    def move_to_pose(
        self,
        position: Sequence[float],
        orientation: Sequence[float],
        velocity_factor: Optional[float] = None,
    ) -> MoveAllResult:
        """Move the TCP to ``position`` [m] and ``orientation`` (a unit quaternion x, y, z, w)
        in the base frame: a joint move, as ``move_all``, to the inverse kinematics' solution
        nearest the present position (PVT mode)."""
        args = _given(
            position=[float(x) for x in position],
            orientation=[float(x) for x in orientation],
            velocity_factor=velocity_factor,
        )
        return MoveAllResult.from_json(self._expect("move_to_pose", args))

    def move_linear(
        self,
        position: Sequence[float],
        orientation: Optional[Sequence[float]] = None,
        velocity: Optional[float] = None,
        acceleration: Optional[float] = None,
    ) -> MoveLinearResult:
        """Move the TCP on a straight line to ``position`` [m], turning on the shortest arc to
        ``orientation`` (a unit quaternion x, y, z, w; None: kept), at most at ``velocity``
        [m/s] and ``acceleration`` [m/s²] (None: 0.25 and 1.2), base frame (PVT mode).
        Answered once the whole path is checked; a path the arm cannot follow raises
        :class:`CommandError` (``unreachable``, ``out_of_range``) and nothing moves."""
        args = _given(
            position=[float(x) for x in position],
            orientation=[float(x) for x in orientation] if orientation is not None else None,
            velocity=velocity,
            acceleration=acceleration,
        )
        return MoveLinearResult.from_json(self._expect("move_linear", args))

    def inverse_kinematics(
        self,
        position: Sequence[float],
        orientation: Sequence[float],
        seed: Optional[Sequence[float]] = None,
    ) -> InverseKinematicsResult:
        """Every joint configuration [deg] that puts the TCP at ``position`` [m] and
        ``orientation`` (a unit quaternion x, y, z, w), the nearest to ``seed`` [deg] (default:
        the present position) first. Nothing moves."""
        args = _given(
            position=[float(x) for x in position],
            orientation=[float(x) for x in orientation],
            seed=[float(x) for x in seed] if seed is not None else None,
        )
        return InverseKinematicsResult.from_json(self._expect("inverse_kinematics", args))

    def pvt_points(self, points: Sequence[Union[PvtPoint, Dict[str, Any]]]) -> None:
        """Queue 1 to 1000 points (all or none)."""
        pts = [p.to_json() if isinstance(p, PvtPoint) else p for p in points]
        self._expect("pvt_points", {"points": pts})

    def sleep(self, duration: float) -> None:
        """Delay this connection's next command by ``duration`` seconds (on the MCM)."""
        self._expect("sleep", {"duration": duration}, timeout=self.timeout + duration)

    def sim(
        self,
        emergency_stop: Optional[bool] = None,
        disconnect_axis: Optional[int] = None,
        reconnect_axis: Optional[int] = None,
        block_axis: Optional[int] = None,
        unblock_axis: Optional[int] = None,
        external_torques: Optional[Sequence[float]] = None,
        power_cycle: Optional[bool] = None,
    ) -> SimResult:
        """Fault injection into the simulated robot; returns the ground truth."""
        args = _given(
            emergency_stop=emergency_stop,
            disconnect_axis=disconnect_axis,
            reconnect_axis=reconnect_axis,
            block_axis=block_axis,
            unblock_axis=unblock_axis,
            external_torques=list(external_torques) if external_torques else None,
            power_cycle=power_cycle,
        )
        return SimResult.from_json(self._expect("sim", args))

    def take_control(self) -> None:
        """Become the client that controls the arm's motion."""
        self._expect("take_control")

    def release_control(self) -> None:
        """Give up control of the arm (its motion ends in HOLD)."""
        self._expect("release_control")

    def authenticate(self, secret: str) -> None:
        """Present the shared secret of an MCM that requires one."""
        self._expect("authenticate", {"secret": secret})

    # -- spontaneous results ----------------------------------------------------------------

    def events(self, timeout: float = 0.0) -> List[Event]:
        """The spontaneous results received so far, oldest first; waits up to ``timeout``
        seconds for the first one when there is none yet."""
        if not self._events and self._sock is not None:
            deadline = time.monotonic() + timeout
            while not self._events:
                v = self._read_line(deadline)
                if v is None:
                    break
                if not self._spontaneous(v, None):
                    raise ProtocolError("a result came without a command: %r" % v)
        out = list(self._events)
        self._events.clear()
        return out

    def wait_status(self, timeout: Optional[float] = None) -> Status:
        """The next status tick of the torque or velocity session this connection started
        (other events stay queued for :meth:`events`)."""
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        while True:
            for i, e in enumerate(self._events):
                if isinstance(e, StatusEvent):
                    del self._events[i]
                    return e.status
            v = self._read_line(deadline)
            if v is None:
                raise McmTimeout("no status tick within the timeout")
            if not self._spontaneous(v, None):
                raise ProtocolError("a result came without a command: %r" % v)

    def control(
        self,
        callback: Callable[[Status], Union[Sequence[float], Velocities, None]],
        timeout: Optional[float] = None,
    ) -> int:
        """Run a control loop on the status ticks: ``callback(status)`` returns six torques to
        send (TORQUE_CONTROL), :class:`~mcm.types.Velocities` (sent as ``set_velocities``,
        VELOCITY_CONTROL), or None to end. Enter the mode with ``dt_status`` first; the loop
        ends (returns) too when a tick is no longer in a session's mode. Returns the number of
        ticks answered; ticks that queued up while the callback ran are skipped (counted in
        ``skipped_ticks``). A safety error ends the loop with :class:`CommandError`."""
        n = 0
        while True:
            s = self.wait_status(timeout)
            # Answer the newest state: ticks that queued up meanwhile are skipped, not answered.
            self._parse_buffered()
            for i in reversed(range(len(self._events))):
                e = self._events[i]
                if isinstance(e, StatusEvent):
                    s = e.status
                    self.skipped_ticks += sum(isinstance(x, StatusEvent) for x in self._events)
                    self._events = collections.deque(x for x in self._events if not isinstance(x, StatusEvent))
                    break
            sends = "set_velocities" if s.operating_mode == "VELOCITY_CONTROL" else "set_torques"
            for e in self._events:
                if isinstance(e, SafetyErrorEvent) and e.check:
                    raise CommandError(sends, e.message, e.check, "failed")
            out = callback(s)
            if out is None or s.operating_mode not in _SESSIONS.values():
                return n
            if isinstance(out, Velocities):
                self.set_velocities(out.velocities)
            else:
                self.set_torques(out)
            n += 1
