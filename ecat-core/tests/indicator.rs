//! ETG.1300 indicators: every pattern's exact timeline, the AL state and code mapping, restarts
//! on a change, the bicolour LED, the ESC override codes. Time is virtual: instants in ms.

use ecat_core::indicator::{
    Colour, Fault, Indicators, LED_OVERRIDE, LedCode, Levels, Pattern, err_pattern, run_pattern,
};
use ecat_core::{AlState, AlStatus, AlStatusCode, Duration, Instant};

fn ms(ms: u64) -> Instant {
    Instant::from_micros(ms * 1_000)
}

/// The edges of RUN and ERR in `[from, to)`, as (ms, level) pairs, found by following
/// `poll_at` only (as the LED task does), after the levels at `from`.
/// (ms, level) edges of one indicator.
type Timeline = Vec<(u64, bool)>;

fn edges(ind: &Indicators, from: u64, to: u64) -> (Timeline, Timeline) {
    let mut now = ms(from);
    let first = ind.levels(now);
    let (mut run, mut err) = (vec![(from, first.run)], vec![(from, first.err)]);
    let mut last = first;
    while let Some(next) = ind.poll_at(now) {
        assert!(next > now, "poll_at moves forward");
        if next >= ms(to) {
            break;
        }
        now = next;
        let levels = ind.levels(now);
        assert_ne!(levels, last, "poll_at({}) is an edge", now.as_micros());
        if levels.run != last.run {
            run.push((now.as_micros() / 1_000, levels.run));
        }
        if levels.err != last.err {
            err.push((now.as_micros() / 1_000, levels.err));
        }
        last = levels;
    }
    (run, err)
}

/// The timeline of a pattern started at 0, as (ms, level) edges in `[0, to)`.
fn pattern_edges(pattern: Pattern, to: u64) -> Vec<(u64, bool)> {
    code_edges(LedCode::from_register(pattern.led_code()), to)
}

/// The timeline of an LED code started at 0, as (ms, level) edges in `[0, to)`.
fn code_edges(code: LedCode, to: u64) -> Vec<(u64, bool)> {
    let mut out = Vec::new();
    let mut at = 0;
    let mut last = None;
    while at < to {
        let (level, left) = code.level_at(Duration::from_millis(at));
        if last != Some(level) {
            out.push((at, level));
            last = Some(level);
        }
        match left {
            Some(left) => at += left.as_micros() / 1_000,
            None => break,
        }
    }
    out
}

#[test]
fn flickering_is_50_on_50_off() {
    assert_eq!(
        pattern_edges(Pattern::Flickering, 300),
        [
            (0, true),
            (50, false),
            (100, true),
            (150, false),
            (200, true),
            (250, false)
        ]
    );
}

#[test]
fn blinking_is_200_on_200_off() {
    assert_eq!(
        pattern_edges(Pattern::Blinking, 1000),
        [
            (0, true),
            (200, false),
            (400, true),
            (600, false),
            (800, true)
        ]
    );
}

#[test]
fn single_flash_is_200_on_1000_off() {
    assert_eq!(
        pattern_edges(Pattern::SingleFlash, 2500),
        [
            (0, true),
            (200, false),
            (1200, true),
            (1400, false),
            (2400, true)
        ]
    );
}

#[test]
fn double_flash_is_200_on_200_off_200_on_1000_off() {
    assert_eq!(
        pattern_edges(Pattern::DoubleFlash, 3300),
        [
            (0, true),
            (200, false),
            (400, true),
            (600, false),
            (1600, true),
            (1800, false),
            (2000, true),
            (2200, false),
            (3200, true)
        ]
    );
}

#[test]
fn steady_patterns_have_no_edge() {
    assert_eq!(Pattern::On.level_at(Duration::from_millis(5)), (true, None));
    assert_eq!(
        Pattern::Off.level_at(Duration::from_millis(5)),
        (false, None)
    );
}

#[test]
fn a_level_changes_exactly_at_the_edge() {
    let p = Pattern::Blinking;
    assert_eq!(
        p.level_at(Duration::from_micros(199_999)),
        (true, Some(Duration::from_micros(1)))
    );
    assert_eq!(
        p.level_at(Duration::from_millis(200)),
        (false, Some(Duration::from_millis(200)))
    );
}

