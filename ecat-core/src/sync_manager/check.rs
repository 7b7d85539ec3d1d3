//! The checks a SubDevice applies to the MainDevice's SyncManager configuration
//! (ETG.1000.6 §6.4.2 "SyncManager check"; SSC `CheckSmSettings`).
//!
//! - Mailbox (SM0/SM1), at INIT→PREOP and on every SM change in PREOP/SAFEOP/OP: enabled, start
//!   and length exactly as configured, mailbox mode, correct direction. Otherwise 0x0016
//!   (0x0015 for the bootstrap mailbox).
//! - Process data (SM2 outputs, SM3 inputs), at PREOP→SAFEOP and on SM change in SAFEOP/OP:
//!   a direction with data needs the channel enabled with exactly the image length, the right
//!   direction, a buffer mode, inside process RAM and overlapping nothing; a direction without
//!   data needs the channel disabled. Otherwise 0x001D (outputs) or 0x001E (inputs).
//!
//! The control byte is checked in its mode and direction bits; the event and watchdog bits are
//! the MainDevice's choice (the watchdog bit is checked with the watchdog configuration).

use super::{BufferDirection, Channel, Control, Mode};
use crate::AlStatusCode;
use crate::device::{Area, DeviceConfig, MailboxConfig, ProcessDataSizes, spans_overlap};

/// SyncManagers 0..=3 as the PDI read them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Channels(pub [Channel; 4]);

impl Channels {
    /// Bytes of register space the four channels occupy (0x0800..0x0820).
    pub const SIZE: usize = 4 * Channel::SIZE;

    /// Parses the registers of SM0..SM3 (32 bytes from 0x0800).
    pub fn from_bytes(bytes: &[u8; Self::SIZE]) -> Self {
        let mut channels = Self::default();
        channels.update(bytes);
        channels
    }

    /// Parses the registers of SM0..SM3 into `self`, in place: what the SubDevice does with
    /// every read of them (a new value copied over the old costs ≈ 40 B of flash more).
    pub fn update(&mut self, bytes: &[u8; Self::SIZE]) {
        let (channels, _) = bytes.as_chunks::<{ Channel::SIZE }>();
        for (channel, &regs) in self.0.iter_mut().zip(channels) {
            *channel = Channel::from_bytes(regs);
        }
    }

    /// The receive mailbox, SM0.
    pub const fn mailbox_receive(&self) -> &Channel {
        &self.0[0]
    }

    /// The send mailbox, SM1.
    pub const fn mailbox_send(&self) -> &Channel {
        &self.0[1]
    }

    /// The outputs, SM2.
    pub const fn outputs(&self) -> &Channel {
        &self.0[2]
    }

    /// The inputs, SM3.
    pub const fn inputs(&self) -> &Channel {
        &self.0[3]
    }
}

/// Checks SM0/SM1 against `mailbox`; `code` is the answer on mismatch (0x0016 or 0x0015).
pub fn mailbox(
    channels: &Channels,
    mailbox: &MailboxConfig,
    code: AlStatusCode,
) -> Result<(), AlStatusCode> {
    let rx = is_mailbox(channels.mailbox_receive(), mailbox.receive, RECEIVE_CONTROL);
    let tx = is_mailbox(channels.mailbox_send(), mailbox.send, SEND_CONTROL);
    if rx && tx { Ok(()) } else { Err(code) }
}

/// The control bits the mailbox check compares: mode (1:0), direction (3:2), PDI event (5).
const MAILBOX_CONTROL_BITS: u8 = 0x2F;
/// SM0's control in those bits, as the SII describes it: mailbox mode, written by the
/// MainDevice, PDI event.
const RECEIVE_CONTROL: u8 = 0x26;
/// SM1's: mailbox mode, read by the MainDevice, PDI event.
const SEND_CONTROL: u8 = 0x22;
const _: () = {
    let (receive, send) = (Control(RECEIVE_CONTROL), Control(SEND_CONTROL));
    assert!(matches!(receive.mode(), Mode::Mailbox) && matches!(send.mode(), Mode::Mailbox));
    assert!(matches!(
        receive.direction(),
        BufferDirection::MainDeviceWrites
    ));
    assert!(matches!(send.direction(), BufferDirection::MainDeviceReads));
    assert!(receive.pdi_event() && send.pdi_event());
    assert!(MAILBOX_CONTROL_BITS == 0b1111 | Control::PDI_EVENT);
};

