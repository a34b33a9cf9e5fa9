"""Plot a flight-recorder file (written by mcm-rt when a safety check trips, see
docs/safety.md "The flight recorder") to a PNG: measured positions, velocities and currents of
every axis over time, with the cycle of the trip marked and the check (from the file name)
in the title. Needs matplotlib.

    cargo run --release                      # in one terminal; make a check trip, e.g.
    #   {"command":"sim","arguments":{"block_axis":2}} while axis 2 moves
    pip install ./python matplotlib
    python3 examples/python/plot_flight_recorder.py /tmp/mcm-flight-recorder/mcm-default-*.csv --out trip.png

`--host/--port/--instance` are accepted like every example's; with no file given, the newest
file of `--instance` in /tmp/mcm-flight-recorder is plotted.
"""

import csv
import glob
import os
import re
import sys

from _common import parser

p = parser(__doc__.splitlines()[0])
p.add_argument("file", nargs="?", help="flight-recorder CSV (default: the newest of --instance)")
p.add_argument("--dir", default="/tmp/mcm-flight-recorder", help="where to look when no file is given")
p.add_argument("--out", help="PNG to write (default: the CSV's name with .png)")
p.add_argument("--axis", type=int, help="the axis the error named (its `axis`), drawn thicker")
args = p.parse_args()

path = args.file
if path is None:
    files = glob.glob(os.path.join(args.dir, "mcm-%s-*.csv" % args.instance))
    if not files:
        sys.exit("no flight-recorder file of instance %r in %s" % (args.instance, args.dir))
    path = max(files, key=os.path.getmtime)
out = args.out or os.path.splitext(path)[0] + ".png"

with open(path, newline="") as f:
    rows = list(csv.DictReader(f))
if not rows:
    sys.exit("%s has no rows" % path)
m = re.match(r"mcm-(.+)-(\d+)-([a-z_]+)\.csv$", os.path.basename(path))
check = m.group(3) if m else "unknown check"
t_trip = float(rows[-1]["t_s"])  # the last row is the cycle of the trip (mode ERROR)
t = [float(r["t_s"]) - t_trip for r in rows]

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

panels = [("measured_deg", "position [deg]"), ("velocity_deg_s", "velocity [deg/s]"), ("current_a", "current [A]")]
fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(10, 8))
for ax, (col, label) in zip(axes, panels):
    for a in range(1, 7):
        width = 2.5 if a == args.axis else 1
        ax.plot(t, [float(r["%s_%d" % (col, a)]) for r in rows], label="axis %d" % a, linewidth=width)
    ax.axvline(0.0, color="red", linestyle="--", linewidth=1.5)
    ax.set_ylabel(label)
    ax.grid(True, alpha=0.3)
axes[0].legend(ncol=6, fontsize="small", loc="upper left")
where = " on axis %d" % args.axis if args.axis else ""
axes[0].annotate("trip: %s%s (cycle %s)" % (check, where, rows[-1]["cycle"]), xy=(0.0, 1.0), xycoords=("data", "axes fraction"),
                 xytext=(-5, -12), textcoords="offset points", ha="right", color="red")
axes[-1].set_xlabel("time relative to the trip [s]")
fig.suptitle("MCM flight recorder: %s tripped\n%s" % (check, os.path.basename(path)))
fig.tight_layout()
fig.savefig(out, dpi=100)
print("plotted %d cycles (%.2f s before the %s trip) to %s" % (len(rows), -t[0], check, out))