#[test]
fn run_follows_the_state() {
    assert_eq!(run_pattern(AlState::Init), Pattern::Off);
    assert_eq!(run_pattern(AlState::PreOp), Pattern::Blinking);
    assert_eq!(run_pattern(AlState::SafeOp), Pattern::SingleFlash);
    assert_eq!(run_pattern(AlState::Op), Pattern::On);
    assert_eq!(run_pattern(AlState::Boot), Pattern::Flickering);
}

#[test]
fn err_classes_of_every_code() {
    assert_eq!(err_pattern(None), Pattern::Off);
    for code in 0..=0xFFFFu16 {
        let expected = match code {
            0x001A | 0x002C | 0x002D | 0x0032 | 0x0033 | 0x0034 => Pattern::SingleFlash,
            0x001B => Pattern::DoubleFlash,
            _ => Pattern::Blinking,
        };
        assert_eq!(
            err_pattern(Some(AlStatusCode(code))),
            expected,
            "code {code:#06x}"
        );
    }
    // Named ones, to read the table: invalid configuration, local error, watchdog.
    for code in [
        AlStatusCode::INVALID_STATE_CHANGE,
        AlStatusCode::UNKNOWN_STATE,
        AlStatusCode::INVALID_MAILBOX_CONFIG,
        AlStatusCode::INVALID_OUTPUT_CONFIG,
        AlStatusCode::INVALID_WATCHDOG_CONFIG,
        AlStatusCode::SYNC_MODE_NOT_SUPPORTED,
        AlStatusCode::UNSPECIFIED_ERROR,
    ] {
        assert_eq!(err_pattern(Some(code)), Pattern::Blinking, "{code:?}");
    }
    for code in [
        AlStatusCode::SYNC_ERROR,
        AlStatusCode::FATAL_SYNC_ERROR,
        AlStatusCode::NO_SYNC_ERROR,
    ] {
        assert_eq!(err_pattern(Some(code)), Pattern::SingleFlash, "{code:?}");
    }
    assert_eq!(
        err_pattern(Some(AlStatusCode::SM_WATCHDOG)),
        Pattern::DoubleFlash
    );
}

#[test]
fn the_error_indication_decides_not_the_code() {
    let mut ind = Indicators::new();
    // Device ID 0x001B shown without error: ERR stays off.
    let status = AlStatus {
        state: AlState::PreOp,
        error: false,
        id_loaded: true,
    };
    ind.update_status(ms(0), status, AlStatusCode(0x001B));
    assert_eq!(ind.err(), Pattern::Off);
    let status = AlStatus::from_bits(0x14).unwrap();
    ind.update_status(ms(0), status, AlStatusCode::SM_WATCHDOG);
    assert_eq!(
        (ind.run(), ind.err()),
        (Pattern::SingleFlash, Pattern::DoubleFlash)
    );
}

#[test]
fn init_preop_safeop_op_timeline() {
    let mut ind = Indicators::new();
    ind.update(ms(0), AlState::Init, None);
    assert_eq!(
        ind.poll_at(ms(0)),
        None,
        "INIT without error: both steady off"
    );
    assert_eq!(edges(&ind, 0, 1000), (vec![(0, false)], vec![(0, false)]));

    ind.update(ms(1000), AlState::PreOp, None);
    assert_eq!(
        edges(&ind, 1000, 2100).0,
        [
            (1000, true),
            (1200, false),
            (1400, true),
            (1600, false),
            (1800, true),
            (2000, false)
        ],
        "PREOP blinks from the instant it is entered"
    );

    // SAFEOP entered in the middle of a blink's on phase: the single flash starts anew.
    ind.update(ms(2100), AlState::SafeOp, None);
    assert_eq!(
        edges(&ind, 2100, 4600).0,
        [
            (2100, true),
            (2300, false),
            (3300, true),
            (3500, false),
            (4500, true)
        ]
    );

    ind.update(ms(4600), AlState::Op, None);
    assert_eq!(ind.poll_at(ms(4600)), None, "OP: on, steady");
    assert_eq!(
        edges(&ind, 4600, 9000),
        (vec![(4600, true)], vec![(4600, false)])
    );
}

