//! A 4-in/4-out digital I/O SubDevice, board-independent: 4 digital outputs (0x7000:01..04,
//! output image bits 0..3) and 4 digital inputs (0x6000:01..04, input image bits 0..3), 1 byte
//! each way, and its dictionary — the one SOES's sample digital I/O device carries (0x1000,
//! 0x1008, 0x1009, 0x100A, 0x1018, 0x1C00, 0x1600, 0x1A00, 0x1C12, 0x1C13, 0x1C32, 0x1C33, 0x6000,
//! 0x7000), with 4 channels a way.
//!
//! The pins are any embedded-hal 1.0 [`OutputPin`]s and [`InputPin`]s that cannot fail (every
//! Embassy HAL's GPIO): the STM32G474 firmware (`examples/stm32`) and the RP2040 firmware
//! (`examples/rp2040`) run this same code on their own pins.
//!
//! Inputs are sampled at SYNC0 when the MainDevice runs the distributed clock (DC-synchronous
//! sampling: every SubDevice of the segment samples at the same instant), at the cycle otherwise.
//!
//! Feature `storage`: the dictionary also has 0x1010/0x1011 and CiA 401's input polarity 0x6002
//! (one byte: bit n inverts input n), which a "save" keeps in the firmware's flash.
#![no_std]

use core::convert::Infallible;

use ecat_core::Transition;
use ecat_core::device::Identity;
use ecat_core::dictionary::{Communication, DeviceInfo};
use ecat_core::pdo::{MappingEntry, PdoAssignment, PdoMapping};
use ecat_embassy::Application;
use embedded_hal::digital::{InputPin, OutputPin, PinState};

