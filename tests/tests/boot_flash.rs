//! The firmware update path's flash side (issue #16): embassy-boot on the STM32 firmware's flash
//! layout (`examples/stm32-bootloader/memory.x`), with the power cut at every erase and write.
//!
//! The device runs image A; a new image B arrives into DFU (what the FoE hook does with
//! `BlockingFirmwareUpdater::write_firmware`), is marked for swap, and the bootloader swaps it in
//! at the next reset; B confirms itself (`mark_booted`, once it reaches PREOP) or, if it never
//! does, the next reset reverts to A. Whatever operation the power cuts — a torn page erase or a
//! torn double-word write included — the device always boots a whole image: A until B was marked
//! updated, B after (and A again when B never confirmed).

use ecat_emu::flash::{Flash, layout};
use ecat_emu::update::{flashed, reset};
use embassy_boot::{BlockingFirmwareState, BlockingFirmwareUpdater, FirmwareUpdaterConfig, State};

/// An image of `len` bytes that no other version shares a byte pattern with.
fn image(version: u8, len: usize) -> Vec<u8> {
    let mut x = 0x9E37_79B9u32 ^ u32::from(version);
    (0..len)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as u8
        })
        .collect()
}

/// A: the running image; B: the update, not a whole number of pages.
fn images() -> (Vec<u8>, Vec<u8>) {
    (image(1, 45_000), image(2, 61_234))
}

/// The FoE side: B into DFU in 1 KiB pieces, then marked for swap.
fn receive(flash: &Flash, update: &[u8]) -> Result<(), embassy_boot::FirmwareUpdaterError> {
    let mut aligned = [0; 8];
    let config = FirmwareUpdaterConfig {
        dfu: flash.partition(layout::DFU),
        state: flash.partition(layout::STATE),
    };
    let mut updater = BlockingFirmwareUpdater::new(config, &mut aligned);
    let mut padded = update.to_vec();
    padded.resize(update.len().next_multiple_of(8), 0xFF);
    for (n, piece) in padded.chunks(1024).enumerate() {
        updater.write_firmware(n * 1024, piece)?;
    }
    updater.mark_updated()
}

/// A flash with `a` running and `b` received and marked for swap.
fn updated(a: &[u8], b: &[u8]) -> Flash {
    let flash = flashed(a);
    receive(&flash, b).unwrap();
    flash
}

/// [`updated`], then reset once: `b` runs on trial.
fn swapped(a: &[u8], b: &[u8]) -> Flash {
    let flash = updated(a, b);
    assert_eq!(reset(&flash).unwrap(), State::Swap);
    flash
}

/// The running image confirms itself.
fn confirm(flash: &Flash) {
    let mut aligned = [0; 8];
    BlockingFirmwareState::new(flash.partition(layout::STATE), &mut aligned)
        .mark_booted()
        .unwrap();
}

/// Resets until a boot completes with the power on; returns its state.
fn boot_through(flash: &Flash) -> State {
    flash.power_on();
    reset(flash).expect("a boot with the power on completes")
}

/// Whether ACTIVE starts with `image`.
fn runs(flash: &Flash, image: &[u8]) -> bool {
    flash.bytes(layout::ACTIVE)[..image.len()] == *image
}

#[test]
fn the_layout_is_memory_x() {
    let memory_x = include_str!("../../examples/stm32-bootloader/memory.x");
    let origin = |name: &str| -> (usize, usize) {
        let line = memory_x
            .lines()
            .find(|l| l.contains("ORIGIN") && l.trim_start().starts_with(&format!("{name} ")))
            .unwrap();
        let number = |key: &str| {
            line.split(key)
                .nth(1)
                .unwrap()
                .trim_start_matches([' ', '=', ':'])
        };
        let start =
            usize::from_str_radix(number("ORIGIN")[2..10].trim(), 16).unwrap() - 0x0800_0000;
        let len = number("LENGTH")
            .trim_end_matches(['K', ' '])
            .parse::<usize>()
            .unwrap()
            * 1024;
        (start, start + len)
    };
    let range = |r: std::ops::Range<usize>| (r.start, r.end);
    assert_eq!(origin("FLASH"), range(layout::BOOTLOADER));
    assert_eq!(origin("BOOTLOADER_STATE"), range(layout::STATE));
    assert_eq!(origin("PARAMETERS"), range(layout::PARAMETERS));
    assert_eq!(origin("ACTIVE"), range(layout::ACTIVE));
    assert_eq!(origin("DFU"), range(layout::DFU));
    assert_eq!(layout::DFU.end, layout::SIZE);
}

