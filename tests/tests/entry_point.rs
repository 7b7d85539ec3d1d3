//! The entry point of `ecat-embassy`: what `Config` checks and takes from the PDI driver, both
//! runners in one task (`StateMachineRunner::run_with`, what `Resources::run` does), the safe
//! state when the process-data runner stops, and a runner's future as a task's own
//! (`StateMachineRunner::run_then`).

mod common;

use std::cell::Cell;
use std::pin::pin;
use std::rc::Rc;
use std::task::{Context, Waker};

use common::walk_to;
use ecat_core::device::Area;
use ecat_core::{AlEvent, AlState, DeviceConfig};
use ecat_embassy::pdi::Data;
use ecat_embassy::spi::beckhoff::BeckhoffSpi;
use ecat_embassy::spi::lan9252::Lan9252;
use ecat_embassy::{Application, Config, Pdi, Resources};
use ecat_emu::emulator::EmulatedPdi;
use ecat_emu::harness::{self, AcceptAll, Device, Loopback};
use ecat_emu::master::{SM2_CONTROL, SM3_CONTROL};
use ecat_emu::spi::FakeSpi;
use ecat_emu::spi::beckhoff::BeckhoffEsc;
use ecat_emu::spi::lan9252::Lan9252Chip;

type OnLan9252 = Lan9252<FakeSpi<Lan9252Chip>>;
type OnEt1100 = BeckhoffSpi<FakeSpi<BeckhoffEsc>>;

#[test]
fn the_standard_device_has_its_sizes_from_the_buffers_and_its_chip_from_the_driver() {
    const LAN: Config<OnLan9252, 2, 3> = Config::standard();
    let device = LAN.device();
    assert_eq!(
        (device.process_data.outputs, device.process_data.inputs),
        (2, 3)
    );
    assert_eq!(
        (device.mailbox.receive, device.mailbox.send),
        (Area::new(0x1000, 128), Area::new(0x1080, 128))
    );
    assert_eq!(
        (device.sync_manager_count, device.process_ram_end),
        (4, 0x2000),
        "the LAN9252's 4 SyncManagers and 4 KiB"
    );
    const ET1100: Config<OnEt1100, 2, 3, 64> = Config::standard();
    let device = ET1100.device();
    assert_eq!(
        (device.sync_manager_count, device.process_ram_end),
        (8, 0x3000)
    );
    assert_eq!(device.mailbox.send, Area::new(0x1040, 64));
}

#[test]
fn a_driver_without_a_chip_keeps_the_description_s_own() {
    let mut description = common::drive();
    description.sync_manager_count = 6;
    let config = Config::<EmulatedPdi, 12, 11>::new(description);
    assert_eq!(config.device().sync_manager_count, 6);
}

#[test]
#[should_panic(expected = "`OUT` is not the output image's size")]
fn buffers_other_than_the_images_are_refused() {
    let _ = Config::<EmulatedPdi, 11, 11>::new(common::drive());
}

#[test]
#[should_panic(expected = "a mailbox exceeds `MBX`")]
fn a_mailbox_beyond_the_buffers_is_refused() {
    let _ = Config::<EmulatedPdi, 12, 11, 64>::new(common::drive());
}

#[test]
#[should_panic(expected = "the device description is invalid")]
fn an_invalid_description_is_refused() {
    let mut description: DeviceConfig = common::drive();
    description.mailbox.send = description.mailbox.receive;
    let _ = Config::<EmulatedPdi, 12, 11>::new(description);
}

#[test]
fn one_task_runs_the_state_machine_and_the_exchange() {
    let device = Device::new(common::drive(), AcceptAll, Loopback).in_one_task();
    harness::run(device, |master| async move {
        walk_to(&master, AlState::PreOp).await;
        master.configure_sm(2, 0x1100, 12, SM2_CONTROL, true);
        master.configure_sm(3, 0x1180, 11, SM3_CONTROL, true);
        assert_eq!(master.request(0x04).await, (0x04, 0));
        let outputs = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12];
        assert!(master.write(0x1100, &outputs));
        master.settle().await;
        assert_eq!(
            master.read(0x1180, 11),
            Some(vec![0; 11]),
            "SAFEOP: no outputs applied"
        );
        assert_eq!(master.request(0x08).await, (0x08, 0));
        assert!(master.write(0x1100, &outputs));
        master.settle().await;
        assert_eq!(master.read(0x1180, 11), Some(outputs[..11].to_vec()));
    });
}

/// The PDI of the emulated ESC until `fail` is set; then every access fails.
struct Failing {
    inner: EmulatedPdi,
    fail: Rc<Cell<bool>>,
}

impl Pdi for Failing {
    type Error = ();

    async fn access(&mut self, address: u16, data: Data<'_>) -> Result<(), ()> {
        if self.fail.get() {
            return Err(());
        }
        let Ok(()) = self.inner.access(address, data).await;
        Ok(())
    }

    fn al_event(&self) -> AlEvent {
        self.inner.al_event()
    }
}

/// Outputs whose safe state is a panic: the test sees whether the runner asked for it.
struct Outputs;

impl Application for Outputs {
    fn safe_state(&mut self, _: &mut ()) {
        panic!("safe state of the outputs");
    }
}

#[test]
#[should_panic(expected = "safe state of the outputs")]
fn the_process_data_runner_puts_the_outputs_in_their_safe_state_when_it_stops_in_op() {
    let fail = Rc::new(Cell::new(false));
    let device = Device::new(common::drive(), AcceptAll, Outputs);
    let make_pdi = {
        let fail = fail.clone();
        move |emu: &ecat_emu::emulator::Emulator| Failing {
            inner: emu.pdi(),
            fail,
        }
    };
    harness::run_with_pdi(device, make_pdi, |master| async move {
        walk_to(&master, AlState::PreOp).await;
        master.configure_sm(2, 0x1100, 12, SM2_CONTROL, true);
        master.configure_sm(3, 0x1180, 11, SM3_CONTROL, true);
        assert_eq!(master.request(0x04).await, (0x04, 0));
        assert!(master.write(0x1100, &[0; 12]));
        master.settle().await;
        assert_eq!(master.request(0x08).await, (0x08, 0));
        fail.set(true);
        assert!(master.write(0x1100, &[1; 12]));
        master.settle().await;
    });
}

/// A PDI whose every access fails with the same error.
struct Broken;

impl Pdi for Broken {
    type Error = u8;

    async fn access(&mut self, _: u16, _: Data<'_>) -> Result<(), u8> {
        Err(7)
    }

    fn al_event(&self) -> AlEvent {
        AlEvent::NONE
    }
}

/// An application with every default.
struct Idle;

impl Application for Idle {}

#[test]
fn run_then_hands_over_the_error_and_never_completes() {
    let config = Box::leak(Box::new(Config::<Broken, 12, 11>::new(common::drive())));
    let resources = Box::leak(Box::new(Resources::new(config, Broken, Idle, ())));
    let (state_machine, _, _) = resources.split();
    let stopped = Rc::new(Cell::new(None));
    let mut future = pin!(state_machine.run_then({
        let stopped = stopped.clone();
        move |error| stopped.set(Some(error))
    }));
    let mut cx = Context::from_waker(Waker::noop());
    assert!(future.as_mut().poll(&mut cx).is_pending());
    assert_eq!(stopped.get(), Some(7), "the first access failed");
    stopped.set(None);
    assert!(future.as_mut().poll(&mut cx).is_pending());
    assert_eq!(stopped.get(), None, "handed over once");
}
