//! libFuzzer target: a SubDevice session driven by the fuzzer's bytes
//! ([`ecat_emu::fuzz::session`]). Run from the repository root:
//! `cargo fuzz run session -s none -- -max_total_time=60` (stable toolchain; `-s none`: no
//! sanitizer, the core has no unsafe code to check).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ecat_emu::fuzz::session(data);
});
