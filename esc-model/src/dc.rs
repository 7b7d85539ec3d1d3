//! The distributed-clocks unit as far as MainDevices probe it (ESC datasheet section I,
//! "Distributed Clocks"; ETG.1000.4 §6.8): the local system time 0x0910 runs on the emulator's
//! clock plus the offset the MainDevice wrote into 0x0920, and a write to 0x0900 latches the
//! receive times (0x0900 port 0 .. 0x090C port 3, 0x0918 processing unit). Drift control and
//! propagation delays are not modelled: every port receives at the same instant.

use ecat_core::register;

use super::Esc;

/// Receive time port 0 (u32 each for ports 0..3).
const RECEIVE_TIME_PORT0: usize = 0x0900;
/// Receive time of the processing unit (u64).
const RECEIVE_TIME_UNIT: usize = 0x0918;
/// System time offset (u64), written by the MainDevice.
pub(super) const SYSTEM_TIME_OFFSET: u16 = 0x0920;
/// System time delay (u32): the propagation delay from the reference clock, written by the
/// MainDevice (ETG.1000.4 Table 60); kept, not applied (no propagation delay is modelled).
pub(super) const SYSTEM_TIME_DELAY: u16 = 0x0928;
/// 0x0141 bit 2: the SYNC out unit is on.
const SYNC_OUT_UNIT: u8 = 1 << 2;
/// 0x0151 bit 2: SYNC0 is an output (0: the pin is LATCH0, an input).
const SYNC0_OUTPUT: u8 = 1 << 2;

impl Esc {
    /// Lets the DC unit see the time: the local clock is at `ns` (nanoseconds since the emulator's
    /// epoch). Sets the system time register (0x0910) of an ESC with DC.
    pub fn set_local_time(&mut self, ns: u64) {
        self.local_time_ns = ns;
        if self.config.dc_supported {
            let system = self.system_time();
            self.memory
                .write(usize::from(register::DC_SYSTEM_TIME), &system.to_le_bytes());
        }
    }

    /// The system time: local time plus the offset the MainDevice set.
    pub fn system_time(&self) -> u64 {
        let mut offset = [0; 8];
        self.memory
            .read(usize::from(SYSTEM_TIME_OFFSET), &mut offset);
        self.local_time_ns.wrapping_add(u64::from_le_bytes(offset))
    }

    /// Whether the SYNC unit can drive SYNC0 at all: a DC unit, the SYNC out unit on (0x0141
    /// bit 2) and the SYNC0 pin an output (0x0151 bit 2), as the EEPROM's configuration area set
    /// them (ESC datasheet section II, 0x0141 and 0x0151). Otherwise no SYNC0 pulse leaves the
    /// ESC, whatever the MainDevice activates.
    pub fn sync0_output_enabled(&self) -> bool {
        let esc_config = self.memory.byte(usize::from(register::ESC_CONFIGURATION));
        let sync_config = self
            .memory
            .byte(usize::from(register::SYNC_LATCH_CONFIGURATION));
        self.config.dc_supported
            && esc_config & SYNC_OUT_UNIT != 0
            && sync_config & SYNC0_OUTPUT != 0
    }

    /// The SYNC unit generates a SYNC0 pulse: returns whether the pin shows a new edge. None
    /// unless [`Esc::sync0_output_enabled`]. With a pulse length (0x0982) the signal is a pulse
    /// of that length and every pulse is an edge; with 0, acknowledge mode, the signal stays
    /// active until the PDI reads the SYNC0 status (0x098E), so pulses before that read make no
    /// edge (ESC datasheet section II, 0x0982).
    pub fn sync0_pulse(&mut self) -> bool {
        if !self.sync0_output_enabled() {
            return false;
        }
        let at = usize::from(register::DC_SYNC_PULSE_LENGTH);
        let length = u16::from_le_bytes([self.memory.byte(at), self.memory.byte(at + 1)]);
        if length != 0 {
            return true;
        }
        !core::mem::replace(&mut self.sync0_active, true)
    }

    /// After a MainDevice write to `range`: a write touching 0x0900 latches the receive times.
    pub(super) fn dc_written(&mut self, range: core::ops::Range<usize>) {
        if !self.config.dc_supported || !range.contains(&RECEIVE_TIME_PORT0) {
            return;
        }
        let local = self.local_time_ns;
        let port = (local as u32).to_le_bytes();
        for n in 0..4 {
            self.memory.write(RECEIVE_TIME_PORT0 + 4 * n, &port);
        }
        self.memory.write(RECEIVE_TIME_UNIT, &local.to_le_bytes());
    }
}