/// A mailbox channel at `area` with `control` in [`MAILBOX_CONTROL_BITS`]: mode, direction and
/// the PDI event, without which the SubDevice would never see a mailbox event. The ECAT event
/// bit is the MainDevice's choice.
fn is_mailbox(channel: &Channel, area: Area, control: u8) -> bool {
    channel.enabled()
        && channel.start == area.start
        && channel.length == area.length
        && channel.control.0 & MAILBOX_CONTROL_BITS == control
}

/// Checks SM2/SM3 against the process-data `sizes`, and that no enabled channel overlaps
/// another or a mailbox of `device`.
pub fn process_data(
    channels: &Channels,
    sizes: ProcessDataSizes,
    device: &DeviceConfig,
) -> Result<(), AlStatusCode> {
    let ram_end = device.process_ram_end;
    let out_span = process_data_span(channels.outputs(), sizes.outputs, OUTPUTS_CONTROL, ram_end)
        .ok_or(AlStatusCode::INVALID_OUTPUT_CONFIG)?;
    let in_span = process_data_span(channels.inputs(), sizes.inputs, INPUTS_CONTROL, ram_end)
        .ok_or(AlStatusCode::INVALID_INPUT_CONFIG)?;
    let (receive, send) = (device.mailbox.receive.span(), device.mailbox.send.span());
    if spans_overlap(out_span, receive) || spans_overlap(out_span, send) {
        return Err(AlStatusCode::INVALID_OUTPUT_CONFIG);
    }
    let into = |span| spans_overlap(in_span, span);
    if into(receive) || into(send) || into(out_span) {
        return Err(AlStatusCode::INVALID_INPUT_CONFIG);
    }
    Ok(())
}

/// Checks that SM2's watchdog trigger bit and the process-data watchdog time (0x0420) agree:
/// a trigger with time 0, or a time without the trigger, is 0x001F (conformance.md "Watchdogs").
/// Devices without outputs have no SM2 watchdog.
pub fn watchdog(
    channels: &Channels,
    sizes: ProcessDataSizes,
    time: u16,
) -> Result<(), AlStatusCode> {
    if sizes.outputs == 0 {
        return Ok(());
    }
    match (channels.outputs().control.watchdog(), time) {
        (true, 0) => Err(AlStatusCode::INVALID_WATCHDOG_CONFIG),
        (false, t) if t != 0 => Err(AlStatusCode::INVALID_WATCHDOG_CONFIG),
        _ => Ok(()),
    }
}

/// The control bits the process-data check compares: the direction (3:2) and bit 0 of the
/// mode (1:0), which is 0 in both modes a process-data channel may use (3-buffer 0b00, mailbox
/// 0b10).
const PROCESS_DATA_CONTROL_BITS: u8 = 0b1101;
/// SM2's control in those bits: written by the MainDevice.
const OUTPUTS_CONTROL: u8 = 0b0100;
/// SM3's: read by the MainDevice.
const INPUTS_CONTROL: u8 = 0b0000;
const _: () = {
    let (outputs, inputs) = (Control(OUTPUTS_CONTROL), Control(INPUTS_CONTROL));
    assert!(matches!(
        outputs.direction(),
        BufferDirection::MainDeviceWrites
    ));
    assert!(matches!(
        inputs.direction(),
        BufferDirection::MainDeviceReads
    ));
    assert!(matches!(Control(0b10).mode(), Mode::Mailbox));
    assert!(matches!(Control(0b00).mode(), Mode::Buffered));
    assert!(0b10 & PROCESS_DATA_CONTROL_BITS == 0 && 0b01 & PROCESS_DATA_CONTROL_BITS != 0);
};

/// The bytes a process-data channel occupies (all three buffers in 3-buffer mode), from its
/// first to one past its last, when it is as the image of `size` bytes needs it: disabled
/// without data (an empty span, which overlaps nothing), else enabled with exactly that length,
/// `control` in [`PROCESS_DATA_CONTROL_BITS`] (the direction, a buffer mode) and inside process
/// RAM (up to `ram_end`). `None` otherwise.
fn process_data_span(
    channel: &Channel,
    size: u16,
    control: u8,
    ram_end: u32,
) -> Option<(u32, u32)> {
    if size == 0 {
        return (!channel.enabled()).then_some((0, 0));
    }
    let (start, end) = channel.occupied()?;
    let valid = channel.enabled()
        && channel.length == size
        && channel.control.0 & PROCESS_DATA_CONTROL_BITS == control
        && start >= u32::from(crate::register::PROCESS_RAM)
        && end <= ram_end;
    valid.then_some((start, end))
}
