//! A firmware update end to end on the host (issue #16): the test MainDevice writes an update
//! file with FoE in BOOT into the flash of `devices::dio_update` (through embassy-boot's
//! `BlockingFirmwareUpdater` into DFU), leaves BOOT, the bootloader's `prepare_boot` runs at the
//! "reset", and a new device on the same flash runs the new image: its revision (0x1018:03, from
//! the image) is the new version. It confirms itself in PREOP, or is rolled back at the next
//! reset. Refused files change nothing. On a line the device restarts by itself
//! (`update::restarting`, as the virtual slave runs it).

use std::cell::RefCell;
use std::rc::Rc;

use ecat_core::device::MailboxConfig;
use ecat_core::register;
use ecat_emu::coe_client::SdoClient;
use ecat_emu::devices::{dio, dio_update};
use ecat_emu::flash::{Flash, layout};
use ecat_emu::foe_client::{FoeClient, FoeFailure};
use ecat_emu::harness::{self, Spawn};
use ecat_emu::master::TestMaster;
use ecat_emu::restart::Reset;
use ecat_emu::update::{
    self, BOOT_MAILBOX, FILE_NAME, Firmware, Header, PASSWORD, file, flashed, image, reset,
    running_version, state,
};
use embassy_boot::State;

const MAILBOX: MailboxConfig = MailboxConfig::contiguous(0x1000, 128);

/// A device on `flash` (restarted: built from what ACTIVE holds) running `script`.
fn start(flash: &Flash, script: impl AsyncFnOnce(&TestMaster) + 'static) {
    let sample = dio_update(&Firmware::new(flash.clone(), Reset::default()));
    assert_eq!(sample.identity.revision, running_version(flash));
    harness::run(sample.device, |master| async move { script(&master).await });
}

/// INIT, then SM0/SM1 as `mailbox`, then the state `control` asks for.
async fn walk(master: &TestMaster, mailbox: &MailboxConfig, control: u16) {
    master.reset().await;
    assert_eq!(master.request(0x0001).await, (0x0001, 0));
    master.configure_mailbox(mailbox);
    master.settle().await;
    assert_eq!(master.request(control).await, (control, 0));
}

/// Writes `file` in BOOT, then leaves BOOT for INIT; the FoE outcome.
async fn update(
    master: &TestMaster,
    name: &str,
    password: u32,
    file: &[u8],
) -> Result<(), FoeFailure> {
    walk(master, &BOOT_MAILBOX, 0x03).await;
    let result = FoeClient::for_mailbox(master, &BOOT_MAILBOX)
        .write(name, password, file)
        .await;
    assert_eq!(master.request(0x0001).await, (0x0001, 0), "BOOT to INIT");
    result
}

/// 0x1018:03 as the MainDevice reads it in PREOP.
async fn revision_in_preop(master: &TestMaster) -> u32 {
    walk(master, &MAILBOX, 0x02).await;
    let revision = SdoClient::for_mailbox(master, &MAILBOX)
        .upload(0x1018, 3, false)
        .await
        .unwrap();
    u32::from_le_bytes(revision.try_into().unwrap())
}

/// The revision in the SII image the ESC holds (word 0x0C), as a MainDevice's scan reads it.
fn revision_in_sii(master: &TestMaster) -> u32 {
    let revision = master
        .emulator()
        .with(|esc| esc.eeprom()[0x18..0x1C].to_vec());
    u32::from_le_bytes(revision.try_into().unwrap())
}

/// Version 1 in ACTIVE, booted.
fn version_1() -> Flash {
    flashed(&image(1, 45_000))
}

#[test]
fn the_new_image_runs_after_the_reset_and_confirms_itself_in_preop() {
    let flash = version_1();
    let new = image(2, 61_234);
    let update_file = file(&new);
    start(&flash, async move |master| {
        assert_eq!(revision_in_preop(master).await, 1);
        update(master, FILE_NAME, PASSWORD, &update_file)
            .await
            .unwrap();
    });
    assert_eq!(
        flash.bytes(layout::DFU)[..new.len()],
        new[..],
        "the image in DFU"
    );
    assert_eq!(
        running_version(&flash),
        1,
        "nothing swapped before the reset"
    );
    assert_eq!(
        reset(&flash).unwrap(),
        State::Swap,
        "a trial boot of the new image"
    );
    assert_eq!(flash.bytes(layout::ACTIVE)[..new.len()], new[..]);
    start(&flash, async |master| {
        assert_eq!(revision_in_preop(master).await, 2, "the new image runs");
    });
    assert_eq!(state(&flash).unwrap(), State::Boot, "confirmed in PREOP");
    assert_eq!(reset(&flash).unwrap(), State::Boot);
    assert_eq!(running_version(&flash), 2, "and stays");
}

