"""The shared-memory client for controllers on the robot computer (``pip install mcm[shm]``,
the official ``iceoryx2`` package, exactly version 0.10.0 like the MCM itself).

It opens the services of one MCM instance (``shared/src/service.rs``):

- ``mcm/<i>/state``: a blackboard with key type ``u32``: key 0 the :class:`~mcm.layout.StateSample`
  (``mcm.StateSample.v7``), keys 1 to 512 the :class:`~mcm.layout.ReplyBlock` s
  (``mcm.ReplyBlock.v1``) holding the core's answers;
- ``mcm/<i>/state-ready``: the event mcm-rt notifies (id 1) after every new state, so
  :meth:`ShmClient.wait_state` blocks until the next cycle instead of spinning;
- ``mcm/<i>/command``: publish-subscribe of :class:`~mcm.layout.CommandSample`
  (``mcm.CommandSample.v1``).

Commands carry this client's id, ``(pid << 32) | n`` like the gateway's connections, and an
increasing request id; only replies with this client's id are taken. The arm is controlled by
one client at a time, as over TCP (``docs/protocol.md``, "Control of the arm and access").
"""

import ctypes
import itertools
import os
import time
from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Optional, Sequence, Union

from . import codes, wire
from . import encoding as enc
from .errors import CommandError, McmTimeout, OutcomeUnknown, ShmUnavailable
from .layout import (
    PVT_POINTS_PER_COMMAND,
    REPLY_BLOCK,
    REPLY_BLOCKS,
    STATE_EVENT_ID,
    STATE_KEY,
    CommandSample,
    Reply,
    ReplyBlock,
    StateSample,
    reply_location,
)
from .types import MoveAllResult, MoveLinearResult, PayloadResult, PvtPoint, SafetyErrorEvent, Velocities

#: The iceoryx2 version the MCM is built with; the Python package must be the same.
ICEORYX2_VERSION = "0.10.0"

try:  # pragma: no cover - depends on the installation
    import iceoryx2 as iox2

    _IMPORT_ERROR: Optional[BaseException] = None
except ImportError as e:  # pragma: no cover
    iox2 = None
    _IMPORT_ERROR = e

_numbers = itertools.count(1)

#: What a control callback may return: six torques [Nm], six velocities [deg/s] as
#: :class:`~mcm.types.Velocities`, one PVT point, or None to end.
ControlOutput = Union[Sequence[float], Velocities, PvtPoint, None]


def _require_iceoryx2() -> Any:
    if iox2 is None:
        raise ShmUnavailable(
            "the shared-memory client needs the iceoryx2 package, version %s: pip install "
            "'mcm[shm]' (or iceoryx2==%s); import failed: %s"
            % (ICEORYX2_VERSION, ICEORYX2_VERSION, _IMPORT_ERROR)
        )
    try:
        from importlib.metadata import version

        found = version("iceoryx2")
    except Exception:  # noqa: BLE001 - metadata missing: trust the import
        found = ICEORYX2_VERSION
    if found != ICEORYX2_VERSION:
        raise ShmUnavailable(
            "iceoryx2 %s is installed, but the MCM uses %s: samples of other versions do not "
            "interoperate; pip install iceoryx2==%s" % (found, ICEORYX2_VERSION, ICEORYX2_VERSION)
        )
    return iox2


def new_client_id() -> int:
    """A client id of this process: ``(pid << 32) | n``, n = 1, 2, ... (the gateway reaps the
    control of an id whose process is gone)."""
    return (os.getpid() << 32) | next(_numbers)


@dataclass
class ControlStats:
    """What a :meth:`ShmClient.control` loop did.

    Attributes:
        cycles: states the callback answered.
        missed_cycles: states published while the loop was busy, never seen by the callback.
        next_cycle: answers the core applied in the cycle right after the state they answered.
        late: answers applied later than that.
        unanswered: answers whose reply did not come before the loop ended.
    """

    cycles: int = 0
    missed_cycles: int = 0
    next_cycle: int = 0
    late: int = 0
    unanswered: int = 0

    @property
    def on_time_share(self) -> float:
        """Share of answered states whose answer was applied in the next cycle (0..1)."""
        n = self.next_cycle + self.late + self.unanswered
        return self.next_cycle / n if n else 0.0


