//! The stored-parameter record driven by arbitrary bytes: the fuzz target of its parser
//! ([`ecat_core::dictionary::parameters::load`]), on [`StoredOd`], the dictionary of the
//! stored-parameter tests (`tests/tests/parameters.rs`).
//!
//! [`parameters()`] loads the bytes as a record (a flash holding anything: an older firmware's
//! set, a corrupt one) and asserts that
//! - the parser does not panic;
//! - it counts every entry it meets, applied or skipped, and applies no more than the record
//!   holds (an entry is 4 bytes at least after the format byte);
//! - what it applied respects the declared ranges (the typed writers' checks);
//! - the set it left saves into a record that loads back into the same set.
//!
//! Two drivers run it: `fuzz/fuzz_targets/parameters.rs` (`cargo fuzz run parameters`) and the
//! stable test `tests/tests/fuzz_parameters.rs` (random inputs on every `cargo test`).

use ecat_core::dictionary::parameters::{self, StoredParameters};
use ecat_core::dictionary::{Communication, VisibleString};

use crate::devices::DRIVE_INFO;

/// A record entry of a RECORD object.
pub struct Limits {
    /// 0x2003:01, backed up.
    pub min: i32,
    /// 0x2003:02, not backed up.
    pub max: i32,
}

/// A device with storage: backup entries of each kind (VAR, ARRAY, RECORD entry, string) and
/// entries that are not backed up.
pub struct StoredOd {
    /// The communication area, with 0x1010/0x1011.
    pub area: Communication,
    /// The stored-parameters state.
    pub stored: StoredParameters,
    /// 0x2000, backed up, at most 1000.
    pub gain: u16,
    /// 0x2001, not backed up.
    pub scratch: u32,
    /// 0x2002, backed up, -100..=100.
    pub gains: [i16; 3],
    /// 0x2003.
    pub limits: Limits,
    /// 0x2004, backed up.
    pub label: VisibleString<200>,
}

ecat_core::dictionary! {
    minimal StoredOd {
        communication(area, DRIVE_INFO, stored = stored);
        0x2000 => var(gain, RW | BACKUP, "Gain", default = 7, max = 1000);
        0x2001 => var(scratch, RW, "Scratch", default = 5);
        0x2002 => array(gains, RW | BACKUP, "Gains", "Gain", default = 1, min = -100, max = 100);
        0x2003 => record(limits: Limits, "Limits") {
            1 => min, RW | BACKUP, "Min", default = -10;
            2 => max, RW, "Max", default = 10;
        };
        0x2004 => var(label, RW | BACKUP, "Label");
    }
}

/// The record of `od`'s backup entries.
pub fn record(od: &StoredOd) -> Vec<u8> {
    let mut out = vec![0; parameters::record_size::<StoredOd>()];
    let len = parameters::save(od, &mut out).expect("record_size holds every record");
    out.truncate(len);
    out
}

/// Loads `data` as a record into a fresh [`StoredOd`]; asserts the rules of the module.
pub fn parameters(data: &[u8]) {
    let mut od = StoredOd::default();
    let loaded = parameters::load(&mut od, data);
    let entries = usize::from(loaded.applied) + usize::from(loaded.skipped);
    assert!(
        usize::from(loaded.applied) <= data.len().saturating_sub(1) / parameters::ENTRY_HEADER,
        "{loaded:?} from {} bytes",
        data.len()
    );
    assert!(entries <= data.len(), "{loaded:?}");
    assert!(od.gain <= 1000);
    assert!(od.gains.iter().all(|g| (-100..=100).contains(g)));
    assert_eq!((od.scratch, od.limits.max), (5, 10), "not backed up");
    let saved = record(&od);
    let mut again = StoredOd::default();
    let reloaded = parameters::load(&mut again, &saved);
    assert_eq!(reloaded.skipped, 0);
    assert_eq!(record(&again), saved);
}