#[test]
fn an_image_that_never_reaches_preop_is_rolled_back() {
    let flash = version_1();
    let update_file = file(&image(2, 5_000));
    start(&flash, async move |master| {
        update(master, FILE_NAME, PASSWORD, &update_file)
            .await
            .unwrap();
    });
    assert_eq!(reset(&flash).unwrap(), State::Swap);
    start(&flash, async |master| {
        // The new image runs but never reaches PREOP: INIT, BOOT, INIT.
        walk(master, &BOOT_MAILBOX, 0x03).await;
        assert_eq!(master.request(0x0001).await, (0x0001, 0));
    });
    assert_eq!(running_version(&flash), 2);
    assert_eq!(reset(&flash).unwrap(), State::Revert, "rolled back");
    assert_eq!(running_version(&flash), 1);
    start(&flash, async |master| {
        assert_eq!(revision_in_preop(master).await, 1);
    });
}

#[test]
fn refused_files_get_their_codes_and_change_nothing() {
    let flash = version_1();
    let good = image(2, 3_000);
    let mut corrupted = file(&good);
    corrupted[Header::SIZE + 1_000] ^= 0x01;
    let mut no_magic = file(&good);
    no_magic[0] = b'X';
    let mut too_long = Header::of(&good);
    too_long.length = layout::ACTIVE.len() as u32 + 1;
    let mut too_large = too_long.to_bytes().to_vec();
    too_large.extend_from_slice(&good);
    let short = file(&good)[..Header::SIZE + 2_000].to_vec();
    start(&flash, async move |master| {
        let cases = [
            ("firmware.elf", PASSWORD, file(&good), 0x8001),
            (FILE_NAME, PASSWORD + 1, file(&good), 0x800A),
            (FILE_NAME, PASSWORD, too_large, 0x8003),
            (FILE_NAME, PASSWORD, corrupted, 0x8000),
            (FILE_NAME, PASSWORD, no_magic, 0x8000),
            (FILE_NAME, PASSWORD, short, 0x8000),
        ];
        for (name, password, file, code) in cases {
            assert_eq!(
                update(master, name, password, &file).await,
                Err(FoeFailure::Error(code)),
                "{name} {password:#x}, {} bytes",
                file.len()
            );
        }
    });
    assert_eq!(state(&flash).unwrap(), State::Boot, "nothing marked");
    assert_eq!(reset(&flash).unwrap(), State::Boot);
    assert_eq!(running_version(&flash), 1);
}

#[test]
fn a_second_file_replaces_the_first_before_boot_is_left() {
    let flash = version_1();
    let (first, second) = (image(2, 9_000), image(3, 7_000));
    let files = (file(&first), file(&second));
    start(&flash, async move |master| {
        walk(master, &BOOT_MAILBOX, 0x03).await;
        let mut foe = FoeClient::for_mailbox(master, &BOOT_MAILBOX);
        foe.write(FILE_NAME, PASSWORD, &files.0).await.unwrap();
        foe.write(FILE_NAME, PASSWORD, &files.1).await.unwrap();
        assert_eq!(master.request(0x0001).await, (0x0001, 0));
    });
    assert_eq!(reset(&flash).unwrap(), State::Swap);
    assert_eq!(running_version(&flash), 3);
}

#[test]
fn foe_outside_boot_is_bootstrap_only() {
    let flash = version_1();
    start(&flash, async |master| {
        walk(master, &MAILBOX, 0x02).await;
        assert_eq!(
            FoeClient::for_mailbox(master, &MAILBOX)
                .write(FILE_NAME, PASSWORD, &file(&image(2, 100)))
                .await,
            Err(FoeFailure::Error(0x8008))
        );
    });
    assert_eq!(state(&flash).unwrap(), State::Boot);
}

