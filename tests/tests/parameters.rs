//! Stored parameters (0x1010/0x1011, CiA 301 §7.5.2.13/14; conformance.md "Stored
//! parameters"): the test master saves over SDO, the device resets on the same flash and the
//! master reads every backup object back; "load" brings the defaults at the next reset; a
//! power cut at every flash operation of a save leaves the old set or the new one.

mod common;

use common::{client, walk_to};
use ecat_core::AlState;
use ecat_core::coe::AbortCode;
use ecat_core::dictionary::ObjectDictionary;
use ecat_core::dictionary::parameters::Loaded;
use ecat_embassy::storage::Storage;
use ecat_emu::coe_client::{SdoClient, SdoError};
use ecat_emu::flash::{Flash, layout};
use ecat_emu::fuzz_parameters::{StoredOd as Od, record};
use ecat_emu::harness::{self, AcceptAll, Device, Loopback, ParameterStorage};

const SAVE: &[u8] = b"save";
const LOAD: &[u8] = b"load";

fn device(flash: &Flash) -> Device<AcceptAll, Loopback, Od> {
    Device::new(common::drive(), AcceptAll, Loopback)
        .with_dictionary(Od::default())
        .with_parameters(flash.clone())
}

/// One power-on of the device on `flash`: `script` runs in PREOP with one SDO client (a
/// second would repeat the mailbox counter, and the device drop its requests as repeats).
fn power_on(flash: &Flash, script: impl AsyncFnOnce(&mut SdoClient<'_>) + 'static) {
    harness::run(device(flash), |master| async move {
        walk_to(&master, AlState::PreOp).await;
        script(&mut client(&master)).await
    });
}

/// The values a set writes, by SDO: `(index, sub, bytes)`.
fn set(n: u8) -> Vec<(u16, u8, Vec<u8>)> {
    vec![
        (
            0x2000,
            0,
            u16::from(n).wrapping_mul(3).to_le_bytes().to_vec(),
        ),
        (0x2002, 1, (-i16::from(n % 100)).to_le_bytes().to_vec()),
        (0x2002, 2, [n % 100, 0].to_vec()),
        (0x2002, 3, [42, 0].to_vec()),
        (0x2003, 1, (-1000 * i32::from(n)).to_le_bytes().to_vec()),
        (
            0x2004,
            0,
            vec![b'a' + n % 26; 40 + usize::from(n) * 4 % 160],
        ),
    ]
}

/// What every backup entry uploads as after `set(n)`, and after none.
fn backup_values(n: Option<u8>) -> Vec<Vec<u8>> {
    match n {
        Some(n) => set(n).into_iter().map(|(_, _, v)| v).collect(),
        None => vec![
            vec![7, 0],
            vec![1, 0],
            vec![1, 0],
            vec![1, 0],
            (-10i32).to_le_bytes().to_vec(),
            vec![],
        ],
    }
}

async fn write_set(c: &mut SdoClient<'_>, n: u8) {
    for (index, sub, value) in set(n) {
        c.download(index, sub, false, &value).await.unwrap();
    }
    // Not backed up: lost at reset.
    c.download(0x2001, 0, false, &[9, 9, 9, 9]).await.unwrap();
    c.download(0x2003, 2, false, &[99, 0, 0, 0]).await.unwrap();
}

async fn read_backup(c: &mut SdoClient<'_>) -> Vec<Vec<u8>> {
    let mut values = Vec::new();
    for (index, sub, _) in set(0) {
        values.push(c.upload(index, sub, false).await.unwrap());
    }
    values
}

#[test]
fn the_objects_read_their_capabilities() {
    power_on(&Flash::default(), async |c| {
        for index in [0x1010, 0x1011] {
            assert_eq!(
                c.upload(index, 0, false).await,
                Ok(vec![1]),
                "{index:#x}:00"
            );
            // Bit 0: on command; bit 1 (autonomously): 0.
            assert_eq!(
                c.upload(index, 1, false).await,
                Ok(vec![1, 0, 0, 0]),
                "{index:#x}:01"
            );
        }
    });
}

#[test]
fn save_reset_load_keeps_every_backup_object() {
    let flash = Flash::default();
    power_on(&flash, async |c| {
        write_set(c, 3).await;
        c.download(0x1010, 1, false, SAVE).await.unwrap();
    });
    assert!(flash.operations() > 0, "the save wrote the flash");
    power_on(&flash, async |c| {
        assert_eq!(read_backup(c).await, backup_values(Some(3)));
        assert_eq!(
            c.upload(0x2001, 0, false).await,
            Ok(vec![5, 0, 0, 0]),
            "not backed up"
        );
        assert_eq!(
            c.upload(0x2003, 2, false).await,
            Ok(vec![10, 0, 0, 0]),
            "not backed up"
        );
    });
}

#[test]
fn load_restores_the_defaults_at_the_next_reset() {
    let flash = Flash::default();
    power_on(&flash, async |c| {
        write_set(c, 4).await;
        c.download(0x1010, 1, false, SAVE).await.unwrap();
    });
    power_on(&flash, async |c| {
        c.download(0x1011, 1, false, LOAD).await.unwrap();
        // The values in RAM stay until the reset.
        assert_eq!(read_backup(c).await, backup_values(Some(4)));
    });
    power_on(&flash, async |c| {
        assert_eq!(read_backup(c).await, backup_values(None));
    });
}

#[test]
fn a_wrong_signature_aborts_0x08000020_and_stores_nothing() {
    let flash = Flash::default();
    power_on(&flash, async |c| {
        write_set(c, 5).await;
        for (index, value) in [(0x1010, LOAD), (0x1011, SAVE), (0x1010, b"Save".as_slice())] {
            assert_eq!(
                c.download(index, 1, false, value).await,
                Err(SdoError::Abort(AbortCode(0x0800_0020))),
                "{index:#x} <- {value:?}"
            );
        }
        // The exact frame: a 4-byte expedited download of "SAVE" to 0x1010:01.
        assert_eq!(
            c.sdo(&[0x23, 0x10, 0x10, 0x01, b'S', b'A', b'V', b'E'])
                .await,
            Err(SdoError::Abort(AbortCode::CANNOT_STORE))
        );
    });
    assert_eq!(flash.operations(), 0, "nothing written");
}

#[test]
fn a_failed_store_answers_then_raises_emergency_0x5000_and_keeps_the_old_set() {
    let flash = Flash::default();
    let cut = flash.clone();
    power_on(&flash, async move |c| {
        c.download(0x2000, 0, false, &[99, 0]).await.unwrap();
        // The first flash operation of the save is torn: the power is gone for the flash.
        cut.cut_after(0);
        assert_eq!(
            c.sdo(&[0x23, 0x10, 0x10, 0x01, b's', b'a', b'v', b'e'])
                .await,
            Ok(vec![0x60, 0x10, 0x10, 0x01, 0, 0, 0, 0]),
            "the answer was built before the store"
        );
        let mut frame = vec![0x0A, 0, 0, 0, 0, (3 << 4) | 0x03, 0x00, 0x10];
        // 0x5000 device hardware, error register 0x01, manufacturer data 10 10 00 00 00.
        frame.extend([0x00, 0x50, 0x01, 0x10, 0x10, 0, 0, 0]);
        frame.resize(128, 0);
        assert_eq!(c.read().await, Some(frame));
    });
    assert!(flash.power_on());
    power_on(&flash, async |c| {
        assert_eq!(
            read_backup(c).await,
            backup_values(None),
            "the old set: the defaults"
        );
    });
}

// --- the flash side, without the runners: every power cut of many saves -----------------------

/// A dictionary holding `set(n)`.
fn od_with(n: Option<u8>) -> Od {
    let mut od = Od::default();
    if let Some(n) = n {
        for (index, sub, value) in set(n) {
            (Od::object(index).unwrap().write)(&mut od, sub, &value).unwrap();
        }
    }
    od
}

fn storage(flash: &Flash) -> ParameterStorage {
    ParameterStorage::new(flash.partition(layout::PARAMETERS)).unwrap()
}

/// Saves `set(n)` as the runner does after the "save" download; whether the flash took it.
fn save(flash: &Flash, n: u8) -> bool {
    let mut od = od_with(Some(n));
    (Od::object(0x1010).unwrap().write)(&mut od, 1, SAVE).unwrap();
    let mut storage = storage(flash);
    assert!(storage.take(&mut od));
    embassy_futures::block_on(Storage::<Od>::commit(&mut storage)).is_none()
}

/// What a reset loads from `flash`.
fn boot(flash: &Flash) -> (Od, Loaded) {
    let mut od = Od::default();
    let loaded = embassy_futures::block_on(storage(flash).load(&mut od)).unwrap();
    (od, loaded)
}

#[test]
fn a_power_cut_at_every_operation_of_every_save_leaves_the_old_or_the_new_set() {
    // 70 saves of records of 70..230 bytes fill both 4 KiB pages more than once: the cuts
    // reach item writes, page closing and the erase of the older page.
    const SAVES: u8 = 70;
    let written: usize = (0..SAVES).map(|n| record(&od_with(Some(n))).len()).sum();
    assert!(
        written > 2 * 4096,
        "{written} bytes do not reach the erase of a page"
    );
    let mut cuts = 0;
    let mut page_moves = 0;
    for k in 0..SAVES {
        let probe = Flash::default();
        for n in 0..k {
            assert!(save(&probe, n));
        }
        let before = probe.operations();
        assert!(save(&probe, k));
        let total = probe.operations() - before;
        // A save within a page takes 3 or 4 operations (as the probe counts them); one that
        // moves to the other page also closes the full page and erases the next.
        page_moves += usize::from(total > 4);
        for cut in 0..total {
            let flash = Flash::default();
            for n in 0..k {
                assert!(save(&flash, n));
            }
            flash.cut_after(cut);
            assert!(!save(&flash, k), "save {k}, cut {cut} of {total}");
            assert!(flash.power_on());
            let (od, loaded) = boot(&flash);
            let old = record(&od_with(k.checked_sub(1)));
            let new = record(&od_with(Some(k)));
            let got = record(&od);
            assert!(
                got == old || got == new,
                "save {k}, cut {cut} of {total}: a mix"
            );
            assert_eq!(loaded.skipped, 0, "save {k}, cut {cut}");
            // And the flash takes the next save.
            assert!(save(&flash, k), "save {k} after cut {cut}");
            assert_eq!(record(&boot(&flash).0), new, "save {k} after cut {cut}");
            cuts += 1;
        }
    }
    assert!(cuts > 200, "{cuts} cuts");
    assert!(page_moves >= 2, "{page_moves} page moves");
}

// --- the description ------------------------------------------------------------------------

/// The ESI of the stored-parameter device: what a MainDevice learns of 0x1010/0x1011 and of
/// which entries a "save" keeps (ETG.2000 `Flags/Backup`). `ESI_OUT=path` also writes the file
/// (validated with `xmllint --schema EtherCATInfo.xsd` when this test was written).
#[test]
fn the_esi_marks_the_backup_entries_and_lists_0x1010_and_0x1011() {
    let sample = ecat_emu::devices::Sample::new(
        ecat_core::sii::Names {
            name: common::od::INFO.name,
            order_code: "STORED",
            group: "ecat samples",
        },
        common::od::INFO.identity,
        device(&Flash::default()),
    );
    let description = ecat_core::esi::Description {
        vendor: "ecat",
        names: &sample.names,
        identity: &sample.identity,
        config: &sample.device.config,
    };
    let mut xml = String::new();
    ecat_core::esi::write(
        &mut xml,
        &description,
        &Od::default(),
        &sample.device.eeprom,
    )
    .unwrap();
    if let Ok(path) = std::env::var("ESI_OUT") {
        std::fs::write(path, &xml).unwrap();
    }
    // An element of the file: from `start` to the next `end`.
    let element = |start: &str, end: &str| {
        let at = xml
            .find(start)
            .unwrap_or_else(|| panic!("{start} in\n{xml}"));
        let len = xml[at..].find(end).unwrap();
        xml[at..at + len].to_string()
    };
    let backups =
        |start: &str, end: &str| element(start, end).matches("<Backup>1</Backup>").count();
    // 0x1010/0x1011: ARRAYs of one read-write UNSIGNED32, not backed up themselves.
    for name in ["DT1010", "DT1011"] {
        let t = element(&format!("<Name>{name}</Name>"), "</DataType>");
        assert!(
            t.contains("<BitSize>48</BitSize>") && t.contains("<Access>rw</Access>"),
            "{t}"
        );
        assert_eq!(backups(&format!("<Name>{name}</Name>"), "</DataType>"), 0);
    }
    // VARs carry their flags in the object, ARRAYs and RECORDs in their data type.
    assert_eq!(backups("<Index>#x2000</Index>", "</Object>"), 1);
    assert_eq!(backups("<Index>#x2001</Index>", "</Object>"), 0);
    assert_eq!(backups("<Index>#x2004</Index>", "</Object>"), 1);
    assert_eq!(
        backups("<Name>DT2002</Name>", "</DataType>"),
        1,
        "the elements"
    );
    // 0x2003: SI1 backed up, SI2 not.
    let record = element("<Name>DT2003</Name>", "</DataType>");
    let min =
        &record[record.find("<Name>Min</Name>").unwrap()..record.find("<Name>Max</Name>").unwrap()];
    assert!(min.contains("<Backup>1</Backup>"), "{record}");
    assert_eq!(record.matches("<Backup>1</Backup>").count(), 1, "{record}");
}
