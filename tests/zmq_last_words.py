"""What a ZeroMQ subscriber hears when mcm-rt is killed, run by tests/end_to_end/zmq.rs (not an example).
Subscribes to `state` and `error`, prints `subscribed` once a state arrived (the subscription is
through), then prints every `error` message as `error: JSON` until the gateway's own last one
(`the MCM is shutting down ...`). Exits non-zero with the reason when nothing comes within 20 s.

    python3 tests/zmq_last_words.py PUBLISH_ENDPOINT
"""

import json
import sys

import zmq

ctx = zmq.Context()
sub = ctx.socket(zmq.SUB)
sub.setsockopt(zmq.RCVTIMEO, 20_000)
sub.setsockopt(zmq.LINGER, 0)
sub.connect(sys.argv[1])
sub.setsockopt(zmq.SUBSCRIBE, b"state")
sub.setsockopt(zmq.SUBSCRIBE, b"error")


def receive():
    try:
        return sub.recv_multipart()
    except zmq.Again:
        raise SystemExit("FAILED: nothing on the PUB socket within 20 s")


while receive()[0] != b"state":
    pass
print("subscribed", flush=True)
while True:
    topic, payload = receive()
    if topic != b"error":
        continue
    e = json.loads(payload)
    print("error: %s" % json.dumps(e), flush=True)
    if e.get("error_message", "").startswith("the MCM is shutting down"):
        break
