//! The IRQ path and the process-data exchange: the runners act only when the ESC's IRQ line says
//! so, never poll, and exchange the process image in exactly two reads (the AL event, then the
//! outputs) and one write per cycle.

mod common;

use common::{INPUTS, OUTPUTS, walk_to};
use ecat_core::{AlState, register};
use ecat_emu::harness::{self, AcceptAll, Device, Loopback};
use embassy_time::Duration;

#[test]
fn idle_subdevice_never_touches_the_pdi() {
    harness::run(
        Device::new(common::drive(), AcceptAll, Loopback),
        |master| async move {
            // In OP a silent MainDevice is the SM watchdog's business (tests/tests/watchdog.rs).
            for state in [AlState::Init, AlState::PreOp, AlState::SafeOp] {
                walk_to(&master, state).await;
                let before = master.pdi_accesses();
                master.advance(Duration::from_secs(2)).await;
                assert_eq!(
                    master.pdi_accesses(),
                    before,
                    "PDI accessed while idle in {state}"
                );
            }
        },
    );
}

#[test]
fn nothing_happens_until_the_irq_line_fires() {
    harness::run(
        Device::new(common::drive(), AcceptAll, Loopback),
        |master| async move {
            walk_to(&master, AlState::Init).await;
            let emu = master.emulator().clone();
            // Mask every AL event behind the SubDevice's back: the IRQ line can no longer fire.
            emu.with(|esc| esc.pdi_write(register::AL_EVENT_MASK, &[0; 4]));
            common::configure(&master);
            assert_eq!(master.request(0x02).await, (0x01, 0), "no IRQ, no answer");
            master.advance(Duration::from_secs(1)).await;
            assert_eq!(
                (master.al_status(), master.al_status_code()),
                (0x01, 0),
                "no polling either"
            );
            // Unmask AL control: the line fires at once and the SubDevice answers.
            emu.with(|esc| esc.pdi_write(register::AL_EVENT_MASK, &[0x01, 0, 0, 0]));
            master.settle().await;
            assert_eq!((master.al_status(), master.al_status_code()), (0x02, 0));
        },
    );
}

#[test]
fn op_exchanges_process_data_in_two_reads_and_one_write_per_cycle() {
    harness::run(
        Device::new(common::drive(), AcceptAll, Loopback),
        |master| async move {
            walk_to(&master, AlState::Op).await;
            for cycle in 0u8..50 {
                let outputs: Vec<u8> = (0..OUTPUTS.length as u8)
                    .map(|i| i.wrapping_mul(7) ^ cycle)
                    .collect();
                let before = master.emulator().with(|esc| esc.stats());
                assert!(
                    master.write(OUTPUTS.start, &outputs),
                    "SM2 took the outputs"
                );
                master.settle().await;
                let after = master.emulator().with(|esc| esc.stats());
                // The AL event alone (an empty read), which shows SM2, then the outputs: a read
                // of the outputs takes the SM2 buffer, so it follows a sample that shows one.
                assert_eq!(
                    (after.reads - before.reads, after.writes - before.writes),
                    (2, 1),
                    "cycle {cycle}"
                );
                assert_eq!(
                    after.bytes_read - before.bytes_read,
                    u64::from(OUTPUTS.length)
                );
                assert_eq!(
                    after.bytes_written - before.bytes_written,
                    u64::from(INPUTS.length)
                );
                let inputs = master
                    .read(INPUTS.start, usize::from(INPUTS.length))
                    .expect("SM3 readable");
                assert_eq!(
                    inputs,
                    outputs[..usize::from(INPUTS.length)],
                    "loopback in cycle {cycle}"
                );
            }
        },
    );
}

#[test]
fn outputs_are_not_applied_in_safeop() {
    harness::run(
        Device::new(common::drive(), AcceptAll, Loopback),
        |master| async move {
            walk_to(&master, AlState::SafeOp).await;
            let inputs_before = master
                .read(INPUTS.start, usize::from(INPUTS.length))
                .expect("inputs valid in SAFEOP");
            assert!(master.write(OUTPUTS.start, &[0xAA; 12]));
            master.settle().await;
            let inputs = master
                .read(INPUTS.start, usize::from(INPUTS.length))
                .expect("inputs valid in SAFEOP");
            assert_eq!(
                inputs, inputs_before,
                "SAFEOP outputs reached the application"
            );
            assert_eq!(inputs, vec![0; 11]);
            assert_eq!(master.request(0x08).await, (0x08, 0));
            assert!(master.write(OUTPUTS.start, &[0x55; 12]));
            master.settle().await;
            assert_eq!(
                master.read(INPUTS.start, 11).expect("inputs"),
                vec![0x55; 11]
            );
        },
    );
}

/// A MainDevice talked to the ESC before the firmware started: a full mailbox raises AL event bit 8,
/// which the ESC's reset mask (0x00FF_FF0F) puts on the IRQ line and which no runner clears yet.
/// The process-data runner must leave the line alone until the state machine has written its mask.
#[test]
fn irq_asserted_before_start_up_does_not_spin() {
    let mut device = Device::new(common::drive(), AcceptAll, Loopback);
    device.before_start = |master| {
        master.configure_mailbox(&common::MAILBOX);
        assert!(master.write(common::MAILBOX.receive.start, &[0; 128]));
        // The previous firmware run had read the SyncManagers: only the mailbox event is left.
        master
            .emulator()
            .with(|esc| esc.pdi_read(register::SM_BASE, &mut [0; 64]));
        let event = master.emulator().with(|esc| esc.al_event());
        assert_eq!(
            event,
            ecat_core::AlEvent::sync_manager(0),
            "only the mailbox event"
        );
        assert!(
            master.emulator().with(|esc| esc.irq()),
            "IRQ asserted before start-up"
        );
    };
    harness::run(device, |master| async move {
        common::configure(&master);
        assert_eq!(master.request(0x02).await, (0x02, 0));
    });
}
