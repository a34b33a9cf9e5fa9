"""The shared-memory encoding (``mcm.wire``) against the Rust contract's rules
(``shared/src/command.rs``, ``shared/src/reply.rs``). Standard library only: no iceoryx2."""

import time
import unittest

import mcm
from mcm import codes, encoding, layout, wire


class Encode(unittest.TestCase):
    def test_move_axis_and_move_all_put_their_arguments_in_order(self) -> None:
        s = wire.move_axis(2, 30.0, 0.5)
        self.assertEqual((s.kind, s.flags, list(s.args[:3])), (8, 0, [2.0, 30.0, 0.5]))
        s = wire.move_all([1, 2, 3, 4, 5, 6], 0.25)
        self.assertEqual((s.kind, list(s.args[:7])), (9, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 0.25]))

    def test_a_pvt_batch_is_split_into_samples_of_four_the_last_marked(self) -> None:
        pts = [mcm.PvtPoint([k] * 6, [-k] * 6) for k in range(1, 10)]
        chunks = wire.pvt_chunks(pts)
        self.assertEqual([c.flags & 0xFF for c in chunks], [4, 4, 1])
        self.assertEqual([bool(c.flags & layout.PVT_FLAG_LAST) for c in chunks], [False, False, True])
        # Point j of a sample: six positions, then six velocities, at 12 * j.
        self.assertEqual(list(chunks[1].args[12:24]), [6.0] * 6 + [-6.0] * 6)
        self.assertEqual(list(chunks[2].args[:12]), [9.0] * 6 + [-9.0] * 6)

    def test_calibrate_torque_control_and_sim_flags(self) -> None:
        s = wire.calibrate("WRIST", 1, -1, force_mechanical_stop=True)
        self.assertEqual((list(s.args[:3]), s.flags), ([8.0, 1.0, -1.0], layout.CALIBRATE_FLAG_FORCE_STOP))
        self.assertEqual(wire.calibrate(3).args[0], 3.0)
        s = wire.torque_control(None, gravity_compensation=False)
        self.assertEqual((s.args[0], s.flags), (-1.0, layout.TORQUE_FLAG_NO_GRAVITY))
        s = wire.sim(emergency_stop=True, block_axis=2, external_torques=[0, 5, 0, 0, 0, 0], power_cycle=True)
        self.assertEqual(s.flags, 1 | (1 << 3) | (1 << 5) | layout.SIM_FLAG_POWER_CYCLE)
        self.assertEqual((s.args[0], s.args[3], s.args[6]), (1.0, 2.0, 5.0))
        # Request::encode: the true tool's mass and centre of mass in args[11..15], flag bit 6.
        s = wire.sim(true_tool={"mass": 2.0, "center_of_mass": [0.0, 0.0, 0.06]})
        self.assertEqual((s.flags, list(s.args[11:15])), (1 << 6, [2.0, 0.0, 0.0, 0.06]))
        with self.assertRaises(ValueError):
            wire.sim(true_tool={"mass": 2.0, "center_of_mass": [0.0, 0.06]})

    def test_identify_payload_carries_apply_as_its_flag(self) -> None:
        # Request::encode: no arguments; `apply` is flag bit 0.
        s = wire.identify_payload(apply=True)
        self.assertEqual((s.kind, s.flags, list(s.args[:2])), (19, layout.IDENTIFY_FLAG_APPLY, [0.0, 0.0]))
        self.assertEqual(wire.identify_payload().flags, 0)

    def test_velocity_control_and_set_velocities_as_the_contract_lays_them_out(self) -> None:
        # Request::encode: velocity_control's timeout in args[0] (-1: none), no flags;
        # set_velocities' six velocities in args[0..6].
        s = wire.velocity_control(0.5)
        self.assertEqual((s.kind, s.flags, s.args[0]), (codes.KINDS["velocity_control"], 0, 0.5))
        self.assertEqual(s.kind, 16)
        self.assertEqual(wire.velocity_control(None).args[0], -1.0)
        self.assertEqual(wire.velocity_control(-3).args[0], -1.0)
        s = wire.set_velocities([10, 0, 0, 0, 0, -5.5])
        self.assertEqual((s.kind, s.flags, list(s.args[:7])), (17, 0, [10.0, 0, 0, 0, 0, -5.5, 0.0]))
        with self.assertRaises(ValueError):
            wire.velocity_control(0)
        with self.assertRaises(ValueError):
            wire.set_velocities([0] * 5)
        with self.assertRaises(ValueError):
            wire.set_velocities([float("nan")] + [0] * 5)

    def test_set_cartesian_velocity_as_the_contract_lays_it_out(self) -> None:
        # Request::encode: linear in args[0..3], angular in args[3..6], the frame in args[6]
        # (0 base, 1 tool), no flags.
        s = wire.set_cartesian_velocity([0.05, 0, -0.01], [0, 10, 0], "tool")
        self.assertEqual(
            (s.kind, s.flags, list(s.args[:8])),
            (codes.KINDS["set_cartesian_velocity"], 0, [0.05, 0, -0.01, 0, 10.0, 0, 1.0, 0.0]),
        )
        self.assertEqual(wire.set_cartesian_velocity([0, 0, 0], [0, 0, 0]).args[6], 0.0)
        with self.assertRaises(ValueError):
            wire.set_cartesian_velocity([0, 0, 0], [0, 0, 0], "world")
        with self.assertRaises(ValueError):
            wire.set_cartesian_velocity([0, 0], [0, 0, 0])
        with self.assertRaises(ValueError):
            wire.set_cartesian_velocity([0, 0, float("inf")], [0, 0, 0])

    def test_bad_values_are_refused_before_sending(self) -> None:
        with self.assertRaises(ValueError):
            wire.move_axis(7, 0)
        with self.assertRaises(ValueError):
            wire.set_torques([0] * 5)
        with self.assertRaises(ValueError):
            wire.torque_control(0)
        with self.assertRaises(ValueError):
            wire.pvt_chunks([])
        p = mcm.PvtPoint([0.0] * 6, [0.0] * 6)
        most = encoding.MAX_POINTS_PER_BATCH
        self.assertEqual(len(wire.pvt_chunks([p] * most)), -(-most // layout.PVT_POINTS_PER_COMMAND))
        with self.assertRaises(ValueError) as e:
            wire.pvt_chunks([p] * (encoding.MAX_POINTS_PER_BATCH + 1))
        self.assertIn("expected 1 to 1000 points, got 1001", str(e.exception))


class Decode(unittest.TestCase):
    def reply(self, kind: str, status: int, code: int = 0, axis: int = 0, values=()) -> layout.Reply:
        r = layout.Reply(seq=5, client_id=7, request_id=3, cycle=99, kind=codes.KINDS[kind], status=status,
                         code=code, axis=axis)
        for i, v in enumerate(values):
            r.values[i] = v
        return r

    def test_move_all_figures(self) -> None:
        a = wire.decode_reply(self.reply("move_all", codes.REPLY_OK, values=[1, 2, 3, 0, 0, 0, 3, 1.25]))
        assert a.move_all is not None
        self.assertEqual((a.command, a.cycle, a.move_all.longest, a.move_all.max_time_to_target), ("move_all", 99, 3, 1.25))

    def test_payload_figures(self) -> None:
        # Response::encode: mass, the centre of mass, the residual.
        a = wire.decode_reply(self.reply("identify_payload", codes.REPLY_OK, values=[2.01, 0.001, -0.002, 0.059, 0.14]))
        assert a.payload is not None
        p = a.payload
        self.assertEqual((p.mass, p.center_of_mass, p.residual), (2.01, [0.001, -0.002, 0.059], 0.14))
        with self.assertRaises(mcm.CommandError) as e:
            wire.decode_reply(self.reply("identify_payload", codes.REPLY_REJECTED, code=22, values=[45.0, 15.0]))
        self.assertEqual((e.exception.code, e.exception.outcome), ("not_identifiable", "refused"))
        self.assertIn("condition number 45, at most 15", e.exception.message)

    def test_refusals_raise_in_the_gateways_words(self) -> None:
        with self.assertRaises(mcm.CommandError) as e:
            wire.decode_reply(self.reply("move_axis", codes.REPLY_REJECTED, code=16, values=[0.25]))
        self.assertEqual(e.exception.message, "move_axis refused: a motion is in progress (0.250 s left); wait until "
                                              "it ends, or send `hold` to stop it")
        self.assertEqual((e.exception.code, e.exception.outcome), ("busy", "refused"))
        with self.assertRaises(mcm.CommandError) as e:
            wire.decode_reply(self.reply("calibrate", codes.REPLY_FAILED, code=15))
        self.assertEqual((e.exception.code, e.exception.outcome), ("aborted", "failed"))

    def test_reply_location_matches_the_ring(self) -> None:
        ring = layout.REPLY_BLOCKS * layout.REPLY_BLOCK
        self.assertEqual(layout.reply_location(1), (1, 0))
        self.assertEqual(layout.reply_location(17), (2, 0))
        self.assertEqual(layout.reply_location(ring + 1), (1, 0))


class ShmWithoutIceoryx(unittest.TestCase):
    def test_missing_or_wrong_iceoryx2_is_a_clear_error(self) -> None:
        from mcm import shm

        saved = shm.iox2
        try:
            shm.iox2 = None
            with self.assertRaises(mcm.ShmUnavailable) as e:
                shm.ShmClient("nope")
            self.assertIn("pip install", str(e.exception))
            self.assertIn("0.10.0", str(e.exception))
        finally:
            shm.iox2 = saved

    def test_a_missing_reply_is_an_unknown_outcome_naming_the_wait(self) -> None:
        from mcm.shm import ShmClient

        c = ShmClient.__new__(ShmClient)  # no services: no state ever comes
        c.reply_timeout, c._replies, c._sent_at = 5.0, {}, {7: 0}

        def no_state(timeout: float) -> None:
            time.sleep(timeout)  # stands in for the blocking wait on the state-ready event
            raise mcm.McmTimeout("no new state")

        c.wait_state = no_state  # type: ignore[method-assign]
        with self.assertRaises(mcm.OutcomeUnknown) as e:
            c.wait_reply(7, timeout=0.2)
        self.assertEqual((e.exception.code, e.exception.outcome), ("outcome_unknown", "unknown"))
        self.assertIn("no reply from the real-time core within 0.2 s", e.exception.message)
        self.assertEqual(c._sent_at, {}, "the request is forgotten")


if __name__ == "__main__":
    unittest.main()
