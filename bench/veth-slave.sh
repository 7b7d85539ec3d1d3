# Sourced by the virtual-slave benchmarks (rtt-virtual-slave.sh, soak-virtual-slave.sh): one
# end of a veth pair in a network namespace of its own with ecat-virtual-slave serving on it,
# the other end ($master_if) for the MainDevice; all of it removed on exit. Needs root.

# serve_on_veth TAG BIN [LAUNCHER...] -- SLAVE_ARGS...: starts BIN/ecat-virtual-slave under
# LAUNCHER (e.g. `chrt -f 20`) and waits until it serves. Sets master_if, work (a scratch
# directory; the slave's output is $work/slave.log) and slave_pid.
serve_on_veth() {
    local tag=$1 bin=$2
    shift 2
    local launcher=()
    while [ "$1" != -- ]; do launcher+=("$1"); shift; done
    shift
    ns=ecat-$tag-$$
    master_if=e${tag:0:2}m$$
    slave_if=e${tag:0:2}s$$
    work=$(mktemp -d)
    slave_pid=
    trap remove_veth EXIT
    ip netns add "$ns"
    ip link add "$master_if" type veth peer name "$slave_if" netns "$ns"
    ip link set "$master_if" up
    ip netns exec "$ns" ip link set "$slave_if" up
    ip netns exec "$ns" "${launcher[@]}" "$bin/ecat-virtual-slave" --iface "$slave_if" "$@" \
        >"$work/slave.log" 2>&1 &
    slave_pid=$!
    for _ in $(seq 100); do
        grep -q "Ctrl-C to stop" "$work/slave.log" && return
        kill -0 "$slave_pid" 2>/dev/null || { cat "$work/slave.log"; exit 1; }
        sleep 0.1
    done
}

# stop_slave: SIGTERM, then the slave's summary (without its start-up line).
stop_slave() {
    kill -TERM "$slave_pid"
    wait "$slave_pid" || true
    slave_pid=
    grep -v '^serving' "$work/slave.log"
}

remove_veth() {
    [ -n "$slave_pid" ] && kill -INT "$slave_pid" 2>/dev/null && wait "$slave_pid" 2>/dev/null || true
    ip link del "$master_if" 2>/dev/null || true
    ip netns del "$ns" 2>/dev/null || true
    rm -rf "$work"
}
