//! The indicator task (`ecat_embassy::run_indicators`) beside the real runners, in virtual time:
//! the exact (ms, level) writes to the RUN and ERR pins as a MainDevice walks the SubDevice
//! INIT → PREOP → SAFEOP → OP and then stops sending outputs (SM watchdog, 0x001B), and the same
//! on one bicolour LED. Then the ESC's own RUN output (`ecat_esc`'s LED outputs: the AL status
//! the stack writes, the override register 0x0138) in the same walk, in BOOT and with an
//! override. Patterns and code classes: ETG.1300 (`ecat_core::indicator`).

mod common;

use std::cell::{Cell, RefCell};
use std::convert::Infallible;
use std::future::Future;
use std::pin::Pin;
use std::rc::Rc;
use std::task::{Context, Poll};

use common::{configure, send_outputs};
use ecat_core::{DeviceConfig, register};
use ecat_embassy::indicator::{Bicolour, ErrOnly, Lamps, RunErr, run_indicators};
use ecat_emu::emulator::Led;
use ecat_emu::harness::{self, AcceptAll, BoxedTask, Device, Loopback};
use ecat_emu::master::TestMaster;
use embassy_time::{Duration, Instant};
use embedded_hal::digital::{ErrorType, OutputPin};

/// Every write to a pin: (virtual ms, pin name, level).
type Log = Rc<RefCell<Vec<(u64, &'static str, bool)>>>;

/// A pin that records each write with the virtual time.
struct FakePin {
    name: &'static str,
    log: Log,
}

impl ErrorType for FakePin {
    type Error = Infallible;
}

impl OutputPin for FakePin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.log
            .borrow_mut()
            .push((Instant::now().as_millis(), self.name, false));
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Infallible> {
        self.log
            .borrow_mut()
            .push((Instant::now().as_millis(), self.name, true));
        Ok(())
    }
}

fn pin(name: &'static str, log: &Log) -> FakePin {
    FakePin {
        name,
        log: log.clone(),
    }
}

/// The writes to `name`, as (ms, level).
fn writes(log: &Log, name: &str) -> Vec<(u64, bool)> {
    log.borrow()
        .iter()
        .filter(|(_, n, _)| *n == name)
        .map(|&(t, _, level)| (t, level))
        .collect()
}

/// The scenario: INIT until 1000 ms, PREOP at 1000, SAFEOP at 2100, OP at 4050 with outputs
/// every 10 ms until 4490, then silence: the SM watchdog (100 ms) expires at 4590 → SAFEOP with
/// 0x001B. Ends at 7500 ms.
async fn scenario(master: TestMaster) {
    let ms = Duration::from_millis;
    master.reset().await;
    assert_eq!(master.request(0x0001).await, (0x0001, 0));
    configure(&master);
    master.settle().await;
    master.advance(ms(1000)).await;
    assert_eq!(master.request(0x02).await, (0x02, 0), "PREOP at 1000 ms");
    master.advance(ms(1100)).await;
    assert_eq!(master.request(0x04).await, (0x04, 0), "SAFEOP at 2100 ms");
    master.advance(ms(1950)).await;
    send_outputs(&master).await;
    assert_eq!(master.request(0x08).await, (0x08, 0), "OP at 4050 ms");
    for _ in 0..45 {
        send_outputs(&master).await;
        master.advance(ms(10)).await;
    }
    assert_eq!(Instant::now().as_millis(), 4500);
    assert_eq!(master.al_status(), 0x08);
    master.advance(ms(89)).await;
    assert_eq!(master.al_status(), 0x08, "4589 ms: still OP");
    master.advance(ms(1)).await;
    assert_eq!(
        (master.al_status(), master.al_status_code()),
        (0x14, 0x001B),
        "4590 ms: SM watchdog"
    );
    master.advance(ms(2910)).await;
}

/// A future that counts how often it is polled.
struct Counted<F> {
    inner: Pin<Box<F>>,
    polls: Rc<Cell<u32>>,
}

impl<F: Future> Future for Counted<F> {
    type Output = F::Output;

    fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<F::Output> {
        self.polls.set(self.polls.get() + 1);
        self.inner.as_mut().poll(cx)
    }
}

/// The indicator task on `lamps`, as the harness runs it beside the runners; `polls` counts
/// its wake-ups.
fn indicator_task<L: Lamps + 'static>(
    lamps: L,
    polls: Rc<Cell<u32>>,
) -> impl FnOnce(ecat_embassy::Status<'static, ecat_emu::emulator::EmulatedPdi>) -> Vec<BoxedTask> {
    move |status| {
        let inner = Box::pin(run_indicators(status, lamps));
        vec![Box::pin(Counted { inner, polls })]
    }
}

