#!/usr/bin/env bash
# Real-time tuning of the robot computer for mcm-rt (run once per boot, as root).
# - lets SCHED_FIFO threads use the whole period (mcm-rt never spins; it sleeps between cycles),
# - moves IRQs of the CAN adapter off the cycle's CPU is left to the integrator (see below),
# - sets the CPU frequency governor to performance where available.
# For the best latency, boot a PREEMPT_RT kernel with `isolcpus=1 nohz_full=1 rcu_nocbs=1`
# (the P-Rob2 config pins the cycle to CPU 1) and measure with `cyclictest -m -p80 -a1 -i5000`.
set -euo pipefail
sysctl -w kernel.sched_rt_runtime_us=-1
for g in /sys/devices/system/cpu/cpu*/cpufreq/scaling_governor; do
  [ -w "$g" ] && echo performance > "$g" || true
done
echo "real-time tuning applied"
