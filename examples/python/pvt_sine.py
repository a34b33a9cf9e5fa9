"""Stream a sine on one axis with pvt_points: batches of points at `dt` spacing, each sent
while the previous still has points queued, so the stream never runs dry.

    cargo run --release                      # in one terminal
    pip install ./python
    python3 examples/python/pvt_sine.py --host localhost --axis 2 --amplitude 10 --period 2 --cycles 2
"""

import math

import mcm
from _common import parser, ready

p = parser(__doc__.splitlines()[0])
p.add_argument("--axis", type=int, default=2, help="axis 1..6 (default %(default)s)")
p.add_argument("--amplitude", type=float, default=10.0, help="[deg] (default %(default)s)")
p.add_argument("--period", type=float, default=2.0, help="[s] (default %(default)s)")
p.add_argument("--cycles", type=int, default=2, help="sine periods to run (default %(default)s)")
p.add_argument("--dt", type=float, default=0.01, help="point spacing [s] (default %(default)s)")
args = p.parse_args()

with mcm.Client(args.host, args.port) as c:
    ready(c)
    c.pvt(args.dt)
    s = c.status(detail=True)
    assert s.detail is not None
    home = list(s.detail.commanded_position)
    i = args.axis - 1
    w = 2 * math.pi / args.period
    n = int(round(args.cycles * args.period / args.dt))

    def point(k: int) -> mcm.PvtPoint:
        # 1 - cos: starts and ends at rest at `home`, peaks at twice the amplitude.
        t = k * args.dt
        pos, vel = list(home), [0.0] * 6
        pos[i] += args.amplitude * (1 - math.cos(w * t))
        vel[i] = args.amplitude * w * math.sin(w * t)
        return mcm.PvtPoint(pos, vel)

    batch = max(1, int(round(0.5 / args.dt)))  # half a second of points per batch
    k, peak = 1, 0.0
    while k <= n:
        c.pvt_points([point(j) for j in range(k, min(k + batch, n + 1))])
        k += batch
        # Wait until less than half a batch is left, reading the arm meanwhile.
        while True:
            s = c.status(detail=True)
            assert s.detail is not None
            peak = max(peak, abs(s.axis_states.position[i] - home[i]))
            if k > n or s.detail.pvt_queue.get("queued", 0) < batch // 2:
                break
            c.sleep(args.dt * 5)
    while True:
        s = c.status(detail=True)
        assert s.detail is not None
        peak = max(peak, abs(s.axis_states.position[i] - home[i]))
        if s.detail.pvt_queue.get("queued", 0) == 0:
            break
        c.sleep(args.dt * 5)
    print("streamed %d points on axis %d; peak excursion %.3f deg (expected %.3f); starved: %s"
          % (n, args.axis, peak, 2 * args.amplitude, s.detail.pvt_queue.get("starved")))
    c.hold()
