//! libFuzzer target: the FoE parser and server driven by the fuzzer's bytes
//! ([`ecat_emu::fuzz_foe::foe`]). Run from the repository root:
//! `cargo fuzz run foe -s none -- -max_total_time=60` (stable toolchain; `-s none`: no
//! sanitizer, the core has no unsafe code to check).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ecat_emu::fuzz_foe::foe(data);
});
