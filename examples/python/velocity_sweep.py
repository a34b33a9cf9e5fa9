"""A velocity sweep over TCP: VELOCITY_CONTROL, one axis at +speed for 1 s, then -speed for
1 s, then `hold`. The loop answers every status tick (`dt_status` = one cycle) with
`set_velocities`; the time is the arm's own (the ticks' timestamps). It prints the start, the
farthest and the end position of the axis: the arm ramps each velocity within its acceleration
and jerk limits, so the axis goes out by about speed x 1 s and comes back near its start.

    cargo run --release                      # in one terminal
    pip install ./python
    python3 examples/python/velocity_sweep.py --host localhost --axis 1 --speed 10
"""

import mcm
from _common import parser, ready

p = parser(__doc__.splitlines()[0])
p.add_argument("--axis", type=int, default=1, help="axis to sweep, 1..6 (default %(default)s)")
p.add_argument("--speed", type=float, default=10.0, help="[deg/s] (default %(default)s)")
p.add_argument("--phase", type=float, default=1.0, help="duration of each direction [s] (default %(default)s)")
args = p.parse_args()
i = args.axis - 1

with mcm.Client(args.host, args.port) as c:
    ready(c)
    info = c.info()
    s = c.velocity_control(timeout=0.5, dt_status=info.cycle_time)
    t0, start = s.axis_states.time[0], s.axis_states.position[i]
    seen = {"far": start}

    def sweep(st: mcm.Status):
        t = st.axis_states.time[0] - t0
        q = st.axis_states.position[i]
        if abs(q - start) > abs(seen["far"] - start):
            seen["far"] = q
        if t >= 2 * args.phase:
            return None
        v = [0.0] * 6
        v[i] = args.speed if t < args.phase else -args.speed
        return mcm.Velocities(v)

    ticks = c.control(sweep)
    c.hold()
    # `hold` brings the axis to rest with the controlled stop: wait for it (bounded).
    for _ in range(200):
        st = c.status()
        if abs(st.axis_states.velocity[i]) < 1e-3:
            break
        c.sleep(0.01)
    end = st.axis_states.position[i]
    print("velocity sweep: %d status ticks answered, axis %d at +%.1f then -%.1f deg/s for %.1f s each"
          % (ticks, args.axis, args.speed, args.speed, args.phase))
    print("axis %d: start %.3f deg, farthest %.3f deg, end %.3f deg (mode %s)"
          % (args.axis, start, seen["far"], end, st.operating_mode))
