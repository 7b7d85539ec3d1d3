//! The application: 4 digital outputs (output image bits 0..3) and 4 digital inputs (input image
//! bits 0..3), 1 byte each way.
//!
//! Inputs are sampled at SYNC0 when the MainDevice runs the distributed clock (DC-synchronous
//! sampling: every SubDevice of the segment samples at the same instant), at the cycle otherwise.

use core::cell::RefCell;
use core::sync::atomic::{AtomicBool, AtomicU8, Ordering};

use ecat_embassy::CycleHandler;
use embassy_stm32::gpio::{Input, Level, Output};
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;

/// The input pins, sampled by the cycle and by the SYNC0 task.
static INPUTS: Mutex<CriticalSectionRawMutex, RefCell<Option<[Input<'static>; 4]>>> =
    Mutex::new(RefCell::new(None));
/// The inputs as sampled at the last SYNC0.
static LATCHED: AtomicU8 = AtomicU8::new(0);
/// SYNC0 pulses arrive: the cycle sends [`LATCHED`].
static SYNC0_ACTIVE: AtomicBool = AtomicBool::new(false);

/// The pins: the outputs owned here, the inputs shared with the SYNC0 task.
pub struct DigitalIo {
    outputs: [Output<'static>; 4],
}

impl DigitalIo {
    /// Takes the pins.
    pub fn new(outputs: [Output<'static>; 4], inputs: [Input<'static>; 4]) -> Self {
        INPUTS.lock(|cell| cell.replace(Some(inputs)));
        Self { outputs }
    }

    /// Applies the output image's low nibble.
    pub fn apply(&mut self, image: u8) {
        for (bit, pin) in self.outputs.iter_mut().enumerate() {
            pin.set_level(Level::from(image >> bit & 1 != 0));
        }
    }
}

/// The input pins now (bit n = pin n high; the user button, active low, reads 1 when pressed).
pub fn sample() -> u8 {
    INPUTS.lock(|cell| {
        cell.borrow().as_ref().map_or(0, |pins| {
            pins.iter().enumerate().fold(0, |image, (bit, pin)| {
                image | u8::from(pin.is_high() != (bit == 0)) << bit
            })
        })
    })
}

/// A SYNC0 pulse: latch the inputs for the next cycle.
pub fn on_sync0() {
    LATCHED.store(sample(), Ordering::Relaxed);
    SYNC0_ACTIVE.store(true, Ordering::Relaxed);
}

/// The process data stopped (below SAFEOP): the next exchange samples at the cycle until SYNC0
/// shows up again.
pub fn on_process_data_stopped() {
    SYNC0_ACTIVE.store(false, Ordering::Relaxed);
}

impl CycleHandler<()> for DigitalIo {
    fn cycle(&mut self, _od: &mut (), outputs: Option<&[u8]>, inputs: &mut [u8]) {
        match outputs.and_then(|o| o.first()) {
            Some(&image) => self.apply(image),
            // SAFEOP: outputs stay in their safe state.
            None => self.apply(0),
        }
        if let Some(image) = inputs.first_mut() {
            *image = if SYNC0_ACTIVE.load(Ordering::Relaxed) {
                LATCHED.load(Ordering::Relaxed)
            } else {
                sample()
            };
        }
    }
}
