//! A scripted MainDevice on the emulated ESC's EtherCAT port, with virtual time.
//!
//! It does what a real MainDevice does to a SubDevice, one register access at a time, and lets
//! the SubDevice's runners catch up between steps ([`TestMaster::settle`]). Time moves only
//! when the script says so ([`TestMaster::advance`]).

use ecat_core::coe::Emergency;
use ecat_core::device::{Area, MailboxConfig};
use ecat_core::register;
use ecat_core::sync_manager::{Channel, Control};
use embassy_time::{Duration, MockDriver};

use crate::emulator::Emulator;

/// SM0 control byte as MainDevices write it: mailbox mode, MainDevice writes, PDI event.
pub const SM0_CONTROL: u8 = 0x26;
/// SM1 control byte: mailbox mode, MainDevice reads, PDI event.
pub const SM1_CONTROL: u8 = 0x22;
/// SM2 control byte: 3-buffer mode, MainDevice writes, PDI event, watchdog trigger.
pub const SM2_CONTROL: u8 = 0x64;
/// SM3 control byte: 3-buffer mode, MainDevice reads, PDI event.
pub const SM3_CONTROL: u8 = 0x20;

/// How often [`TestMaster::settle`] lets the other tasks run without a PDI access before it
/// calls the SubDevice idle.
const QUIET_POLLS: usize = 8;
/// Upper bound of [`TestMaster::settle`]: a SubDevice still accessing the PDI after this many
/// polls is livelocked, which the test reports.
const MAX_POLLS: usize = 10_000;

/// The MainDevice side of one emulated ESC.
pub struct TestMaster {
    emu: Emulator,
    firmware: Option<Box<dyn Fn(Emergency)>>,
}

impl TestMaster {
    /// A MainDevice attached to `emu`.
    pub fn new(emu: Emulator) -> Self {
        Self {
            emu,
            firmware: None,
        }
    }

    /// The same MainDevice, able to make the firmware raise emergencies.
    pub fn with_firmware(self, raise_emergency: impl Fn(Emergency) + 'static) -> Self {
        Self {
            firmware: Some(Box::new(raise_emergency)),
            ..self
        }
    }

    /// Makes the firmware raise `emergency` (as its application would through
    /// `Control::raise_emergency`). Panics when the harness did not connect the firmware.
    pub fn raise_emergency(&self, emergency: Emergency) {
        match &self.firmware {
            Some(raise) => raise(emergency),
            None => panic!("this TestMaster is not connected to the firmware"),
        }
    }

    /// The ESC it talks to.
    pub fn emulator(&self) -> &Emulator {
        &self.emu
    }

    /// Writes `data` at `address` through the EtherCAT port; `true` if the ESC took it.
    pub fn write(&self, address: u16, data: &[u8]) -> bool {
        self.emu.with(|esc| esc.ecat_write(address, data))
    }

    /// Reads `len` bytes at `address` through the EtherCAT port; `None` if the ESC refused.
    pub fn read(&self, address: u16, len: usize) -> Option<Vec<u8>> {
        let mut buf = vec![0; len];
        self.emu
            .with(|esc| esc.ecat_read(address, &mut buf))
            .then_some(buf)
    }

    /// Reads a little-endian u16 register.
    pub fn read_u16(&self, address: u16) -> u16 {
        let mut buf = [0; 2];
        self.emu.with(|esc| esc.ecat_read(address, &mut buf));
        u16::from_le_bytes(buf)
    }

    /// AL status (0x0130).
    pub fn al_status(&self) -> u16 {
        self.read_u16(register::AL_STATUS)
    }

    /// AL status code (0x0134).
    pub fn al_status_code(&self) -> u16 {
        self.read_u16(register::AL_STATUS_CODE)
    }

    /// Writes AL control (0x0120).
    pub fn write_al_control(&self, value: u16) {
        self.write(register::AL_CONTROL, &value.to_le_bytes());
    }

    /// Writes AL control, lets the SubDevice answer, and returns (AL status, AL status code).
    pub async fn request(&self, value: u16) -> (u16, u16) {
        self.write_al_control(value);
        self.settle().await;
        (self.al_status(), self.al_status_code())
    }

    /// Writes SyncManager `n`'s 8 registers in one access, as MainDevices do. The ESC accepts
    /// start, length and control only while the channel is disabled, so an enabled channel is
    /// disabled first.
    pub fn configure_sm(&self, n: u8, start: u16, length: u16, control: u8, enable: bool) {
        self.write(register::sync_manager(n) + 6, &[0]);
        let channel = Channel {
            start,
            length,
            control: Control(control),
            activate: u8::from(enable),
            ..Channel::default()
        };
        self.write(register::sync_manager(n), &channel.to_bytes());
    }

    /// Configures SM0/SM1 as the mailboxes described by `mailbox`.
    pub fn configure_mailbox(&self, mailbox: &MailboxConfig) {
        self.configure_sm(
            0,
            mailbox.receive.start,
            mailbox.receive.length,
            SM0_CONTROL,
            true,
        );
        self.configure_sm(
            1,
            mailbox.send.start,
            mailbox.send.length,
            SM1_CONTROL,
            true,
        );
    }

    /// Configures SM2 (outputs) and SM3 (inputs); a missing area leaves the channel disabled with
    /// length 0, as MainDevices do for a direction without data.
    pub fn configure_process_data(&self, outputs: Option<Area>, inputs: Option<Area>) {
        let (o, i) = (
            outputs.unwrap_or(Area::new(0, 0)),
            inputs.unwrap_or(Area::new(0, 0)),
        );
        self.configure_sm(2, o.start, o.length, SM2_CONTROL, outputs.is_some());
        self.configure_sm(3, i.start, i.length, SM3_CONTROL, inputs.is_some());
    }

    /// The reset every MainDevice starts with: INIT with acknowledge, then all SyncManagers zeroed.
    pub async fn reset(&self) {
        self.write_al_control(0x0011);
        self.write(register::SM_BASE, &[0; 16 * 8]);
        self.settle().await;
    }

    /// Lets the SubDevice's tasks run until they stop accessing the PDI. Panics (fails the test)
    /// when they never stop: a livelock.
    pub async fn settle(&self) {
        let mut quiet = 0;
        let mut last = self.pdi_accesses();
        for _ in 0..MAX_POLLS {
            embassy_futures::yield_now().await;
            self.emu.script_ran();
            let now = self.pdi_accesses();
            quiet = if now == last { quiet + 1 } else { 0 };
            last = now;
            if quiet >= QUIET_POLLS {
                return;
            }
        }
        panic!("the SubDevice keeps accessing the PDI: livelock");
    }

    /// Advances virtual time by `duration` in 1 ms steps, settling after each.
    pub async fn advance(&self, duration: Duration) {
        let step = Duration::from_millis(1);
        let mut left = duration;
        while left > Duration::from_ticks(0) {
            let d = if left < step { left } else { step };
            MockDriver::get().advance(d);
            left -= d;
            self.emu.tick();
            self.settle().await;
        }
    }

    /// PDI reads and writes so far.
    pub fn pdi_accesses(&self) -> u64 {
        let stats = self.emu.with(|esc| esc.stats());
        stats.reads + stats.writes
    }
}
