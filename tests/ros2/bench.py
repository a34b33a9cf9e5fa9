"""Benchmark of the MCM's ROS 2 node with real ROS 2 (rclpy, Fast DDS): docs/performance.md,
"ROS 2 node". Run by hand through tests/ros2/bench.sh, which makes a private network namespace,
starts the simulated MCM with its node in it, runs this script there with the environment
rclpy needs, and cleans up:

    tests/ros2/bench.sh --seconds 600 --goals 20           # the real run: about 12 minutes
    nice -n 10 tests/ros2/bench.sh --seconds 600 --goals 20 # the same at low priority
    tests/ros2/bench.sh --seconds 30 --goals 5              # a short try

By hand, as root (what bench.sh does; PY is the venv of tests/end_to_end/ros2.rs,
target/tmp/ros2-venv/bin/python; N a free namespace name, D a domain id 1..=101):

    ip netns add N; ip -n N link set lo up; ip -n N link set lo multicast on
    ip -n N route add 224.0.0.0/4 dev lo
    ip netns exec N target/release/mcm --instance bench1 --bind 127.0.0.1 --json-port 0 \\
        --hmi-port 0 --http-port 0 --ros2 --ros2-arg=--domain-id=D \\
        --ros2-arg=--ros-distro=kilted &    # note json=ADDR
    ip netns exec N env RMW_IMPLEMENTATION=rmw_fastrtps_cpp ROS_DOMAIN_ID=D PYTHONUNBUFFERED=1 \\
        PY tests/ros2/bench.py --json ADDR --seconds 600 --goals 20
    kill %1; ip netns del N

What it measures (each figure printed with its target and PASS/FAIL; `n/a` where a figure
could not be taken, never an invented number):

1. `/joint_states` for `--seconds`: every message's receive time (`time.time_ns()` in the
   rclpy callback, a SingleThreadedExecutor spun in this thread) and header stamp (the
   CLOCK_REALTIME time of the cycle that measured it). The window is two JSON `status` replies
   (cycle counter and CLOCK_MONOTONIC time of their cycles): the cycles the core ran in it
   against the messages stamped in it (target: at least 99.9 % published); the gaps between
   consecutive stamps (a gap of k periods is k - 1 periods without a message: a state the node
   missed or DDS lost, or a cycle the core itself did not run, an overrun; the core's overrun
   count over the window is printed beside it); the node's own counters from `/diagnostics`
   ("joint states missed", "joint states not sent") over the window; the age of each sample
   when the callback got it, receive time minus stamp (targets: p50 below 1 ms, p99 below 5
   ms).
2. `--goals` FollowJointTrajectory goals, each from rest (the truth's velocity below 1e-3
   rad/s), alternately out and back: "trajectory start latency [cycles]" from the first
   `/diagnostics` message received after each goal's result (target: at most 2 cycles from
   acceptance to the cycle that queued the first points); during the goals a thread samples
   JSON `status` `detail.following_error` (commanded minus measured, per cycle it saw) against
   each axis's `following_error_deg` of the configuration (`--config`), and another the
   simulation's truth (`sim`) to compare with the desired positions of the goals' feedback
   (the truth interpolated at the feedback's stamp between the two `sim` replies around it).
"""

import argparse
import bisect
import math
import os
import sys
import threading
import time
import tomllib

import rclpy
from rclpy.action import ActionClient
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

from action_msgs.msg import GoalStatus
from control_msgs.action import FollowJointTrajectory
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectoryPoint

from node_checks import AXES, Failure, Json, dur, expect

WAIT = 30.0  # longest single wait [s]
LATENCY_KEY = "trajectory start latency [cycles]"


def stamp_ns(t):
    return t.sec * 1_000_000_000 + t.nanosec


