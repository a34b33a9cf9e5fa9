"""The manual's "Basic Python3 Example" (MCM User Manual v0.18, "Getting started"), as written:
one `release` command sent without a newline, a fixed 0.1 s wait, one recv. Only two things
differ: the address comes from the command line (the manual hard-codes the robot's), and the
JSON text is in single quotes (the manual prints it in double quotes, which is not valid
Python). It needs no package.

Run against the simulated arm (the MCM executes a complete JSON object at once, newline or not):

    cargo run --release                      # in one terminal
    python3 examples/python/basic.py --host localhost

It prints `generic` (ERROR: `release` needs HOLD and a calibrated arm) or `status`.
"""

import argparse

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--host", default="192.168.80.203", help="MCM address (default: the robot's)")
parser.add_argument("--port", type=int, default=18010, help="JSON port (default 18010)")
parser.add_argument("--instance", default="default", help="unused: this example speaks TCP only")
args = parser.parse_args()

# --- the manual's example from here on ---
import json
import socket
import time
mcm_host = (args.host, args.port)
sock = socket.create_connection(mcm_host)
sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

command_string = '{"command":"release"}' # JSON command
sock.send(command_string.encode("ascii"))
time.sleep(0.1)
data_bytes = sock.recv(4096)
result_string = data_bytes.decode("ascii")
result_json = json.loads(result_string)
print(result_json["result_type"])
