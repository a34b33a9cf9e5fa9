"""Draw a square in the air with move_linear: the TCP on four straight sides in the horizontal
plane through where it starts, its orientation kept, each corner checked on the TCP state the
MCM reports once the arm is at rest there.

    cargo run --release                      # in one terminal
    pip install ./python
    python3 examples/python/draw_square.py --host localhost --side 0.1 --velocity 0.1
"""

import mcm
from _common import parser, ready

p = parser(__doc__.splitlines()[0])
p.add_argument("--start", type=float, nargs=6, default=[20, 30, 60, -40, 50, 10],
               help="the joint angles [deg] the square starts from (a corner)")
p.add_argument("--side", type=float, default=0.1, help="the square's side [m]")
p.add_argument("--velocity", type=float, default=0.1, help="the TCP's speed on each side [m/s]")
args = p.parse_args()


def at_rest(c: mcm.Client, until: float) -> mcm.Status:
    """The status once the robot's clock has passed ``until`` [s] and every axis is at rest."""
    s = c.status()
    for _ in range(2000):
        still = all(abs(v) < 1e-6 for v in s.axis_states.velocity)
        if s.axis_states.time[0] >= until and still:
            return s
        c.sleep(0.02)
        s = c.status()
    raise RuntimeError("the arm did not come to rest by %.3f s (robot clock)" % until)


with mcm.Client(args.host, args.port) as c:
    ready(c)
    c.pvt()
    r = c.move_all(args.start, 0.5)
    s = at_rest(c, c.status().axis_states.time[0] + r.max_time_to_target)
    assert s.cartesian_state is not None, "no cartesian_state: is every axis calibrated?"
    x, y, z = s.cartesian_state.position
    d = args.side
    corners = [(x + d, y, z), (x + d, y + d, z), (x, y + d, z), (x, y, z)]
    print("start corner [m]: %.4f %.4f %.4f" % (x, y, z))
    worst = 0.0
    for i, corner in enumerate(corners, 1):
        line = c.move_linear(corner, velocity=args.velocity)
        s = at_rest(c, c.status().axis_states.time[0] + line.duration)
        got = s.cartesian_state.position
        err = max(abs(a - b) for a, b in zip(got, corner))
        worst = max(worst, err)
        print("side %d: %.3f s, corner %s, reached %s, error %.6f m"
              % (i, line.duration, [round(v, 4) for v in corner], [round(v, 4) for v in got], err))
    print("square of %.3f m drawn; largest corner error %.6f m" % (d, worst))
    c.hold()
