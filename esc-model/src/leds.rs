//! The ESC's own RUN and ERR LED outputs (ESC datasheet section I, "LED Signals"; section II,
//! 0x0138/0x0139): the LED code each output shows, from the AL status and the errors the ESC
//! detects itself, or from the override registers while their enable bit (bit 4) is set.
//!
//! | output | code without override |
//! |---|---|
//! | RUN | the state in AL status 0x0130 bits 3:0: INIT off, PREOP blinking, BOOT flickering, SAFEOP single flash, OP on; any other value off |
//! | ERR | flickering while the last EEPROM load failed (0x0502 bit 11 checksum or bit 12 device information error); else a double flash from a process-data watchdog expiry in OP to the next ESM state change; else a single flash while the error indication (0x0130 bit 4) is set and device emulation (0x0141 bit 0) is off; else off |
//!
//! Both ports may write the override registers. An ESM state change, a write of AL status with
//! a new valid state (1, 2, 3, 4 or 8; by the PDI, or the ESC's own copy of AL control under
//! device emulation), clears RUN's enable bit ("the RUN LED override is disabled automatically
//! by a following ESM state change", section I); a new error condition the ESC detects (the
//! error indication set, the watchdog expiry in OP) clears ERR's (section II's note on 0x0139).
//! Not modelled: ERR on for a PDI watchdog timeout (the model has no PDI watchdog), ERR
//! blinking for an invalid hardware configuration (pin sharing), RUN flickering while the
//! EEPROM loads (optional on ESCs; the model loads it at once).
//!
//! Timing: the code's ETG.1300 timeline ([`LedCode::level_at`]) on an
//! [`LedOutput`](ecat_core::indicator::LedOutput), started when the code an output shows
//! changes. The datasheets do not say how an ESC phases its blink generator; a restart is what
//! the firmware's own indicators do, so a RUN LED moved from a pin to the ESC blinks the same.
//! The model keeps no time (like its watchdog): the caller runs the codes on its clock (the host
//! emulator on virtual time).

use ecat_core::indicator::{LED_OVERRIDE, LedCode};
use ecat_core::register;

use super::Esc;
use super::registers::DEVICE_EMULATION;
use super::sii::{CHECKSUM_ERROR, DEVICE_INFO_ERROR};

/// AL status bits 3:0, the state.
const STATE: u8 = 0x0F;
/// AL status bit 4, the error indication.
const ERROR_INDICATION: u8 = 1 << 4;
/// AL status state OP.
const OP: u8 = 8;

/// RUN's code for the state in AL status bits 3:0 (section I, "RUN LED").
const fn run_code(state: u8) -> LedCode {
    LedCode::from_register(match state {
        2 => 0xD,
        3 => 0xE,
        4 => 0x1,
        8 => 0xF,
        _ => 0x0,
    })
}

/// Whether `state` is one of the ESM's states (AL status bits 3:0).
const fn valid_state(state: u8) -> bool {
    matches!(state, 1..=4 | 8)
}

impl Esc {
    /// The code the RUN LED output shows now: the override's while its enable bit is set, else
    /// the AL status's state's.
    pub fn run_led(&self) -> LedCode {
        let value = self.memory.byte(usize::from(register::RUN_LED_OVERRIDE));
        if value & LED_OVERRIDE != 0 {
            return LedCode::from_register(value);
        }
        run_code(self.memory.byte(usize::from(register::AL_STATUS)) & STATE)
    }

    /// The code the ERR LED output shows now: the override's while its enable bit is set, else
    /// the errors the ESC detects itself (see the module docs).
    pub fn err_led(&self) -> LedCode {
        let value = self.memory.byte(usize::from(register::ERR_LED_OVERRIDE));
        if value & LED_OVERRIDE != 0 {
            return LedCode::from_register(value);
        }
        let status = self.memory.byte(usize::from(register::AL_STATUS));
        let emulation =
            self.memory.byte(usize::from(register::ESC_CONFIGURATION)) & DEVICE_EMULATION;
        let eeprom_failed = self.previous_sii_status & (CHECKSUM_ERROR | DEVICE_INFO_ERROR) != 0;
        LedCode::from_register(if eeprom_failed {
            0xE
        } else if self.watchdog_led {
            0x2
        } else if status & ERROR_INDICATION != 0 && emulation == 0 {
            0x1
        } else {
            0x0
        })
    }

    /// AL status's first byte went from `old` to `new`: an ESM state change ends RUN's
    /// override and the watchdog's double flash; a new error indication ends ERR's override.
    pub(super) fn al_status_changed(&mut self, old: u8, new: u8) {
        if new & STATE != old & STATE && valid_state(new & STATE) {
            self.clear_override(register::RUN_LED_OVERRIDE);
            self.watchdog_led = false;
        }
        if new & !old & ERROR_INDICATION != 0 {
            self.clear_override(register::ERR_LED_OVERRIDE);
        }
    }

    /// The process-data watchdog expired: in OP, ERR double-flashes (a new error condition,
    /// which ends ERR's override).
    pub(super) fn watchdog_expired_led(&mut self) {
        if self.memory.byte(usize::from(register::AL_STATUS)) & STATE == OP {
            self.watchdog_led = true;
            self.clear_override(register::ERR_LED_OVERRIDE);
        }
    }

    /// Clears the enable bit of the override register at `address`; the code stays.
    fn clear_override(&mut self, address: u16) {
        let at = usize::from(address);
        let value = self.memory.byte(at);
        self.memory.set_byte(at, value & !LED_OVERRIDE);
    }
}
