#!/usr/bin/env bash
# Instruction counts of the core, measured with callgrind (repeatable on a shared machine).
# Usage: bench/callgrind.sh    (prints a markdown table; for `line <slaves>` a case is one cycle)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { echo "valgrind is needed (apt-get install valgrind)"; exit 1; }
cargo build --release -q -p ecat-bench --bins
count() { # binary case n -> total instructions
    local out; out=$(mktemp)
    valgrind --tool=callgrind --callgrind-out-file="$out" "target/release/$1" "$2" "$3" >/dev/null 2>&1
    grep -E '^summary:' "$out" | awk '{print $2}'
    rm -f "$out"
}
echo "| benchmark | case | instructions per case |"
echo "|---|---|---|"
for run in "sdo expedited-upload" "sdo upload-1k-128" "sdo upload-1k-1024" "sdo download-1k-128" \
           "sdo download-1k-1024" "pd cia402" "pd cia402-remapped" "pd io64" "pd axis" "line 1" "line 3" "line 100"; do
    set -- $run
    one=$(count "$1" "$2" 1)
    many=$(count "$1" "$2" 1001)
    echo "| $1 | $2 | $(( (many - one) / 1000 )) |"
done
target/release/sdo sizes | sed 's/^/    /'
