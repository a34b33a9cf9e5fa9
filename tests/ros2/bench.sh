#!/usr/bin/env bash
# The ROS 2 node's benchmark (tests/ros2/bench.py, docs/performance.md "ROS 2 node"), by hand,
# as root: makes a private network namespace (DDS's multicast stays on its loopback, never on
# the machine's network), starts the simulated MCM with its ROS 2 node in it, runs bench.py
# there with the environment rclpy needs, and on exit (or Ctrl-C) stops the MCM and deletes
# the namespace.
#
#   tests/ros2/bench.sh [--mcm PATH] [--python PATH] [--domain N] [bench.py arguments...]
#   tests/ros2/bench.sh --seconds 600 --goals 20
#
# --mcm: the launcher (default target/release/mcm); --python: the venv that tests/end_to_end/ros2.rs
# makes (default target/tmp/ros2-venv/bin/python; `cargo test --test end_to_end ros2::` makes it);
# --domain: the ROS domain id, 1..=101 (default from the process id). The rest goes to bench.py
# (`--seconds`, `--goals`, `--config`: see its docstring). Run it under `nice -n 10` to keep the
# node and the subscriber at low priority (the core's cycle thread is SCHED_FIFO either way).
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
mcm=$repo/target/release/mcm
py=$repo/target/tmp/ros2-venv/bin/python
domain=$(($$ % 101 + 1))
args=()
while (($#)); do
    case $1 in
    --mcm) mcm=$2; shift 2 ;;
    --python) py=$2; shift 2 ;;
    --domain) domain=$2; shift 2 ;;
    *) args+=("$1"); shift ;;
    esac
done
[[ -x $mcm ]] || { echo "bench.sh: no MCM launcher at $mcm (cargo build --release, or --mcm PATH)" >&2; exit 2; }
[[ -x $py ]] || { echo "bench.sh: no ROS 2 venv Python at $py (cargo test --test end_to_end ros2:: makes it, or --python PATH)" >&2; exit 2; }
((domain >= 1 && domain <= 101)) || { echo "bench.sh: --domain $domain: allowed 1..=101" >&2; exit 2; }

ns=mcm-bench-$$
instance=rosbench$$
log=$(mktemp -d)
mcm_pid=

cleanup() {
    if [[ -n $mcm_pid ]] && kill -0 "$mcm_pid" 2>/dev/null; then
        kill -TERM "$mcm_pid"
        for _ in $(seq 100); do kill -0 "$mcm_pid" 2>/dev/null || break; sleep 0.1; done
        kill -0 "$mcm_pid" 2>/dev/null && kill -KILL "$mcm_pid"
        wait "$mcm_pid" 2>/dev/null || true
        grep '^mcm-rt: stopped' "$log/mcm.out" || true
    fi
    ip netns del "$ns" 2>/dev/null || true
    rm -rf "$log"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

ip netns add "$ns"
ip -n "$ns" link set lo up
ip -n "$ns" link set lo multicast on
ip -n "$ns" route add 224.0.0.0/4 dev lo

ip netns exec "$ns" "$mcm" --instance "$instance" --bind 127.0.0.1 --json-port 0 --hmi-port 0 \
    --http-port 0 --ros2 --ros2-arg=--domain-id="$domain" --ros2-arg=--ros-distro=kilted \
    >"$log/mcm.out" 2>&1 &
mcm_pid=$!
json=
for _ in $(seq 600); do
    json=$(sed -n 's/^MCM ready .* json=\([^ ]*\) .*/\1/p' "$log/mcm.out")
    [[ -n $json ]] && grep -q '^mcm-ros2 ready' "$log/mcm.out" && break
    kill -0 "$mcm_pid" 2>/dev/null || { cat "$log/mcm.out" >&2; echo "bench.sh: the MCM stopped" >&2; exit 2; }
    sleep 0.1
done
[[ -n $json ]] || { cat "$log/mcm.out" >&2; echo "bench.sh: the MCM was not ready within 60 s" >&2; exit 2; }
echo "MCM $(basename "$mcm") instance $instance in netns $ns, JSON $json, ROS domain $domain"

ip netns exec "$ns" env -u _ROS_WHEELS_BOOTSTRAP_COMPLETE -u ROS_AUTOMATIC_DISCOVERY_RANGE \
    -u ROS_STATIC_PEERS -u ROS_LOCALHOST_ONLY -u ROS_DISCOVERY_SERVER \
    -u FASTDDS_DEFAULT_PROFILES_FILE -u FASTRTPS_DEFAULT_PROFILES_FILE \
    -u RMW_FASTRTPS_USE_QOS_FROM_XML -u ROS_SECURITY_ENABLE \
    RMW_IMPLEMENTATION=rmw_fastrtps_cpp ROS_DOMAIN_ID="$domain" ROS_LOG_DIR="$log/ros" \
    PYTHONUNBUFFERED=1 PYTHONDONTWRITEBYTECODE=1 \
    "$py" "$repo/tests/ros2/bench.py" --json "$json" ${args[@]+"${args[@]}"}
