"""SOEM (pysoem) as the MainDevice of a benchmark: brings a line to OP and runs process-data
cycles at a fixed period for a given time, counting the cycles whose frame came back late (after
--late-us, 2 ms), not at all (lost: nothing within --receive-us, 20 ms) or with another working
counter, and the round trips (send to receive). SOEM waits the longer time so that a late frame
is taken in its own cycle: one left in the socket after SOEM gave its slot up is taken later for
the answer to a newer frame with the same index (SOEM cycles through 16), and from then on every
cycle got the answer of an earlier one (round trips of 16 us, AL status reads unanswered). Every --sample seconds it prints a line: the cycles of the
window, their round-trip p50/p99/max, whether every SubDevice is in OP (AL status read between
two cycles), and the RSS and CPU share of the processes given with --pid (the virtual slaves).
Every second a BRD of the AL status (one frame, between two cycles) checks that every
SubDevice is still in OP; one that fell back (the SM watchdog expires when a cycle comes more
than 100 ms after the last, as a stalled MainDevice or slave on a loaded machine makes it) is
counted, reported and brought back to OP as a MainDevice does (error acknowledged, SAFEOP,
OP), and the cycles go on. Exit status 1 when any cycle was lost, late or wrong, or a SubDevice
left OP.

Used by bench/soak-virtual-slave.sh and for the figures in docs/performance.md.
"""

import argparse
import os
import sys
import time

import pysoem

TICK = os.sysconf("SC_CLK_TCK")


def rss_kb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return -1


