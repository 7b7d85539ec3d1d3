//! No process-data cycle is lost or run twice, wherever the MainDevice's SM2 write falls in the PDI
//! traffic: for both SPI drivers and the 16-bit microcontroller interface (each bus cycle a
//! transaction of its data bytes), under mailbox traffic (an SDO exchange in flight, so the IRQ also
//! prompts the runners' reads for the state machine), the new outputs are placed before every
//! byte of every transaction of an exchange, one placement at a time ([`Probe::at`]), and every
//! new output buffer must be processed exactly once and answered with its inputs.
//!
//! The hazards (issue #21, point 0): the output area read on an IRQ whatever the AL event sampled
//! before the read says (the LAN9252 driver samples 0x0220 18 bytes before its PRAM read starts,
//! the Beckhoff ESC shifts it out before the read starts at the end of the address phase). A
//! buffer completed in between is taken (and its SM2 event cleared) by the read, yet the event
//! reported has no SM2: no cycle, and nothing left to raise the IRQ again. And a cycle run twice
//! when both runners see the same SM2 event. Each placement reports what it found; the tests
//! assert none of either.

use core::cell::{Cell, RefCell};
use std::rc::Rc;

use ecat_core::chip::Chip;
use ecat_core::device::{Area, MailboxConfig, ProcessDataSizes};
use ecat_core::mailbox::{MailboxHeader, MailboxType, next_counter};
use ecat_core::{AlEvent, DeviceConfig};
use ecat_embassy::mcu::Mcu16;
use ecat_embassy::spi::beckhoff::{self, BeckhoffSpi};
use ecat_embassy::spi::lan9252::{self, Lan9252};
use ecat_embassy::{Application, Pdi};
use ecat_emu::emulator::Emulator;
use ecat_emu::esc::EscConfig;
use ecat_emu::harness::{self, AcceptAll, Device};
use ecat_emu::master::TestMaster;
use ecat_emu::mcu::{self, Cycles, FakeBus16};
use ecat_emu::spi::beckhoff::BeckhoffEsc;
use ecat_emu::spi::lan9252::{Lan9252Chip, Lan9252Config};
use ecat_emu::spi::{FakeSpi, Probe};

/// Bytes of outputs and of inputs.
const IMAGE: u16 = 12;

/// Every output image the application's cycle was given, in order; inputs = outputs.
#[derive(Clone, Default)]
struct Recorder(Rc<RefCell<Vec<Vec<u8>>>>);

impl<D> Application<D> for Recorder {
    fn cycle(&mut self, _od: &mut D, outputs: Option<&[u8]>, inputs: &mut [u8]) {
        if let Some(outputs) = outputs {
            self.0.borrow_mut().push(outputs.to_vec());
            inputs.copy_from_slice(outputs);
        }
    }
}

/// The image the MainDevice writes for placement `n`: unique per placement.
fn image(tag: u8, n: usize) -> Vec<u8> {
    let [lo, hi] = (n as u16).to_le_bytes();
    let mut image = vec![tag, lo, hi];
    image.resize(usize::from(IMAGE), tag ^ lo);
    image
}

/// What the placements found.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
struct Findings {
    /// Placements tried.
    placements: usize,
    /// Buffers taken by a read but never given to the cycle (stale inputs for the MainDevice).
    lost: usize,
    /// Buffers given to the cycle more than once, or cycles on outputs no one wrote since.
    repeated: usize,
}

/// One scenario: the mailboxes, the process image, and whether a first output buffer (`A`) comes
/// with the SDO request (so the exchange contains a whole process-data cycle as well). The
/// placements walk through the exchange's traffic (`B`, the buffer placed).
struct Scenario {
    mailbox: MailboxConfig,
    outputs: Area,
    inputs: Area,
    with_cycle: bool,
}

impl Scenario {
    fn new(mailbox_size: u16, with_cycle: bool) -> Self {
        let mailbox = MailboxConfig::contiguous(0x1000, mailbox_size);
        let outputs = Area::new(0x1000 + 2 * mailbox_size, IMAGE);
        let inputs = Area::new(outputs.start + 0x80, IMAGE);
        Self {
            mailbox,
            outputs,
            inputs,
            with_cycle,
        }
    }

    fn config(&self, esc: &EscConfig) -> DeviceConfig {
        let mut config = DeviceConfig::new(
            self.mailbox,
            ProcessDataSizes {
                outputs: IMAGE,
                inputs: IMAGE,
            },
        );
        config.sync_manager_count = esc.sync_managers;
        config.process_ram_end = esc.process_ram_end;
        config
    }

