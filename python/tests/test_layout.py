"""The ctypes structures against the Rust layouts.

The truth comes from the Rust compiler: ``cargo run -p mcm-shared --example layout`` prints it
as JSON, and ``tests/end_to_end/python_layout.rs`` (run by ``cargo test --workspace``) writes it to a
file named by the environment variable ``MCM_LAYOUT_JSON`` before running this test. Without
that variable the test is skipped, saying so (a failure instead when ``CI`` is set).
"""

import inspect
import json
import os
import re
import unittest

from mcm import codes, layout, wire
from mcm.types import PvtPoint

from . import needs

_PATH = os.environ.get("MCM_LAYOUT_JSON")


@needs.env("MCM_LAYOUT_JSON", "run `cargo test --test end_to_end python_layout::`")
class LayoutMatchesRust(unittest.TestCase):
    @classmethod
    def setUpClass(cls) -> None:
        with open(str(_PATH)) as f:
            cls.rust = json.load(f)

    def test_every_rust_struct_is_mirrored(self) -> None:
        self.assertEqual(sorted(self.rust["structs"]), sorted(layout.STRUCTS))

    def test_sizes_alignments_and_field_offsets(self) -> None:
        for name, want in self.rust["structs"].items():
            got = layout.layout_of(layout.STRUCTS[name])
            with self.subTest(struct=name):
                self.assertEqual(got["size"], want["size"], "%s size" % name)
                self.assertEqual(got["align"], want["align"], "%s alignment" % name)
                # Same fields, same order, same offsets.
                self.assertEqual(list(got["fields"].items()), list(want["fields"].items()))

    def test_type_names_and_layout_versions(self) -> None:
        for name, want in self.rust["structs"].items():
            cls = layout.STRUCTS[name]
            with self.subTest(struct=name):
                if want["type_name"] is None:
                    self.assertFalse(hasattr(cls, "type_name"), "%s is never a payload of its own" % name)
                    continue
                got = cls.type_name()
                self.assertEqual(got, want["type_name"])
                self.assertRegex(got, r"^mcm\.%s\.v\d+$" % name)
        version = re.search(r"\.v(\d+)$", layout.StateSample.type_name())
        self.assertIsNotNone(version)

    def test_constants(self) -> None:
        for name, value in self.rust["constants"].items():
            with self.subTest(constant=name):
                self.assertEqual(getattr(layout, name), value)

    def test_commands_encode_as_rust_encodes_them(self) -> None:
        # Each command as a client writes it in JSON, every argument given, through the function
        # of `wire` of the same name (its keyword arguments are the protocol's names): the
        # samples Rust's `Request::encode` gives.
        kinds = set()
        for c in self.rust["commands"]:
            name, args = c["json"]["command"], c["json"].get("arguments", {})
            kinds.add(name)
            if name == "pvt_points":
                got = wire.pvt_chunks([PvtPoint(p["position"], p["velocity"]) for p in args["points"]])
            elif hasattr(wire, name):
                f = getattr(wire, name)
                params = inspect.signature(f).parameters
                got = [f(**{k: v for k, v in args.items() if k in params})]
            else:
                self.assertEqual(args, {}, "%s has arguments but no function in wire" % name)
                got = [wire.sample(name)]
            with self.subTest(command=c["json"]):
                self.assertEqual(
                    [[s.kind, s.flags, list(s.args)] for s in got],
                    c["samples"],
                )
        self.assertEqual(
            kinds,
            {k for k in codes.KINDS if k != "client_gone"},
            "every command of the protocol that travels in a sample is encoded",
        )

    def test_reply_locations(self) -> None:
        for seq, key, slot in self.rust["reply_locations"]:
            self.assertEqual(layout.reply_location(seq), (key, slot), "reply %d" % seq)

    def test_reason_words(self) -> None:
        for code, axis, values, text in self.rust["reasons"]:
            with self.subTest(code=code):
                self.assertEqual(codes.reason_text(code, axis, values), text)


if __name__ == "__main__":
    unittest.main()
