#!/usr/bin/env bash
# The command path benchmark (docs/performance.md, "Command path benchmark"): builds the `mcm`
# launcher and `mcm-bench` in the release profile, installs cyclictest (Debian's rt-tests) with
# apt-get when it is missing and this runs as root, then runs the benchmark, which starts its
# own simulated MCM (unique instance, free ports), measures, stops it and prints one table.
#
#   scripts/bench.sh            # the real run (60 s latency, 10,000-cycle torque loops)
#   scripts/bench.sh --quick    # a short run to check that everything works
#   scripts/bench.sh --help     # every option of mcm-bench
#
# Run it as root on an otherwise idle machine: mcm-rt and cyclictest need SCHED_FIFO, and the
# torque-loop target assumes nothing else competes for the CPUs.
# Exit status: 0 every target passed, 1 a target failed or was not measured, 2 the run failed.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v cyclictest >/dev/null 2>&1; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
        echo "bench.sh: installing rt-tests (cyclictest) with apt-get" >&2
        DEBIAN_FRONTEND=noninteractive apt-get install -y rt-tests >/dev/null \
            || { apt-get update >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y rt-tests >/dev/null; }
    else
        echo "bench.sh: cyclictest is missing (install rt-tests as root); the latency ratio will not be measured" >&2
    fi
fi

cargo build --release -p mcm -p mcm-bench
target_dir="${CARGO_TARGET_DIR:-target}"
exec "$target_dir/release/mcm-bench" "$@"
