#!/usr/bin/env bash
# Round trips through ecat-virtual-slave at 1 kHz (a benchmark, not a test): N copies of DEVICE
# (default 256 × dio) on one end of a veth pair inside a network namespace, ecat-scan --lrw on
# the other (ethercrab brings the line to OP, then CYCLES cycles of one LRW frame over the whole
# image, one a millisecond, on a raw socket of its own, as SOEM's send_processdata does). Both
# run at a real-time priority, SCHED_FIFO 20 (`RT=0`: normal scheduling), as EtherCAT masters
# and soft-real-time SubDevices run on Linux. Prints the load, ecat-scan's round trips (p50, p99,
# max; late = no answer within 2 ms), the slave's CPU share over the cycles, and its summary.
# Needs root (netns, raw sockets, SCHED_FIFO).
#
# Usage: bench/rtt-virtual-slave.sh [N [CYCLES [DEVICE]]]
#   BIN=DIR takes ecat-virtual-slave from DIR (default: the release build of this tree), e.g.
#   the build of an earlier commit for a before/after comparison under the same load.
set -euo pipefail
cd "$(dirname "$0")/.."
count=${1:-256}
cycles=${2:-20000}
device=${3:-dio}

command -v ip >/dev/null || { apt-get update -qq && apt-get install -y -qq iproute2 >/dev/null; }
cargo build --locked --release -q -p ecat-examples --bin ecat-virtual-slave --bin ecat-scan
release=${CARGO_TARGET_DIR:-target}/release
bin=${BIN:-$release}
rt="chrt -f 20"
[ "${RT:-1}" = 0 ] && rt=
[ -z "$rt" ] || $rt true || { echo "SCHED_FIFO not permitted (RT=0 runs without it)"; exit 1; }

. bench/veth-slave.sh
serve_on_veth rtt "$bin" $rt -- --device "$device" --count "$count"

ticks() { awk '{print $14 + $15}' "/proc/$slave_pid/stat"; }
echo "$count × $device, $cycles cycles at 1 kHz, ${rt:-normal scheduling}, $bin; load $(cut -d' ' -f1-3 /proc/loadavg)"
status=0
$rt "$release/ecat-scan" --iface "$master_if" --cycles "$cycles" --lrw >"$work/scan.log" 2>&1 &
scan=$!
# The slave's CPU over the cycles, not over ethercrab's start-up: from the first LRW on.
until grep -q "SubDevices in OP" "$work/scan.log" 2>/dev/null || ! kill -0 "$scan" 2>/dev/null; do sleep 0.05; done
t0=$(ticks)
s0=$(date +%s.%N)
wait "$scan" || status=$?
t1=$(ticks)
s1=$(date +%s.%N)
grep -v "^  0x" "$work/scan.log"
echo "slave CPU over the cycles: $(echo "$t0 $t1 $s0 $s1 $(getconf CLK_TCK)" | awk '{printf "%.1f %%", 100 * ($2 - $1) / $5 / ($4 - $3)}'); load at the end $(cut -d' ' -f1-3 /proc/loadavg)"
stop_slave
exit $status
