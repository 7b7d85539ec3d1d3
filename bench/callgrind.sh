#!/usr/bin/env bash
# Instruction counts of the core, measured with callgrind (repeatable on a shared machine).
# Usage: bench/callgrind.sh    (prints a markdown table; for `line <slaves>` a case is one cycle,
# for `served <slaves>` one frame)
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
per_case() { # binary case [function pattern [cases]] -> instructions of one case
    local one many n=${4:-1000}
    one=$(count "$1" "$2" 1 "${3:-}")
    many=$(count "$1" "$2" $((n + 1)) "${3:-}")
    echo $(( (many - one) / n ))
}
# For an sdo or foe case the second figure is the SubDevice's side alone (`Bench::serve`: the AL event,
# the accesses through the memory driver, the mailbox service), without the MainDevice writing
# the request and reading the answer.
echo "| benchmark | case | instructions per case | SubDevice side |"
echo "|---|---|---|---|"
for run in "sdo expedited-upload" "sdo expedited-upload-pdo" "sdo upload-1k-128" "sdo upload-1k-1024" "sdo download-1k-128" \
           "sdo download-1k-1024" "foe segment-128" "foe segment-1024" "pd cia402" "pd cia402-remapped" "pd io64" "pd axis" "pd axis-pp" "pd axis-pv" "pd axis-hm" "line 1" "line 3" "line 100"; do
    set -- $run
    side="—"
    case $1 in sdo | foe) side=$(per_case "$1" "$2" '*Bench*serve*') ;; esac
    echo "| $1 | $2 | $(per_case "$1" "$2") | $side |"
done
# What ecat-virtual-slave does per frame of a MainDevice at 1 kHz with 256 × dio in OP (one LRW
# over the image; the ESCs, the runners, the line's clock): 100 frames, not 1000 (each is millions).
echo "| served | 256 | $(per_case served 256 '' 100) | — |"
target/release/sdo sizes | sed 's/^/    /'
# FoE: a 256 KiB image with 128- and 1024-byte mailboxes, round trips against the minimum.
target/release/foe throughput
