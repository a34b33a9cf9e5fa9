"""Log the arm's state to a CSV file: one row per status read (every `--interval` seconds),
with the robot's time, the mode, and each axis's position, velocity and current.

    cargo run --release                      # in one terminal
    pip install ./python
    python3 examples/python/state_logger.py --host localhost --duration 5 --out state.csv
"""

import csv

import mcm
from _common import parser

p = parser(__doc__.splitlines()[0])
p.add_argument("--out", default="mcm-state.csv", help="CSV file to write (default %(default)s)")
p.add_argument("--duration", type=float, default=5.0, help="[s] (default %(default)s)")
p.add_argument("--interval", type=float, default=0.05, help="[s] between reads (default %(default)s)")
args = p.parse_args()

header = ["time_s", "mode"]
for name in ("position_deg", "velocity_deg_s", "current_a"):
    header += ["%s_%d" % (name, a) for a in range(1, 7)]

rows = 0
with mcm.Client(args.host, args.port) as c, open(args.out, "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(header)
    s = c.status()
    start = last = s.axis_states.time[0]
    while True:
        a = s.axis_states
        if rows == 0 or a.time[0] != last:  # several reads within one cycle show one state
            w.writerow([a.time[0], s.operating_mode] + a.position + a.velocity + a.current)
            rows += 1
            last = a.time[0]
        if last - start >= args.duration:
            break
        c.sleep(args.interval)  # waits on the MCM, so the connection never idles out
        s = c.status()
print("wrote %d rows over %.2f s (robot clock) to %s" % (rows, last - start, args.out))
