#!/usr/bin/env bash
# The virtual slave's soak (a benchmark, not a test): SOEM (pysoem, bench/soem_cycle.py) drives
# ecat-virtual-slave (release build) over a veth pair at 1 kHz for DURATION seconds (default one
# hour), with a line of N copies of DEVICE (default 64 × dio). Every minute it prints the cycles,
# the cycles lost (no frame back within 20 ms), late (back after 2 ms) or with a wrong working
# counter, the round trip p50/p99/max, whether every SubDevice is in OP (AL status read between
# two cycles), and the virtual slave's RSS and CPU share; then a total. SubDevices that fell out
# of OP (checked every second) are counted and brought back. Exit status 1 when any cycle was
# lost, late or wrong, or a SubDevice left OP. Needs root (netns, raw sockets).
#
# Ends with the RSS at the start and the end, the lost and late cycles, and whether every
# SubDevice stayed in OP throughout; then the virtual slave's own summary (frames lost on the
# line). Both processes run at SCHED_FIFO 20 when allowed, as EtherCAT MainDevices and
# soft-real-time SubDevices do on Linux (a shared machine's other jobs then do not delay them).
#
# The machine's own floor, measured beside it: cyclictest (rt-tests) wakes a thread per CPU at
# SCHED_FIFO 20 every millisecond for the same time and counts the wakeups more than 2 ms late
# (summed over the CPUs: a round trip crosses both ends, and a stall of either CPU delays it),
# and the hypervisor's steal time is read from /proc/stat. A virtual machine that stops its vCPUs
# for milliseconds makes every 1 kHz loop late, ecat's or not: compare the soak's late cycles
# with that floor.
#
# Usage: bench/soak-virtual-slave.sh [DURATION_S [N [DEVICE]]]
#   RT=0 runs them with normal scheduling instead; NICE=-15 (default 0) at that niceness.
set -euo pipefail
cd "$(dirname "$0")/.."
duration=${1:-3600}
count=${2:-64}
device=${3:-dio}
nice_level=${NICE:-0}
rt="chrt -f 20"
[ "${RT:-1}" = 0 ] && rt=
[ -z "$rt" ] || $rt true 2>/dev/null || rt=

command -v ip >/dev/null || { apt-get update -qq && apt-get install -y -qq iproute2 >/dev/null; }
command -v cyclictest >/dev/null || { apt-get update -qq && apt-get install -y -qq rt-tests >/dev/null; }
venv=$(.ci/soem-venv)
cargo build --locked --release -q -p ecat-examples --bin ecat-virtual-slave
bin=${CARGO_TARGET_DIR:-target}/release

. bench/veth-slave.sh
serve_on_veth soak "$bin" nice -n "$nice_level" $rt -- --device "$device" --count "$count"

echo "soak: $count × $device, $duration s at 1 kHz, nice $nice_level, ${rt:-normal scheduling}; load $(cut -d' ' -f1-3 /proc/loadavg)"
steal() { awk '/^cpu / {print $9}' /proc/stat; }
steal0=$(steal)
cyclictest -m -p 20 -a -t -i 1000 -D "$duration" -q -h 100000 >"$work/cyclictest" 2>&1 &
floor_pid=$!
status=0
nice -n "$nice_level" $rt "$venv/bin/python" bench/soem_cycle.py --iface "$master_if" --count "$count" \
    --seconds "$duration" --sample 60 --pid "$slave_pid" || status=$?
echo "load at the end $(cut -d' ' -f1-3 /proc/loadavg)"
wait "$floor_pid" || true
awk -v tick="$(getconf CLK_TCK)" -v stolen="$(( $(steal) - steal0 ))" '
    /^# Total:/ { for (i = 3; i <= NF; i++) total += $i }
    /^# Max Latencies:/ { for (i = 4; i <= NF; i++) if ($i + 0 > max) max = $i + 0 }
    !/^#/ && $1 + 0 > 2000 { for (i = 2; i <= NF; i++) late += $i }
    END { printf "machine floor: cyclictest at SCHED_FIFO 20, 1 kHz, a thread per CPU: %d of %d wakeups more than 2 ms late (max %d us); hypervisor steal %.1f s\n", late, total, max, stolen / tick }
' "$work/cyclictest"
stop_slave
exit $status
