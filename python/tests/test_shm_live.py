"""The shared-memory client against a running MCM (simulated), named by the environment
variable ``MCM_INSTANCE`` (``tests/end_to_end/examples_python.rs`` starts one and sets it). Skipped,
saying so, without it; a failure instead when ``CI`` is set."""

import math
import os
import signal
import subprocess
import sys
import threading
import time
import unittest
from typing import Any, Callable, List

import mcm

from . import needs

INSTANCE = os.environ.get("MCM_INSTANCE")
#: The longest any wait may take on the test's own clock (a bound on the wait, not a measure
#: of the robot: how fast the robot was is judged on its clock, the states' ``t_ns``).
WAIT_S = 20.0
#: The controlled stop of axis 3 from the loop's 6 to 8 deg/s to rest, on the robot's clock [s]
#: (measured: 0.045 s; at 180 deg/s^2 it takes 0.04 s), with room to spare.
STOP_S = 0.5
#: Points the PVT test's loop sends ahead of the core (``control``'s ``pvt_lookahead``): as many
#: missed states run its stream dry.
LOOKAHEAD = 3


@needs.env("MCM_INSTANCE", "run `cargo test --test end_to_end examples_python::`")
class ShmLive(unittest.TestCase):
    def setUp(self) -> None:
        self.a = mcm.ShmClient(str(INSTANCE))
        self.addCleanup(self.a.close)

    def wait_until(self, what: str, done: Callable[[Any], bool], within_s: float) -> Any:
        """The first new state where ``done(state)`` holds, which must come within ``within_s``
        on the robot's clock: no state where it does not hold is more than ``within_s`` newer
        than the newest state at the call. A test process that falls behind only misses
        states, so it cannot make this fail; the test's own clock only bounds the wait."""
        t0 = self.a.state().t_ns
        last_not = t0
        deadline = time.monotonic() + WAIT_S
        while True:
            s = self.a.wait_state()
            if done(s):
                break
            last_not = s.t_ns
            self.assertLess(time.monotonic(), deadline, "%s: not within %.0f s" % (what, WAIT_S))
        took = (last_not - t0) / 1e9
        self.assertLessEqual(took, within_s, "%s: still not after %.3f s of robot time" % (what, took))
        return s

    def test_wait_state_returns_each_new_cycle_once(self) -> None:
        first = self.a.wait_state()
        seqs = [self.a.wait_state().seq for _ in range(50)]
        self.assertTrue(all(b > a for a, b in zip([first.seq] + seqs, seqs)), seqs)
        # Blocking on the event, not spinning: 50 states take about 50 cycles (5 ms each).
        gaps = sum(b - a - 1 for a, b in zip([first.seq] + seqs, seqs))
        self.assertLess(gaps, 25, "states missed while nothing else ran: %s" % seqs)

    def test_wait_state_goes_on_through_signals(self) -> None:
        """A wait cut short by a signal is waited again: under a stream of signals with a
        (no-op) handler, and while another process stops and continues this one 20 times,
        every ``wait_state`` returns the next state."""
        main = threading.get_ident()
        old = signal.signal(signal.SIGUSR1, lambda *_: None)
        self.addCleanup(signal.signal, signal.SIGUSR1, old)
        stop = threading.Event()
        sent = [0]

        def signals() -> None:
            while not stop.is_set():
                signal.pthread_kill(main, signal.SIGUSR1)
                sent[0] += 1
                stop.wait(0.0005)  # paces the signals

        sender = threading.Thread(target=signals, daemon=True)
        sender.start()
        try:
            seqs = [self.a.wait_state(timeout=WAIT_S).seq for _ in range(100)]
        finally:
            stop.set()
            sender.join()
        self.assertTrue(all(b > a for a, b in zip(seqs, seqs[1:])), seqs)
        self.assertGreater(sent[0], 50)

        # The pauses only pace the stops; the waits below end when the other process does.
        stopper = (
            "import os, signal, sys, time\n"
            "pid = int(sys.argv[1])\n"
            "for _ in range(20):\n"
            "    os.kill(pid, signal.SIGSTOP); time.sleep(0.02)\n"
            "    os.kill(pid, signal.SIGCONT); time.sleep(0.02)\n"
        )
        child = subprocess.Popen([sys.executable, "-c", stopper, str(os.getpid())])
        self.addCleanup(child.wait)
        deadline = time.monotonic() + WAIT_S
        last = self.a.wait_state(timeout=WAIT_S).seq
        while child.poll() is None:
            self.assertLess(time.monotonic(), deadline, "the stops did not end within %.0f s" % WAIT_S)
            s = self.a.wait_state(timeout=WAIT_S)
            self.assertGreater(s.seq, last)
            last = s.seq
        self.assertEqual(child.returncode, 0)

    def test_ids_and_replies_belong_to_each_client(self) -> None:
        b = mcm.ShmClient(str(INSTANCE))
        self.addCleanup(b.close)
        self.assertEqual(self.a.client_id >> 32, os.getpid())
        self.assertNotEqual(self.a.client_id, b.client_id)
        ra, rb = self.a.send(mcm.wire.sample("info")), b.send(mcm.wire.sample("status"))
        self.assertEqual(ra, rb, "both clients number their requests from 1")
        self.assertEqual(self.a.wait_reply(ra).command, "info")
        self.assertEqual(b.wait_reply(rb).command, "status")
        info = self.a.info()
        self.assertEqual((info.num_axes, info.period_s), (6, 0.005))

    def test_refusals_carry_the_cores_code_and_words(self) -> None:
        self.a.hold()
        with self.assertRaises(mcm.CommandError) as e:
            self.a.move_axis(1, 10.0)
        self.assertEqual((e.exception.command, e.exception.code), ("move_axis", "wrong_mode"))
        self.assertIn("move_axis refused: not allowed in mode HOLD", e.exception.message)

    def test_control_loop_counts_cycles_and_sends_client_gone(self) -> None:
        self.a.take_control()
        self.assertEqual(self.a.state().owner_client_id, self.a.client_id)
        n = [0]

        def cb(s):
            n[0] += 1
            return None if n[0] > 20 else [0.0] * 6

        # Not in TORQUE_CONTROL: each set_torques is refused, which ends the loop with the
        # core's words; client_gone is sent all the same.
        with self.assertRaises(mcm.CommandError) as e:
            self.a.control(cb)
        self.assertEqual(e.exception.code, "wrong_mode")
        # client_gone went out before control() returned: the core serves it in its next cycle.
        self.wait_until("client_gone ending the ownership", lambda s: s.owner_client_id == 0, 0.05)

    def test_pvt_points_stream_through_the_control_loop(self) -> None:
        # The loop sends one point per state it sees, LOOKAHEAD ahead: each state it misses
        # takes one point from the core's queue for good, and after LOOKAHEAD the stream runs
        # dry, the core stops the axes and refuses the next points (busy while the stop runs,
        # then as too sudden a start from rest), as it must. That is this process kept off the
        # CPU by the machine's load, not the MCM, when the states the loop saw show those
        # misses: then the stream is run again from rest, at most three times. A refusal
        # without them fails the test.
        for attempt in range(3):
            late = self._stream_a_ramp_on_axis_6()
            if late is None:
                return
            print("attempt %d: %s; again" % (attempt + 1, late))
        self.fail("the PVT stream ran dry in each of 3 attempts: %s" % late)

    def _stream_a_ramp_on_axis_6(self) -> Any:
        """Stream axis 6 to +1 deg and check it; None when done, or why the stream ran dry
        because this process missed states."""
        self.a.hold()
        if not self.a.state().flags & mcm.layout.STATE_ALL_CALIBRATED:
            self.a.calibrate()
        # A stop that a `hold` began carries on into PVT and makes points wait: let any end
        # (a stop from the ramp's 5 deg/s takes hundredths of a second of robot time).
        t0 = self.a.state().t_ns
        self.wait_until("0.5 s of robot time after hold", lambda s: s.t_ns - t0 >= STOP_S * 1e9, 1.0)
        self.a.pvt(0.005)  # one point per cycle
        start = list(self.a.state().commanded_position)
        k = [0]
        seen = {"seq": None, "missed": 0}

        def ramp(s):
            # Axis 6 to +1 deg in 0.3 s (half a cosine, at rest at both ends), a point per state.
            if seen["seq"] is not None:
                seen["missed"] += max(0, s.seq - seen["seq"] - 1)
            seen["seq"] = s.seq
            k[0] += 1
            if k[0] > 60:
                return None
            w = math.pi / 0.3
            t = 0.005 * k[0]
            pos, vel = list(start), [0.0] * 6
            pos[5] += 0.5 * (1 - math.cos(w * t))
            vel[5] = 0.5 * w * math.sin(w * t)
            return mcm.PvtPoint(pos, vel)

        try:
            stats = self.a.control(ramp, pvt_lookahead=LOOKAHEAD)
        except mcm.CommandError as e:
            if e.command == "pvt_points" and seen["missed"] >= LOOKAHEAD:
                return "the loop missed %d states, then %s" % (seen["missed"], e)
            raise
        self.assertEqual(stats.cycles, 60)
        # The first LOOKAHEAD points went out as one batch, the others one by one: all applied.
        self.assertEqual(stats.next_cycle + stats.late, 60 - LOOKAHEAD + 1, stats)
        # control() returned when the core's queue was empty: the last point is in force.
        self.wait_until(
            "axis 6 commanded at +1 deg",
            lambda s: abs(s.commanded_position[5] - (start[5] + 1.0)) <= 1e-6,
            0.05,
        )
        return None

    def test_velocity_control_moves_an_axis_through_the_control_loop(self) -> None:
        self.a.hold()
        if not self.a.state().flags & mcm.layout.STATE_ALL_CALIBRATED:
            self.a.calibrate()
        self.a.velocity_control(timeout=0.5)
        self.assertEqual(mcm.codes.MODES[self.a.state().mode], "VELOCITY_CONTROL")
        start = self.a.state().position[2]
        seen = []

        def towards(s):
            # Axis 3 at +8 deg/s until its measured velocity is past 6 deg/s.
            if s.velocity[2] > 6.0:
                seen.append(s.velocity[2])
                return None
            return mcm.Velocities([0, 0, 8.0, 0, 0, 0])

        stats = self.a.control(towards, max_cycles=2000)
        self.assertEqual(len(seen), 1, "axis 3 never passed 6 deg/s in %d cycles" % stats.cycles)
        self.assertLess(seen[0], 8.5)
        self.assertGreater(self.a.state().position[2], start)
        self.assertGreater(stats.next_cycle + stats.late, 10, stats)
        # The loop's client_gone ended the mode with the controlled stop (from about 6 deg/s).
        self.wait_until(
            "the controlled stop to HOLD after the loop",
            lambda s: mcm.codes.MODES[s.mode] == "HOLD" and abs(s.velocity[2]) < 0.01,
            STOP_S,
        )
        # A velocity beyond the axis's maximum is refused with the core's code.
        self.a.velocity_control(timeout=0.5)
        with self.assertRaises(mcm.CommandError) as e:
            self.a.wait_reply(self.a.set_velocities([0, 0, 1e4, 0, 0, 0]))
        self.assertEqual((e.exception.command, e.exception.code), ("set_velocities", "out_of_range"), e.exception)
        self.a.hold()

    def test_safety_errors_are_reported_once(self) -> None:
        self.a.hold()
        self.assertEqual(self.a.events(), [])
        self.a.sim(emergency_stop=True)
        # The trip comes a few cycles after the press (the reply of `sim` came with the press).
        events: List[Any] = []

        def tripped(_: Any) -> bool:
            events.extend(self.a.events())
            return bool(events)

        self.wait_until("the safety error after the emergency stop", tripped, 0.05)
        self.assertEqual(events[0].check, "emergency_stop", events)
        self.assertIn("safety check tripped: the emergency stop is pressed", events[0].message)
        self.a.sim(emergency_stop=False)
        self.a.hold()
        self.assertEqual([e for e in self.a.events() if e.check != "emergency_stop"], [])


if __name__ == "__main__":
    unittest.main()
