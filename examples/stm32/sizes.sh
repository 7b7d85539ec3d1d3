#!/usr/bin/env bash
# The firmware size benchmark (docs/performance.md, "Firmware size"): builds every variant and
# prints its flash (text + data) and RAM (data + bss) and its ecat share (the variant less the
# `baseline` binary: the same board, executors and drivers without ecat).
# Usage: ./sizes.sh [--top N]   (--top: also the N largest symbols of the digital I/O firmware)
# Every ELF measured is kept in target/sizes/ (`baseline`, `ecat-stm32-no-dictionary-no-leds`, …).
set -euo pipefail
cd "$(dirname "$0")"
export CARGO_TARGET_DIR=target   # the sizes are read from here, whatever the caller set
# Panic locations (embassy's and the "async fn resumed after completion" of ecat-embassy's
# futures) carry source paths: remapped to fixed prefixes, the sizes do not depend on where the
# checkout or cargo's registry lies. Cargo adds these flags to .cargo/config.toml's.
root=$(cd ../.. && pwd)
export CARGO_TARGET_THUMBV7EM_NONE_EABIHF_RUSTFLAGS="--remap-path-prefix=$root=/ecat --remap-path-prefix=${CARGO_HOME:-$HOME/.cargo}=/cargo"
release=target/thumbv7em-none-eabihf/release
size_tool=$(command -v llvm-size || command -v size || true)
[ -n "$size_tool" ] || { echo "(neither llvm-size nor size installed: sizes not printed)"; exit 0; }
# flash and RAM of an ELF: "text+data data+bss"
measure() { "$size_tool" "$1" | awk 'NR == 2 { print $1 + $2, $2 + $3 }'; }
cargo build --release --locked --bin baseline
mkdir -p target/sizes && cp "$release/baseline" target/sizes/baseline
read -r base_flash base_ram < <(measure "$release/baseline")
echo "| variant | flash | RAM | ecat share flash | ecat share RAM |"
echo "|---|---|---|---|---|"
echo "| baseline (no ecat) | $base_flash | $base_ram | — | — |"
row() { # label elf
    local flash ram
    read -r flash ram < <(measure "$2")
    echo "| $1 | $flash | $ram | $((flash - base_flash)) | $((ram - base_ram)) |"
}
# Each variant's ELF is kept as target/sizes/BIN[-FEATURES] for a closer look (llvm-nm, objdump).
variant() { # label cargo-args…
    local label=$1 bin keep; shift
    cargo build --release --locked "$@"
    bin=$(echo "$@" | grep -o 'bin [a-z0-9-]*' | cut -d' ' -f2)
    keep=$(echo "$@" | sed 's/--bin [a-z0-9-]*//; s/--no-default-features//; s/--features//; s/[^a-z0-9]\+/-/g; s/^-*//; s/-*$//')
    cp "$release/$bin" "target/sizes/$bin${keep:+-$keep}"
    row "$label" "$release/$bin"
}
variant "digital I/O, no dictionary, no LED task" --bin ecat-stm32 --features no-dictionary,no-leds
variant "digital I/O, no dictionary (\`no-dictionary\`)" --bin ecat-stm32 --features no-dictionary
variant "digital I/O, SOES's dictionary, no LED task (\`no-leds\`)" --bin ecat-stm32 --features no-leds
variant "axis, its dictionary (\`axis\`)" --bin axis
variant "digital I/O, LAN9252" --bin ecat-stm32 --no-default-features --features lan9252
# Under examples/stm32-bootloader, linked at ACTIVE: FoE in BOOT writes an update into DFU.
variant "digital I/O, SOES's dictionary, firmware update (\`bootloader\`)" --bin ecat-stm32 --features bootloader
variant "digital I/O, stored parameters 0x1010/0x1011 (\`storage\`)" --bin ecat-stm32 --features storage
# The AX58100 on the FMC needs an STM32G474QE (the FMC's pins), not the NUCLEO's RE: its share is
# over the same baseline built for it (no SPI, the FMC's bus cycles instead).
fmc=(--no-default-features --features fmc)
cargo build --release --locked --bin baseline "${fmc[@]}"
cp "$release/baseline" target/sizes/baseline-fmc
read -r spi_flash spi_ram < <(echo "$base_flash $base_ram")
read -r base_flash base_ram < <(measure "$release/baseline")
echo "| baseline on the FMC (no ecat, STM32G474QE) | $base_flash | $base_ram | — | — |"
variant "digital I/O, AX58100 on the FMC (\`fmc\`)" --bin ecat-stm32 "${fmc[@]}"
read -r base_flash base_ram < <(echo "$spi_flash $spi_ram")
# Last, so the binary left behind is the default firmware.
variant "**digital I/O, SOES's dictionary (\`ecat-stm32\`)**" --bin ecat-stm32
if [ "${1:-}" = --top ] && command -v llvm-nm >/dev/null; then
    echo
    echo "Largest symbols of \`ecat-stm32\` (bytes, llvm-nm --size-sort):"
    llvm-nm -C --size-sort --print-size --radix=d "$release/ecat-stm32" \
        | awk '$3 ~ /^[tTrRdD]$/' | tail -n "${2:-25}" | sort -k2 -rn \
        | awk '{ size = $2 + 0; $1 = $2 = $3 = ""; sub(/^ +/, ""); sub(/::h[0-9a-f]+$/, ""); printf "%6d  %s\n", size, substr($0, 1, 110) }'
fi
