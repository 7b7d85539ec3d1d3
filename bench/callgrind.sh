#!/usr/bin/env bash
# Instruction counts of the core, measured with callgrind (repeatable on a shared machine).
# Usage: bench/callgrind.sh    (prints a markdown table)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { echo "valgrind is needed (apt-get install valgrind)"; exit 1; }
cargo build --release -q -p ecat-bench --bin sdo
bin=target/release/sdo
count() { # case n -> total instructions
    local out; out=$(mktemp)
    valgrind --tool=callgrind --callgrind-out-file="$out" "$bin" "$1" "$2" >/dev/null 2>&1
    grep -E '^summary:' "$out" | awk '{print $2}'
    rm -f "$out"
}
echo "| case | instructions per case |"
echo "|---|---|"
for case in expedited-upload upload-1k-128 upload-1k-1024 download-1k-128 download-1k-1024; do
    one=$(count "$case" 1)
    many=$(count "$case" 1001)
    echo "| $case | $(( (many - one) / 1000 )) |"
done
"$bin" sizes | sed 's/^/    /'
