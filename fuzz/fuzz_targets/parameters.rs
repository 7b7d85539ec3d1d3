//! libFuzzer target: the stored-parameter record (0x1010) loaded from the fuzzer's bytes
//! ([`ecat_emu::fuzz_parameters::parameters`]). Run from the repository root:
//! `cargo fuzz run parameters -s none -- -max_total_time=60`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    ecat_emu::fuzz_parameters::parameters(data);
});
