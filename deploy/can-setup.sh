#!/usr/bin/env bash
# Bring up the P-Rob2 CAN interface for mcm-rt: 500 kbit/s, a transmit queue deep enough for a
# whole cycle of frames, automatic restart after bus-off.
# Usage: sudo deploy/can-setup.sh [can0] [500000]
set -euo pipefail
iface=${1:-can0}
bitrate=${2:-500000}
ip link set "$iface" down 2>/dev/null || true
ip link set "$iface" type can bitrate "$bitrate" restart-ms 100
ip link set "$iface" txqueuelen 1000
ip link set "$iface" up
ip -details link show "$iface"
