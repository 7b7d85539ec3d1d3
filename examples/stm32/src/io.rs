//! The application: 4 digital outputs (0x7000:01..04, output image bits 0..3) and 4 digital
//! inputs (0x6000:01..04, input image bits 0..3), 1 byte each way, and its dictionary — the one
//! SOES's sample digital I/O device carries (0x1000, 0x1008, 0x1009, 0x100A, 0x1018, 0x1C00,
//! 0x1600, 0x1A00, 0x1C12, 0x1C13, 0x1C32, 0x1C33, 0x6000, 0x7000), with 4 channels a way.
//!
//! Inputs are sampled at SYNC0 when the MainDevice runs the distributed clock (DC-synchronous
//! sampling: every SubDevice of the segment samples at the same instant), at the cycle otherwise.

use ecat_core::Transition;
use ecat_core::device::Identity;
use ecat_core::dictionary::{Communication, DeviceInfo};
use ecat_core::pdo::{MappingEntry, PdoAssignment, PdoMapping};
use ecat_embassy::Application;
use embassy_stm32::gpio::{Input, Level, Output};

/// The communication area: CiA 401 generic I/O with digital inputs and outputs (0x1000 =
/// 0x0003_0191), the identity the SII image must carry.
pub const INFO: DeviceInfo = DeviceInfo {
    device_type: 0x0003_0191,
    name: "ecat STM32 digital I/O",
    hardware_version: "NUCLEO-G474RE",
    software_version: env!("CARGO_PKG_VERSION"),
    identity: Identity {
        vendor_id: 0xE000_0001,
        product_code: 0x0000_1044,
        revision: 1,
        serial: 1,
    },
};

/// The dictionary of the digital I/O device.
pub struct IoOd {
    /// The communication area ([`INFO`]).
    pub area: Communication,
    /// 0x1600: the outputs, then a 4-bit gap.
    pub rx: PdoMapping<5>,
    /// 0x1A00: the inputs, then a 4-bit gap.
    pub tx: PdoMapping<5>,
    /// 0x1C12.
    pub rx_assign: PdoAssignment<1>,
    /// 0x1C13.
    pub tx_assign: PdoAssignment<1>,
    /// 0x6000: input n = pin n high (the user button, active low, reads 1 when pressed).
    pub inputs: [bool; 4],
    /// 0x1010/0x1011 (feature `storage`).
    #[cfg(feature = "storage")]
    pub stored: ecat_core::dictionary::parameters::StoredParameters,
    /// 0x6002 (feature `storage`): bit n inverts input n; stored by "save".
    #[cfg(feature = "storage")]
    pub polarity: u8,
    /// 0x7000: output n drives pin n.
    pub outputs: [bool; 4],
}

/// 0x7000:01..04, one bit each, and 4 bits of gap: one output byte.
const RX: [MappingEntry; 5] = [
    MappingEntry::new(0x7000, 1, 1),
    MappingEntry::new(0x7000, 2, 1),
    MappingEntry::new(0x7000, 3, 1),
    MappingEntry::new(0x7000, 4, 1),
    MappingEntry::new(0, 0, 4),
];

/// 0x6000:01..04 and 4 bits of gap: one input byte.
const TX: [MappingEntry; 5] = [
    MappingEntry::new(0x6000, 1, 1),
    MappingEntry::new(0x6000, 2, 1),
    MappingEntry::new(0x6000, 3, 1),
    MappingEntry::new(0x6000, 4, 1),
    MappingEntry::new(0, 0, 4),
];

