"""Calibrate the arm, enter PVT mode and move one axis, then read back where it stands.

    cargo run --release                      # in one terminal
    pip install ./python
    python3 examples/python/calibrate_and_move.py --host localhost --axis 1 --target 20
"""

import time

import mcm
from _common import parser, ready

p = parser(__doc__.splitlines()[0])
p.add_argument("--axis", type=int, default=1, help="axis 1..6 (default %(default)s)")
p.add_argument("--target", type=float, default=20.0, help="target angle [deg] (default %(default)s)")
p.add_argument("--velocity-factor", type=float, default=0.5, help="share of the maximum velocity")
args = p.parse_args()

with mcm.Client(args.host, args.port) as c:
    ready(c)
    c.pvt()
    c.move_axis(args.axis, args.target, args.velocity_factor)
    print("move_axis %d -> %.3f deg accepted; moving" % (args.axis, args.target))
    deadline = time.monotonic() + 30
    while True:
        s = c.status()
        pos = s.axis_states.position[args.axis - 1]
        vel = s.axis_states.velocity[args.axis - 1]
        if abs(pos - args.target) < 1e-3 and abs(vel) < 1e-6:
            break
        if time.monotonic() > deadline:
            raise SystemExit("axis %d did not arrive: at %.3f deg" % (args.axis, pos))
        c.sleep(0.05)
    print("axis %d at %.3f deg (mode %s)" % (args.axis, pos, s.operating_mode))
    c.hold()
