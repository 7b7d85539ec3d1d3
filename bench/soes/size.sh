#!/usr/bin/env bash
# SOES's flash and RAM on the MCU of ecat's digital I/O firmware, measured as ecat's share is
# (examples/stm32/sizes.sh; docs/performance.md, "SOES built here, like for like"): SOES's core
# (soes/esc.c, esc_coe.c, ecat_slv.c; FoE and EoE off), the object list of its sample digital I/O
# device (applications/tiesc_am335x/am335xice_objectlist.c), the ET1100/AX58100 SPI layer of
# this directory (esc_hw.c) and a polling main (main.c), for a Cortex-M4F by arm-none-eabi-gcc,
# less `baseline` (baseline.c: the same startup, board and SPI transfer without SOES).
#
# NOT run in CI: SOES comes from GitHub, which CI cannot reach (crates.io, PyPI and apt only).
# Usage: bench/soes/size.sh SOES_SOURCE_DIR
#   SOES_SOURCE_DIR: a checkout of github.com/OpenEtherCATsociety/SOES (measured at 6ef7b94; its
#   commit is printed when the directory is a git checkout).
#   Needs gcc-arm-none-eabi and libnewlib-arm-none-eabi (apt). Builds into a temporary directory,
#   one compile at a time; prints markdown tables: every variant's flash (text + data) and RAM
#   (data + bss) by arm-none-eabi-size and its SOES share, each object's part of the linked -Os
#   firmware (from the link map, after --gc-sections), the 20 largest symbols, and the largest
#   stack frames (gcc -fstack-usage: the stack is in neither figure).
# Variants, each at -Os and at -Os -flto (the share is over the baseline built with the same flags):
#   - the sample's object list as SOES ships it;
#   - the same with 0x1C32 (the table of SOES's applications/rtl_xmc4_dynpdo, the only sample
#     with one) and its copy as 0x1C33, the two objects ecat's dictionary adds;
#   - an object list holding only its terminator: SOES's code without a dictionary.
set -euo pipefail
[ $# -eq 1 ] && [ -f "$1/soes/esc.c" ] || { echo "usage: $0 SOES_SOURCE_DIR (a SOES checkout)" >&2; exit 2; }
src=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
command -v arm-none-eabi-gcc >/dev/null ||
    { echo "arm-none-eabi-gcc is needed (apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi)" >&2; exit 1; }
work=$(mktemp -d)
[ -n "${KEEP:-}" ] && echo "keeping $work" >&2 || trap 'rm -rf "$work"' EXIT

cpu=(-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16)
# -DNDEBUG: SOES's CC_ASSERT is assert(), which would pull printf into the firmware. The
# stringop warnings: with -flto gcc sees the 4-byte process images under SOES's generic PDO copy
# (bounded at run time by the SyncManager's length) and warns of an overflow it cannot rule out.
cflags=("${cpu[@]}" -Os -ffunction-sections -fdata-sections -DNDEBUG -std=gnu11
        -Wno-stringop-overflow -Wno-stringop-overread
        -I"$here" -I"$src/soes" -I"$src/soes/include/sys/gcc")
ldflags=("${cpu[@]}" -Os -Wno-stringop-overflow -Wno-stringop-overread -nostartfiles -specs=nano.specs -specs=nosys.specs -Wl,--gc-sections
         -T "$here/link.ld")

# The object lists, copied out of the tree so that "utypes.h" is this directory's.
sample="$src/applications/tiesc_am335x/am335xice_objectlist.c"
dynpdo="$src/applications/rtl_xmc4_dynpdo/slave_objectlist.c"
cp "$sample" "$work/objectlist.c"
for pair in 1C32: 1C33:In; do   # 0x1C32 as rtl_xmc4_dynpdo declares it, then as 0x1C33 over its own storage
    index=${pair%%:*} suffix=${pair#*:}
    sed -n '/acName1C32\[\]/,/acName1C32_20\[\]/p; /^const _objd SDO1C32\[\]/,/^};/p' "$dynpdo" |
        sed "s/1C32/$index/g; s/SyncMgrParam\./SyncMgrParam$suffix./g" >> "$work/sync_objects.c"
    grep '{0x1C32,' "$dynpdo" | sed "s/1C32/$index/g" >> "$work/sync_entries.c"
done
[ -s "$work/sync_objects.c" ] && [ "$(wc -l < "$work/sync_entries.c")" -eq 2 ] ||
    { echo "0x1C32 not found in $dynpdo" >&2; exit 1; }
awk -v defs="$work/sync_objects.c" -v entries="$work/sync_entries.c" '
    /^const _objectlist SDOobjects/ { while ((getline line < defs) > 0) print line }
    { print }
    /\{0x1C13,/ { while ((getline line < entries) > 0) print line }' "$sample" > "$work/objectlist_sync.c"
cat > "$work/objectlist_empty.c" <<'EOF'
#include "esc_coe.h"
#include <stddef.h>
const _objectlist SDOobjects[] = { {0xffff, 0xff, 0xff, 0xff, NULL, NULL} };
EOF

compile() { # out.o source extra-flags…
    local out=$1 source=$2; shift 2
    arm-none-eabi-gcc "${cflags[@]}" "$@" -c "$source" -o "$out"
}
flash_ram() { arm-none-eabi-size "$1" | awk 'NR == 2 { print $1 + $2, $2 + $3 }'; }

core=(esc esc_coe ecat_slv)
build() { # dir extra-flags… : every object of every variant, then the ELFs
    local dir=$1 f; shift
    mkdir -p "$dir"
    for f in "${core[@]}"; do compile "$dir/$f.o" "$src/soes/$f.c" "$@"; done
    for f in esc_hw board main baseline startup; do compile "$dir/$f.o" "$here/$f.c" "$@"; done
    compile "$dir/objectlist.o" "$work/objectlist.c" "$@"
    compile "$dir/objectlist_sync.o" "$work/objectlist_sync.c" -DSOES_SYNC_PARAMS "$@"
    compile "$dir/main_sync.o" "$here/main.c" -DSOES_SYNC_PARAMS "$@"
    compile "$dir/objectlist_empty.o" "$work/objectlist_empty.c" "$@"
    local common=("$dir/esc.o" "$dir/esc_coe.o" "$dir/ecat_slv.o" "$dir/esc_hw.o" "$dir/board.o" "$dir/startup.o")
    arm-none-eabi-gcc "${ldflags[@]}" "$@" "$dir/board.o" "$dir/baseline.o" "$dir/startup.o" -o "$dir/baseline.elf"
    arm-none-eabi-gcc "${ldflags[@]}" "$@" "${common[@]}" "$dir/main.o" "$dir/objectlist.o" \
        -Wl,-Map="$dir/soes.map" -o "$dir/soes.elf"
    arm-none-eabi-gcc "${ldflags[@]}" "$@" "${common[@]}" "$dir/main_sync.o" "$dir/objectlist_sync.o" \
        -o "$dir/soes-sync.elf"
    arm-none-eabi-gcc "${ldflags[@]}" "$@" "${common[@]}" "$dir/main.o" "$dir/objectlist_empty.o" \
        -o "$dir/soes-empty.elf"
}
build "$work/os" -fstack-usage
build "$work/lto" -flto

echo "SOES $(git -C "$src" rev-parse --short HEAD 2>/dev/null || echo "(not a git checkout)"), $(arm-none-eabi-gcc --version | head -n 1)"
echo
echo "| variant | flash | RAM | SOES share flash | SOES share RAM |"
echo "|---|---|---|---|---|"
for opt in os lto; do
    flags="-Os"; [ "$opt" = lto ] && flags="-Os -flto"
    read -r base_flash base_ram < <(flash_ram "$work/$opt/baseline.elf")
    echo "| baseline (no SOES), $flags | $base_flash | $base_ram | — | — |"
    for variant in "soes-empty:SOES core, empty object list" \
                   "soes:SOES core + sample object list (tiesc_am335x)" \
                   "soes-sync:the same + 0x1C32/0x1C33"; do
        read -r flash ram < <(flash_ram "$work/$opt/${variant%%:*}.elf")
        echo "| ${variant#*:}, $flags | $flash | $ram | $((flash - base_flash)) | $((ram - base_ram)) |"
    done
done

# Each input file's part of the linked -Os firmware, from the link map: .isr_vector, .text and
# .rodata count as flash, .data as flash and RAM, .bss as RAM.
echo
echo "Parts of the -Os firmware (SOES core + sample object list), after --gc-sections:"
echo
echo "| object | flash | RAM |"
echo "|---|---|---|"
awk '
    function hex(s,   n, i, c) { n = 0; s = tolower(substr(s, 3))
        for (i = 1; i <= length(s); i++) { c = index("0123456789abcdef", substr(s, i, 1)) - 1; n = n * 16 + c }
        return n }
    /^Linker script and memory map/ { on = 1; next }
    !on { next }
    /^ \.[^ ]+$/ { pending = $1; next }
    /^ (\.[^ ]+)? +0x[0-9a-f]+ +0x[0-9a-f]+ +[^ ]/ {
        if ($1 ~ /^\./) { name = $1; size = $3 } else { name = pending; size = $2 }
        file = $NF; sub(/.*\//, "", file); sub(/^lib(c|g)_nano\.a\(lib_a-/, "libc ", file); sub(/\)$/, "", file)
        n = hex(size)
        if (name ~ /^\.(text|rodata|isr_vector|ARM\.exidx)/) flash[file] += n
        else if (name ~ /^\.data/) { flash[file] += n; ram[file] += n }
        else if (name ~ /^\.bss|^COMMON/) ram[file] += n
        else next
        seen[file] = 1
    }
    END { for (f in seen) if (flash[f] + ram[f] > 0) printf "| %s | %d | %d |\n", f, flash[f], ram[f] }
' "$work/os/soes.map" | sort -t'|' -k3 -rn

echo
echo "20 largest symbols of the -Os firmware (bytes; arm-none-eabi-nm --size-sort; t/T/r/R code or"
echo "read-only data, d/D data, b/B bss):"
echo
arm-none-eabi-nm --size-sort --print-size --radix=d "$work/os/soes.elf" | tail -n 20 | sort -k2 -rn |
    awk '{ printf "    %5d %s %s\n", $2, $3, $4 }'

echo
echo "Largest stack frames at -Os (bytes, gcc -fstack-usage; outside data + bss):"
echo
cat "$work"/os/*.su | sort -t$'\t' -k2 -rn | head -n 8 | awk -F'\t' '{ n = split($1, p, ":"); printf "    %5d %s (%s)\n", $2, p[n], $3 }'
