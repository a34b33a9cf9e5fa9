"""Drive the MCM over its ZeroMQ interface with pyzmq alone: subscribe to the state, check that
no cycle is missed, calibrate, move one axis and watch it arrive on the state topic.

    cargo run --release -- --zmq             # in one terminal (ROUTER 18012, PUB 18013)
    pip install pyzmq
    python3 examples/python/zmq_client.py --axis 1 --target 20

Commands go to the ROUTER socket from a REQ socket (one JSON command per message, one JSON
result per reply, the same as one line of the JSON/TCP port); the PUB socket sends every cycle's
state as [b"state", status JSON with "cycle"] and every spontaneous error as [b"error", JSON].
"""

import argparse
import json
import time

import zmq

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--router", default="tcp://localhost:18012", help="command endpoint (default %(default)s)")
p.add_argument("--publish", default="tcp://localhost:18013", help="state endpoint (default %(default)s)")
p.add_argument("--cycles", type=int, default=400, help="cycles to count on the state topic (default %(default)s)")
p.add_argument("--axis", type=int, default=1, help="axis 1..6 (default %(default)s)")
p.add_argument("--target", type=float, default=20.0, help="target angle [deg] (default %(default)s)")
p.add_argument("--velocity-factor", type=float, default=0.5, help="share of the maximum velocity")
args = p.parse_args()

ctx = zmq.Context()
sub = ctx.socket(zmq.SUB)
sub.connect(args.publish)
sub.setsockopt(zmq.SUBSCRIBE, b"state")
req = ctx.socket(zmq.REQ)
req.connect(args.router)
req.setsockopt(zmq.RCVTIMEO, 700_000)  # a calibration takes a while; never wait forever


def command(name, **arguments):
    """Send one command, return its result; an ERROR result ends the example."""
    msg = {"command": name}
    if arguments:
        msg["arguments"] = arguments
    req.send(json.dumps(msg).encode())
    result = json.loads(req.recv())
    if result.get("error_status") == "ERROR":
        raise SystemExit("%s: %s" % (name, result["error_message"]))
    return result


def next_state(timeout_s=2.0):
    if not sub.poll(int(timeout_s * 1000)):
        raise SystemExit("no state on %s within %.1f s" % (args.publish, timeout_s))
    _topic, payload = sub.recv_multipart()
    return json.loads(payload)


# 1. The state topic: consecutive cycle numbers, none missed.
first = next_state(5.0)
last, missed, samples = first["cycle"], 0, 1
while samples < args.cycles:
    s = next_state()
    if s["cycle"] <= last:
        raise SystemExit("cycle %d came after cycle %d: repeated or out of order" % (s["cycle"], last))
    missed += s["cycle"] - last - 1
    last, samples = s["cycle"], samples + 1
print("state: %d samples, cycles %d..%d, %d missed" % (samples, first["cycle"], last, missed), flush=True)

# 2. Commands: the drives online, calibrated, PVT, one move.
command("hold")
deadline = time.monotonic() + 20
while not all(command("status", detail=True)["detail"]["drive_online"]):
    if time.monotonic() > deadline:
        raise SystemExit("the drives did not come online within 20 s")
    time.sleep(0.1)
if not command("status", detail=True)["detail"]["all_calibrated"]:
    print("calibrating (about 12 s on the simulated arm) ...", flush=True)
    print("calibrate:", json.dumps(command("calibrate")), flush=True)
print("pvt: mode %s" % command("pvt")["operating_mode"], flush=True)
print("move_axis:", json.dumps(command("move_axis", axis_index=args.axis, target_position=args.target,
                                        velocity_factor=args.velocity_factor)), flush=True)

# 3. Watch it arrive on the state topic (the newest states: drop what queued meanwhile).
deadline = time.monotonic() + 30
while True:
    s = next_state()
    pos = s["axis_states"]["position"][args.axis - 1]
    vel = s["axis_states"]["velocity"][args.axis - 1]
    if abs(pos - args.target) < 1e-3 and abs(vel) < 1e-6:
        break
    if time.monotonic() > deadline:
        raise SystemExit("axis %d did not arrive: at %.3f deg" % (args.axis, pos))
print("axis %d at %.3f deg in cycle %d (mode %s)" % (args.axis, pos, s["cycle"], s["operating_mode"]), flush=True)
command("hold")
