//! The SPI port the firmware wires the drivers to (`ecat_embassy::spi::port::Exclusive`: an
//! `SpiBus` and the chip-select pin): what it does on the bus, call by call, alone and under the
//! Beckhoff driver. The emulator suites drive the same drivers through an `SpiDevice` model.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::convert::Infallible;
use std::rc::Rc;

use ecat_core::AlEvent;
use ecat_embassy::Pdi;
use ecat_embassy::spi::beckhoff::{BeckhoffSpi, Config};
use ecat_embassy::spi::port::{Error, Exclusive, Part, Port};
use ecat_emu::spi::BusError;
use embassy_futures::block_on;
use embedded_hal::digital::OutputPin;
use embedded_hal_async::spi::{ErrorType, SpiBus};

/// One call on the bus or the pin.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Call {
    CsLow,
    CsHigh,
    /// `transfer_in_place` with these bytes on MOSI.
    Exchange(Vec<u8>),
    Write(Vec<u8>),
    Read(usize),
    Transfer(Vec<u8>),
    Flush,
}

#[derive(Default)]
struct Wire {
    calls: Vec<Call>,
    /// What the chip shifts out, byte by byte (0 when empty).
    miso: VecDeque<u8>,
    /// The bus call (counted from 0, chip select excluded) that fails.
    fail_at: Option<usize>,
}

#[derive(Clone, Default)]
struct Recorder(Rc<RefCell<Wire>>);

impl Recorder {
    fn calls(&self) -> Vec<Call> {
        self.0.borrow().calls.clone()
    }

    /// Records a bus call; whether it fails.
    fn bus_call(&self, call: Call) -> Result<(), BusError> {
        let mut wire = self.0.borrow_mut();
        let index = wire
            .calls
            .iter()
            .filter(|c| !matches!(c, Call::CsLow | Call::CsHigh))
            .count();
        wire.calls.push(call);
        if wire.fail_at == Some(index) {
            return Err(BusError);
        }
        Ok(())
    }
}

struct Bus(Recorder);

impl ErrorType for Bus {
    type Error = BusError;
}

impl SpiBus for Bus {
    async fn read(&mut self, words: &mut [u8]) -> Result<(), BusError> {
        self.0.bus_call(Call::Read(words.len()))
    }

    async fn write(&mut self, words: &[u8]) -> Result<(), BusError> {
        self.0.bus_call(Call::Write(words.to_vec()))
    }

    async fn transfer(&mut self, _read: &mut [u8], write: &[u8]) -> Result<(), BusError> {
        self.0.bus_call(Call::Transfer(write.to_vec()))
    }

    async fn transfer_in_place(&mut self, words: &mut [u8]) -> Result<(), BusError> {
        self.0.bus_call(Call::Exchange(words.to_vec()))?;
        let mut wire = self.0.0.borrow_mut();
        for byte in words {
            *byte = wire.miso.pop_front().unwrap_or(0);
        }
        Ok(())
    }

    async fn flush(&mut self) -> Result<(), BusError> {
        self.0.bus_call(Call::Flush)
    }
}

struct Cs(Recorder);

impl embedded_hal::digital::ErrorType for Cs {
    type Error = Infallible;
}

impl OutputPin for Cs {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.0.0.borrow_mut().calls.push(Call::CsLow);
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Infallible> {
        self.0.0.borrow_mut().calls.push(Call::CsHigh);
        Ok(())
    }
}

fn port() -> (Exclusive<Bus, Cs>, Recorder) {
    let recorder = Recorder::default();
    let port = Exclusive::new(Bus(recorder.clone()), Cs(recorder.clone()));
    (port, recorder)
}

#[test]
fn parts_go_out_in_order_within_one_chip_select_cycle() {
    let (mut port, recorder) = port();
    recorder.0.borrow_mut().miso.extend([0xA1, 0xA2]);
    let mut exchanged = [0x11, 0x12];
    let result = block_on(port.transaction([
        Part::Exchange(&mut exchanged),
        Part::Write(&[0x21, 0x22, 0x23]),
    ]));
    assert_eq!(result, Ok(()));
    assert_eq!(
        exchanged,
        [0xA1, 0xA2],
        "what came in replaces what went out"
    );
    assert_eq!(
        recorder.calls(),
        [
            Call::CsLow,
            Call::Exchange(vec![0x11, 0x12]),
            Call::Write(vec![0x21, 0x22, 0x23]),
            Call::Flush,
            Call::CsHigh,
        ]
    );
}

#[test]
fn a_failing_part_ends_the_cycle_with_chip_select_released() {
    let (mut port, recorder) = port();
    recorder.0.borrow_mut().fail_at = Some(0);
    let result = block_on(port.transaction([Part::Exchange(&mut [0x11]), Part::Write(&[0x21])]));
    assert_eq!(result, Err(Error::Spi(BusError)));
    assert_eq!(
        recorder.calls(),
        [
            Call::CsLow,
            Call::Exchange(vec![0x11]),
            Call::Flush,
            Call::CsHigh,
        ],
        "no part after the failed one; flushed and deselected all the same"
    );
}

#[test]
fn the_beckhoff_driver_reads_and_writes_through_the_port() {
    let (port, recorder) = port();
    let mut driver = BeckhoffSpi::new(port, Config::default());
    // The AL event (0x0220, 0x0221) during the address phase, nothing during the wait state
    // byte, then the two data bytes.
    recorder
        .0
        .borrow_mut()
        .miso
        .extend([0x01, 0x00, 0x00, 0x34, 0x12]);
    let mut buf = [0xEE; 2];
    let event = block_on(driver.read(0x0130, &mut buf));
    assert_eq!(event, Ok(AlEvent(0x0001)));
    assert_eq!(buf, [0x34, 0x12]);
    let event = block_on(driver.write(0x0120, &[0x02, 0x00]));
    assert_eq!(event, Ok(AlEvent(0)));
    assert_eq!(
        recorder.calls(),
        [
            // 0x0130 = A[12:5] 0x09, A[4:0] 0x10 << 3 | read with wait state (0b011), wait state.
            Call::CsLow,
            Call::Exchange(vec![0x09, 0x83, 0xFF]),
            Call::Exchange(vec![0x00, 0xFF]),
            Call::Flush,
            Call::CsHigh,
            // 0x0120 = A[12:5] 0x09, A[4:0] 0x00 << 3 | write (0b100).
            Call::CsLow,
            Call::Exchange(vec![0x09, 0x04]),
            Call::Write(vec![0x02, 0x00]),
            Call::Flush,
            Call::CsHigh,
        ],
        "no read or transfer call: the driver needs neither"
    );
}
