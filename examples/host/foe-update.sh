#!/usr/bin/env bash
# A firmware update of the virtual axis with SOEM (README, "Updating the virtual axis's
# firmware"): ecat-virtual-slave serves the axis (`cia402`, image version 1 in its flash) on one
# end of a veth pair inside a network namespace; on the other end SOEM (pysoem,
# tests/soem/foe_update.py) writes FILE by FoE in BOOT, takes the axis out of BOOT, scans again
# once it restarted into the new image, and runs it in OP. Prints the revision before and after;
# exit status 1 when it is not the version of FILE's image. Needs root (a network namespace, raw
# sockets): as another user it builds the virtual slave, then runs the rest through sudo. It
# installs what it needs (iproute2; python3-venv, gcc and pysoem through .ci/soem-venv).
#
# Usage: examples/host/foe-update.sh FILE    (FILE from `ecat-firmware --version N --out FILE`)
set -euo pipefail
built=
[ "${1:-}" = --built ] && { built=1; shift; }
[ $# -eq 1 ] && [ -f "$1" ] || {
    echo "usage: $0 FILE (an update file: ecat-firmware --version 2 --out FILE)" >&2
    exit 2
}
file=$(realpath "$1")
self=$(realpath "$0")
cd "$(dirname "$self")/../.."

build() { cargo build --locked --release -q -p ecat-examples --bin ecat-virtual-slave; }
if [ "$(id -u)" -ne 0 ]; then
    # With the caller's toolchain; root's environment under sudo may have none. The target
    # directory goes along, so that the root half finds what this half built.
    build
    exec sudo env CARGO_TARGET_DIR="$(realpath -m "${CARGO_TARGET_DIR:-target}")" \
        "$self" --built "$file"
fi
[ -n "$built" ] || build
command -v ip >/dev/null || { apt-get update -qq && apt-get install -y -qq iproute2 >/dev/null; }
venv=$(.ci/soem-venv)

. bench/veth-slave.sh
serve_on_veth foe "${CARGO_TARGET_DIR:-target}/release" -- --device cia402
status=0
"$venv/bin/python" tests/soem/foe_update.py "$master_if" "$file" || status=$?
stop_slave
exit $status
