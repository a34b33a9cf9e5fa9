"""The shared-memory client's own logic, without iceoryx2 or a running MCM (its live tests
are in ``test_shm_live.py``)."""

import time
import unittest

import mcm
from mcm.shm import ShmClient


class ShmWithoutMcm(unittest.TestCase):
    def test_a_missing_reply_is_an_unknown_outcome_naming_the_wait(self) -> None:
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