#[test]
fn boot_flickers() {
    let mut ind = Indicators::new();
    ind.update(ms(10), AlState::Boot, None);
    assert_eq!(
        edges(&ind, 10, 210).0,
        [(10, true), (60, false), (110, true), (160, false)]
    );
}

#[test]
fn watchdog_in_op_gives_single_flash_and_double_flash() {
    let mut ind = Indicators::new();
    ind.update(ms(0), AlState::Op, None);
    ind.update(ms(500), AlState::SafeOp, Some(AlStatusCode::SM_WATCHDOG));
    let (run, err) = edges(&ind, 500, 3000);
    assert_eq!(
        run,
        [
            (500, true),
            (700, false),
            (1700, true),
            (1900, false),
            (2900, true)
        ]
    );
    assert_eq!(
        err,
        [
            (500, true),
            (700, false),
            (900, true),
            (1100, false),
            (2100, true),
            (2300, false),
            (2500, true),
            (2700, false)
        ]
    );
}

#[test]
fn every_err_pattern_from_its_cause() {
    let cases = [
        (
            Some(AlStatusCode::INVALID_STATE_CHANGE),
            None,
            vec![(0, true), (200, false), (400, true), (600, false)],
        ),
        (
            Some(AlStatusCode::SYNC_ERROR),
            None,
            vec![(0, true), (200, false)],
        ),
        (
            Some(AlStatusCode::SM_WATCHDOG),
            None,
            vec![(0, true), (200, false), (400, true), (600, false)],
        ),
        (
            None,
            Some(Fault::Booting),
            vec![
                (0, true),
                (50, false),
                (100, true),
                (150, false),
                (200, true),
                (250, false),
                (300, true),
                (350, false),
                (400, true),
                (450, false),
                (500, true),
                (550, false),
                (600, true),
                (650, false),
            ],
        ),
        (None, Some(Fault::ApplicationController), vec![(0, true)]),
        (None, None, vec![(0, false)]),
    ];
    for (error, fault, expected) in cases {
        let mut ind = Indicators::new();
        ind.update(ms(0), AlState::PreOp, error);
        ind.set_fault(ms(0), fault);
        assert_eq!(edges(&ind, 0, 700).1, expected, "{error:?} {fault:?}");
    }
    // The double flash's long pause: next flash pair at 1600.
    let mut ind = Indicators::new();
    ind.update(ms(0), AlState::SafeOp, Some(AlStatusCode::SM_WATCHDOG));
    assert_eq!(
        ind.poll_at(ms(600)),
        Some(ms(1200)),
        "RUN's flash comes first"
    );
    ind.update(ms(0), AlState::Op, Some(AlStatusCode::SM_WATCHDOG));
    assert_eq!(ind.poll_at(ms(600)), Some(ms(1600)));
}

#[test]
fn a_fault_outranks_the_code_and_its_end_restores_it() {
    let mut ind = Indicators::new();
    ind.update(ms(0), AlState::SafeOp, Some(AlStatusCode::SYNC_ERROR));
    ind.set_fault(ms(100), Some(Fault::ApplicationController));
    assert_eq!(ind.err(), Pattern::On);
    ind.set_fault(ms(300), None);
    assert_eq!(ind.err(), Pattern::SingleFlash);
    assert_eq!(
        edges(&ind, 300, 1600).1,
        [(300, true), (500, false), (1500, true)]
    );
}