/// RUN: off in INIT; PREOP blinks from 1000 (200/200); SAFEOP's single flash starts at 2100
/// (200/1000); OP on from 4050; the watchdog's SAFEOP at 4590 starts a single flash, whose
/// first flash continues OP's light.
const RUN: &[(u64, bool)] = &[
    (0, false),
    (1000, true),
    (1200, false),
    (1400, true),
    (1600, false),
    (1800, true),
    (2000, false),
    (2100, true),
    (2300, false),
    (3300, true),
    (3500, false),
    (4050, true),
    (4790, false),
    (5790, true),
    (5990, false),
    (6990, true),
    (7190, false),
];

/// ERR: off until the watchdog at 4590, then a double flash (200 on, 200 off, 200 on, 1000 off).
const ERR: &[(u64, bool)] = &[
    (0, false),
    (4590, true),
    (4790, false),
    (4990, true),
    (5190, false),
    (6190, true),
    (6390, false),
    (6590, true),
    (6790, false),
];

#[test]
fn run_and_err_pins_follow_the_state_and_the_watchdog() {
    let log = Log::default();
    let lamps = RunErr {
        run: pin("run", &log),
        err: pin("err", &log),
    };
    let polls = Rc::new(Cell::new(0));
    harness::run_with_tasks(
        Device::new(common::drive(), AcceptAll, Loopback),
        indicator_task(lamps, polls.clone()),
        scenario,
    );
    assert_eq!(writes(&log, "run"), RUN, "RUN pin");
    // No polling loop: the task runs once at the start, once when the runner first publishes
    // INIT, at each of the 19 instants with an edge after 0 ms, at the 4 state changes after
    // INIT (1000, 2100, 4050, 4590), at 2 deadlines armed before a state change that replaced
    // them (2200 and 4500: embassy-time still wakes a dropped timer's task) and at the end.
    assert_eq!(
        polls.get(),
        1 + 1 + 19 + 4 + 2 + 1,
        "wake-ups of the indicator task"
    );
    assert_eq!(writes(&log, "err"), ERR, "ERR pin");
}

/// Green where RUN is on and ERR off, red where ERR is on, from the two timelines above.
fn expected_colours() -> Vec<(u64, &'static str)> {
    let level = |timeline: &[(u64, bool)], t: u64| {
        timeline
            .iter()
            .take_while(|(at, _)| *at <= t)
            .last()
            .is_some_and(|&(_, l)| l)
    };
    let mut instants: Vec<u64> = RUN.iter().chain(ERR).map(|&(t, _)| t).collect();
    instants.sort_unstable();
    instants.dedup();
    let mut out: Vec<(u64, &str)> = Vec::new();
    for t in instants {
        let colour = match (level(RUN, t), level(ERR, t)) {
            (_, true) => "red",
            (true, false) => "green",
            (false, false) => "off",
        };
        if out.last().map(|&(_, c)| c) != Some(colour) {
            out.push((t, colour));
        }
    }
    out
}

#[test]
fn one_bicolour_led_shows_err_over_run() {
    let log = Log::default();
    let lamps = Bicolour {
        green: pin("green", &log),
        red: pin("red", &log),
    };
    harness::run_with_tasks(
        Device::new(common::drive(), AcceptAll, Loopback),
        indicator_task(lamps, Rc::default()),
        scenario,
    );
    // Replay the writes: never both lit, and the colour after each instant's writes.
    let (mut green, mut red) = (false, false);
    let mut colours: Vec<(u64, &str)> = Vec::new();
    let log = log.borrow();
    for (i, &(t, name, level)) in log.iter().enumerate() {
        match name {
            "green" => green = level,
            _ => red = level,
        }
        assert!(!(green && red), "both elements lit at {t} ms");
        if log.get(i + 1).is_some_and(|&(next, _, _)| next == t) {
            continue;
        }
        let colour = match (green, red) {
            (_, true) => "red",
            (true, false) => "green",
            (false, false) => "off",
        };
        if colours.last().map(|&(_, c)| c) != Some(colour) {
            colours.push((t, colour));
        }
    }
    assert_eq!(colours, expected_colours());
    // Spot checks of the rule: red during ERR's flashes even where RUN is lit.
    assert!(colours.contains(&(4590, "red")));
    assert!(colours.contains(&(4790, "off")));
}

