"""The torque_spring.py loop over shared memory, at the cycle rate: ShmClient.control() calls
the callback with every state the real-time core publishes (it blocks on the core's
state-ready event) and sends its torques; the core applies them in the next cycle. It must run
on the robot computer, as the same user as the MCM, with the package's `shm` extra.

    cargo run --release                      # in one terminal
    pip install './python[shm]'
    python3 examples/python/torque_spring_shm.py --host localhost --instance default --axis 1 --push 10

`--host/--port` are used only to calibrate first (over TCP); `--instance` names the MCM.
"""

import mcm
from mcm import wire
from _common import parser, ready
from mcm.codes import MODES

p = parser(__doc__.splitlines()[0])
p.add_argument("--axis", type=int, default=1, help="axis with the spring, 1..6 (default %(default)s)")
p.add_argument("--stiffness", type=float, default=2.0, help="[Nm/deg] (default %(default)s)")
p.add_argument("--damping", type=float, default=0.2, help="[Nm/(deg/s)] (default %(default)s)")
p.add_argument("--push", type=float, default=0.0, help="external torque [Nm] from 1 s to 2.5 s (simulated arm only)")
p.add_argument("--duration", type=float, default=4.0, help="[s] (default %(default)s)")
args = p.parse_args()
i = args.axis - 1

with mcm.Client(args.host, args.port) as tcp:
    ready(tcp)  # calibrated, in HOLD; the TCP connection does not keep control

with mcm.ShmClient(args.instance) as shm:
    shm.torque_control(timeout=0.25, gravity_compensation=True)
    first = shm.wait_state()
    t0, rest = first.t_ns, first.position[i]
    pushed = {"on": False, "off": False}
    seen = {"pushed": 0.0, "end": 0.0}

    def spring(st):
        if MODES.get(st.mode) != "TORQUE_CONTROL":
            raise SystemExit("the mode left TORQUE_CONTROL: %s" % MODES.get(st.mode))
        t = (st.t_ns - t0) / 1e9
        q, v = st.position[i], st.velocity[i]
        if args.push and not pushed["on"] and t >= 1.0:
            torques = [0.0] * 6
            torques[i] = args.push
            shm.send(wire.sim(external_torques=torques))  # its reply is not waited for
            pushed["on"] = True
        if args.push and pushed["on"] and not pushed["off"] and t >= 2.5:
            seen["pushed"] = q - rest
            shm.send(wire.sim(external_torques=[0.0] * 6))
            pushed["off"] = True
        if t >= args.duration:
            seen["end"] = q - rest
            return None
        torques = [0.0] * 6
        torques[i] = -args.stiffness * (q - rest) - args.damping * v
        return torques

    stats = shm.control(spring)
    print("shared-memory torque loop: %d cycles, %d missed, %.2f %% of answers applied in the next cycle"
          % (stats.cycles, stats.missed_cycles, 100 * stats.on_time_share))
    if args.push:
        print("spring on axis %d: deflection under %.1f Nm %.3f deg (push / stiffness = %.3f deg); "
              "%.3f deg after the push ended"
              % (args.axis, args.push, seen["pushed"], args.push / args.stiffness, seen["end"]))
