"""The TCP client against a scripted fake MCM (standard library only)."""

import socket
import unittest

import mcm
from mcm import codes

from .fake_mcm import OK, FakeMcm, error, status

SAFETY = error(
    "safety check tripped: following error: axis 2 is 2.056 deg away from its commanded position, "
    "band 2.000 deg; mode is now ERROR; flight recorder: /tmp/x.csv",
    error_code="following_error",
    check="following_error",
    axis=2,
    flight_recorder="/tmp/x.csv",
)


class TcpClient(unittest.TestCase):
    def connect(self, handler, **kw) -> mcm.Client:
        self.fake = FakeMcm(handler)
        self.addCleanup(self.fake.close)
        c = mcm.Client("127.0.0.1", self.fake.port, timeout=kw.pop("timeout", 2.0), **kw)
        self.addCleanup(c.close)
        return c

    def test_commands_are_sent_as_one_json_line_with_their_arguments(self) -> None:
        def h(cmd):
            if cmd["command"] == "move_all":
                return [{"result_type": "move_all", "velocities": [1, 2, 3, 0, 0, 0], "longest": 3,
                         "max_time_to_target": 1.25}]
            return [OK]

        c = self.connect(h)
        r = c.move_all([0, 10, 20, 0, 0, 0], 0.5)
        self.assertEqual(r.velocities, [1.0, 2.0, 3.0, 0.0, 0.0, 0.0])
        self.assertEqual((r.longest, r.max_time_to_target), (3, 1.25))
        c.move_axis(1, 30)
        self.assertEqual(self.fake.received[0], {"command": "move_all", "arguments": {
            "target_positions": [0.0, 10.0, 20.0, 0.0, 0.0, 0.0], "velocity_factor": 0.5}})
        # An argument left out is left to the MCM's default.
        self.assertEqual(self.fake.received[1]["arguments"], {"axis_index": 1, "target_position": 30})

    def test_a_pose_is_sent_in_metres_and_a_quaternion(self) -> None:
        def h(cmd):
            if cmd["command"] == "inverse_kinematics":
                return [{"result_type": "inverse_kinematics", "solutions": [[1, 2, 3, 4, 5, 6], [6, 5, 4, 3, 2, 1]]}]
            return [{"result_type": "move_all", "velocities": [1, 2, 3, 0, 0, 0], "longest": 3,
                     "max_time_to_target": 1.25}]

        c = self.connect(h)
        r = c.inverse_kinematics([0.4, 0, 0.5], [0, 1, 0, 0], seed=[0, 10, 20, 0, 0, 0])
        self.assertEqual(r.solutions, [[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], [6.0, 5.0, 4.0, 3.0, 2.0, 1.0]])
        self.assertEqual(c.move_to_pose([0.4, 0, 0.5], [0, 1, 0, 0]).longest, 3)
        self.assertEqual(self.fake.received[0], {"command": "inverse_kinematics", "arguments": {
            "position": [0.4, 0.0, 0.5], "orientation": [0.0, 1.0, 0.0, 0.0],
            "seed": [0.0, 10.0, 20.0, 0.0, 0.0, 0.0]}})
        # The velocity factor left out is left to the MCM's default.
        self.assertEqual(self.fake.received[1], {"command": "move_to_pose", "arguments": {
            "position": [0.4, 0.0, 0.5], "orientation": [0.0, 1.0, 0.0, 0.0]}})

    def test_status_result_is_typed(self) -> None:
        c = self.connect(lambda cmd: [dict(status("PVT", 3.5), hardware_status="ok", detail={
            "cycle": 7, "all_calibrated": True, "pvt_queue": {"queued": 2}, "tool": {"mass": 2.0}})])
        s = c.status(detail=True)
        self.assertEqual(s.operating_mode, "PVT")
        self.assertEqual(s.axis_states.time, [3.5] * 6)
        self.assertEqual(s.hardware_status, "ok")
        assert s.detail is not None
        self.assertEqual((s.detail.cycle, s.detail.all_calibrated, s.detail.pvt_queue["queued"]), (7, True, 2))
        self.assertEqual(s.detail.tool["mass"], 2.0)
        self.assertEqual(self.fake.received[0]["arguments"], {"detail": True})
        self.assertIsNone(s.cartesian_state)

    def test_the_cartesian_state_is_typed(self) -> None:
        tcp = {"position": [0.1, 0.0, 0.9], "orientation": [0.0, 0.0, 0.0, 1.0],
               "linear_velocity": [0.0, 0.02, 0.0], "angular_velocity": [0.0, 0.0, 15.0]}
        c = self.connect(lambda cmd: [dict(status("HOLD"), cartesian_state=tcp)])
        s = c.status()
        assert s.cartesian_state is not None
        self.assertEqual(s.cartesian_state.position, [0.1, 0.0, 0.9])
        self.assertEqual(s.cartesian_state.orientation, [0.0, 0.0, 0.0, 1.0])
        self.assertEqual(s.cartesian_state.linear_velocity, [0.0, 0.02, 0.0])
        self.assertEqual(s.cartesian_state.angular_velocity, [0.0, 0.0, 15.0])

    def test_set_tool_sends_the_tool_as_the_protocol_takes_it(self) -> None:
        c = self.connect(lambda cmd: [{"result_type": "generic", "error_status": "OK"}])
        c.set_tool(2.0, [0, 0, 0.06], tcp_position=[0, 0, 0.15])
        self.assertEqual(self.fake.received[0]["command"], "set_tool")
        self.assertEqual(
            self.fake.received[0]["arguments"],
            {
                "tcp": {"position": [0.0, 0.0, 0.15], "orientation": [0.0, 0.0, 0.0, 1.0]},
                "mass": 2.0,
                "center_of_mass": [0.0, 0.0, 0.06],
            },
        )

    def test_an_error_result_raises_with_command_message_and_code(self) -> None:
        msg = "move_all refused: a motion is in progress (0.845 s left); wait until it ends, or send `hold` to stop it"
        c = self.connect(lambda cmd: [error(msg, error_code="busy", command="move_all", outcome="refused")])
        with self.assertRaises(mcm.CommandError) as e:
            c.move_all([0] * 6)
        self.assertEqual((e.exception.command, e.exception.code, e.exception.outcome), ("move_all", "busy", "refused"))
        self.assertEqual(e.exception.message, msg)

    def test_failed_and_unknown_outcomes_are_told_apart(self) -> None:
        replies = iter([
            error("calibrate failed: calibration of axis 3 failed: no mechanical stop found within 310.0 deg; the arm holds where it is",
                  error_code="calibration_failed", command="calibrate", outcome="failed"),
            error("move_axis: no reply from the real-time core within 5 s: the command may or may not have been executed; check the state",
                  error_code="outcome_unknown", command="move_axis", outcome="unknown"),
        ])
        c = self.connect(lambda cmd: [next(replies)])
        with self.assertRaises(mcm.CommandError) as e:
            c.calibrate()
        self.assertEqual((e.exception.outcome, e.exception.code), ("failed", "calibration_failed"))
        with self.assertRaises(mcm.OutcomeUnknown) as u:
            c.move_axis(1, 2)
        self.assertEqual((u.exception.outcome, u.exception.code), ("unknown", codes.ErrorCode.OUTCOME_UNKNOWN))

    def test_spontaneous_safety_errors_are_kept_apart_from_results(self) -> None:
        c = self.connect(lambda cmd: [SAFETY, status("ERROR")])
        s = c.status()
        self.assertEqual(s.operating_mode, "ERROR")
        ev = c.events()
        self.assertEqual(len(ev), 1)
        self.assertIsInstance(ev[0], mcm.SafetyErrorEvent)
        self.assertEqual((ev[0].check, ev[0].axis, ev[0].flight_recorder), ("following_error", 2, "/tmp/x.csv"))
        self.assertEqual(c.events(), [])

    def test_torque_ticks_are_events_and_set_torques_errors_come_later(self) -> None:
        def h(cmd):
            if cmd["command"] == "torque_control":
                return [status("TORQUE_CONTROL", 1.0), status("TORQUE_CONTROL", 1.005)]
            if cmd["command"] == "set_torques":
                if cmd["arguments"]["torques"][0] > 100:
                    return [error("set_torques refused: axis 1: value 200 is outside the allowed range [-129.6, 129.6]",
                                  error_code="out_of_range", command="set_torques", outcome="refused")]
                return [status("TORQUE_CONTROL", 1.01)]
            if cmd["command"] == "hold":
                return [status("TORQUE_CONTROL", 1.015), status("HOLD", 1.02)]
            return [status("TORQUE_CONTROL", 1.0)]

        c = self.connect(h)
        self.assertEqual(c.torque_control(timeout=0.1, dt_status=0.005).operating_mode, "TORQUE_CONTROL")
        self.assertEqual(c.wait_status().axis_states.time[0], 1.005)
        c.set_torques([1, 0, 0, 0, 0, 0])
        self.assertEqual(c.wait_status().axis_states.time[0], 1.01)
        c.set_torques([200, 0, 0, 0, 0, 0])
        # The refusal arrives after the call returned: an event, then raised by the next call.
        self.assertEqual(c.status().axis_states.time[0], 1.0)
        with self.assertRaises(mcm.CommandError) as e:
            c.set_torques([0] * 6)
        self.assertEqual((e.exception.command, e.exception.code, e.exception.outcome),
                         ("set_torques", "out_of_range", "refused"))
        # `hold` ends the session: its result is the status not in TORQUE_CONTROL.
        self.assertEqual(c.hold().operating_mode, "HOLD")

    def test_velocity_ticks_are_events_and_set_velocities_errors_come_later(self) -> None:
        refusal = ('set_velocities: argument "velocities" = [0,0,0,900,0,0] is not allowed; expected a '
                   "velocity of axis 4 from -150 to 150 deg/s (its maximum velocity)")

        def h(cmd):
            if cmd["command"] == "velocity_control":
                return [status("VELOCITY_CONTROL", 2.0), status("VELOCITY_CONTROL", 2.005)]
            if cmd["command"] == "set_velocities":
                if cmd["arguments"]["velocities"][3] > 150:
                    return [error(refusal, error_code="out_of_range", command="set_velocities", outcome="invalid")]
                return [status("VELOCITY_CONTROL", 2.01)]
            if cmd["command"] == "hold":
                return [status("VELOCITY_CONTROL", 2.015), status("HOLD", 2.02)]
            return [status("VELOCITY_CONTROL", 2.0)]

        c = self.connect(h)
        self.assertEqual(c.velocity_control(timeout=0.5, dt_status=0.005).operating_mode, "VELOCITY_CONTROL")
        self.assertEqual(self.fake.received[0], {"command": "velocity_control",
                                                 "arguments": {"timeout": 0.5, "dt_status": 0.005}})
        self.assertEqual(c.wait_status().axis_states.time[0], 2.005)
        c.set_velocities([10, 0, 0, 0, 0, 0])
        self.assertEqual(c.wait_status().axis_states.time[0], 2.01)  # the fake has read it
        self.assertEqual(self.fake.received[1], {"command": "set_velocities",
                                                 "arguments": {"velocities": [10.0, 0.0, 0.0, 0.0, 0.0, 0.0]}})
        c.set_velocities([0, 0, 0, 900, 0, 0])
        # The refusal arrives after the call returned: an event, then raised by the next call.
        self.assertEqual(c.status().axis_states.time[0], 2.0)
        with self.assertRaises(mcm.CommandError) as e:
            c.set_velocities([0] * 6)
        self.assertEqual((e.exception.command, e.exception.code, e.exception.outcome),
                         ("set_velocities", "out_of_range", "invalid"))
        self.assertEqual(e.exception.message, refusal)
        with self.assertRaises(ValueError):
            c.set_velocities([0] * 5)
        # `hold` ends the session: the tick before it is an event, its result the HOLD status.
        self.assertEqual(c.hold().operating_mode, "HOLD")
        self.assertEqual([type(x).__name__ for x in c.events()], ["StatusEvent"])

    def test_set_cartesian_velocity_sends_three_finite_numbers_per_vector(self) -> None:
        c = self.connect(lambda cmd: [] if cmd["command"] == "set_cartesian_velocity" else [status()])
        c.set_cartesian_velocity([0, 0, 0.02], [-5, 0, 0], "tool")
        c.status()  # the fake has read what came before it
        self.assertEqual(self.fake.received[0], {"command": "set_cartesian_velocity", "arguments": {
            "linear": [0.0, 0.0, 0.02], "angular": [-5.0, 0.0, 0.0], "frame": "tool"}})
        for linear, angular in (([0, 0], [0, 0, 0]), ([0, 0, 0], [0, 0, float("inf")])):
            with self.assertRaisesRegex(ValueError, "expected three finite numbers"):
                c.set_cartesian_velocity(linear, angular)
        c.status()
        self.assertEqual([x["command"] for x in self.fake.received], ["set_cartesian_velocity", "status", "status"])

    def test_control_loop_sends_velocities_in_velocity_control(self) -> None:
        ticks = iter(range(100))

        def h(cmd):
            if cmd["command"] == "velocity_control":
                return [status("VELOCITY_CONTROL", 1.0), status("VELOCITY_CONTROL", 1.0 + next(ticks) * 0.005)]
            if cmd["command"] == "set_velocities":
                # The third answer is the last tick in the mode (a timeout): the loop ends.
                k = next(ticks)
                return [status("VELOCITY_CONTROL" if k < 3 else "HOLD", 1.0 + k * 0.005)]
            return [OK]

        c = self.connect(h)
        c.velocity_control(dt_status=0.005)
        n = c.control(lambda s: mcm.Velocities([5.0, 0, 0, 0, 0, 0]))
        self.assertEqual(n, 3)
        sent = [m for m in self.fake.received if m["command"] == "set_velocities"]
        self.assertEqual([m["arguments"]["velocities"][0] for m in sent], [5.0] * 3)
        self.assertEqual([m for m in self.fake.received if m["command"] == "set_torques"], [])

    def test_control_loop_answers_each_tick_until_the_callback_ends_it(self) -> None:
        ticks = iter(range(100))

        def h(cmd):
            if cmd["command"] == "torque_control":
                return [status("TORQUE_CONTROL", 1.0), status("TORQUE_CONTROL", 1.0 + next(ticks) * 0.005)]
            if cmd["command"] == "set_torques":
                return [status("TORQUE_CONTROL", 1.0 + next(ticks) * 0.005)]
            return [OK]

        c = self.connect(h)
        c.torque_control(dt_status=0.005)
        seen = []
        n = c.control(lambda s: None if len(seen) >= 5 else seen.append(s.axis_states.time[0]) or [0.5] * 6)
        self.assertEqual(n, 5)
        self.assertEqual(len([m for m in self.fake.received if m["command"] == "set_torques"]), 5)

    def test_control_answers_the_newest_tick_and_skips_the_queued_ones(self) -> None:
        def h(cmd):
            if cmd["command"] == "torque_control":
                # The result, then three ticks at once (a slow client).
                return [status("TORQUE_CONTROL", 1.0)] + [status("TORQUE_CONTROL", 1.0 + k * 0.005) for k in (1, 2, 3)]
            return []

        c = self.connect(h)
        c.torque_control(dt_status=0.005)
        while len(c._buf.split(b"\n")) < 4:  # all three ticks received
            c._buf += c._sock.recv(65536)
        seen = []
        c.control(lambda s: seen.append(s.axis_states.time[0]))
        self.assertEqual(seen, [1.015])
        self.assertEqual(c.skipped_ticks, 2)

    def test_a_timeout_closes_the_connection_and_the_next_command_reconnects(self) -> None:
        c = self.connect(lambda cmd: [] if cmd["command"] == "info" else [status()], timeout=0.2)
        with self.assertRaises(mcm.McmTimeout):
            c.info()
        self.assertFalse(c.connected)
        self.assertEqual(c.status().operating_mode, "HOLD")
        self.assertEqual(c.connections, 2)

    def test_a_lost_connection_raises_and_reconnects_unless_told_not_to(self) -> None:
        c = self.connect(lambda cmd: ["CLOSE"] if cmd["command"] == "hold" else [status()])
        with self.assertRaises(mcm.ConnectionLost):
            c.hold()
        self.assertEqual(c.status().operating_mode, "HOLD")
        c2 = mcm.Client("127.0.0.1", self.fake.port, reconnect=False)
        self.addCleanup(c2.close)
        with self.assertRaises(mcm.ConnectionLost):
            c2.hold()
        with self.assertRaises(mcm.ConnectionLost):
            c2.status()

    def test_the_secret_is_presented_after_every_connect(self) -> None:
        c = self.connect(lambda cmd: [OK] if cmd["command"] == "authenticate" else ["CLOSE"], secret="s3")
        with self.assertRaises(mcm.ConnectionLost):
            c.take_control()
        c.connect()
        auths = [m for m in self.fake.received if m["command"] == "authenticate"]
        self.assertEqual(auths, [{"command": "authenticate", "arguments": {"secret": "s3"}}] * 2)

    def test_every_command_of_the_protocol_has_a_method(self) -> None:
        # The protocol's commands as the Rust contract lists them (codes.py is generated).
        self.assertIn("set_velocities", codes.COMMANDS)
        missing = [c for c in codes.COMMANDS if not callable(getattr(mcm.Client, c, None))]
        self.assertEqual(missing, [])

    def test_a_command_without_a_result_on_success_is_not_waited_for(self) -> None:
        # The fake answers `set_torques` with nothing, as the MCM does on success: waiting for a
        # result would end in a timeout.
        c = self.connect(lambda cmd: [] if cmd["command"] in codes.NO_RESULT else [status()], timeout=0.2)
        self.assertEqual(c.command("set_torques", {"torques": [0.0] * 6}), {})
        self.assertEqual(c.status().operating_mode, "HOLD")
        self.assertEqual([m["command"] for m in self.fake.received], ["set_torques", "status"])
        # Told to wait, it waits (and times out here).
        with self.assertRaises(mcm.McmTimeout):
            c.command("set_velocities", {"velocities": [0.0] * 6}, expect_result=True)

    def test_a_result_of_another_type_than_the_protocol_defines_is_refused(self) -> None:
        c = self.connect(lambda cmd: [status()] if cmd["command"] == "info" else [OK])
        with self.assertRaises(mcm.ProtocolError) as e:
            c.info()
        self.assertIn("expected a result of type \"initialization\"", str(e.exception))
        c.take_control()  # a generic result, as defined

    def test_unreachable_mcm_says_where_it_tried(self) -> None:
        closed = socket.socket()  # bound, not listening: connections are refused
        self.addCleanup(closed.close)
        closed.bind(("127.0.0.1", 0))
        port = closed.getsockname()[1]
        with self.assertRaises(mcm.ConnectionLost) as e:
            mcm.Client("127.0.0.1", port)
        self.assertIn("127.0.0.1:%d" % port, str(e.exception))


    def test_the_outcome_and_command_are_read_not_the_words(self) -> None:
        # Reworded refusals: the result's `outcome` and `command` decide, never its words.
        def h(cmd):
            if cmd["command"] == "set_torques":
                return [error("Drehmoment abgelehnt", error_code="wrong_mode", command="set_torques", outcome="refused")]
            if cmd["command"] == "calibrate":
                return [error("move_axis refused: reworded", error_code="calibration_failed", command="calibrate",
                              outcome="failed")]
            if cmd["command"] == "move_axis":
                # An MCM too old to send the fields: words that say "refused" make no refusal.
                return [error("move_axis refused: not allowed in mode OFF", error_code="wrong_mode")]
            return [status("HOLD", 1.0)]

        c = self.connect(h)
        c.set_torques([0] * 6)
        self.assertEqual(c.status().operating_mode, "HOLD")
        [ev] = c.events()
        self.assertIsInstance(ev, mcm.CommandErrorEvent)
        self.assertEqual((ev.command, ev.code, ev.outcome), ("set_torques", "wrong_mode", "refused"))
        with self.assertRaises(mcm.CommandError) as e:
            c.calibrate()
        self.assertEqual((e.exception.command, e.exception.outcome), ("calibrate", "failed"))
        with self.assertRaises(mcm.CommandError) as e:
            c.move_axis(1, 2)
        self.assertEqual((e.exception.command, e.exception.code, e.exception.outcome),
                         ("move_axis", "wrong_mode", "invalid"))


