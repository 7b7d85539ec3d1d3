#!/usr/bin/env bash
# Instruction counts of the core, measured with callgrind (repeatable on a shared machine).
# Usage: bench/callgrind.sh    (prints a markdown table; for `line <slaves>` a case is one cycle)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { echo "valgrind is needed (apt-get install valgrind)"; exit 1; }
cargo build --release -q -p ecat-bench --bins
count() { # binary case n [function pattern] -> instructions (in that function only, if given)
    local out; out=$(mktemp)
    valgrind --tool=callgrind ${4:+--toggle-collect="$4"} --callgrind-out-file="$out" \
        "target/release/$1" "$2" "$3" >/dev/null 2>&1
    grep -E '^summary:' "$out" | awk '{print $2}'
    rm -f "$out"
}
per_case() { # binary case [function pattern] -> instructions of one case
    local one many
    one=$(count "$1" "$2" 1 "${3:-}")
    many=$(count "$1" "$2" 1001 "${3:-}")
    echo $(( (many - one) / 1000 ))
}
# For an sdo case the second figure is the SubDevice's side alone (`Bench::serve`: the AL event,
# the accesses through the memory driver, the mailbox service), without the MainDevice writing
# the request and reading the answer.
echo "| benchmark | case | instructions per case | SubDevice side |"
echo "|---|---|---|---|"
for run in "sdo expedited-upload" "sdo expedited-upload-pdo" "sdo upload-1k-128" "sdo upload-1k-1024" "sdo download-1k-128" \
           "sdo download-1k-1024" "pd cia402" "pd cia402-remapped" "pd io64" "pd axis" "pd axis-pp" "pd axis-pv" "pd axis-hm" "line 1" "line 3" "line 100"; do
    set -- $run
    side="—"
    [ "$1" = sdo ] && side=$(per_case "$1" "$2" '*Bench*serve*')
    echo "| $1 | $2 | $(per_case "$1" "$2") | $side |"
done
target/release/sdo sizes | sed 's/^/    /'