/// The communication area: CiA 401 generic I/O with digital inputs and outputs (0x1000 =
/// 0x0003_0191), the identity the SII image must carry. One product on every board: the same
/// process images and objects.
pub const INFO: DeviceInfo = DeviceInfo {
    device_type: 0x0003_0191,
    name: "ecat digital I/O",
    hardware_version: "4 DI / 4 DO",
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
    /// 0x6000: input n = pin n active (see [`DigitalIo::new`]), inverted where the polarity
    /// says so (feature `storage`).
    pub inputs: [bool; 4],
    /// 0x1010/0x1011 (feature `storage`).
    #[cfg(feature = "storage")]
    pub stored: ecat_core::dictionary::parameters::StoredParameters,
    /// 0x6002 (feature `storage`), CiA 401's input polarity, one byte here: bit n inverts
    /// input n. Kept by "save" (BACKUP).
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
// With storage: 0x1010/0x1011, and the input polarity as the parameter a "save" keeps.
#[cfg(feature = "storage")]
io_dictionary!((area, INFO, stored = stored) 0x6002 => var(polarity, RW | BACKUP, "Polarity input", max = 0x0F););

/// The pins, and the inputs as the SYNC0 task latched them.
pub struct DigitalIo<O, I> {
    outputs: [O; 4],
    inputs: [I; 4],
    /// Bit n set: input n reads 1 when its pin is low (a button to ground).
    active_low: u8,
    /// The inputs as sampled at the last SYNC0.
    latched: u8,
    /// SYNC0 pulses arrive: the cycle sends `latched`.
    sync0_active: bool,
}

impl<O, I> DigitalIo<O, I>
where
    O: OutputPin<Error = Infallible>,
    I: InputPin<Error = Infallible>,
{
    /// Takes the pins; bit n of `active_low` set: input n reads 1 when pin n is low.
    pub fn new(outputs: [O; 4], inputs: [I; 4], active_low: u8) -> Self {
        Self {
            outputs,
            inputs,
            active_low,
            latched: 0,
            sync0_active: false,
        }
    }

    /// Applies the output image's low nibble (bit n drives output n high).
    pub fn apply(&mut self, image: u8) {
        for (bit, pin) in self.outputs.iter_mut().enumerate() {
            let Ok(()) = pin.set_state(PinState::from(image >> bit & 1 != 0));
        }
    }

    /// The inputs now: bit n = input n active.
    pub fn sample(&mut self) -> u8 {
        let high = self
            .inputs
            .iter_mut()
            .enumerate()
            .fold(0, |image, (bit, pin)| {
                let Ok(high) = pin.is_high();
                image | u8::from(high) << bit
            });
        (high ^ self.active_low) & 0x0F
    }

    /// A SYNC0 pulse: latch the inputs for the next cycle.
    pub fn on_sync0(&mut self) {
        self.latched = self.sample();
        self.sync0_active = true;
    }

    /// The inputs of this cycle: latched at SYNC0 when it runs, sampled now otherwise.
    fn sampled(&mut self) -> u8 {
        if self.sync0_active {
            self.latched
        } else {
            self.sample()
        }
    }

    /// Logs the new state (feature `defmt`); below SAFEOP the next exchange samples at the cycle
    /// until SYNC0 shows up again.
    fn state_changed(&mut self, transition: Transition) {
        #[cfg(feature = "defmt")]
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

/// Without a dictionary (a size variant of the firmwares): output bits 0..3 drive the pins, input
/// bits 0..3 are the pins, straight from and into the process images.
impl<O, I> Application for DigitalIo<O, I>
where
    O: OutputPin<Error = Infallible>,
    I: InputPin<Error = Infallible>,
{
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

impl<O, I> Application<IoOd> for DigitalIo<O, I>
where
    O: OutputPin<Error = Infallible>,
    I: InputPin<Error = Infallible>,
{
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

#[cfg(test)]
mod tests {
    use core::cell::Cell;
    use core::convert::Infallible;

    use ecat_core::Transition;
    use ecat_core::al::AlState;
    use ecat_embassy::Application;
    use embedded_hal::digital::{ErrorType, InputPin, OutputPin};

    use super::{DigitalIo, IoOd};

    /// A pin level the test sets (inputs) or reads (outputs).
    struct Pin<'a>(&'a Cell<bool>);

    impl ErrorType for Pin<'_> {
        type Error = Infallible;
    }

    impl OutputPin for Pin<'_> {
        fn set_low(&mut self) -> Result<(), Infallible> {
            self.0.set(false);
            Ok(())
        }
        fn set_high(&mut self) -> Result<(), Infallible> {
            self.0.set(true);
            Ok(())
        }
    }

    impl InputPin for Pin<'_> {
        fn is_high(&mut self) -> Result<bool, Infallible> {
            Ok(self.0.get())
        }
        fn is_low(&mut self) -> Result<bool, Infallible> {
            Ok(!self.0.get())
        }
    }

    fn levels(cells: &[Cell<bool>; 4]) -> [bool; 4] {
        cells.each_ref().map(Cell::get)
    }

    fn set(cells: &[Cell<bool>; 4], values: [bool; 4]) {
        for (cell, value) in cells.iter().zip(values) {
            cell.set(value);
        }
    }

    fn io<'a>(out: &'a [Cell<bool>; 4], inp: &'a [Cell<bool>; 4]) -> DigitalIo<Pin<'a>, Pin<'a>> {
        DigitalIo::new(out.each_ref().map(Pin), inp.each_ref().map(Pin), 0b0001)
    }

    #[test]
    fn op_cycle_drives_the_outputs_from_0x7000_and_fills_0x6000() {
        let (out, inp) = (Default::default(), Default::default());
        let mut io = io(&out, &inp);
        let mut od = IoOd {
            outputs: [true, false, true, true],
            ..IoOd::default()
        };
        // Input 0 is active low: a low pin reads 1.
        set(&inp, [false, true, false, true]);
        io.cycle(&mut od, Some(&[0]), &mut [0]);
        assert_eq!(levels(&out), [true, false, true, true]);
        assert_eq!(od.inputs, [true, true, false, true]);
        // SAFEOP: the outputs go low whatever 0x7000 holds.
        io.cycle(&mut od, None, &mut [0]);
        assert_eq!(levels(&out), [false; 4]);
    }

    #[test]
    fn sync0_latches_the_inputs_until_the_state_falls_below_safeop() {
        let (out, inp) = (Default::default(), Default::default());
        let mut io = io(&out, &inp);
        set(&inp, [true, true, false, false]);
        io.on_sync0();
        set(&inp, [false, false, true, true]);
        let mut image = [0xFF];
        Application::<()>::cycle(&mut io, &mut (), Some(&[0x0A]), &mut image);
        assert_eq!(image, [0b0010], "the inputs of the SYNC0 instant");
        assert_eq!(levels(&out), [false, true, false, true]);
        Application::<()>::on_state_change(
            &mut io,
            Transition {
                from: AlState::SafeOp,
                to: AlState::PreOp,
            },
        );
        Application::<()>::cycle(&mut io, &mut (), None, &mut image);
        assert_eq!(image, [0b1101], "sampled at the cycle again");
        assert_eq!(levels(&out), [false; 4]);
    }

    /// Feature `storage`: 0x6002 inverts the inputs bit by bit, is backed up (what a "save"
    /// keeps) and refuses bits beyond the four inputs.
    #[cfg(feature = "storage")]
    #[test]
    fn the_polarity_inverts_inputs_and_is_a_backup_entry() {
        use ecat_core::dictionary::{Access, ObjectDictionary};

        let (out, inp) = (Default::default(), Default::default());
        let mut io = io(&out, &inp);
        let mut od = IoOd {
            polarity: 0b0110,
            ..IoOd::default()
        };
        set(&inp, [false, true, false, true]);
        io.cycle(&mut od, None, &mut [0]);
        assert_eq!(od.inputs, [true, false, true, true]);
        let object = IoOd::object(0x6002).expect("0x6002");
        let entry = object.info.entry(0).expect("SI0");
        assert!(entry.access.0 & Access::BACKUP.0 != 0);
        assert_eq!(
            (object.write)(&mut od, 0, &[0x10]),
            Err(ecat_core::coe::AbortCode::VALUE_TOO_HIGH)
        );
        assert!(IoOd::object(0x1010).is_some() && IoOd::object(0x1011).is_some());
    }

    #[test]
    fn safe_state_clears_the_outputs() {
        let (out, inp) = (Default::default(), Default::default());
        let mut io = io(&out, &inp);
        io.apply(0x0F);
        assert_eq!(levels(&out), [true; 4]);
        Application::<IoOd>::safe_state(&mut io, &mut IoOd::default());
        assert_eq!(levels(&out), [false; 4]);
    }
}
