//! The sync error counter limit comes from 0x10F1:02 when the dictionary declares the Error
//! Settings object (ETG.1020 §6.3), else SSC's default 4.

use ecat_core::sync_error::{DEFAULT_LIMIT, SyncSupervision, limit};

/// 0x10F1.
pub struct ErrorSettings {
    /// 0x10F1:01.
    pub local_error_reaction: u32,
    /// 0x10F1:02.
    pub sync_error_counter_limit: u16,
}

/// A dictionary with 0x10F1.
pub struct Od {
    /// 0x1000.
    pub device_type: u32,
    /// 0x10F1.
    pub error_settings: ErrorSettings,
}

ecat_core::dictionary! {
    // 0x10F1 alone: a test of the limit lookup, no CoE device.
    minimal Od {
        0x1000 => var(device_type, RO, "Device type");
        0x10F1 => record(error_settings: ErrorSettings, "Error settings") {
            1 => local_error_reaction, RW, "Local error reaction";
            2 => sync_error_counter_limit, RW, "Sync error counter limit", default = 4;
        };
    }
}

/// A dictionary without 0x10F1.
pub struct Plain {
    /// 0x1000.
    pub device_type: u32,
}

ecat_core::dictionary! {
    minimal Plain {
        0x1000 => var(device_type, RO, "Device type");
    }
}

/// The cycle at which one loss in `n` trips the supervision with `od`'s limit.
fn trips(od: &impl ecat_core::dictionary::ObjectDictionary, n: u32) -> Option<u32> {
    let mut s = SyncSupervision::new();
    (1..=1000).find(|k| s.cycle(true, k % n == 0, limit(od)))
}

#[test]
fn the_limit_is_0x10f1_02() {
    let mut od = Od::default();
    assert_eq!(limit(&od), 4, "declared default");
    assert_eq!(trips(&od, 3), Some(6));
    od.error_settings.sync_error_counter_limit = 7;
    assert_eq!(limit(&od), 7);
    // One loss in three: 3, 2, 1, 4, 3, 2, 5, 4, 3, 6, 5, 4, 7 → cycle 15.
    assert_eq!(trips(&od, 3), Some(15));
    od.error_settings.sync_error_counter_limit = 0;
    assert_eq!(trips(&od, 1), None, "0: supervision off");
}

#[test]
fn without_0x10f1_ssc_default_4() {
    assert_eq!(limit(&Plain::default()), DEFAULT_LIMIT);
    assert_eq!(DEFAULT_LIMIT, 4);
}
