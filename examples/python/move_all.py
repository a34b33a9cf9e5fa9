"""Move all axes together with move_all and print its result: each axis's peak velocity, the
axis that sets the pace, and the time to the target; then check the arrival on the robot's clock.

    cargo run --release                      # in one terminal
    pip install ./python
    python3 examples/python/move_all.py --host localhost --targets 10 -20 30 0 15 0
"""

import mcm
from _common import parser, ready

p = parser(__doc__.splitlines()[0])
p.add_argument("--targets", type=float, nargs=6, default=[10, -20, 30, 0, 15, 0], help="six angles [deg]")
p.add_argument("--velocity-factor", type=float, default=0.5, help="share of the maximum velocities")
args = p.parse_args()

with mcm.Client(args.host, args.port) as c:
    ready(c)
    c.pvt()
    start = c.status().axis_states.time[0]
    r = c.move_all(args.targets, args.velocity_factor)
    print("move_all result: velocities %s deg/s, longest axis %d, max_time_to_target %.3f s"
          % ([round(v, 3) for v in r.velocities], r.longest, r.max_time_to_target))
    # Wait until the planned time has passed on the robot's clock (not the wall clock) and
    # every axis is at rest.
    s = c.status()
    for _ in range(1000):
        at_rest = all(abs(v) < 1e-6 for v in s.axis_states.velocity)
        if s.axis_states.time[0] - start >= r.max_time_to_target and at_rest:
            break
        c.sleep(0.02)
        s = c.status()
    err = max(abs(a - b) for a, b in zip(s.axis_states.position, args.targets))
    print("arrived after %.3f s (robot clock): positions %s, largest error %.6f deg"
          % (s.axis_states.time[0] - start, [round(x, 3) for x in s.axis_states.position], err))
    c.hold()