/// The ESC's `led` output over `script` (until its end) for a device `config`, with `lamps` on
/// the indicator task.
fn esc_led<L, F>(
    config: DeviceConfig,
    lamps: L,
    led: Led,
    script: impl FnOnce(TestMaster) -> F + 'static,
) -> Vec<(u64, bool)>
where
    L: Lamps + 'static,
    F: Future<Output = ()> + 'static,
{
    let timeline = Rc::new(RefCell::new(Vec::new()));
    let out = timeline.clone();
    harness::run_with_tasks(
        Device::new(config, AcceptAll, Loopback),
        indicator_task(lamps, Rc::default()),
        move |master| async move {
            let emu = master.emulator().clone();
            script(master).await;
            *out.borrow_mut() = emu.led_timeline(led, Instant::now());
        },
    );
    timeline.take()
}

/// A device whose ESC drives RUN: no RUN pin (`ErrOnly`: ERR on its pin, as before), nothing
/// written for RUN. The ESC's RUN output, from the AL status the stack writes, shows exactly
/// the timeline the RUN pin showed above.
#[test]
fn the_escs_run_output_follows_the_state_as_the_pin_did() {
    let log = Log::default();
    let run = esc_led(
        common::drive(),
        ErrOnly(pin("err", &log)),
        Led::Run,
        scenario,
    );
    assert_eq!(run, RUN, "the ESC's RUN output");
    assert_eq!(writes(&log, "err"), ERR, "the ERR pin");
    assert!(writes(&log, "run").is_empty());
}

/// The ESC's own ERR output in the same walk: the watchdog expiry's double flash lasts only
/// until the stack enters SAFEOP with the error indication, which the ESC shows as a single
/// flash (ESC datasheet section I, "ERR LED"): why ERR stays on a pin, or takes the override
/// 0x0139 (next test), for ETG.1300's double flash.
#[test]
fn the_escs_own_err_output_shows_a_single_flash_for_the_watchdog() {
    let err = esc_led(
        common::drive(),
        ErrOnly(pin("err", &Log::default())),
        Led::Err,
        scenario,
    );
    assert_eq!(
        err,
        [
            (0, false),
            (4590, true),
            (4790, false),
            (5790, true),
            (5990, false),
            (6990, true),
            (7190, false),
        ]
    );
}

/// Both LEDs on the ESC (`DeviceConfig::esc_err_led`, no pin at all): the stack writes the ERR
/// override after each AL status, and the ESC's ERR output shows exactly the ERR pin's
/// timeline, the double flash included; RUN as before.
#[test]
fn with_the_err_override_the_escs_err_output_is_the_pins() {
    let mut config = common::drive();
    config.esc_err_led = true;
    let err = esc_led(
        config,
        ErrOnly(pin("err", &Log::default())),
        Led::Err,
        scenario,
    );
    assert_eq!(err, ERR, "the ESC's ERR output");
    let run = esc_led(
        config,
        ErrOnly(pin("err", &Log::default())),
        Led::Run,
        scenario,
    );
    assert_eq!(run, RUN, "the ESC's RUN output");
}

/// BOOT flickers (50/50 ms); a MainDevice's override (0x0138 = 0x13: three flashes, "device
/// identification") shows until the next state change, which also clears its enable bit.
#[test]
fn the_escs_run_output_in_boot_and_under_an_override() {
    let lamps = ErrOnly(pin("err", &Log::default()));
    let run = esc_led(common::drive(), lamps, Led::Run, |master| async move {
        let ms = Duration::from_millis;
        master.reset().await;
        assert_eq!(master.request(0x0001).await, (0x0001, 0));
        configure(&master);
        master.settle().await;
        master.advance(ms(500)).await;
        assert!(master.write(register::RUN_LED_OVERRIDE, &[0x13]));
        master.advance(ms(1500)).await;
        assert_eq!(
            master.request(0x0001).await,
            (0x0001, 0),
            "INIT again: no change"
        );
        master.advance(ms(1000)).await;
        assert_eq!(master.request(0x03).await, (0x03, 0), "BOOT at 3000 ms");
        assert_eq!(
            master.read(register::RUN_LED_OVERRIDE, 1),
            Some(vec![0x03]),
            "the state change cleared the enable bit"
        );
        master.advance(ms(300)).await;
        assert_eq!(master.request(0x01).await, (0x01, 0), "INIT at 3300 ms");
        master.advance(ms(200)).await;
    });
    assert_eq!(
        run,
        [
            (0, false),
            // Three flashes from 500 ms, 2000 ms apart.
            (500, true),
            (700, false),
            (900, true),
            (1100, false),
            (1300, true),
            (1500, false),
            (2500, true),
            (2700, false),
            (2900, true),
            // BOOT at 3000: flickering starts lit, so the flash's light goes on.
            (3050, false),
            (3100, true),
            (3150, false),
            (3200, true),
            (3250, false),
            // INIT at 3300: dark, as the flicker was.
        ]
    );
}
