//! Arbitrary AL control values, SyncManager register bytes, application answers and time steps,
//! in any order: the SubDevice never panics, does bounded work per call, and keeps its invariants.

mod common;

use common::{DEVICE, Regs, configure_all};
use ecat_core::sync_manager::check::{self, Channels};
use ecat_core::{
    AlEvent, AlState, AlStatus, AlStatusCode, Event, Instant, SubDevice, Transition, register,
};
use proptest::prelude::*;

#[derive(Debug, Clone)]
enum Step {
    Control(u16),
    SyncManager(u8, [u8; 8]),
    ConfigureAll,
    Answer(Option<u16>),
    Advance(u64),
}

fn step() -> impl Strategy<Value = Step> {
    prop_oneof![
        4 => prop_oneof![any::<u16>(), (0u16..0x40)].prop_map(Step::Control),
        2 => (0u8..4, any::<[u8; 8]>()).prop_map(|(n, b)| Step::SyncManager(n, b)),
        2 => Just(Step::ConfigureAll),
        3 => proptest::option::of(any::<u16>()).prop_map(Step::Answer),
        1 => (0u64..2_000_000).prop_map(Step::Advance),
    ]
}

fn is_single_step_up(t: Transition) -> bool {
    use AlState::*;
    matches!(
        (t.from, t.to),
        (Init, PreOp) | (PreOp, SafeOp) | (SafeOp, Op) | (Init, Boot)
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2_000, ..ProptestConfig::default() })]

    #[test]
    fn invariants_hold_for_any_input(steps in proptest::collection::vec(step(), 1..60), id in any::<u16>()) {
        let mut regs = Regs::new();
        let mut sub = SubDevice::new::<()>(&DEVICE);
        sub.set_device_id(id);
        let mut now = Instant::from_micros(0);
        let mut requested: Option<Transition> = None;
        let mut accepted: Option<Transition> = None;
        for step in steps {
            match step {
                Step::Control(v) => regs.al_control(v),
                Step::SyncManager(n, bytes) => {
                    regs.put(register::sync_manager(n), &bytes);
                    regs.event |= AlEvent::SM_CHANGE.bits();
                }
                Step::ConfigureAll => configure_all(&mut regs),
                Step::Answer(answer) => {
                    if let Some(t) = requested.take() {
                        let result = answer.map_or(Ok(()), |c| Err(AlStatusCode(c.max(1))));
                        if result.is_ok() { accepted = Some(t); }
                        sub.complete_transition(t, result);
                    }
                }
                Step::Advance(us) => {
                    now = Instant::from_micros(now.as_micros() + us);
                    sub.handle_timeout(now);
                }
            }
            sub.handle_al_event(AlEvent(regs.event));
            regs.drive(&mut sub, now);
            while let Some(event) = sub.poll_event() {
                match event {
                    Event::TransitionRequested(t) => {
                        prop_assert!(is_single_step_up(t), "requested {t:?}");
                        requested = Some(t);
                    }
                    Event::TransitionAborted(t) => {
                        if requested == Some(t) { requested = None; }
                    }
                    Event::StateChanged(t) => {
                        if t.is_upward() {
                            prop_assert!(is_single_step_up(t), "jumped {t:?}");
                            prop_assert_eq!(accepted.take(), Some(t), "upward without the application's consent");
                        }
                    }
                }
            }

            let status = AlStatus::from_bits(regs.u16_at(register::AL_STATUS));
            prop_assert!(status.is_some(), "AL status {:#06x} names no state", regs.u16_at(register::AL_STATUS));
            let status = status.unwrap();
            let code = regs.u16_at(register::AL_STATUS_CODE);
            prop_assert_eq!(status, sub.al_status(), "presented status is the core's");
            prop_assert_eq!(code, sub.al_status_code().0);
            if status.error {
                prop_assert!(code != 0, "error indication without a code");
                prop_assert!(!status.id_loaded);
            } else if status.id_loaded {
                prop_assert_eq!(code, id);
            } else {
                prop_assert_eq!(code, 0, "a code without the error indication");
            }

            let a = usize::from(register::SM_BASE);
            let channels = Channels::from_bytes(regs.mem[a..a + Channels::SIZE].try_into().unwrap());
            if status.state == AlState::PreOp || status.state.has_process_data() {
                prop_assert!(check::mailbox(&channels, &DEVICE.mailbox, AlStatusCode::INVALID_MAILBOX_CONFIG).is_ok(),
                    "{:?} with invalid mailbox SyncManagers", status.state);
            }
            if status.state.has_process_data() {
                prop_assert!(check::process_data(&channels, DEVICE.process_data, &DEVICE).is_ok(), "{:?} with invalid process-data SyncManagers", status.state);
            }
        }
    }
}