    /// The exchange every placement repeats: (the first buffer and) an SDO upload request, the
    /// SubDevice's answer read from SM1, then the traffic the SM1 read causes. `counter` is the
    /// MainDevice's mailbox counter.
    async fn exchange(
        &self,
        master: &TestMaster,
        probe: &Probe,
        counter: &mut u8,
        a: Option<&[u8]>,
    ) {
        if let Some(a) = a {
            assert!(master.write(self.outputs.start, a));
        }
        // CoE SDO upload request of 0x1000:00 (the device has no dictionary: an abort answers).
        *counter = next_counter(*counter);
        let sdo = [0x00, 0x20, 0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0];
        let header = MailboxHeader::new(MailboxType::Coe, sdo.len() as u16, *counter);
        let mut request = header.to_bytes().to_vec();
        request.extend_from_slice(&sdo);
        request.resize(usize::from(self.mailbox.receive.length), 0);
        assert!(master.write(self.mailbox.receive.start, &request));
        settle(master, probe).await;
        let send = self.mailbox.send;
        let answer = master
            .read(send.start, usize::from(send.length))
            .expect("an answer in SM1");
        let header = MailboxHeader::parse(&answer).expect("a mailbox header");
        // CoE service 3 (SDO response) or 2 (an abort, ETG.1000.6 Table 41).
        let service = answer.get(7).map(|b| b >> 4);
        assert_eq!(header.kind, MailboxType::Coe);
        assert!(
            matches!(service, Some(2 | 3)),
            "an SDO answer: {answer:02x?}"
        );
        settle(master, probe).await;
    }
}

/// Lets the runners run until neither the ESC nor the SPI bus sees traffic for a while (the
/// MainDevice's `settle` watches the ESC only, and a LAN9252 moving a long mailbox through its
/// FIFO clocks many transactions between two ESC accesses).
async fn settle(master: &TestMaster, probe: &Probe) {
    let mut quiet = 0;
    let mut last = (master.pdi_accesses(), probe.stats());
    for _ in 0..100_000 {
        embassy_futures::yield_now().await;
        master.emulator().script_ran();
        let now = (master.pdi_accesses(), probe.stats());
        quiet = if now == last { quiet + 1 } else { 0 };
        last = now;
        if quiet >= 8 {
            return;
        }
    }
    panic!("the SubDevice keeps the bus busy: livelock");
}

/// Runs `scenario` on the driver `make` builds: measures the exchange's traffic, then places the
/// SM2 write before each of its bytes in turn.
fn place_everywhere<P: Pdi + 'static>(
    scenario: Scenario,
    esc: EscConfig,
    make: impl FnOnce(&Emulator, Probe) -> P + 'static,
) -> Findings {
    let recorder = Recorder::default();
    let seen = recorder.0.clone();
    let mut device = Device::new(scenario.config(&esc), AcceptAll, recorder);
    device.esc = esc;
    let probe = Probe::default();
    let bus = probe.clone();
    let findings = Rc::new(Cell::new(Findings::default()));
    let out = findings.clone();
    harness::run_with_pdi(
        device,
        move |emu: &Emulator| make(emu, bus),
        move |master| async move {
            let s = &scenario;
            master.reset().await;
            assert_eq!(master.request(0x01).await, (0x01, 0));
            master.configure_mailbox(&s.mailbox);
            master.configure_process_data(Some(s.outputs), Some(s.inputs));
            for state in [0x02, 0x04, 0x08] {
                assert_eq!(master.request(state).await, (state, 0));
                if state == 0x04 {
                    assert!(master.write(s.outputs.start, &image(0xEE, 0)));
                    master.settle().await;
                }
            }
            let mut counter = 0;
            // The exchange's traffic, after one to warm up (the first request changes the event
            // mask), twice: it must not depend on the mailbox counter or on anything else that
            // changes from one exchange to the next.
            let mut traffic = Vec::new();
            for round in 0..3 {
                probe.take_log();
                let a = image(0xA0, 1000 + round);
                s.exchange(
                    &master,
                    &probe,
                    &mut counter,
                    s.with_cycle.then_some(&a[..]),
                )
                .await;
                let lengths: Vec<usize> = probe.take_log().iter().map(Vec::len).collect();
                if round == 2 {
                    assert_eq!(lengths, traffic, "the exchange's traffic repeats");
                }
                traffic = lengths;
            }
            let emu = master.emulator().clone();
            let sm2 = AlEvent::sync_manager(2);
            let mut findings = Findings::default();
            let mut placement = 0;
            for (m, &len) in traffic.iter().enumerate() {
                for byte in 0..len {
                    placement += 1;
                    seen.borrow_mut().clear();
                    let (a, b) = (image(0xA0, placement), image(0xB0, placement));
                    // Whether `A` was still waiting (not taken by a read) when `B` came: then
                    // `B` replaces it, as a 3-buffer SyncManager does.
                    let a_waiting = Rc::new(Cell::new(None));
                    let waiting = a_waiting.clone();
                    let (esc, write, at) = (emu.clone(), b.clone(), s.outputs.start);
                    let base = probe.stats().transactions;
                    probe.take_log();
                    probe.at(base + m as u64, byte, move || {
                        let pending = esc.with(|esc| esc.al_event()).intersects(sm2);
                        waiting.set(Some(pending));
                        assert!(esc.with(|esc| esc.ecat_write(at, &write)));
                    });
                    s.exchange(
                        &master,
                        &probe,
                        &mut counter,
                        s.with_cycle.then_some(&a[..]),
                    )
                    .await;
                    assert!(!probe.armed(), "placement {m}/{byte} reached");
                    let seen = seen.borrow().clone();
                    let count = |image: &[u8]| seen.iter().filter(|o| *o == image).count();
                    let expected_a = match a_waiting.get() {
                        _ if !s.with_cycle => 0,
                        Some(true) => 0,
                        _ => 1,
                    };
                    let (got_a, got_b) = (count(&a), count(&b));
                    let lost = usize::from(got_b == 0) + usize::from(got_a < expected_a);
                    let repeated = seen.len() - got_a.min(expected_a) - got_b.min(1);
                    if lost + repeated > 0 {
                        println!(
                            "transaction {m} ({len} bytes), byte {byte}: A {got_a} of \
                             {expected_a}, B {got_b} of 1, {} cycles",
                            seen.len()
                        );
                    }
                    findings.placements += 1;
                    findings.lost += lost;
                    findings.repeated += repeated;
                    if got_b == 1 {
                        assert_eq!(
                            master.read(s.inputs.start, usize::from(IMAGE)),
                            Some(b.clone()),
                            "B's inputs"
                        );
                    }
                }
            }
            assert!(probe.violations().is_empty(), "{:?}", probe.violations());
            out.set(findings);
        },
    );
    findings.get()
}