#[test]
fn an_unchanged_pattern_keeps_its_phase_a_changed_one_restarts() {
    let mut ind = Indicators::new();
    ind.update(ms(0), AlState::PreOp, None);
    // A new error while RUN keeps blinking: RUN's phase is untouched, ERR starts at 300.
    ind.update(
        ms(300),
        AlState::PreOp,
        Some(AlStatusCode::INVALID_MAILBOX_CONFIG),
    );
    let (run, err) = edges(&ind, 300, 1000);
    assert_eq!(run, [(300, false), (400, true), (600, false), (800, true)]);
    assert_eq!(err, [(300, true), (500, false), (700, true), (900, false)]);
    // Acknowledged at 950 and refused again with another code of the same class at 950: ERR
    // keeps blinking in phase (same pattern), it is not restarted.
    ind.update(
        ms(950),
        AlState::PreOp,
        Some(AlStatusCode::INVALID_STATE_CHANGE),
    );
    assert_eq!(edges(&ind, 950, 1200).1, [(950, false), (1100, true)]);
    // Cleared, then raised again: a restart.
    ind.update(ms(1000), AlState::PreOp, None);
    ind.update(
        ms(1050),
        AlState::PreOp,
        Some(AlStatusCode::INVALID_STATE_CHANGE),
    );
    assert_eq!(edges(&ind, 1050, 1300).1, [(1050, true), (1250, false)]);
}

#[test]
fn poll_at_from_before_the_start_is_the_start() {
    let mut ind = Indicators::new();
    ind.update(ms(100), AlState::PreOp, None);
    assert_eq!(ind.poll_at(ms(50)), Some(ms(100)));
}

#[test]
fn bicolour_red_wins() {
    let l = |run, err| Levels { run, err }.bicolour();
    assert_eq!(l(false, false), Colour::Off);
    assert_eq!(l(true, false), Colour::Green);
    assert_eq!(l(false, true), Colour::Red);
    assert_eq!(l(true, true), Colour::Red);
    // PREOP with a refused transition: green and red blinks started 100 ms apart share the LED.
    let mut ind = Indicators::new();
    ind.update(ms(0), AlState::PreOp, None);
    ind.update(
        ms(100),
        AlState::PreOp,
        Some(AlStatusCode::INVALID_STATE_CHANGE),
    );
    let colours: Vec<_> = [100, 199, 200, 299, 300, 399, 400, 499, 500]
        .iter()
        .map(|&t| ind.levels(ms(t)).bicolour())
        .collect();
    assert_eq!(
        colours,
        [
            Colour::Red,
            Colour::Red,
            Colour::Red,
            Colour::Red,
            Colour::Off,
            Colour::Off,
            Colour::Green,
            Colour::Green,
            Colour::Red
        ]
    );
}

#[test]
fn esc_override_codes() {
    let codes: Vec<u8> = [
        Pattern::Off,
        Pattern::SingleFlash,
        Pattern::DoubleFlash,
        Pattern::Blinking,
        Pattern::Flickering,
        Pattern::On,
    ]
    .iter()
    .map(|p| p.override_register())
    .collect();
    assert_eq!(codes, [0x10, 0x11, 0x12, 0x1D, 0x1E, 0x1F]);
    assert_eq!(LED_OVERRIDE, 0x10);
}

/// The ESC's codes 0x3..=0xC: that many 200 ms flashes 200 ms apart, then 1000 ms dark (the
/// patterns' timelines above are their codes' 0x1, 0x2, 0xD and 0xE).
#[test]
fn led_codes_count_flashes() {
    assert_eq!(
        code_edges(LedCode::from_register(0x13), 3000),
        [
            (0, true),
            (200, false),
            (400, true),
            (600, false),
            (800, true),
            (1000, false),
            (2000, true),
            (2200, false),
            (2400, true),
            (2600, false),
            (2800, true),
        ],
        "0x3, the enable bit ignored: a triple flash in 2000 ms"
    );
    let twelve = code_edges(LedCode::from_register(0x0C), 5700);
    assert_eq!(twelve.len(), 12 * 2 + 1);
    assert_eq!(twelve[22..], [(4400, true), (4600, false), (5600, true)]);
    assert_eq!(code_edges(LedCode::OFF, 1000), [(0, false)]);
    assert_eq!(code_edges(LedCode::ON, 1000), [(0, true)]);
    // 12 × 400 − 200 + 1000: the longest period, 5.6 s, repeats.
    assert_eq!(
        LedCode::from_register(0xC).level_at(Duration::from_millis(5600 + 4400)),
        (true, Some(Duration::from_millis(200)))
    );
}
