"""A torque-control loop over TCP: the MCM compensates gravity (`gravity_compensation`), and
this loop adds a virtual spring with damping on one axis, answering every status tick
(`dt_status` = one cycle) with `set_torques`. With `--push` (simulated arm only) a second
connection pushes the axis with `sim` external torques for a while: the spring gives way by
about push / stiffness and pulls back when the push ends.

    cargo run --release                      # in one terminal
    pip install ./python
    python3 examples/python/torque_spring.py --host localhost --axis 1 --push 10
"""

import mcm
from _common import parser, ready

p = parser(__doc__.splitlines()[0])
p.add_argument("--axis", type=int, default=1, help="axis with the spring, 1..6 (default %(default)s)")
p.add_argument("--stiffness", type=float, default=2.0, help="[Nm/deg] (default %(default)s)")
p.add_argument("--damping", type=float, default=0.2, help="[Nm/(deg/s)] (default %(default)s)")
p.add_argument("--push", type=float, default=0.0, help="external torque [Nm] from 1 s to 2.5 s (simulated arm only)")
p.add_argument("--duration", type=float, default=4.0, help="[s] (default %(default)s)")
args = p.parse_args()
i = args.axis - 1

with mcm.Client(args.host, args.port) as c, mcm.Client(args.host, args.port) as pusher:
    ready(c)
    info = c.info()
    s = c.torque_control(timeout=0.25, dt_status=info.cycle_time, gravity_compensation=True)
    t0, rest = s.axis_states.time[0], s.axis_states.position[i]
    pushed = {"on": False, "off": False}
    seen = {"pushed": 0.0, "end": 0.0}

    def spring(st: mcm.Status):
        t = st.axis_states.time[0] - t0
        q, v = st.axis_states.position[i], st.axis_states.velocity[i]
        if args.push and not pushed["on"] and t >= 1.0:
            torques = [0.0] * 6
            torques[i] = args.push
            pusher.sim(external_torques=torques)
            pushed["on"] = True
        if args.push and pushed["on"] and not pushed["off"] and t >= 2.5:
            seen["pushed"] = q - rest
            pusher.sim(external_torques=[0.0] * 6)
            pushed["off"] = True
        if t >= args.duration:
            seen["end"] = q - rest
            return None
        torques = [0.0] * 6
        torques[i] = -args.stiffness * (q - rest) - args.damping * v
        return torques

    ticks = c.control(spring)
    print("torque loop: %d status ticks answered over %.1f s" % (ticks, args.duration))
    if args.push:
        print("spring on axis %d: deflection under %.1f Nm %.3f deg (push / stiffness = %.3f deg); "
              "%.3f deg after the push ended"
              % (args.axis, args.push, seen["pushed"], args.push / args.stiffness, seen["end"]))
    c.hold()