class ShmClient:
    """A co-located controller's connection to the MCM through shared memory.

    Args:
        instance: the MCM instance (``mcm --instance``; ``default`` on the robot).
        open_timeout: how long to retry while the services do not exist yet [s].
        reply_timeout: longest wait for a command's reply [s] (``calibrate``: 600 s).
    """

    def __init__(self, instance: str = "default", open_timeout: float = 5.0, reply_timeout: float = 5.0) -> None:
        iox = _require_iceoryx2()
        self.instance = instance
        self.reply_timeout = reply_timeout
        self.client_id = new_client_id()
        self._next_request = 1
        self._replies: Dict[int, Reply] = {}
        self._sent_at: Dict[int, int] = {}
        self._sent_control = False
        self._closed = False
        iox.set_log_level(iox.LogLevel.Error)
        node_name = "mcm-py-%d-%d.%s" % (os.getpid(), self.client_id & 0xFFFFFFFF, instance)
        self._node = (
            iox.NodeBuilder.new()
            .name(iox.NodeName.new(node_name))
            .signal_handling_mode(iox.SignalHandlingMode.Disabled)
            .create(iox.ServiceType.Ipc)
        )
        self._open_within(iox, open_timeout, any_error=False)

    def _open_within(self, iox: Any, open_timeout: float, any_error: bool) -> None:
        """Open the services, retrying every 50 ms for up to ``open_timeout`` seconds while they
        do not exist yet (``any_error``: while opening fails in any way, as while a restarted
        core creates them again), and read from its newest state on."""
        deadline = time.monotonic() + open_timeout
        while True:
            try:
                self._open(iox)
                break
            except ShmUnavailable:
                raise
            except Exception as e:  # noqa: BLE001 - iceoryx2 raises its own classes
                if not (any_error or "DoesNotExist" in repr(e)) or time.monotonic() > deadline:
                    raise ShmUnavailable(
                        "cannot open the services of MCM instance %r (is `mcm --instance %s` "
                        "running as this user?): %r" % (self.instance, self.instance, e)
                    ) from e
                time.sleep(0.05)
        self._start_from(self._read_state())

    def _start_from(self, state: StateSample) -> None:
        # Replies and errors from before this client opened the services are not its own.
        self._seen_seq = 0
        self._last_reply = state.reply_head
        self._last_error = state.last_error.seq
        self._events: List[SafetyErrorEvent] = []

    def reconnect(self, open_timeout: float = 5.0) -> None:
        """Open the services again, e.g. after mcm-rt restarted (a restarted core creates new
        services; the old ones publish nothing more, so :meth:`wait_state` times out). The
        client keeps its id; requests in flight are forgotten."""
        iox = _require_iceoryx2()
        self._replies.clear()
        self._sent_at.clear()
        self._open_within(iox, open_timeout, any_error=True)

    def _open(self, iox: Any) -> None:
        name = "mcm/%s/state" % self.instance
        try:
            bb = self._node.service_builder(iox.ServiceName.new(name)).blackboard_opener(ctypes.c_uint32).open()
        except Exception as e:
            if "IncompatibleKeys" in repr(e):
                raise ShmUnavailable("service %s: its key type is not u32 (another MCM version)" % name) from e
            raise
        self._bb = bb
        self._reader = bb.reader_builder().create()
        try:
            self._state_entry = self._reader.entry(ctypes.c_uint32(STATE_KEY), StateSample)
        except Exception as e:
            raise ShmUnavailable(
                "service %s has no %s entry under key 0: the MCM was built with another "
                "layout; use the mcm package of the same MCM version (%r)" % (name, StateSample.type_name(), e)
            ) from e
        self._reply_entries: Dict[int, Any] = {}
        ev = self._node.service_builder(iox.ServiceName.new("mcm/%s/state-ready" % self.instance)).event().open()
        self._event_service = ev
        self._listener = ev.listener_builder().create()
        self._wait_error = iox.ListenerWaitError
        cmd_name = "mcm/%s/command" % self.instance
        try:
            cmd = self._node.service_builder(iox.ServiceName.new(cmd_name)).publish_subscribe(CommandSample).open()
        except Exception as e:
            if "IncompatibleTypes" in repr(e):
                raise ShmUnavailable(
                    "service %s does not take %s: the MCM was built with another layout"
                    % (cmd_name, CommandSample.type_name())
                ) from e
            raise
        self._command_service = cmd
        self._publisher = cmd.publisher_builder().create()
        self._duration = iox.Duration

    # -- state ------------------------------------------------------------------------------

    def _read_state(self) -> StateSample:
        state: StateSample = self._state_entry.get().decode_as(StateSample)
        return state

    def state(self) -> StateSample:
        """The newest state (a copy), without waiting."""
        s = self._read_state()
        self._route(s)
        return s

    def wait_state(self, timeout: float = 1.0) -> StateSample:
        """The next state newer than the last one this method returned: at once if there is
        one, else blocking on the core's ``state-ready`` event (no spinning). Raises
        :class:`McmTimeout` when no new state came within ``timeout`` seconds."""
        deadline = time.monotonic() + timeout
        while True:
            s = self._read_state()
            if s.seq != self._seen_seq:
                self._seen_seq = s.seq
                self._route(s)
                return s
            left = deadline - time.monotonic()
            if left <= 0:
                raise McmTimeout(
                    "no new state from MCM instance %r within %.3f s (is mcm-rt running?)" % (self.instance, timeout)
                )
            self._wait_event(left)

    def _wait_event(self, left: float) -> None:
        """Block on the state event for at most ``left`` seconds. A wait cut short by a signal
        (the process stopped and continued, e.g. Ctrl-Z and ``fg``, or any signal handler) ends
        like a wake-up: the caller reads the state and waits again with the time left. Any
        other failure is raised."""
        try:
            self._listener.timed_wait(self._duration.from_secs_f64(left))
        except self._wait_error as e:
            if e.args[:1] != ("InterruptSignal",):
                raise

    def _block(self, key: int) -> ReplyBlock:
        e = self._reply_entries.get(key)
        if e is None:
            e = self._reader.entry(ctypes.c_uint32(key), ReplyBlock)
            self._reply_entries[key] = e
        block: ReplyBlock = e.get().decode_as(ReplyBlock)
        return block

    def events(self) -> List[SafetyErrorEvent]:
        """The safety errors reported since the last call (the state's error record, seen as
        new states are read), oldest first."""
        out, self._events = self._events, []
        return out

    def _route(self, s: StateSample) -> None:
        """Take this client's replies up to the state's ``reply_head``, and note a new error."""
        e = s.last_error
        if e.seq != self._last_error:
            self._last_error = e.seq
            if e.seq != 0:
                check = codes.REJECT_CODES.get(e.code, str(e.code))
                text = codes.reason_text(e.code, e.axis, list(e.values))
                self._events.append(
                    SafetyErrorEvent(
                        message="safety check tripped: %s; mode is now %s" % (text, codes.MODES.get(s.mode, "?")),
                        check=check,
                        axis=e.axis or None,
                    )
                )
        head = s.reply_head
        if head < self._last_reply:  # the core restarted: its replies start again
            self._last_reply = 0
        oldest = max(1, head - (REPLY_BLOCKS * REPLY_BLOCK - 1))
        block_key, block = -1, ReplyBlock()
        for n in range(max(self._last_reply + 1, oldest), head + 1):
            key, slot = reply_location(n)
            if key != block_key:
                block_key, block = key, self._block(key)
            r = block.replies[slot]
            if r.seq == n and r.client_id == self.client_id:
                self._replies[r.request_id] = Reply.from_buffer_copy(r)
        self._last_reply = max(self._last_reply, head)

    # -- commands ---------------------------------------------------------------------------

    def send(self, s: CommandSample) -> int:
        """Stamp this client's ids on a sample, publish it, and return its request id (read
        the answer with :meth:`wait_reply`)."""
        s.client_id = self.client_id
        s.request_id = self._next_request
        self._next_request += 1
        if codes.KIND_NAMES.get(s.kind) in codes.NEEDS_CONTROL:
            self._sent_control = True
        self._publisher.send_copy(s)
        self._sent_at[s.request_id] = self._seen_seq
        return int(s.request_id)

    def wait_reply(self, request_id: int, timeout: Optional[float] = None) -> wire.Answer:
        """The answer to a request this client sent; raises :class:`CommandError` for a
        refusal, :class:`OutcomeUnknown` when none came in time."""
        wait = self.reply_timeout if timeout is None else timeout
        deadline = time.monotonic() + wait
        while request_id not in self._replies:
            left = deadline - time.monotonic()
            if left <= 0:
                self._sent_at.pop(request_id, None)
                raise OutcomeUnknown(
                    "request %d" % request_id,
                    "no reply from the real-time core within %.1f s: the command may or may not "
                    "have been executed; check the state" % wait,
                    "outcome_unknown",
                    "unknown",
                )
            try:
                self.wait_state(min(left, 0.5))
            except McmTimeout:
                continue
        self._sent_at.pop(request_id, None)
        return wire.decode_reply(self._replies.pop(request_id))

    def request(self, s: CommandSample, timeout: Optional[float] = None) -> wire.Answer:
        """Send a sample and wait for its answer."""
        return self.wait_reply(self.send(s), timeout)

    def hold(self) -> None:
        """Enter HOLD (stops any motion; clears errors and powers the drives from OFF/ERROR)."""
        self.request(wire.sample("hold"))

    def calibrate(self, which: Union[str, int] = enc.DEFAULT_WHICH, elbow_direction: int = 1,
                  wrist_direction: int = 1, force_mechanical_stop: bool = False) -> None:
        """Home the axes; returns when the calibration has finished."""
        self.request(wire.calibrate(which, elbow_direction, wrist_direction, force_mechanical_stop), timeout=600.0)

    def release(self) -> None:
        """Enter RELEASE."""
        self.request(wire.sample("release"))

    def torque_control(
        self, timeout: Optional[float] = enc.DEFAULT_MODE_TIMEOUT, gravity_compensation: bool = True
    ) -> None:
        """Enter TORQUE_CONTROL (``timeout`` None: no timeout)."""
        self.request(wire.torque_control(timeout, gravity_compensation))

    def set_torques(self, torques: Sequence[float]) -> int:
        """Send six torques [Nm] without waiting; returns the request id."""
        return self.send(wire.set_torques(torques))

    def velocity_control(self, timeout: Optional[float] = enc.DEFAULT_MODE_TIMEOUT) -> None:
        """Enter VELOCITY_CONTROL (``timeout`` None: no timeout; every axis starts at target
        velocity 0). Without a ``set_velocities`` for ``timeout`` seconds the arm stops in HOLD."""
        self.request(wire.velocity_control(timeout))

    def set_velocities(self, velocities: Sequence[float]) -> int:
        """Send six joint velocities [deg/s] without waiting; returns the request id (a refusal
        is read with :meth:`wait_reply`)."""
        return self.send(wire.set_velocities(velocities))

    def set_cartesian_velocity(
        self, linear: Sequence[float], angular: Sequence[float], frame: str = "base"
    ) -> int:
        """Send the TCP's velocity (as :meth:`mcm.Client.set_cartesian_velocity`) without
        waiting; returns the request id (a refusal is read with :meth:`wait_reply`)."""
        return self.send(wire.set_cartesian_velocity(linear, angular, frame))

    def set_tool(
        self,
        mass: float,
        center_of_mass: Sequence[float],
        tcp_position: Sequence[float] = (0.0, 0.0, 0.0),
        tcp_orientation: Sequence[float] = (0.0, 0.0, 0.0, 1.0),
        inertia: Optional[Sequence[float]] = None,
    ) -> None:
        """Set the tool the arm carries (as :meth:`mcm.Client.set_tool`), from the next cycle."""
        tcp = {"position": list(tcp_position), "orientation": list(tcp_orientation)}
        self.request(wire.set_tool(tcp, mass, center_of_mass, inertia))

    def identify_payload(self, apply: bool = False) -> PayloadResult:
        """Estimate the load on the flange (as :meth:`mcm.Client.identify_payload`); returns
        once the arm is back where it started (under 30 s)."""
        a = self.request(wire.identify_payload(apply), timeout=60.0)
        assert a.payload is not None
        return a.payload

    def pvt(self, dt: float = enc.DEFAULT_PVT_DT) -> None:
        """Enter PVT mode with point spacing ``dt`` [s]."""
        self.request(wire.pvt(dt))

    def move_axis(
        self, axis_index: int, target_position: float, velocity_factor: float = enc.DEFAULT_VELOCITY_FACTOR
    ) -> None:
        """Move one axis; returns as the motion starts."""
        self.request(wire.move_axis(axis_index, target_position, velocity_factor))

    def move_all(
        self, target_positions: Sequence[float], velocity_factor: float = enc.DEFAULT_VELOCITY_FACTOR
    ) -> MoveAllResult:
        """Move all axes together; returns the planned move."""
        a = self.request(wire.move_all(target_positions, velocity_factor))
        assert a.move_all is not None
        return a.move_all

    def move_linear(
        self,
        position: Sequence[float],
        orientation: Optional[Sequence[float]] = None,
        velocity: Optional[float] = None,
        acceleration: Optional[float] = None,
    ) -> MoveLinearResult:
        """Move the TCP on a straight line (as :meth:`mcm.Client.move_linear`); returns the
        line as planned, once the core's planner has checked the whole path."""
        a = self.request(wire.move_linear(position, orientation, velocity, acceleration))
        assert a.move_linear is not None
        return a.move_linear

    def pvt_points(self, points: Sequence[PvtPoint]) -> None:
        """Queue a batch of points (all or none); at most 8 samples are in flight at once."""
        ids: List[int] = []
        for s in wire.pvt_chunks(points):
            if len(ids) >= 8:
                self.wait_reply(ids.pop(0))
            ids.append(self.send(s))
        for i in ids:
            self.wait_reply(i)

    def sim(self, **kwargs: Any) -> None:
        """Fault injection into the simulated robot (the arguments of :func:`mcm.wire.sim`)."""
        self.request(wire.sim(**kwargs))

    def take_control(self) -> None:
        """Become the client that controls the arm."""
        self.request(wire.sample("take_control"))

    def release_control(self) -> None:
        """Give up control of the arm (its motion ends in HOLD)."""
        self.request(wire.sample("release_control"))

    def client_gone(self) -> None:
        """Tell the core this client is gone: it loses control, and what it drove stops in
        HOLD. Sent by :meth:`control` and :meth:`close`."""
        self.request(wire.sample("client_gone"))

    def info(self) -> wire.Answer:
        """The core's number of axes and cycle period (``num_axes``, ``period_s``)."""
        return self.request(wire.sample("info"))

    # -- control loop -----------------------------------------------------------------------

    def control(
        self,
        callback: Callable[[StateSample], ControlOutput],
        max_cycles: Optional[int] = None,
        state_timeout: float = 1.0,
        pvt_lookahead: int = 3,
    ) -> ControlStats:
        """Run a control loop at the cycle rate: ``callback(state)`` gets each new state and
        returns six torques [Nm] (sent as ``set_torques``: enter TORQUE_CONTROL first),
        :class:`~mcm.types.Velocities` (sent as ``set_velocities``: enter VELOCITY_CONTROL
        first), a :class:`~mcm.types.PvtPoint` (queued as a one-point ``pvt_points``: enter PVT first),
        or None to finish (the PVT points already sent are run to their end first). Missed
        states are counted, not replayed.

        PVT points stream best with ``pvt(dt)`` equal to the cycle period: the first
        ``pvt_lookahead`` points go out together as one batch, then one point per cycle, so
        the core's queue keeps that many points and never runs dry between two answers (a
        stream that runs dry while moving stops the axes, and further points are refused as
        ``busy`` until they stand). When the loop ends (also
        by an exception) it sends ``client_gone``, so what it drove stops in HOLD.

        Raises :class:`CommandError` when the core refuses an answer (e.g. the mode left
        TORQUE_CONTROL or VELOCITY_CONTROL after a safety trip)."""
        stats = ControlStats()
        expected: Dict[int, int] = {}
        last_seq: Optional[int] = None
        held: List[PvtPoint] = []
        if not 1 <= pvt_lookahead <= PVT_POINTS_PER_COMMAND:
            raise ValueError("pvt_lookahead = %r is not allowed; expected 1 to 4" % pvt_lookahead)
        lookahead = pvt_lookahead
        streamed = False
        try:
            while max_cycles is None or stats.cycles < max_cycles:
                s = self.wait_state(state_timeout)
                if last_seq is not None and s.seq > last_seq + 1:
                    stats.missed_cycles += s.seq - last_seq - 1
                last_seq = s.seq
                self._collect(expected, stats)
                out = callback(s)
                if out is None:
                    break
                if isinstance(out, PvtPoint):
                    # One sample carries up to four points: the lookahead batch is one sample.
                    held.append(out)
                    stats.cycles += 1
                    if len(held) < lookahead:
                        continue
                    lookahead = 1
                    rid = self.send(wire.pvt_chunks(held)[0])
                    streamed = True
                    held = []
                    expected[rid] = s.seq
                    continue
                elif isinstance(out, Velocities):
                    rid = self.send(wire.set_velocities(out.velocities))
                else:
                    rid = self.send(wire.set_torques(out))
                expected[rid] = s.seq
                stats.cycles += 1
            if held:  # the loop ended before the lookahead batch was full
                expected[self.send(wire.pvt_chunks(held)[0])] = last_seq or 0
                streamed = True
            # The answers to the last states: their replies come within a cycle or two.
            deadline = time.monotonic() + 0.5
            while expected and time.monotonic() < deadline:
                try:
                    self.wait_state(0.1)
                except McmTimeout:
                    pass
                self._collect(expected, stats)
            stats.unanswered += len(expected)
            if streamed:
                self._drain_pvt_queue()
        finally:
            try:
                self.client_gone()
                self._sent_control = False
            except Exception:  # noqa: BLE001 - the loop's own error matters more
                pass
        return stats

    def _drain_pvt_queue(self, timeout: float = 10.0) -> None:
        """Wait until the core's PVT queue is empty (the streamed points have run)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            s = self.wait_state(1.0)
            if s.pvt_queued == 0 or codes.MODES.get(s.mode) != "PVT":
                return

    def _collect(self, expected: Dict[int, int], stats: ControlStats) -> None:
        for rid in [r for r in expected if r in self._replies]:
            seq = expected.pop(rid)
            r = self._replies.pop(rid)
            self._sent_at.pop(rid, None)
            if r.cycle == seq + 1:
                stats.next_cycle += 1
            else:
                stats.late += 1
            if r.status != codes.REPLY_OK:
                wire.decode_reply(r)  # raises CommandError with the core's words

    # -- end --------------------------------------------------------------------------------

    def close(self) -> None:
        """Send ``client_gone`` if this client sent motion commands, and drop the ports."""
        if self._closed:
            return
        self._closed = True
        if self._sent_control:
            try:
                self.client_gone()
            except Exception:  # noqa: BLE001 - closing anyway
                pass
        for name in ("_publisher", "_listener", "_reader"):
            port = getattr(self, name, None)
            if port is not None and hasattr(port, "delete"):
                port.delete()
        self._reply_entries = {}

    def __enter__(self) -> "ShmClient":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


__all__ = ["ShmClient", "ControlStats", "ControlOutput", "new_client_id", "ICEORYX2_VERSION", "CommandError"]