/// The dictionary's declaration: `$communication` is the area's item, `$polarity` the objects
/// only the `storage` variant has (between 0x6000 and 0x7000).
macro_rules! io_dictionary {
    (($($communication:tt)*) $($polarity:tt)*) => {
        ecat_core::dictionary! {
            IoOd {
                communication($($communication)*);
                0x1600 => pdo(rx, RO, "Outputs", "Mapped object", default = PdoMapping::mapping(&RX));
                0x1A00 => pdo(tx, RO, "Inputs", "Mapped object", default = PdoMapping::mapping(&TX));
                0x1C12 => pdo(rx_assign, RO, "SM2 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1600]));
                0x1C13 => pdo(tx_assign, RO, "SM3 PDO assignment", "Assigned PDO", default = PdoAssignment::assignment(&[0x1A00]));
                0x6000 => array(inputs, RO | TXPDO, "Digital inputs", "Input");
                $($polarity)*
                0x7000 => array(outputs, RW | RXPDO, "Digital outputs", "Output");
            }
        }
    };
}

#[cfg(not(feature = "storage"))]
io_dictionary!((area, INFO));
// With storage: 0x1010/0x1011, and the input polarity (CiA 401's 0x6002, one byte here: bit n
// inverts input n) as the parameter a "save" keeps.
#[cfg(feature = "storage")]
io_dictionary!((area, INFO, stored = stored) 0x6002 => var(polarity, RW | BACKUP, "Polarity input", max = 0x0F););

/// The pins, and the inputs as the SYNC0 task latched them.
pub struct DigitalIo {
    outputs: [Output<'static>; 4],
    inputs: [Input<'static>; 4],
    /// The inputs as sampled at the last SYNC0.
    latched: u8,
    /// SYNC0 pulses arrive: the cycle sends `latched`.
    sync0_active: bool,
}

impl DigitalIo {
    /// Takes the pins.
    pub fn new(outputs: [Output<'static>; 4], inputs: [Input<'static>; 4]) -> Self {
        Self {
            outputs,
            inputs,
            latched: 0,
            sync0_active: false,
        }
    }

    /// Applies the output image's low nibble.
    pub fn apply(&mut self, image: u8) {
        for (bit, pin) in self.outputs.iter_mut().enumerate() {
            pin.set_level(Level::from(image >> bit & 1 != 0));
        }
    }

    /// The input pins now (bit n = pin n high; the user button, active low, reads 1 when
    /// pressed).
    pub fn sample(&self) -> u8 {
        self.inputs.iter().enumerate().fold(0, |image, (bit, pin)| {
            image | u8::from(pin.is_high() != (bit == 0)) << bit
        })
    }

    /// A SYNC0 pulse: latch the inputs for the next cycle.
    pub fn on_sync0(&mut self) {
        self.latched = self.sample();
        self.sync0_active = true;
    }

    /// The inputs of this cycle: latched at SYNC0 when it runs, sampled now otherwise.
    fn sampled(&self) -> u8 {
        if self.sync0_active {
            self.latched
        } else {
            self.sample()
        }
    }

    /// Logs the new state; below SAFEOP the next exchange samples at the cycle until SYNC0 shows
    /// up again.
    fn state_changed(&mut self, transition: Transition) {
        defmt::info!(
            "AL state {=u8:#x} -> {=u8:#x}",
            transition.from as u8,
            transition.to as u8
        );
        if !transition.to.has_process_data() {
            self.sync0_active = false;
        }
    }
}

/// Without a dictionary (feature `no-dictionary`, a size variant): output bits 0..3 drive the
/// pins, input bits 0..3 are the pins, straight from and into the process images.
impl Application for DigitalIo {
    fn cycle(&mut self, _: &mut (), outputs: Option<&[u8]>, inputs: &mut [u8]) {
        self.apply(outputs.and_then(|o| o.first().copied()).unwrap_or(0));
        if let Some(byte) = inputs.first_mut() {
            *byte = self.sampled();
        }
    }

    fn safe_state(&mut self, _: &mut ()) {
        self.apply(0);
    }

    fn on_state_change(&mut self, transition: Transition) {
        self.state_changed(transition);
    }
}

impl Application<IoOd> for DigitalIo {
    /// In OP the outputs arrive unpacked in 0x7000; the inputs leave packed from 0x6000.
    fn cycle(&mut self, od: &mut IoOd, outputs: Option<&[u8]>, _inputs: &mut [u8]) {
        let image = match outputs {
            Some(_) => bits(&od.outputs),
            // SAFEOP: outputs stay in their safe state.
            None => 0,
        };
        self.apply(image);
        #[cfg(not(feature = "storage"))]
        let sampled = self.sampled();
        #[cfg(feature = "storage")]
        let sampled = self.sampled() ^ od.polarity;
        for (bit, input) in od.inputs.iter_mut().enumerate() {
            *input = sampled >> bit & 1 != 0;
        }
    }

    fn safe_state(&mut self, _: &mut IoOd) {
        self.apply(0);
    }

    fn on_state_change(&mut self, transition: Transition) {
        self.state_changed(transition);
    }
}

/// Bit n = `values[n]`.
fn bits(values: &[bool; 4]) -> u8 {
    values
        .iter()
        .enumerate()
        .fold(0, |image, (bit, &on)| image | u8::from(on) << bit)
}
