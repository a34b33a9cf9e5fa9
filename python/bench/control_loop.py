"""Benchmark of the shared-memory control loop (ShmClient.control): over N cycles (10,000 by
default) in TORQUE_CONTROL, the share of answers to state k that the core applied in cycle
k + 1 (the reply's cycle), against a target of 99.9 %. Prints the figures and PASS or FAIL.
Not a test: run it on an idle machine, as the same user as the MCM.

    cargo run --release -- --instance bench       # in one terminal
    pip install './python[shm]'
    python3 python/bench/control_loop.py --instance bench --host localhost

It calibrates first if needed (over TCP: --host/--port), enters TORQUE_CONTROL with gravity
compensation and answers every state with zero extra torques (the arm floats where it is).
"""

import argparse
import os
import sys
import time

import mcm

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--host", default=mcm.DEFAULT_HOST, help="MCM address, to calibrate (default %(default)s)")
p.add_argument("--port", type=int, default=mcm.DEFAULT_PORT, help="JSON port (default %(default)s)")
p.add_argument("--instance", default="default", help="MCM instance (default %(default)s)")
p.add_argument("--cycles", type=int, default=10_000, help="cycles to measure (default %(default)s)")
p.add_argument("--target", type=float, default=99.9, help="required share [%%] (default %(default)s)")
p.add_argument("--cpu", type=int, help="run on this CPU only, e.g. the core's cycle.cpu (docs/clients.md)")
args = p.parse_args()
if args.cpu is not None:
    os.sched_setaffinity(0, {args.cpu})
    print("running on CPU %d" % args.cpu)

with mcm.Client(args.host, args.port) as c:
    c.hold()
    s = c.status(detail=True)
    if s.detail is not None and not s.detail.all_calibrated:
        print("calibrating ...", flush=True)
        c.calibrate()
    c.hold()

with mcm.ShmClient(args.instance) as shm:
    shm.torque_control(timeout=0.1, gravity_compensation=True)
    zero = [0.0] * 6
    t0 = time.monotonic()
    stats = shm.control(lambda state: zero, max_cycles=args.cycles)
    wall = time.monotonic() - t0

share = 100 * stats.on_time_share
print("cycles %d in %.1f s, missed %d, applied in the next cycle %d, later %d, unanswered %d"
      % (stats.cycles, wall, stats.missed_cycles, stats.next_cycle, stats.late, stats.unanswered))
verdict = "PASS" if share >= args.target else "FAIL"
print("%s: %.3f %% of answers applied in cycle k+1 (target >= %.1f %%)" % (verdict, share, args.target))
sys.exit(0 if verdict == "PASS" else 1)
