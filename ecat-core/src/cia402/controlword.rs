//! The device control commands of the controlword 0x6040 (IEC 61800-7-201 §6.2.1.2, Table 28).
//!
//! Bits 0..3 and 7 form the command: 0 switch on, 1 enable voltage, 2 quick stop (active low),
//! 3 enable operation, 7 fault reset. While bit 7 is set no other command is decoded (every
//! command of Table 28 has bit 7 clear); the fault reset itself is the rising edge of bit 7,
//! which [`PowerDriveSystem`](super::PowerDriveSystem) detects across cycles.
//!
//! conformance.md words "switch on" as 0x07/0xC7; Table 28 gives `0xxx 0111`, i.e. mask 0x8F:
//! bit 3 tells "switch on" (0x07) from "switch on + enable operation" (0x0F), so this module
//! uses 0x8F.

/// Controlword bit 7: fault reset (rising edge).
pub const FAULT_RESET: u16 = 1 << 7;
/// Controlword bit 4 in profile position: new set-point (rising edge; CiA 402-2 0x6040, PP).
pub const NEW_SET_POINT: u16 = 1 << 4;
/// Controlword bit 4 in homing: homing operation start (rising edge starts, falling edge
/// interrupts; CiA 402-2 0x6040, HM).
pub const HOMING_START: u16 = 1 << 4;
/// Controlword bit 5 in profile position: change set immediately (1: single set-point, the new
/// one replaces the current; 0: set of set-points, the new one follows the current).
pub const CHANGE_SET_IMMEDIATELY: u16 = 1 << 5;
/// Controlword bit 6 in profile position: 0 absolute, 1 relative target.
pub const RELATIVE: u16 = 1 << 6;
/// Controlword bit 8: halt, in every mode (stop with the 0x605D ramp, stay Operation enabled).
pub const HALT: u16 = 1 << 8;
/// Controlword bit 9 in profile position: change on set-point (with bit 5 = 0: pass the current
/// target at its profile velocity and go on to the buffered one without stopping).
pub const CHANGE_ON_SET_POINT: u16 = 1 << 9;

/// A device control command of Table 28. "Disable operation" has the bits of "switch on", and
/// "switch on + enable operation" those of "enable operation": the state decides which one is
/// meant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    /// `0xxx xx0x` (mask 0x82): transitions 7, 9, 10, 12.
    DisableVoltage,
    /// `0xxx x01x` (mask 0x86): transitions 7, 10, 11.
    QuickStop,
    /// `0xxx x110` (mask 0x87): transitions 2, 6, 8.
    Shutdown,
    /// `0xxx 0111` (mask 0x8F): switch on (3) or disable operation (5).
    SwitchOn,
    /// `0xxx 1111` (mask 0x8F): enable operation (4, 16) or switch on + enable operation (3+4).
    EnableOperation,
}

impl Command {
    /// Every command with the mask that identifies it (Table 28).
    const MASKS: [(u16, Command); 5] = [
        (0x82, Command::DisableVoltage),
        (0x86, Command::QuickStop),
        (0x87, Command::Shutdown),
        (0x8F, Command::SwitchOn),
        (0x8F, Command::EnableOperation),
    ];

    /// The controlword a MainDevice sends for this command (Table 28, every other bit 0).
    pub const fn controlword(self) -> u16 {
        match self {
            Command::DisableVoltage => 0x00,
            Command::QuickStop => 0x02,
            Command::Shutdown => 0x06,
            Command::SwitchOn => 0x07,
            Command::EnableOperation => 0x0F,
        }
    }

    /// The command in `controlword`; `None` while bit 7 (fault reset) is set.
    pub fn decode(controlword: u16) -> Option<Self> {
        Self::MASKS
            .into_iter()
            .find(|&(mask, command)| controlword & mask == command.controlword())
            .map(|(_, command)| command)
    }
}