/// The power fails at each flash operation of an update in turn (an erase or a write of DFU
/// while the file arrives, or of the state while BOOT is left): the device always boots a whole
/// image, the old one unless the new one was completely written and marked.
#[test]
fn a_power_cut_at_any_flash_operation_of_the_update_leaves_a_whole_image() {
    let new = image(2, 9_000);
    let update_file = file(&new);
    let total = {
        let flash = version_1();
        let (before, update_file) = (flash.operations(), update_file.clone());
        start(&flash, async move |master| {
            update(master, FILE_NAME, PASSWORD, &update_file)
                .await
                .unwrap();
        });
        flash.operations() - before
    };
    assert_eq!(
        total, 9,
        "3 page erases and writes of DFU; the state's progress mark, erase and magic"
    );
    for cut in 0..total {
        let flash = version_1();
        flash.cut_after(cut);
        let outcome = Rc::new(RefCell::new(None));
        let (seen, update_file) = (outcome.clone(), update_file.clone());
        start(&flash, async move |master| {
            let result = update(master, FILE_NAME, PASSWORD, &update_file).await;
            *seen.borrow_mut() = Some(result);
        });
        assert!(flash.power_on(), "cut {cut}: the power was cut");
        let written = outcome.borrow().clone().unwrap();
        let state = reset(&flash).unwrap();
        match (written, state) {
            (Err(FoeFailure::Error(0x8000)), State::Boot) => {
                assert_eq!(running_version(&flash), 1, "cut {cut}")
            }
            // Cut while BOOT was left: the image is whole, marked or not.
            (Ok(()), State::Boot) => assert_eq!(running_version(&flash), 1, "cut {cut}"),
            (Ok(()), State::Swap) => assert_eq!(running_version(&flash), 2, "cut {cut}"),
            other => panic!("cut {cut} of {total}: {other:?}"),
        }
    }
}

/// On a line, the device restarts by itself once the MainDevice takes it out of BOOT with the new
/// image marked (`update::restarting`, as the virtual slave runs it): the bootloader's swap, a
/// fresh ESC (no station address: a MainDevice scans again) with the new revision in its SII and
/// 0x1018:03, the new image confirmed in PREOP. BOOT left without an update restarts nothing, and
/// the device beside it stays in PREOP at its address.
#[test]
fn leaving_boot_with_an_update_restarts_the_device_on_its_line() {
    let flash = version_1();
    let updatable = update::restarting(flash.clone(), |firmware| {
        Box::new(dio_update(firmware).device)
    });
    let line: Vec<Box<dyn Spawn>> = vec![Box::new(updatable), Box::new(dio().device)];
    let update_file = file(&image(2, 30_000));
    let trial = flash.clone();
    harness::run_many(line, move |escs| async move {
        let device = TestMaster::new(escs[0].clone());
        let beside = TestMaster::new(escs[1].clone());
        let address = |master: &TestMaster| master.read_u16(register::STATION_ADDRESS);
        device.write(register::STATION_ADDRESS, &0x1000u16.to_le_bytes());
        beside.write(register::STATION_ADDRESS, &0x1001u16.to_le_bytes());
        walk(&beside, &MAILBOX, 0x02).await;
        walk(&device, &BOOT_MAILBOX, 0x03).await;
        assert_eq!(device.request(0x0001).await, (0x0001, 0));
        assert_eq!(address(&device), 0x1000, "no update, no restart");
        assert_eq!(revision_in_sii(&device), 1);
        update(&device, FILE_NAME, PASSWORD, &update_file)
            .await
            .unwrap();
        device.settle().await;
        assert_eq!(address(&device), 0, "restarted: the ESC's reset value");
        assert_eq!(revision_in_sii(&device), 2, "the new image's SII");
        assert_eq!(state(&trial).unwrap(), State::Swap, "a trial boot");
        assert_eq!(revision_in_preop(&device).await, 2, "the new image runs");
        assert_eq!(state(&trial).unwrap(), State::Boot, "confirmed in PREOP");
        assert_eq!(
            (beside.al_status(), address(&beside)),
            (0x0002, 0x1001),
            "the rest of the line goes on"
        );
    });
    assert_eq!(running_version(&flash), 2);
}