#[test]
fn update_swaps_in_b_and_confirmed_b_stays() {
    let (a, b) = images();
    let flash = flashed(&a);
    let parameters = image(9, layout::PARAMETERS.len());
    let mut stored = flash.partition(layout::PARAMETERS);
    embedded_storage::nor_flash::NorFlash::write(&mut stored, 0, &parameters).unwrap();
    assert_eq!(reset(&flash).unwrap(), State::Boot);
    receive(&flash, &b).unwrap();
    assert!(runs(&flash, &a), "nothing changes ACTIVE before the reset");
    assert_eq!(reset(&flash).unwrap(), State::Swap);
    assert!(runs(&flash, &b));
    confirm(&flash);
    assert_eq!(reset(&flash).unwrap(), State::Boot);
    assert!(runs(&flash, &b));
    assert_eq!(
        flash.bytes(layout::PARAMETERS),
        parameters,
        "the stored parameters survive"
    );
}

#[test]
fn unconfirmed_b_is_rolled_back_to_a() {
    let (a, b) = images();
    let flash = swapped(&a, &b);
    assert!(runs(&flash, &b));
    // B never reached PREOP: the next reset reverts.
    assert_eq!(reset(&flash).unwrap(), State::Revert);
    assert!(runs(&flash, &a));
    // A is booted again and can take the next update.
    confirm(&flash);
    assert_eq!(reset(&flash).unwrap(), State::Boot);
    assert!(runs(&flash, &a));
}

/// Counts the operations of `step` on a fresh copy of the scene `setup` builds.
fn operations_of(setup: impl Fn() -> Flash, step: impl Fn(&Flash)) -> usize {
    let flash = setup();
    let before = flash.operations();
    step(&flash);
    flash.operations() - before
}

#[test]
fn power_cut_while_receiving_keeps_a() {
    let (a, b) = images();
    let total = operations_of(|| flashed(&a), |f| receive(f, &b).unwrap());
    assert!(total > 20, "{total} operations");
    for cut in 0..total {
        let flash = flashed(&a);
        flash.cut_after(cut);
        assert!(receive(&flash, &b).is_err(), "cut {cut} of {total}");
        // The magic is the last write: cut before it, A stays and boots.
        assert_eq!(boot_through(&flash), State::Boot, "cut {cut}");
        assert!(runs(&flash, &a), "cut {cut}");
        // The master starts the download again: it completes.
        receive(&flash, &b).unwrap();
        assert_eq!(boot_through(&flash), State::Swap);
        assert!(runs(&flash, &b), "cut {cut}");
    }
}

#[test]
fn power_cut_anywhere_in_the_swap_ends_in_b() {
    let (a, b) = images();
    let total = operations_of(
        || updated(&a, &b),
        |f| {
            reset(f).unwrap();
        },
    );
    assert!(total >= 4 * 60, "{total} operations for 60 pages");
    for cut in 0..total {
        let flash = updated(&a, &b);
        flash.cut_after(cut);
        assert!(reset(&flash).is_err(), "cut {cut} of {total}");
        // The next reset resumes the swap from its recorded progress.
        assert_eq!(boot_through(&flash), State::Swap, "cut {cut}");
        assert!(runs(&flash, &b), "cut {cut}");
        // And an unconfirmed B still reverts to a whole A.
        assert_eq!(boot_through(&flash), State::Revert, "cut {cut}");
        assert!(runs(&flash, &a), "cut {cut}");
    }
}

#[test]
fn power_cut_anywhere_in_the_revert_ends_in_a() {
    let (a, b) = images();
    let total = operations_of(
        || swapped(&a, &b),
        |f| {
            reset(f).unwrap();
        },
    );
    for cut in 0..total {
        let flash = swapped(&a, &b);
        flash.cut_after(cut);
        assert!(reset(&flash).is_err(), "cut {cut} of {total}");
        // A whole A runs; only a cut of the last two operations (the state page's erase, the
        // revert magic's write) loses the record that a rollback happened.
        let state = boot_through(&flash);
        assert!(runs(&flash, &a), "cut {cut}");
        let last = cut + 2 >= total;
        assert_eq!(
            state,
            if last { State::Boot } else { State::Revert },
            "cut {cut}"
        );
    }
}

#[test]
fn power_cut_while_confirming_keeps_b_or_reverts_to_a() {
    let (a, b) = images();
    let total = operations_of(|| swapped(&a, &b), confirm);
    for cut in 0..total {
        let flash = swapped(&a, &b);
        flash.cut_after(cut);
        let mut aligned = [0; 8];
        let confirmed = BlockingFirmwareState::new(flash.partition(layout::STATE), &mut aligned)
            .mark_booted()
            .is_ok();
        assert!(!confirmed, "cut {cut} of {total}");
        // Confirmation lost: B was never confirmed, so the reset reverts to a whole A.
        let state = boot_through(&flash);
        assert!(
            (state == State::Revert && runs(&flash, &a))
                || (state == State::Boot && runs(&flash, &b)),
            "cut {cut}: {state:?}"
        );
    }
}