def clock_offset_ns():
    """CLOCK_REALTIME minus CLOCK_MONOTONIC [ns], from the tightest of a few reads."""
    best = None
    for _ in range(20):
        a = time.monotonic_ns()
        r = time.time_ns()
        b = time.monotonic_ns()
        if best is None or b - a < best[0]:
            best = (b - a, r - (a + b) // 2)
    return best[1]


def percentile(sorted_values, q):
    """The nearest-rank percentile q (0..100) of sorted values."""
    if not sorted_values:
        return float("nan")
    k = max(0, math.ceil(q / 100 * len(sorted_values)) - 1)
    return sorted_values[k]


def verdict(ok):
    return "PASS" if ok else "FAIL"


def row(what, value, target=""):
    print(f"| {what} | {value} | {target} |", flush=True)


class Bench:
    def __init__(self, args):
        rclpy.init()
        self.node = Node("mcm_bench")
        self.ex = SingleThreadedExecutor()
        self.ex.add_node(self.node)
        ns = args.namespace.rstrip("/")
        self.names = [args.prefix + a for a in AXES]
        self.recording = False
        self.recv = []  # receive CLOCK_REALTIME [ns]
        self.stamps = []  # header stamp [ns]
        self.latest_state = None
        self.diagnostics = []  # (receive monotonic [s], {key: value})
        qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST)
        self.node.create_subscription(JointState, f"{ns}/joint_states", self._state, qos)
        self.node.create_subscription(DiagnosticArray, "/diagnostics", self._diag, 10)
        self.action = ActionClient(self.node, FollowJointTrajectory, f"{ns}/follow_joint_trajectory")
        self.args = args

    @property
    def json(self):
        """A new JSON connection: the gateway closes one that sent nothing for
        `idle_timeout_s` (300 s by default), as this one would between the window's ends."""
        return Json(self.args.json)

    def _state(self, m):
        t = time.time_ns()
        self.latest_state = m
        if self.recording:
            self.recv.append(t)
            self.stamps.append(stamp_ns(m.header.stamp))

    def _diag(self, m):
        for s in m.status:
            if s.name.startswith("mcm:"):
                self.diagnostics.append((time.monotonic(), {kv.key: kv.value for kv in s.values}))
                del self.diagnostics[:-100]

    def spin_until(self, pred, what, timeout=WAIT):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            v = pred()
            if v:
                return v
            self.ex.spin_once(timeout_sec=0.05)
        raise Failure(f"{what}: not within {timeout} s")

    def diag_after(self, t, what):
        """The first diagnostics received after monotonic time t."""
        return self.spin_until(
            lambda: next((d for (r, d) in self.diagnostics if r > t), None), what, timeout=5.0)

    def close(self):
        self.ex.shutdown(timeout_sec=WAIT)
        self.node.destroy_node()
        rclpy.shutdown()

    # ---- /joint_states ---------------------------------------------------------------------

    def joint_states(self, seconds):
        self.spin_until(lambda: self.latest_state, "/joint_states")
        self.spin_until(lambda: self.diagnostics, "/diagnostics")
        # Warm-up: discovery settled, the first messages' setup costs out of the window.
        end = time.monotonic() + 2.0
        while time.monotonic() < end:
            self.ex.spin_once(timeout_sec=0.05)
        diag0 = self.diagnostics[-1][1]
        s0 = self.json.status()
        off0 = clock_offset_ns()
        period_ns = round(s0["detail"]["timing"]["period_s"] * 1e9)
        load0 = os.getloadavg()
        self.recording = True
        start = time.monotonic()
        next_report = start + 60
        while time.monotonic() < start + seconds:
            self.ex.spin_once(timeout_sec=0.05)
            if time.monotonic() >= next_report:
                next_report += 60
                ages = sorted(r - s for r, s in zip(self.recv, self.stamps))
                print(f"... {time.monotonic() - start:.0f} s: {len(ages)} joint states, age p50 "
                      f"{percentile(ages, 50) / 1e6:.3f} ms, p99 {percentile(ages, 99) / 1e6:.3f} ms",
                      flush=True)
        s1 = self.json.status()
        t1 = time.monotonic()
        # Messages of the window's last cycles still on their way.
        end = time.monotonic() + 0.5
        while time.monotonic() < end:
            self.ex.spin_once(timeout_sec=0.05)
        self.recording = False
        off1 = clock_offset_ns()
        diag1 = self.diag_after(t1, "/diagnostics after the window")
        load1 = os.getloadavg()

        c0, c1 = s0["detail"]["cycle"], s1["detail"]["cycle"]
        m0 = round(s0["axis_states"]["time"][0] * 1e9)
        m1 = round(s1["axis_states"]["time"][0] * 1e9)
        off = (off0 + off1) // 2
        # The window: cycles after the first `status`'s, up to and including the last's. A stamp
        # maps to its cycle's CLOCK_MONOTONIC time within the offsets' difference (microseconds);
        # a quarter period keeps the edges clear of that.
        margin = period_ns // 4
        lo, hi = m0 + off + margin, m1 + off + margin
        window = [(s, r) for s, r in zip(self.stamps, self.recv) if lo < s <= hi]
        stamps = [s for s, _ in window]
        ages = sorted(r - s for s, r in window)
        cycles = c1 - c0
        dupes = len(stamps) - len(set(stamps))
        # Consecutive stamps k periods apart: k - 1 periods without a message. A stamp is its
        # cycle's wake-up time, so a cycle that woke more than half a period late widens the
        # interval before it to 2 and shortens the one after it to 0 periods: the net count
        # (the periods the window's stamps span minus the intervals between them) is what is
        # missing, messages or cycles the core did not run (overruns).
        wide, short = [], 0
        for a, b in zip(stamps, stamps[1:]):
            k = round((b - a) / period_ns)
            if k >= 2:
                wide.append(k - 1)
            elif k <= 0:
                short += 1
        net = round((stamps[-1] - stamps[0]) / period_ns) - (len(stamps) - 1) if stamps else 0
        largest_ms = max((b - a for a, b in zip(stamps, stamps[1:])), default=0) / 1e6
        out_of_order = sum(1 for a, b in zip(stamps, stamps[1:]) if b < a)
        overruns = s1["detail"]["timing"]["overruns"] - s0["detail"]["timing"]["overruns"]

        def counter(d, key):
            try:
                return int(d[key])
            except (KeyError, ValueError):
                return None
        node_missed = [counter(d, "joint states missed") for d in (diag0, diag1)]
        node_unsent = [counter(d, "joint states not sent") for d in (diag0, diag1)]

        published = len(set(stamps))
        share = 100.0 * published / cycles if cycles else float("nan")
        print(f"\n/joint_states over {seconds:.0f} s (cycles {c0}..{c1}, load average "
              f"{load0[0]:.2f} at the start, {load1[0]:.2f} at the end)")
        row("measurement", "value", "target")
        row("---", "---", "---")
        row("cycles the core ran in the window (JSON cycle counter)", cycles)
        row("joint states received, stamped in the window (distinct stamps)", published)
        row("received / cycles", f"{share:.3f} %", f"at least 99.9 %  {verdict(share >= 99.9)}")
        row("stamp intervals of 2 periods or more: count, periods without a message",
            f"{len(wide)}, {sum(wide)}")
        row("stamp intervals under half a period (after a late cycle)", short)
        row("net periods without a message by the stamps; largest interval [ms]",
            f"{net}; {largest_ms:.2f}")
        row("core overruns in the window (deadlines the core did not run)", overruns)
        row("node: joint states missed / not sent in the window (diagnostics, +-1 s at the edges)",
            " / ".join("n/a" if a is None or b is None else str(b - a)
                       for a, b in (node_missed, node_unsent)))
        row("duplicate / out-of-order stamps", f"{dupes} / {out_of_order}")
        if ages:
            p50, p99 = percentile(ages, 50) / 1e6, percentile(ages, 99) / 1e6
            row("age at the subscriber p50 [ms]", f"{p50:.3f}", f"< 1 ms  {verdict(p50 < 1)}")
            row("age at the subscriber p99 [ms]", f"{p99:.3f}", f"< 5 ms  {verdict(p99 < 5)}")
            row("age p99.9 / max [ms]", f"{percentile(ages, 99.9) / 1e6:.3f} / {ages[-1] / 1e6:.3f}")
            row("age min [ms]; ages above 1 ms / 5 ms",
                f"{ages[0] / 1e6:.3f}; {sum(1 for a in ages if a > 1e6)} / {sum(1 for a in ages if a > 5e6)}")
            edges = [0.5, 1, 2, 3, 4, 5, 10, 20]
            counts = [0] * (len(edges) + 1)
            for a in ages:
                counts[bisect.bisect_left(edges, a / 1e6)] += 1
            names = [f"<{edges[0]}"] + [f"{a}-{b}" for a, b in zip(edges, edges[1:])] + [f">{edges[-1]}"]
            row("ages by range [ms]: messages", ", ".join(f"{n}: {c}" for n, c in zip(names, counts)))
        else:
            row("age at the subscriber", "n/a (no message in the window)", "FAIL")
        row("CLOCK_REALTIME - CLOCK_MONOTONIC moved by [us]", f"{(off1 - off0) / 1e3:.1f}")

    # ---- goals -----------------------------------------------------------------------------

    def calibrate(self):
        if self.json.status()["detail"]["all_calibrated"]:
            return
        self.spin_until(lambda: self.diagnostics and self.diagnostics[-1][1].get("drives online") == "6/6",
                        "diagnostics saying all 6 drives are online", timeout=60)
        from std_srvs.srv import Trigger
        cli = self.node.create_client(Trigger, f"{self.args.namespace.rstrip('/')}/calibrate")
        self.spin_until(lambda: cli.service_is_ready(), "the calibrate service")
        fut = cli.call_async(Trigger.Request())
        self.spin_until(fut.done, "calibration", timeout=180)
        expect(fut.result().success, f"calibrate service: {fut.result().message}")
        print(f"calibrated: {fut.result().message}", flush=True)

    def goals(self, n, bands_deg):
        self.calibrate()
        truth, status, rest = self.json, self.json, self.json
        sampling = threading.Event()
        stop = threading.Event()
        fe = []  # (cycle, CLOCK_MONOTONIC of the cycle [ns], following_error deg[6], commanded deg[6])
        tr = []  # (mid CLOCK_MONOTONIC [ns], half the request's span [ns], true position rad[6])

        def sample_status():
            while not stop.is_set():
                if not sampling.is_set():
                    time.sleep(0.005)
                    continue
                r = status.status()
                d = r["detail"]
                fe.append((d["cycle"], round(r["axis_states"]["time"][0] * 1e9), d["following_error"],
                           d["commanded_position"]))
                time.sleep(0.002)

        def sample_truth():
            while not stop.is_set():
                if not sampling.is_set():
                    time.sleep(0.005)
                    continue
                a = time.monotonic_ns()
                q, _ = truth.truth()
                b = time.monotonic_ns()
                tr.append(((a + b) // 2, (b - a) // 2, q))
                time.sleep(0.002)

        threads = [threading.Thread(target=f, daemon=True) for f in (sample_status, sample_truth)]
        for t in threads:
            t.start()
        expect(self.action.wait_for_server(timeout_sec=WAIT), "the follow_joint_trajectory action server")
        latencies, outcomes, feedback = [], [], []
        offset = clock_offset_ns()
        swing = [0.4, -0.3, 0.3, 0.4, -0.4, 0.5]  # rad; out on even goals, back on odd ones
        try:
            for i in range(n):
                # From rest.
                end = time.monotonic() + WAIT
                while max(abs(v) for v in rest.truth()[1]) >= 1e-3:
                    expect(time.monotonic() < end, "the arm at rest before a goal")
                    time.sleep(0.01)
                self.ex.spin_once(timeout_sec=0.01)
                q0 = list(self.latest_state.position)
                sign = 1 if i % 2 == 0 else -1
                target = [q + sign * s for q, s in zip(q0, swing)]
                mid = [(a + b) / 2 for a, b in zip(q0, target)]
                g = FollowJointTrajectory.Goal()
                g.trajectory.joint_names = self.names
                g.trajectory.points = [
                    JointTrajectoryPoint(positions=mid, time_from_start=dur(0.75)),
                    JointTrajectoryPoint(positions=target, velocities=[0.0] * 6, time_from_start=dur(1.5)),
                ]

                def on_feedback(fb):
                    f = fb.feedback
                    des = dict(zip(f.joint_names, f.desired.positions))
                    feedback.append((stamp_ns(f.header.stamp) - offset, [des[nm] for nm in self.names]))

                sampling.set()
                fut = self.action.send_goal_async(g, feedback_callback=on_feedback)
                self.spin_until(fut.done, "goal response")
                handle = fut.result()
                expect(handle.accepted, "the goal was rejected")
                res = handle.get_result_async()
                self.spin_until(res.done, "goal result")
                sampling.clear()
                done = time.monotonic()
                st, r = res.result().status, res.result().result
                outcomes.append(st == GoalStatus.STATUS_SUCCEEDED and r.error_code == 0)
                if not outcomes[-1]:
                    print(f"goal {i + 1}: status {st}, code {r.error_code}: {r.error_string!r}", flush=True)
                d = self.diag_after(done, "/diagnostics after a goal's result")
                lat = d.get(LATENCY_KEY)
                latencies.append(int(lat) if lat is not None and lat.isdigit() else None)
                print(f"goal {i + 1}/{n}: {'SUCCEEDED' if outcomes[-1] else 'not succeeded'}, "
                      f"start latency {lat} cycles", flush=True)
        finally:
            stop.set()
            for t in threads:
                t.join(timeout=WAIT)

        print(f"\n{n} FollowJointTrajectory goals from rest, 1.5 s each "
              f"(swing {', '.join(f'{abs(s):.1f}' for s in swing)} rad)")
        row("measurement", "value", "target")
        row("---", "---", "---")
        row("goals succeeded", f"{sum(outcomes)} of {n}")
        known = [x for x in latencies if x is not None]
        if known:
            worst = max(known)
            counts = {v: known.count(v) for v in sorted(set(known))}
            row("trajectory start latency [cycles]: max (value: goals)",
                f"{worst} ({', '.join(f'{k}: {v}' for k, v in counts.items())})",
                f"at most 2  {verdict(worst <= 2 and len(known) == n)}")
        else:
            row("trajectory start latency [cycles]", "n/a (not in /diagnostics)", "FAIL")
        if len(known) != n:
            row("goals without a start latency in /diagnostics", n - len(known))
        cycles = {c: e for c, _, e, _ in fe}
        if cycles:
            per_axis = [max(abs(e[i]) for e in cycles.values()) for i in range(6)]
            within = all(per_axis[i] <= bands_deg[i] for i in range(6))
            row("following error (commanded - measured), worst per axis [deg]",
                " ".join(f"{x:.4f}" for x in per_axis),
                f"within {' '.join(f'{b:g}' for b in bands_deg)} deg  {verdict(within)}")
            row("worst share of the band", f"{max(per_axis[i] / bands_deg[i] for i in range(6)) * 100:.1f} %")
            row("cycles sampled by `status` during the goals", len(cycles))
        else:
            row("following error", "n/a (no status sample)", "FAIL")
        errs, spans = [], []
        times = [x[0] for x in tr]
        for t, des in feedback:
            j = bisect.bisect_left(times, t)
            if j == 0 or j == len(tr):
                continue
            (ta, ha, qa), (tb, hb, qb) = tr[j - 1], tr[j]
            w = (t - ta) / (tb - ta) if tb > ta else 0.0
            q = [a + w * (b - a) for a, b in zip(qa, qb)]
            errs.append(max(abs(x - y) for x, y in zip(des, q)))
            spans.append(max(ha, hb, tb - ta))
        if errs:
            errs.sort()
            row("feedback desired - truth, p50 / p99 / max over joints [deg]",
                f"{math.degrees(percentile(errs, 50)):.4f} / {math.degrees(percentile(errs, 99)):.4f} / "
                f"{math.degrees(errs[-1]):.4f}")
            row("feedback messages compared; truth samples' spacing p50 / max [ms]",
                f"{len(errs)}; {percentile(sorted(spans), 50) / 1e6:.2f} / {max(spans) / 1e6:.2f}")
        else:
            row("feedback desired - truth", "n/a (no feedback between truth samples)")
        # The desired positions against the core's commanded ones of the newest cycle when the
        # feedback was made (its stamp is taken in the arm loop right after that cycle's state).
        # Which cycle's commanded positions the desired ones match best (0: its own; +1: the
        # next cycle's) says whether the difference is a shift in time.
        by_cycle = {c: (t, q) for c, t, _, q in fe}
        by_time = sorted((t, c) for c, (t, _) in by_cycle.items())
        times = [t for t, _ in by_time]
        period_ns = round(self.json.status()["detail"]["timing"]["period_s"] * 1e9)
        dc, shifts = [], {}
        for t, des in feedback:
            j = bisect.bisect_right(times, t) - 1
            if j < 0 or t - times[j] > period_ns:
                continue
            c = by_time[j][1]

            def error(cycle):
                return max(abs(math.degrees(x) - y) for x, y in zip(des, by_cycle[cycle][1]))
            dc.append(error(c))
            near = [o for o in range(-2, 3) if c + o in by_cycle]
            best = min(near, key=lambda o: error(c + o))
            shifts[best] = shifts.get(best, 0) + 1
        if dc:
            dc.sort()
            row("feedback desired - commanded of its cycle, p50 / p99 / max over joints [deg]",
                f"{percentile(dc, 50):.4f} / {percentile(dc, 99):.4f} / {dc[-1]:.4f} ({len(dc)} feedback messages)")
            row("the cycle whose commanded positions match the desired best, relative to the feedback's (cycles: messages)",
                ", ".join(f"{o:+d}: {n}" for o, n in sorted(shifts.items())))


def bands_from(path):
    with open(path, "rb") as f:
        cfg = tomllib.load(f)
    axes = cfg.get("axis", [])
    expect(len(axes) == 6, f"{path}: {len(axes)} [[axis]] tables, expected 6")
    return [float(a["following_error_deg"]) for a in axes]


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--json", required=True, help="the MCM's JSON address, HOST:PORT")
    p.add_argument("--seconds", type=float, default=60, help="length of the joint-states window (0: skip)")
    p.add_argument("--goals", type=int, default=20, help="how many goals (0: skip)")
    p.add_argument("--config", default=os.path.join(here, "..", "..", "deploy", "prob2.toml"),
                   help="the MCM's configuration, for the following-error bands")
    p.add_argument("--namespace", default="/")
    p.add_argument("--prefix", default="")
    args = p.parse_args()
    bench = Bench(args)
    try:
        bands = bands_from(args.config)
        if args.seconds > 0:
            bench.joint_states(args.seconds)
        if args.goals > 0:
            bench.goals(args.goals, bands)
    except Failure as e:
        print(f"FAILED: {e}", flush=True)
        sys.exit(2)
    finally:
        bench.close()


if __name__ == "__main__":
    main()
