//! The LAN9252 driver's waits, in virtual time: start-up polling of the byte-order test and
//! `HW_CFG.READY`, and every timeout with what it waited for.
//!
//! embassy-time's mock driver is one clock per process, so the tests of this binary take turns.

use core::pin::pin;
use core::task::{Context, Poll, Waker};
use std::sync::{Mutex, MutexGuard, PoisonError};

use ecat_core::chip::Chip;
use ecat_embassy::Pdi;
use ecat_embassy::spi::lan9252::{self, Error, Lan9252, Wait, WriteSpace};
use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::spi::lan9252::{BYTE_TEST_PATTERN, Lan9252Chip, Lan9252Config};
use ecat_emu::spi::{FakeSpi, Probe};
use embassy_time::{Duration, Instant, MockDriver};

static CLOCK: Mutex<()> = Mutex::new(());

/// Takes the clock and sets it to zero.
fn clock() -> MutexGuard<'static, ()> {
    let guard = CLOCK.lock().unwrap_or_else(PoisonError::into_inner);
    MockDriver::get().reset();
    guard
}

/// Polls `future` to completion, advancing virtual time by 100 µs whenever it waits for time (not
/// when it yields inside an SPI transaction). Returns its output and the virtual time it took.
fn run<F: Future>(probe: &Probe, future: F) -> (F::Output, Duration) {
    let start = Instant::now();
    let mut future = pin!(future);
    let mut cx = Context::from_waker(Waker::noop());
    loop {
        let before = probe.stats();
        if let Poll::Ready(output) = future.as_mut().poll(&mut cx) {
            return (output, Instant::now() - start);
        }
        if probe.stats() == before {
            MockDriver::get().advance(Duration::from_micros(100));
        }
    }
}

fn chip(config: Lan9252Config) -> (FakeSpi<Lan9252Chip>, Probe) {
    let probe = Probe::default();
    let emu = Emulator::new(EscConfig::of(Chip::LAN9252));
    (
        FakeSpi::new(Lan9252Chip::new(emu, config), probe.clone()),
        probe,
    )
}

/// Transactions that read the register at `address`.
fn reads_of(probe: &Probe, address: u16) -> usize {
    let [high, low] = address.to_be_bytes();
    probe
        .take_log()
        .iter()
        .filter(|t| t[..3] == [0x03, high, low])
        .count()
}

#[test]
fn start_up_waits_for_the_byte_order_test_then_for_ready() {
    let _clock = clock();
    let (spi, probe) = chip(Lan9252Config {
        reset_polls: 3,
        ready_after: Some(2),
        ..Lan9252Config::default()
    });
    let (result, _) = run(&probe, Lan9252::start(spi, lan9252::Config::default()));
    assert!(result.is_ok());
    let log = probe.take_log();
    let count = |address: u8| {
        log.iter()
            .filter(|t| t[..3] == [0x03, 0x00, address])
            .count()
    };
    assert_eq!(
        (count(0x64), count(0x74)),
        (4, 3),
        "BYTE_TEST, HW_CFG reads"
    );
}

#[test]
fn a_wrong_byte_order_test_value_fails_with_the_value_read() {
    let _clock = clock();
    let (spi, probe) = chip(Lan9252Config {
        byte_test: 0x2143_6587,
        ..Lan9252Config::default()
    });
    let (result, took) = run(&probe, Lan9252::start(spi, lan9252::Config::default()));
    assert_eq!(result.err(), Some(Error::ByteTest { read: 0x2143_6587 }));
    assert!(took >= Duration::from_secs(1), "gave up after {took}");
    assert!(took < Duration::from_millis(1_001), "gave up after {took}");
}

#[test]
fn a_chip_that_never_gets_ready_times_out() {
    let _clock = clock();
    let (spi, probe) = chip(Lan9252Config {
        ready_after: None,
        ..Lan9252Config::default()
    });
    let config = lan9252::Config {
        startup_timeout: Duration::from_millis(50),
        ..lan9252::Config::default()
    };
    let (result, took) = run(&probe, Lan9252::start(spi, config));
    assert_eq!(result.err(), Some(Error::Timeout(Wait::Ready)));
    assert!(took >= Duration::from_millis(50) && took < Duration::from_millis(51));
    assert_eq!(reads_of(&probe, 0x0064), 1, "the byte test passed at once");
}

#[test]
fn the_byte_test_value_is_accepted_whenever_it_comes() {
    let _clock = clock();
    let (spi, probe) = chip(Lan9252Config {
        reset_polls: 100,
        ..Lan9252Config::default()
    });
    assert_eq!(BYTE_TEST_PATTERN, lan9252::BYTE_TEST_PATTERN);
    let (result, took) = run(&probe, Lan9252::start(spi, lan9252::Config::default()));
    assert!(result.is_ok());
    assert!(took < Duration::from_millis(20), "{took}");
}

/// A started driver on a chip with `config`.
fn started(
    config: Lan9252Config,
    driver: lan9252::Config,
) -> (Lan9252<FakeSpi<Lan9252Chip>>, Probe) {
    let (spi, probe) = chip(config);
    let (result, _) = run(&probe, Lan9252::start(spi, driver));
    (result.expect("start"), probe)
}

#[test]
fn a_csr_command_that_stays_busy_times_out() {
    let _clock = clock();
    let (mut driver, probe) = started(
        Lan9252Config {
            csr_latency: u32::MAX,
            ..Lan9252Config::default()
        },
        lan9252::Config::default(),
    );
    let (result, took) = run(&probe, driver.read(0x0130, &mut [0; 2]));
    assert_eq!(result, Err(Error::Timeout(Wait::Csr)));
    assert!(
        took >= Duration::from_millis(1) && took < Duration::from_micros(1_200),
        "{took}"
    );
}

#[test]
fn a_csr_command_that_takes_a_while_is_waited_for() {
    let _clock = clock();
    let (mut driver, probe) = started(
        Lan9252Config {
            csr_latency: 4,
            ..Lan9252Config::default()
        },
        lan9252::Config::default(),
    );
    probe.take_log();
    let (result, _) = run(&probe, driver.write(0x0134, &[0x1D, 0x00]));
    assert_eq!(result, Ok(ecat_core::AlEvent::NONE));
    assert_eq!(
        reads_of(&probe, 0x0304),
        5,
        "ECAT_CSR_CMD polled until no longer busy"
    );
    assert!(probe.violations().is_empty(), "{:?}", probe.violations());
}

#[test]
fn an_empty_read_fifo_times_out() {
    let _clock = clock();
    let (mut driver, probe) = started(
        Lan9252Config {
            fifo_fill: 0,
            ..Lan9252Config::default()
        },
        lan9252::Config::default(),
    );
    let (result, _) = run(&probe, driver.read(0x1100, &mut [0; 8]));
    assert_eq!(result, Err(Error::Timeout(Wait::PramRead)));
}

#[test]
fn a_full_write_fifo_times_out() {
    let _clock = clock();
    for write_space in [WriteSpace::EmptyAtStart, WriteSpace::Polled] {
        let (mut driver, probe) = started(
            Lan9252Config {
                fifo_drain: 0,
                ..Lan9252Config::default()
            },
            lan9252::Config {
                write_space,
                ..lan9252::Config::default()
            },
        );
        let (result, _) = run(&probe, driver.write(0x1100, &[0; 65]));
        assert_eq!(
            result,
            Err(Error::Timeout(Wait::PramWrite)),
            "{write_space:?}"
        );
    }
}