def cpu_ticks(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return int(fields[11]) + int(fields[12])  # utime + stime


def read_states(master):
    """Reads every AL status; a status of 0 is SOEM's mark for no answer within its own 2 ms
    (EC_TIMEOUTRET), not a state: read again, up to five times."""
    for _ in range(5):
        master.read_state()
        if all(s.state != 0 for s in master.slaves):
            return


def not_op(master):
    """The SubDevices not in OP: position, AL status, AL status code."""
    return [
        (n, hex(s.state), hex(s.al_status))
        for n, s in enumerate(master.slaves)
        if s.state != pysoem.OP_STATE
    ][:10]


def recover(master):
    """Brings every SubDevice that left OP back: acknowledge its error into SAFEOP, then OP
    (completed by the next cycles' outputs). Returns what they were: (position, state, code)."""
    read_states(master)
    fallen = not_op(master)
    for n, s in enumerate(master.slaves):
        if s.state != pysoem.OP_STATE:
            s.state = pysoem.SAFEOP_STATE | pysoem.STATE_ACK
            s.write_state()
            s.state = pysoem.OP_STATE
            s.write_state()
    return fallen


def percentile(sorted_us, p):
    if not sorted_us:
        return 0
    return sorted_us[min(len(sorted_us) - 1, max(0, -(-len(sorted_us) * p // 100) - 1))]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--iface", required=True)
    ap.add_argument("--count", type=int, required=True, help="SubDevices expected on the line")
    ap.add_argument("--seconds", type=float, default=10)
    ap.add_argument("--period-us", type=int, default=1000)
    ap.add_argument("--late-us", type=int, default=2000, help="a frame later than this is late")
    ap.add_argument("--receive-us", type=int, default=20000, help="SOEM's receive timeout")
    ap.add_argument("--sample", type=float, default=60, help="seconds between report lines")
    ap.add_argument("--pid", type=int, action="append", default=[], help="process to sample")
    args = ap.parse_args()

    m = pysoem.Master()
    m.open(args.iface)
    found = m.config_init()
    if found != args.count:
        print(f"found {found} SubDevices, expected {args.count}")
        return 1
    try:
        size = m.config_map()
    except pysoem.ConfigMapError as e:
        # SOEM mapped the line all the same; the sample devices of this tree have no 0x1C00,
        # which SOEM reads and records as an error.
        size = sum(len(s.output) + len(s.input) for s in m.slaves)
        print(f"config_map recorded {len(e.error_list)} SDO errors (e.g. {e.error_list[0]})")
    if m.state_check(pysoem.SAFEOP_STATE, 10_000_000) != pysoem.SAFEOP_STATE:
        read_states(m)
        if any(s.state != pysoem.SAFEOP_STATE for s in m.slaves):
            print("not all in SAFEOP:", not_op(m))
            return 1
    expected = m.expected_wkc
    m.send_processdata()
    m.receive_processdata(args.receive_us)
    m.state = pysoem.OP_STATE
    m.write_state()
    for _ in range(2000):
        m.send_processdata()
        m.receive_processdata(args.receive_us)
        if m.state_check(pysoem.OP_STATE, 1000) == pysoem.OP_STATE:
            break
    if m.state_check(pysoem.OP_STATE, 100_000) != pysoem.OP_STATE:
        read_states(m)
        if any(s.state != pysoem.OP_STATE for s in m.slaves):
            print("not all in OP:", not_op(m))
            return 1
    print(
        f"{found} SubDevices in OP, image {size} bytes, expected WKC {expected}; "
        f"{args.seconds:.0f} s at {args.period_us} us, late over {args.late_us} us",
        flush=True,
    )

    period = args.period_us * 1000
    start = time.monotonic_ns()
    deadline = start
    end = start + int(args.seconds * 1e9)
    window_end = start + int(args.sample * 1e9)
    window, all_us = [], []
    totals = {"cycles": 0, "lost": 0, "late": 0, "wrong": 0, "not_op": 0, "fallbacks": 0}
    next_check = start + 1_000_000_000
    lost = late = wrong = 0
    ticks = {pid: cpu_ticks(pid) for pid in args.pid}
    rss0 = {pid: rss_kb(pid) for pid in args.pid}
    rss_max = dict(rss0)
    window_start = start
    print("t_s cycles lost late wrong p50_us p99_us max_us all_op " + " ".join(
        f"rss_kB[{p}] cpu%[{p}]" for p in args.pid), flush=True)
    while True:
        now = time.monotonic_ns()
        if now >= end:
            break
        t0 = time.perf_counter_ns()
        m.send_processdata()
        wkc = m.receive_processdata(args.receive_us)
        rt = (time.perf_counter_ns() - t0) // 1000
        if wkc < 0:
            lost += 1
        else:
            window.append(rt)
            if rt > args.late_us:
                late += 1
            if wkc != expected:
                wrong += 1
        deadline += period
        now = time.monotonic_ns()
        if now < deadline:
            time.sleep((deadline - now) / 1e9)
        elif now > deadline + 10 * period:
            deadline = now  # far behind: start again from now rather than burst
        if now >= next_check:
            next_check = now + 1_000_000_000
            # SOEM's own receive timeout (EC_TIMEOUTRET): with none, the BRD's answer arrives
            # after SOEM gave its frame slot up, and SOEM takes later frames for wrong ones.
            if m.state_check(pysoem.OP_STATE, args.receive_us) != pysoem.OP_STATE:
                fallen = recover(m)
                totals["fallbacks"] += 1
                print(f"{(now - start) / 1e9:.1f} s: left OP {fallen}", flush=True)
        if now >= window_end:
            read_states(m)
            all_op = all(s.state == pysoem.OP_STATE for s in m.slaves)
            if not all_op:
                print("not in OP:", not_op(m), flush=True)
            elapsed = (now - window_start) / 1e9
            window.sort()
            cols = []
            for pid in args.pid:
                t = cpu_ticks(pid)
                r = rss_kb(pid)
                rss_max[pid] = max(rss_max[pid], r)
                cols.append(f"{r} {100 * (t - ticks[pid]) / TICK / elapsed:.1f}")
                ticks[pid] = t
            cycles = len(window) + lost
            print(
                f"{(now - start) / 1e9:.0f} {cycles} {lost} {late} {wrong} {percentile(window, 50)} "
                f"{percentile(window, 99)} {window[-1] if window else 0} {int(all_op)} "
                + " ".join(cols),
                flush=True,
            )
            totals["cycles"] += cycles
            totals["lost"] += lost
            totals["late"] += late
            totals["wrong"] += wrong
            totals["not_op"] += 0 if all_op else 1
            all_us.extend(window)
            window, lost, late, wrong = [], 0, 0, 0
            window_start = now
            window_end = now + int(args.sample * 1e9)
    cycles = len(window) + lost
    totals["cycles"] += cycles
    totals["lost"] += lost
    totals["late"] += late
    totals["wrong"] += wrong
    all_us.extend(window)
    all_us.sort()
    read_states(m)
    all_op = all(s.state == pysoem.OP_STATE for s in m.slaves)
    if not all_op:
        print("not in OP:", not_op(m), flush=True)
    totals["not_op"] += 0 if all_op else 1
    seconds = (time.monotonic_ns() - start) / 1e9
    rss = " ".join(f"RSS[{p}] {rss0[p]} -> {rss_kb(p)} kB (max {rss_max[p]})" for p in args.pid)
    print(
        f"total: {totals['cycles']} cycles in {seconds:.0f} s ({totals['cycles'] / seconds:.0f}/s), "
        f"{totals['lost']} lost, {totals['late']} late, {totals['wrong']} wrong WKC, round trip p50 "
        f"{percentile(all_us, 50)} us p99 {percentile(all_us, 99)} us max "
        f"{all_us[-1] if all_us else 0} us; fallbacks out of OP (recovered): "
        f"{totals['fallbacks']}; samples not all in OP: {totals['not_op']}; {rss}",
        flush=True,
    )
    in_op = totals["fallbacks"] == 0 and totals["not_op"] == 0
    for p in args.pid:
        print(f"RSS of {p}: {rss0[p]} kB at the start, {rss_kb(p)} kB at the end, {rss_max[p]} kB at most")
    print(
        f"lost: {totals['lost']}, late: {totals['late']} of {totals['cycles']} cycles; "
        f"wrong WKC: {totals['wrong']}; every SubDevice in OP throughout: "
        f"{'yes' if in_op else 'no'} (OP checked every second, AL status of all every "
        f"{args.sample:.0f} s)",
        flush=True,
    )
    m.state = pysoem.INIT_STATE
    m.write_state()
    m.close()
    failed = (
        totals["lost"] or totals["late"] or totals["wrong"] or totals["not_op"] or totals["fallbacks"]
    )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
