//! The fuzz target of the stored-parameter record ([`ecat_emu::fuzz_parameters::parameters`])
//! on the stable toolchain: a saved record as a seed, cut at every length, and random bytes.

use ecat_emu::fuzz_parameters::{StoredOd, parameters, record};
use proptest::prelude::*;

/// A record this firmware saves, and every prefix of it (a record cut short).
#[test]
fn a_saved_record_and_its_prefixes_run_clean() {
    let saved = record(&StoredOd::default());
    for len in 0..=saved.len() {
        parameters(&saved[..len]);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn random_bytes_run_clean(data in proptest::collection::vec(any::<u8>(), 0..400)) {
        parameters(&data);
    }

    /// Records of well-formed entries of the dictionary's indices with random values, so the
    /// random inputs reach the typed writers.
    #[test]
    fn random_entries_run_clean(
        entries in proptest::collection::vec(
            (0x2000u16..=0x2004, 0u8..=4, proptest::collection::vec(any::<u8>(), 0..8)),
            0..20,
        )
    ) {
        let mut data = vec![1];
        for (index, sub, value) in entries {
            data.extend(index.to_le_bytes());
            data.extend([sub, value.len() as u8]);
            data.extend(value);
        }
        parameters(&data);
    }
}