class Codes(unittest.TestCase):
    def test_the_code_is_read_not_the_words(self) -> None:
        # A program decides on the code: words reworded (or in another language) change nothing.
        self.assertEqual(codes.error_code(error("move_axis refused: quelqu'un d'autre", error_code="not_owner")),
                         codes.ErrorCode.NOT_OWNER)
        self.assertEqual(codes.ErrorCode.NOT_OWNER, "not_owner")
        self.assertIsNone(codes.error_code(error("a code of a newer MCM", error_code="something_new")))
        self.assertIsNone(codes.error_code(error("no code")))

    def test_the_outcome_is_read_by_its_wire_name(self) -> None:
        self.assertEqual([o.value for o in codes.Outcome], ["refused", "failed", "invalid", "unknown"])
        self.assertEqual(codes.outcome(error("x", outcome="failed")), codes.Outcome.FAILED)
        self.assertIsNone(codes.outcome(error("an outcome of a newer MCM", outcome="postponed")))
        self.assertIsNone(codes.outcome(error("move_axis refused: no outcome")))

    def test_notices_are_spontaneous_and_refusals_are_not(self) -> None:
        self.assertIn(codes.ErrorCode.GATEWAY_STOPPING, codes.SPONTANEOUS)
        self.assertIn(codes.ErrorCode.IDLE_TIMEOUT, codes.SPONTANEOUS)
        self.assertNotIn(codes.ErrorCode.SHUTTING_DOWN, codes.SPONTANEOUS)
        self.assertNotIn(codes.ErrorCode.NOT_OWNER, codes.SPONTANEOUS)


if __name__ == "__main__":
    unittest.main()
