//! The sync error counter limit comes from 0x10F1:02 when the dictionary declares the Error
//! Settings object (ETG.1020 §6.3), else SSC's default 4.

use ecat_core::coe::AbortCode;
use ecat_core::dictionary::{At, Limit, ObjectDictionary};
use ecat_core::sync_error::{
    DEFAULT_LIMIT, ERROR_SETTINGS, ErrorSettings, LOCAL_ERROR_REACTION, REACTION_SAFEOP,
    SyncSupervision, limit,
};

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
            1 => local_error_reaction, RW, "Local error reaction", default = REACTION_SAFEOP,
                 min = REACTION_SAFEOP, max = REACTION_SAFEOP;
            2 => sync_error_counter_limit, RW, "Sync error counter limit", default = DEFAULT_LIMIT;
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

/// 0x10F1:01 is SSC's 1, the stack's one reaction (SAFEOP with the error indication): read as
/// 1, declared as default, minimum and maximum (what the ESI's `DefaultData`, `MinData` and
/// `MaxData` carry), and any other value is refused.
#[test]
fn the_local_error_reaction_is_sscs_1_and_nothing_else() {
    let mut od = Od::default();
    assert_eq!(od.error_settings, ErrorSettings::new());
    let object = Od::object(ERROR_SETTINGS).expect("0x10F1");
    let mut out = [0; 4];
    (object.read)(&od, At::start(LOCAL_ERROR_REACTION), &mut out).expect("read");
    assert_eq!(out, [1, 0, 0, 0]);
    for limit in [Limit::Default, Limit::Min, Limit::Max] {
        let mut value = [0; 4];
        assert_eq!(object.limit(LOCAL_ERROR_REACTION, limit, &mut value), 4);
        assert_eq!(value, [1, 0, 0, 0], "{limit:?}");
    }
    assert_eq!(
        (object.write)(&mut od, LOCAL_ERROR_REACTION, &[0, 0, 0, 0]),
        Err(AbortCode::VALUE_TOO_LOW)
    );
    assert_eq!(
        (object.write)(&mut od, LOCAL_ERROR_REACTION, &[2, 0, 0, 0]),
        Err(AbortCode::VALUE_TOO_HIGH)
    );
    assert_eq!(
        (object.write)(&mut od, LOCAL_ERROR_REACTION, &[1, 0, 0, 0]),
        Ok(())
    );
    assert_eq!(od.error_settings.local_error_reaction, REACTION_SAFEOP);
}
