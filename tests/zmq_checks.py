"""Checks of the MCM's ZeroMQ interface with pyzmq, run by tests/end_to_end/zmq.rs against a calibrated
simulated arm (not an example): one reply per request and an ERROR result for garbage; each
peer is a client of its own (a second peer's motion is refused while the first owns, and its
`hold` is not); a peer whose connection closes loses control; a safety error appears on the
`error` topic. Prints one line per check; exits non-zero with the reason on the first failure.

    python3 tests/zmq_checks.py ROUTER_ENDPOINT PUBLISH_ENDPOINT
"""

import json
import sys
import time

import zmq

router, publish = sys.argv[1], sys.argv[2]
ctx = zmq.Context()


def peer(kind=zmq.REQ):
    s = ctx.socket(kind)
    s.setsockopt(zmq.RCVTIMEO, 10_000)
    s.setsockopt(zmq.LINGER, 0)
    s.connect(router)
    return s


def ask(s, msg):
    s.send(msg if isinstance(msg, bytes) else json.dumps(msg).encode())
    return json.loads(s.recv())


def check(cond, what, got):
    if not cond:
        raise SystemExit("FAILED: %s: %s" % (what, json.dumps(got)))
    print("ok: %s" % what, flush=True)


def move(axis, target, vf=0.5):
    return {"command": "move_axis", "arguments": {"axis_index": axis, "target_position": target, "velocity_factor": vf}}


errors = ctx.socket(zmq.SUB)
errors.connect(publish)
errors.setsockopt(zmq.SUBSCRIBE, b"error")

a, b = peer(zmq.DEALER), peer()
# Garbage and two commands in one message: one ERROR reply each, and the peer goes on.
r = ask(b, b"\xff\x00 not json")
check(r["error_status"] == "ERROR", "garbage bytes get an ERROR result", r)
r = ask(b, b'{"command":"hold"}{"command":"hold"}')
check("more than one command" in r["error_message"], "two commands in one message are refused", r)
r = ask(b, {"command": "status"})
check(r["result_type"] == "status", "the peer goes on after garbage", r)

# Ownership: A (a DEALER) takes control; B's motion is refused, naming A; B's hold is not.
check(ask(a, {"command": "hold"})["operating_mode"] == "HOLD", "hold from A", {})
r = ask(a, {"command": "pvt"})
check(r.get("operating_mode") == "PVT", "A enters PVT and takes control", r)
r = ask(b, move(2, 5.0))
check(r["error_status"] == "ERROR" and "controlled by ZeroMQ client" in r["error_message"],
      "B's move is refused while A owns", r)
r = ask(b, {"command": "status", "arguments": {"detail": True}})
control = r["detail"]["control"]
check(control["owner"].startswith("ZeroMQ client 127.0.0.1") and not control["this_connection"],
      "status detail names the ZeroMQ owner", control)
r = ask(b, {"command": "hold"})
check(r.get("operating_mode") == "HOLD", "B's hold is open to all", r)

# A's connection closes: it loses control (bounded wait), B may take it.
a.close()
deadline = time.monotonic() + 5
while True:
    r = ask(b, {"command": "take_control"})
    if r["error_status"] == "OK":
        break
    if time.monotonic() > deadline:
        check(False, "B takes control after A's connection closed", r)
    time.sleep(0.05)
check(True, "B takes control after A's connection closed", r)

# A safety error on the `error` topic: block axis 1 while it moves.
check(ask(b, {"command": "pvt"}).get("operating_mode") == "PVT", "B enters PVT", {})
start = ask(b, {"command": "status"})["axis_states"]["position"][0]
r = ask(b, move(1, start + 60.0 if start < 0 else start - 60.0))
check(r["error_status"] == "OK", "B moves axis 1", r)
deadline = time.monotonic() + 10
while abs(ask(b, {"command": "status"})["axis_states"]["velocity"][0]) < 10.0:
    if time.monotonic() > deadline:
        check(False, "axis 1 moves", {})
    time.sleep(0.02)
r = ask(b, {"command": "sim", "arguments": {"block_axis": 1}})
check(r["result_type"] == "sim", "sim blocks axis 1", r)
if not errors.poll(10_000):
    check(False, "an error on the error topic within 10 s", {})
topic, payload = errors.recv_multipart()
e = json.loads(payload)
check(topic == b"error" and e["error_status"] == "ERROR" and e.get("check") == "following_error",
      "the following error appears on the error topic", e)
print("error topic: %s" % payload.decode(), flush=True)
print("all checks passed", flush=True)
