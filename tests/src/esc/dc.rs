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