fn beckhoff(scenario: Scenario) -> Findings {
    place_everywhere(scenario, EscConfig::default(), |emu, probe| {
        BeckhoffSpi::new(
            FakeSpi::new(BeckhoffEsc::new(emu.clone()), probe),
            beckhoff::Config::default(),
        )
    })
}

fn lan9252(scenario: Scenario) -> Findings {
    // The LAN9252 as it is (4 SyncManagers, 3 FMMUs, 4 KiB), its EEPROM's area selecting its SPI.
    let esc = EscConfig::of(Chip::LAN9252);
    place_everywhere(scenario, esc, |emu, probe| {
        let chip = Lan9252Chip::new(emu.clone(), Lan9252Config::default());
        let spi = FakeSpi::new(chip, probe);
        embassy_futures::block_on(Lan9252::start(spi, lan9252::Config::default())).expect("start")
    })
}

fn mcu16(scenario: Scenario) -> Findings {
    place_everywhere(scenario, mcu::et1100(), |emu, probe| {
        Mcu16::new(FakeBus16::new(emu.clone(), probe, Cycles::default()))
    })
}

fn check(name: &str, findings: Findings) {
    println!("{name}: {findings:?}");
    assert!(findings.placements > 0);
    assert_eq!(
        (findings.lost, findings.repeated),
        (0, 0),
        "{name}: {findings:?}"
    );
}

#[test]
fn lan9252_under_an_sdo_exchange() {
    check("LAN9252, SDO", lan9252(Scenario::new(128, false)));
}

#[test]
fn lan9252_under_an_sdo_exchange_and_a_cycle() {
    check("LAN9252, SDO + cycle", lan9252(Scenario::new(128, true)));
}

#[test]
fn lan9252_under_an_sdo_exchange_with_1024_byte_mailboxes() {
    check(
        "LAN9252, 1024-byte mailboxes, SDO",
        lan9252(Scenario::new(1024, false)),
    );
}

#[test]
fn beckhoff_under_an_sdo_exchange() {
    check("Beckhoff, SDO", beckhoff(Scenario::new(128, false)));
}

#[test]
fn beckhoff_under_an_sdo_exchange_and_a_cycle() {
    check("Beckhoff, SDO + cycle", beckhoff(Scenario::new(128, true)));
}

#[test]
fn mcu16_under_an_sdo_exchange() {
    check("µC 16-bit, SDO", mcu16(Scenario::new(128, false)));
}

#[test]
fn mcu16_under_an_sdo_exchange_and_a_cycle() {
    check("µC 16-bit, SDO + cycle", mcu16(Scenario::new(128, true)));
}
