//! The sans-IO SubDevice, access by access: which registers it reads and writes, in which order,
//! with which bytes.

mod common;

use common::{DEVICE, Op, Regs, configure_all};
use ecat_core::coe::Emergency;
use ecat_core::device::MailboxConfig;
use ecat_core::{
    AlEvent, AlState, AlStatusCode, DeviceConfig, Duration, Event, Instant, RegisterAccess,
    SubDevice, Transition, register,
};

const T0: Instant = Instant::from_micros(0);

fn up(from: AlState, to: AlState) -> Transition {
    Transition { from, to }
}

/// The MainDevice writes AL control and the SubDevice does what it needs to; returns its accesses.
fn request(regs: &mut Regs, sub: &mut SubDevice<'_>, control: u16) -> Vec<Op> {
    regs.al_control(control);
    sub.handle_al_event(ecat_core::AlEvent(regs.event));
    regs.drive(sub, T0)
}

/// The MainDevice requests `to`, the application accepts; returns the accesses after the answer.
fn step_up(
    regs: &mut Regs,
    sub: &mut SubDevice<'_>,
    control: u16,
    from: AlState,
    to: AlState,
) -> Vec<Op> {
    request(regs, sub, control);
    sub.complete_transition(up(from, to), Ok(()));
    regs.drive(sub, T0)
}

/// A SubDevice after its start-up accesses.
fn started(regs: &mut Regs) -> SubDevice<'static> {
    let mut sub = SubDevice::new::<()>(&DEVICE);
    regs.drive(&mut sub, T0);
    sub
}

#[test]
fn start_up_writes_mask_deactivates_sync_managers_and_presents_init() {
    let mut regs = Regs::new();
    let mut sub = SubDevice::new::<()>(&DEVICE);
    let log = regs.drive(&mut sub, T0);
    assert_eq!(
        log,
        [
            Op::Write(0x0204, vec![0x11, 0, 0, 0]),
            // Deactivations in the order of a downward transition: outputs, inputs, mailbox.
            Op::Write(0x0817, vec![1]),
            Op::Write(0x081F, vec![1]),
            Op::Write(0x080F, vec![1]),
            Op::Write(0x0807, vec![1]),
            Op::Write(0x0134, vec![0, 0]),
            Op::Write(0x0130, vec![1, 0]),
        ]
    );
    assert_eq!(sub.poll_event(), None);
    assert!(
        regs.drive(&mut sub, T0).is_empty(),
        "idle SubDevice accessed the ESC"
    );
}

#[test]
fn a_device_id_asked_for_before_the_first_status_write_is_written_whatever_its_value() {
    // 0xFFFF: a code no older bookkeeping could tell from "not written yet".
    let mut regs = Regs::new();
    let mut sub = SubDevice::new::<()>(&DEVICE);
    sub.set_device_id(0xFFFF);
    regs.al_control(0x0021);
    sub.handle_al_event(AlEvent(regs.event));
    let log = regs.drive(&mut sub, T0);
    let status: Vec<_> = log
        .iter()
        .filter(|op| matches!(op, Op::Write(0x0130 | 0x0134, _)))
        .collect();
    assert_eq!(
        status,
        [
            &Op::Write(0x0134, vec![0xFF, 0xFF]),
            &Op::Write(0x0130, vec![0x21, 0]),
        ]
    );
    assert_eq!((regs.u16_at(0x0130), regs.u16_at(0x0134)), (0x0021, 0xFFFF));
}

#[test]
fn al_control_event_reads_sync_managers_then_al_control_and_asks_the_application() {
    let mut regs = Regs::new();
    let mut sub = started(&mut regs);
    configure_all(&mut regs);
    let log = request(&mut regs, &mut sub, 0x0002);
    assert_eq!(
        log,
        [
            Op::Read(0x0820, 32),
            Op::Read(0x0800, 32),
            Op::Read(0x0420, 2),
            Op::Read(0x0981, 1),
            Op::Read(0x0120, 2)
        ]
    );
    assert_eq!(regs.event, 0, "both events cleared by the reads");
    assert_eq!(
        sub.poll_event(),
        Some(Event::TransitionRequested(up(
            AlState::Init,
            AlState::PreOp
        )))
    );
    assert_eq!(regs.u16_at(0x0130), 0x0001, "pending: still INIT");

    sub.complete_transition(up(AlState::Init, AlState::PreOp), Ok(()));
    let log = regs.drive(&mut sub, T0);
    assert_eq!(
        log,
        [
            // The mailbox receive event (SM0, bit 8) joins the mask in PREOP.
            Op::Write(0x0204, vec![0x11, 0x01, 0, 0]),
            Op::Write(0x0807, vec![0]),
            Op::Write(0x080F, vec![0]),
            Op::Write(0x0130, vec![2, 0])
        ]
    );
    assert_eq!(
        sub.poll_event(),
        Some(Event::StateChanged(up(AlState::Init, AlState::PreOp)))
    );
}

/// An SM-change event handled while a chunk of SyncManager registers is being read (between the
/// poll and its completion) starts the reads over: the chunk in flight is read again, then
/// SM0..SM3; the same access is returned until it completes.
#[test]
fn an_sm_change_during_a_chunk_read_starts_the_reads_over() {
    let mut regs = Regs::new();
    let mut sub = SubDevice::new::<()>(&DEVICE);
    regs.drive(&mut sub, T0);
    sub.handle_al_event(AlEvent::SM_CHANGE);
    let high = |sub: &mut SubDevice<'_>| {
        matches!(
            sub.poll_access(),
            Some(RegisterAccess::Read { address: 0x0820, buf, .. }) if buf.len() == 32
        )
    };
    assert!(high(&mut sub), "SM4..SM7 first");
    sub.handle_al_event(AlEvent::SM_CHANGE);
    assert!(high(&mut sub), "the same access until it completes");
    sub.access_done(T0, AlEvent::NONE);
    assert_eq!(
        regs.drive(&mut sub, T0),
        [Op::Read(0x0820, 32), Op::Read(0x0800, 32)],
        "read again from the top"
    );
}

#[test]
fn sync_manager_reads_cover_every_channel_of_the_esc_four_at_a_time() {
    // Reading a channel's activation register is what clears its share of the SM-change event,
    // so every channel the ESC has is read: beyond SM3 in chunks of four channels, the last
    // chunk shorter when the count is not a multiple of four, SM0..SM3 last.
    let cases: [(u8, &[Op]); 6] = [
        (4, &[Op::Read(0x0800, 32)]),
        (6, &[Op::Read(0x0820, 16), Op::Read(0x0800, 32)]),
        (8, &[Op::Read(0x0820, 32), Op::Read(0x0800, 32)]),
        (
            16,
            &[
                Op::Read(0x0860, 32),
                Op::Read(0x0840, 32),
                Op::Read(0x0820, 32),
                Op::Read(0x0800, 32),
            ],
        ),
        (2, &[Op::Read(0x0800, 32)]),
        (
            200,
            &[
                Op::Read(0x0860, 32),
                Op::Read(0x0840, 32),
                Op::Read(0x0820, 32),
                Op::Read(0x0800, 32),
            ],
        ),
    ];
    for (count, reads) in cases {
        let config = DeviceConfig {
            sync_manager_count: count,
            ..DEVICE
        };
        let mut regs = Regs::new();
        let mut sub = SubDevice::new::<()>(&config);
        regs.drive(&mut sub, T0);
        regs.event |= AlEvent::SM_CHANGE.bits();
        sub.handle_al_event(AlEvent::SM_CHANGE);
        assert_eq!(regs.drive(&mut sub, T0), reads, "{count} SyncManagers");
        assert_eq!(regs.event, 0, "{count} SyncManagers: SM change cleared");
    }
}

#[test]
fn mailbox_start_copies_the_repeat_request_into_the_repeat_ack() {
    // SM1's repeat request (0x080E bit 1) is set before INIT→PREOP: at mailbox start the
    // acknowledge (0x080F bit 1) takes its value (conformance.md "Mailbox"), and nothing is
    // repeated.
    let mut regs = Regs::new();
    let mut sub = started(&mut regs);
    configure_all(&mut regs);
    regs.put(0x080E, &[0x03]);
    let log = step_up(&mut regs, &mut sub, 2, AlState::Init, AlState::PreOp);
    assert_eq!(
        log,
        [
            Op::Write(0x0204, vec![0x11, 0x01, 0, 0]),
            Op::Write(0x0807, vec![0]),
            Op::Write(0x080F, vec![0x02]),
            Op::Write(0x0130, vec![2, 0])
        ]
    );
}

#[test]
fn refusal_writes_the_code_before_the_error_indication() {
    let mut regs = Regs::new();
    let mut sub = started(&mut regs);
    regs.al_control(0x0002); // SyncManagers not configured
    sub.handle_al_event(ecat_core::AlEvent(regs.event));
    let log = regs.drive(&mut sub, T0);
    assert_eq!(
        log,
        [
            Op::Read(0x0820, 32),
            Op::Read(0x0800, 32),
            Op::Read(0x0420, 2),
            Op::Read(0x0981, 1),
            Op::Read(0x0120, 2),
            Op::Write(0x0134, vec![0x16, 0]),
            Op::Write(0x0130, vec![0x11, 0]),
        ]
    );
    assert_eq!(
        sub.poll_event(),
        None,
        "the application is not asked about a refused transition"
    );
}

/// With the ERR LED on the ESC (`esc_err_led`) every AL status write is followed by the ERR
/// override: off (with the enable bit) at start-up, blinking for an invalid configuration
/// (0x0016), which the ESC would show as a single flash; without the option, never.
#[test]
fn an_esc_driven_err_led_gets_its_override_after_each_status() {
    static ESC_LEDS: DeviceConfig = DeviceConfig {
        esc_err_led: true,
        ..DEVICE
    };
    let mut regs = Regs::new();
    let mut sub = SubDevice::new::<()>(&ESC_LEDS);
    let log = regs.drive(&mut sub, T0);
    assert_eq!(
        log[log.len() - 3..],
        [
            Op::Write(0x0134, vec![0, 0]),
            Op::Write(0x0130, vec![1, 0]),
            Op::Write(0x0139, vec![0x10]),
        ]
    );
    regs.al_control(0x0002); // SyncManagers not configured
    sub.handle_al_event(ecat_core::AlEvent(regs.event));
    let log = regs.drive(&mut sub, T0);
    assert_eq!(
        log[log.len() - 3..],
        [
            Op::Write(0x0134, vec![0x16, 0]),
            Op::Write(0x0130, vec![0x11, 0]),
            Op::Write(0x0139, vec![0x1D]),
        ]
    );
    // Acknowledged back to INIT: off again, after the status.
    let log = request(&mut regs, &mut sub, 0x0011);
    assert_eq!(
        log[log.len() - 2..],
        [Op::Write(0x0130, vec![1, 0]), Op::Write(0x0139, vec![0x10])]
    );
    assert!(regs.drive(&mut sub, T0).is_empty(), "written once");
}

#[test]
fn process_data_trigger_joins_the_event_mask_in_safeop() {
    let mut regs = Regs::new();
    let mut sub = started(&mut regs);
    configure_all(&mut regs);
    step_up(&mut regs, &mut sub, 2, AlState::Init, AlState::PreOp);
    assert_eq!(
        step_up(&mut regs, &mut sub, 4, AlState::PreOp, AlState::SafeOp),
        [
            Op::Write(0x0204, vec![0x11, 0x05, 0, 0]),
            Op::Write(0x0817, vec![0]),
            Op::Write(0x081F, vec![0]),
            Op::Write(0x0130, vec![4, 0]),
        ]
    );
    let layout = sub.process_data().expect("layout in SAFEOP");
    assert_eq!(
        (layout.outputs, layout.inputs),
        (Some(common::OUTPUTS), Some(common::INPUTS))
    );
    assert!(
        !layout.outputs_active,
        "outputs are never applied in SAFEOP"
    );
}

#[test]
fn a_mailbox_larger_than_mbx_is_refused_with_0x0002() {
    // SM0/SM1 of 256 bytes, as the device describes them, on a SubDevice<128>: no memory.
    const BIG: MailboxConfig = MailboxConfig::contiguous(0x1000, 256);
    static CONFIG: DeviceConfig = DeviceConfig::new(BIG, DEVICE.process_data);
    let mut regs = Regs::new();
    let mut sub: SubDevice<'_, 128> = SubDevice::new::<()>(&CONFIG);
    regs.drive(&mut sub, T0);
    regs.sm(0, BIG.receive.start, BIG.receive.length, 0x26, true);
    regs.sm(1, BIG.send.start, BIG.send.length, 0x22, true);
    let log = request(&mut regs, &mut sub, 0x0002);
    assert_eq!(
        log[5..],
        [
            Op::Write(0x0134, vec![0x02, 0]),
            Op::Write(0x0130, vec![0x11, 0]),
        ]
    );
    assert_eq!(sub.poll_event(), None, "the application is not asked");
    assert_eq!(
        (sub.state(), sub.al_status_code()),
        (AlState::Init, AlStatusCode::NO_MEMORY)
    );
}

#[test]
fn pending_transition_is_answered_with_0x0001_at_the_deadline() {
    let mut regs = Regs::new();
    let mut sub = started(&mut regs);
    configure_all(&mut regs);
    request(&mut regs, &mut sub, 0x0002);
    let deadline = sub
        .poll_timeout()
        .expect("a pending transition has a deadline");
    assert_eq!(deadline, T0.saturating_add(DEVICE.transition_timeout));
    assert_eq!(DEVICE.transition_timeout, Duration::from_millis(1_000));

    sub.handle_timeout(Instant::from_micros(deadline.as_micros() - 1));
    assert!(
        regs.drive(&mut sub, T0).is_empty(),
        "nothing happens before the deadline"
    );
    sub.handle_timeout(deadline);
    let log = regs.drive(&mut sub, deadline);
    assert_eq!(
        log,
        [
            Op::Write(0x0134, vec![0x01, 0]),
            Op::Write(0x0130, vec![0x11, 0])
        ]
    );
    let t = up(AlState::Init, AlState::PreOp);
    assert_eq!(sub.poll_event(), Some(Event::TransitionRequested(t)));
    assert_eq!(sub.poll_event(), Some(Event::TransitionAborted(t)));
    assert_eq!(sub.poll_timeout(), None);

    sub.complete_transition(t, Ok(()));
    assert!(
        regs.drive(&mut sub, deadline).is_empty(),
        "a late answer changes nothing"
    );
}

#[test]
fn a_new_request_aborts_the_pending_transition() {
    let mut regs = Regs::new();
    let mut sub = started(&mut regs);
    configure_all(&mut regs);
    request(&mut regs, &mut sub, 0x0002);
    request(&mut regs, &mut sub, 0x0002);
    assert!(
        sub.pending_transition().is_some(),
        "the same request again keeps waiting"
    );

    request(&mut regs, &mut sub, 0x0001);
    let t = up(AlState::Init, AlState::PreOp);
    assert_eq!(sub.poll_event(), Some(Event::TransitionRequested(t)));
    assert_eq!(sub.poll_event(), Some(Event::TransitionAborted(t)));
    assert_eq!(sub.poll_event(), None);
    assert_eq!((regs.u16_at(0x0130), regs.u16_at(0x0134)), (0x0001, 0));
}

/// An application's refusal shows its code; one without a code (0x0000) still shows the
/// MainDevice an error with a code: 0x0001, unspecified (found by the fuzz target).
#[test]
fn application_refusal_carries_its_code_or_0x0001() {
    for (refusal, shown) in [(0x8001, 0x8001), (0x0000, 0x0001)] {
        let mut regs = Regs::new();
        let mut sub = started(&mut regs);
        configure_all(&mut regs);
        request(&mut regs, &mut sub, 0x0002);
        sub.complete_transition(
            up(AlState::Init, AlState::PreOp),
            Err(AlStatusCode(refusal)),
        );
        regs.drive(&mut sub, T0);
        assert_eq!(
            (regs.u16_at(0x0130), regs.u16_at(0x0134)),
            (0x0011, shown),
            "refused with {refusal:#06x}"
        );
    }
}

#[test]
fn register_reads_clear_the_events_the_esc_clears() {
    use ecat_core::AlEvent;
    let cleared = AlEvent::cleared_by_register_read;
    assert_eq!(cleared(0x0120, 2), AlEvent::AL_CONTROL);
    assert_eq!(
        cleared(0x011F, 2),
        AlEvent::AL_CONTROL,
        "a read that spans 0x0120"
    );
    assert_eq!(cleared(0x011F, 1), AlEvent::NONE);
    assert_eq!(
        cleared(0x0121, 1),
        AlEvent::NONE,
        "only the low byte clears it"
    );
    assert_eq!(cleared(0x0806, 1), AlEvent::SM_CHANGE, "SM0 activation");
    assert_eq!(
        cleared(0x0800, 6),
        AlEvent::NONE,
        "SM0 without its activation byte"
    );
    assert_eq!(cleared(0x0878, 8), AlEvent::SM_CHANGE, "SM15");
    assert_eq!(cleared(0x0880, 8), AlEvent::NONE, "no SM16");
    assert_eq!(cleared(0x0440, 2), AlEvent::WATCHDOG_PROCESS_DATA);
    assert_eq!(
        cleared(0x0000, 0x1000),
        AlEvent::AL_CONTROL | AlEvent::SM_CHANGE | AlEvent::WATCHDOG_PROCESS_DATA
    );
    assert_eq!(cleared(0x0120, 0), AlEvent::NONE, "an empty read");
    assert_eq!(cleared(0xFFFF, usize::MAX), AlEvent::NONE, "no overflow");
}

#[test]
fn expired_watchdog_in_op_reads_0x0440_and_falls_back_to_safeop() {
    let mut regs = Regs::new();
    let mut sub = started(&mut regs);
    configure_all(&mut regs);
    step_up(&mut regs, &mut sub, 2, AlState::Init, AlState::PreOp);
    step_up(&mut regs, &mut sub, 4, AlState::PreOp, AlState::SafeOp);
    step_up(&mut regs, &mut sub, 8, AlState::SafeOp, AlState::Op);
    sub.outputs_received();
    regs.drive(&mut sub, T0);
    assert_eq!(sub.state(), AlState::Op);
    assert!(
        sub.event_mask()
            .contains(ecat_core::AlEvent::WATCHDOG_PROCESS_DATA)
    );

    regs.put(ecat_core::register::WATCHDOG_STATUS_PROCESS_DATA, &[0, 0]); // expired
    regs.event |= ecat_core::AlEvent::WATCHDOG_PROCESS_DATA.bits();
    sub.handle_al_event(ecat_core::AlEvent(regs.event));
    let log = regs.drive(&mut sub, T0);
    assert_eq!(log.first(), Some(&Op::Read(0x0440, 2)));
    assert_eq!(
        (sub.state(), sub.al_status_code()),
        (AlState::SafeOp, AlStatusCode(0x001B))
    );
    assert_eq!(
        regs.event & ecat_core::AlEvent::WATCHDOG_PROCESS_DATA.bits(),
        0
    );
}

/// The registers the core keeps at a value, as the ESC holds them: AL status, AL status code, AL
/// event mask and PDI control of SM0..SM3.
fn presented(regs: &Regs) -> (u16, u16, u32, [u8; 4]) {
    let pdi = |n: u8| regs.mem[usize::from(register::sync_manager(n)) + 7];
    let a = usize::from(register::AL_EVENT_MASK);
    let mask = u32::from_le_bytes(regs.mem[a..a + 4].try_into().unwrap());
    (
        regs.u16_at(register::AL_STATUS),
        regs.u16_at(register::AL_STATUS_CODE),
        mask,
        [pdi(0), pdi(1), pdi(2), pdi(3)],
    )
}

/// The MainDevice's upload of 0x1018:01 (which the empty dictionary refuses) in SM0, with
/// mailbox counter `counter`.
fn put_request(regs: &mut Regs, counter: u8) {
    let coe = (counter << 4) | 3;
    regs.put(
        common::MAILBOX.receive.start,
        &[
            10, 0, 0, 0, 0, coe, 0x00, 0x20, 0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0,
        ],
    );
}

/// What the state-machine runner does with `event`: the accesses it asks for, the mailbox
/// served until it has nothing more, the accesses after each message. Returns the accesses.
fn serve(regs: &mut Regs, sub: &mut SubDevice<'_>, event: AlEvent) -> Vec<Op> {
    sub.handle_al_event(event);
    let mut log = regs.drive(sub, T0);
    while sub.service_mailbox(T0, &mut (), &mut ()) {
        log.extend(regs.drive(sub, T0));
    }
    log
}

/// The MainDevice sends an upload the empty dictionary refuses (`counter` 1..=7) and the
/// SubDevice answers; the answer stays unread in SM1.
fn mailbox_request(regs: &mut Regs, sub: &mut SubDevice<'_>, counter: u8) {
    put_request(regs, counter);
    let log = serve(regs, sub, AlEvent::sync_manager(0));
    let send = common::MAILBOX.send.start;
    assert!(
        log.iter()
            .any(|op| matches!(op, Op::Write(a, _) if *a == send))
    );
    assert_eq!(regs.mem[usize::from(send) + 8], 0x80, "an abort answers");
}

/// The MainDevice reads SM1; whatever waited for it is sent.
fn answer_read(regs: &mut Regs, sub: &mut SubDevice<'_>) {
    serve(regs, sub, AlEvent::sync_manager(1));
}

/// A SubDevice in PREOP, all four SyncManagers configured.
fn in_preop(regs: &mut Regs) -> SubDevice<'static> {
    let mut sub = started(regs);
    configure_all(regs);
    step_up(regs, &mut sub, 2, AlState::Init, AlState::PreOp);
    sub
}

#[test]
fn every_register_follows_errors_acknowledges_state_changes_and_deactivation() {
    let mut regs = Regs::new();
    let mut sub = started(&mut regs);
    assert_eq!(presented(&regs), (0x01, 0, 0x011, [1, 1, 1, 1]));
    configure_all(&mut regs);
    step_up(&mut regs, &mut sub, 2, AlState::Init, AlState::PreOp);
    assert_eq!(presented(&regs), (0x02, 0, 0x111, [0, 0, 1, 1]));
    mailbox_request(&mut regs, &mut sub, 1);
    answer_read(&mut regs, &mut sub);
    assert_eq!(presented(&regs), (0x02, 0, 0x111, [0, 0, 1, 1]));

    // An emergency waits behind the answer: with the answer in SM1 the SM1 event joins the mask,
    // and once the emergency is sent it leaves it.
    assert!(sub.emergency(Emergency::default()));
    mailbox_request(&mut regs, &mut sub, 2);
    assert_eq!(presented(&regs), (0x02, 0, 0x311, [0, 0, 1, 1]));
    answer_read(&mut regs, &mut sub);
    assert_eq!(presented(&regs), (0x02, 0, 0x111, [0, 0, 1, 1]));
    answer_read(&mut regs, &mut sub);

    // SM2 too short for the outputs: SAFEOP is refused with 0x001D, PREOP stays, error set.
    regs.sm(2, common::OUTPUTS.start, 1, 0x64, true);
    request(&mut regs, &mut sub, 4);
    assert_eq!(presented(&regs), (0x12, 0x1D, 0x111, [0, 0, 1, 1]));
    mailbox_request(&mut regs, &mut sub, 3);
    answer_read(&mut regs, &mut sub);
    assert_eq!(presented(&regs), (0x12, 0x1D, 0x111, [0, 0, 1, 1]));

    // The acknowledge clears the error and its code.
    request(&mut regs, &mut sub, 0x12);
    assert_eq!(presented(&regs), (0x02, 0, 0x111, [0, 0, 1, 1]));

    // SM0 deactivated by the MainDevice: back to INIT with 0x0016, mailbox channels off and
    // the SM0 event out of the mask.
    regs.sm(0, common::MAILBOX.receive.start, 128, 0x26, false);
    sub.handle_al_event(AlEvent(regs.event));
    regs.drive(&mut sub, T0);
    assert_eq!(presented(&regs), (0x11, 0x16, 0x011, [1, 1, 1, 1]));
    assert_eq!(sub.state(), AlState::Init);
}

/// The answer (an abort of the empty dictionary) to `mailbox_request`'s upload, with the
/// SubDevice's message counter `counter`.
fn abort_answer(counter: u8) -> Vec<u8> {
    let coe = (counter << 4) | 3;
    vec![
        10, 0, 0, 0, 0, coe, 0x00, 0x20, 0x80, 0x18, 0x10, 0x01, 0x00, 0x00, 0x02, 0x06,
    ]
}

#[test]
fn a_request_in_the_rhythm_is_read_and_answered_without_mask_writes() {
    let mut regs = Regs::new();
    let mut sub = in_preop(&mut regs);
    let (receive, send) = (common::MAILBOX.receive, common::MAILBOX.send);
    let last = send.start + send.length - 1;
    let answered = |counter| {
        vec![
            Op::Read(receive.start, usize::from(receive.length)),
            Op::Write(send.start, abort_answer(counter)),
            Op::Write(last, vec![0]),
        ]
    };

    // The first request, and the next after the MainDevice read the answer (SM1's event
    // latched beside SM0's): the SM0 read and the answer, with SM1's last byte, and nothing else.
    put_request(&mut regs, 1);
    assert_eq!(
        serve(&mut regs, &mut sub, AlEvent::sync_manager(0)),
        answered(1)
    );
    put_request(&mut regs, 2);
    let both = AlEvent::sync_manager(0) | AlEvent::sync_manager(1);
    assert_eq!(serve(&mut regs, &mut sub, both), answered(2));

    // A request while the answer is still unread cannot be read: the SM0 event leaves the mask
    // (it would hold the IRQ line) and the SM1 event joins it.
    put_request(&mut regs, 3);
    assert_eq!(
        serve(&mut regs, &mut sub, AlEvent::sync_manager(0)),
        [Op::Write(0x0204, vec![0x11, 0x02, 0, 0])]
    );
    // The MainDevice reads the answer: the mask takes SM0 back, then the request is served.
    let mut expected = vec![Op::Write(0x0204, vec![0x11, 0x01, 0, 0])];
    expected.extend(answered(3));
    assert_eq!(
        serve(&mut regs, &mut sub, AlEvent::sync_manager(1)),
        expected
    );
}

#[test]
fn a_request_waiting_in_sm0_is_read_before_an_emergency_takes_sm1() {
    // The SM0 event makes the read due at once; an emergency raised and the mailbox served
    // before the driver polls must not take SM1 from the request's answer ("a request is read
    // only when its answer can be written at once"): the request is read and answered first.
    let mut regs = Regs::new();
    let mut sub = in_preop(&mut regs);
    let (receive, send) = (common::MAILBOX.receive, common::MAILBOX.send);
    put_request(&mut regs, 1);
    sub.handle_al_event(AlEvent::sync_manager(0));
    assert!(sub.emergency(Emergency::default()));
    assert!(
        !sub.service_mailbox(T0, &mut (), &mut ()),
        "the request first"
    );
    assert_eq!(
        regs.drive(&mut sub, T0),
        [Op::Read(receive.start, usize::from(receive.length))]
    );
    assert!(sub.service_mailbox(T0, &mut (), &mut ()));
    let log = regs.drive(&mut sub, T0);
    assert_eq!(log.first(), Some(&Op::Write(send.start, abort_answer(1))));
    // The emergency waits behind the answer: the MainDevice's read of SM1 is in the mask.
    assert_eq!(sub.event_mask(), AlEvent(0x0311));
    sub.handle_al_event(AlEvent::sync_manager(1));
    regs.drive(&mut sub, T0);
    assert!(sub.service_mailbox(T0, &mut (), &mut ()));
    let log = regs.drive(&mut sub, T0);
    let Some(Op::Write(address, emergency)) = log.first() else {
        panic!("the emergency is written: {log:x?}");
    };
    assert_eq!(
        (*address, emergency[5] & 0x0F, emergency[7] >> 4),
        (send.start, 3, 1)
    );
}

#[test]
fn a_mailbox_stopped_before_the_poll_drops_the_read_made_due() {
    // PREOP→SAFEOP waits for the application; SM1's length changes without an SM-change event
    // and the same request comes again (the SyncManagers are read, the transition stays
    // pending); a request arrives; the application accepts before the driver polls, the
    // mailbox check fails (0x0016) and the SubDevice falls back to INIT: the SM0 read the
    // request's event made due is not made on the stopped mailbox.
    let mut regs = Regs::new();
    let mut sub = in_preop(&mut regs);
    request(&mut regs, &mut sub, 4);
    assert!(sub.pending_transition().is_some());
    let sm1 = register::sync_manager(1);
    regs.put(sm1 + 2, &64u16.to_le_bytes());
    request(&mut regs, &mut sub, 4);
    put_request(&mut regs, 1);
    sub.handle_al_event(AlEvent::sync_manager(0));
    sub.complete_transition(up(AlState::PreOp, AlState::SafeOp), Ok(()));
    assert_eq!((sub.state(), sub.al_status_code().0), (AlState::Init, 0x16));
    let log = regs.drive(&mut sub, T0);
    let receive = common::MAILBOX.receive.start;
    assert!(
        !log.iter()
            .any(|op| matches!(op, Op::Read(a, _) if *a == receive || *a == 0)),
        "an access of the stopped mailbox: {log:x?}"
    );
}

/// A SubDevice walked up to OP, its outputs received.
fn in_op(regs: &mut Regs) -> SubDevice<'static> {
    let mut sub = started(regs);
    configure_all(regs);
    step_up(regs, &mut sub, 2, AlState::Init, AlState::PreOp);
    step_up(regs, &mut sub, 4, AlState::PreOp, AlState::SafeOp);
    step_up(regs, &mut sub, 8, AlState::SafeOp, AlState::Op);
    sub.outputs_received();
    regs.drive(&mut sub, T0);
    assert_eq!(sub.state(), AlState::Op);
    sub
}

#[test]
fn downward_transitions_stop_outputs_then_inputs_then_the_mailbox() {
    // Deactivations SM2, SM3, then SM1, SM0 (conformance.md "ESM"), before AL status shows the
    // lower state: all four on OP→INIT, the process-data channels on OP→PREOP.
    let cases = [
        (
            0x0001,
            vec![
                Op::Write(0x0204, vec![0x11, 0, 0, 0]),
                Op::Write(0x0817, vec![1]),
                Op::Write(0x081F, vec![1]),
                Op::Write(0x080F, vec![1]),
                Op::Write(0x0807, vec![1]),
                Op::Write(0x0130, vec![1, 0]),
            ],
        ),
        (
            0x0002,
            vec![
                Op::Write(0x0204, vec![0x11, 0x01, 0, 0]),
                Op::Write(0x0817, vec![1]),
                Op::Write(0x081F, vec![1]),
                Op::Write(0x0130, vec![2, 0]),
            ],
        ),
    ];
    for (control, writes) in cases {
        let mut regs = Regs::new();
        let mut sub = in_op(&mut regs);
        let log = request(&mut regs, &mut sub, control);
        let reads = [
            Op::Read(0x0820, 32),
            Op::Read(0x0800, 32),
            Op::Read(0x0420, 2),
            Op::Read(0x0981, 1),
            Op::Read(0x0120, 2),
        ];
        assert_eq!(log[..reads.len()], reads, "AL control {control:#06x}");
        assert_eq!(log[reads.len()..], writes, "AL control {control:#06x}");
    }
}

/// A dictionary with a diagnosis history of 4 messages alone.
pub struct DiagOd {
    /// 0x10F3.
    pub history: ecat_core::diagnosis::DiagnosisHistory<4>,
}

ecat_core::dictionary! {
    minimal DiagOd {
        0x10F3 => diagnosis(history);
    }
}

/// Reads 0x10F3:`sub` as a MainDevice's upload does.
fn history_entry(od: &DiagOd, sub: u8) -> Vec<u8> {
    use ecat_core::dictionary::{At, ObjectDictionary};
    let object = DiagOd::object(0x10F3).unwrap();
    let mut out = [0u8; 64];
    let read = (object.read)(od, At::start(sub), &mut out).unwrap();
    out[..read.size()].to_vec()
}

/// The history holds one message, new (SI2 = 6, SI4 = 1), and it is `message` byte for byte.
fn assert_only_message(od: &DiagOd, message: [u8; 16]) {
    assert_eq!(
        (history_entry(od, 2), history_entry(od, 4)),
        (vec![6], vec![1])
    );
    assert_eq!(history_entry(od, 6), message);
}

/// The mailbox served with `od` at `now` until it has nothing more; the SM1 messages written.
fn serve_with(
    regs: &mut Regs,
    sub: &mut SubDevice<'_>,
    now: Instant,
    od: &mut DiagOd,
) -> Vec<Vec<u8>> {
    let send = common::MAILBOX.send.start;
    let mut sent = Vec::new();
    while sub.service_mailbox(now, od, &mut ()) {
        for op in regs.drive(sub, now) {
            if let Op::Write(a, data) = op
                && a == send
            {
                sent.push(data);
            }
        }
    }
    sent
}

/// An emergency message as SM1 carries it: mailbox header (10 bytes, CoE, `counter`), CoE
/// header (service 1), the 8 bytes.
fn emergency_message(counter: u8, bytes: [u8; 8]) -> Vec<u8> {
    let mut m = vec![10, 0, 0, 0, 0, (counter << 4) | 3, 0x00, 0x10];
    m.extend(bytes);
    m
}

#[test]
fn a_watchdog_expiry_raises_0x8100_and_logs_0x001b_in_the_diagnosis_history() {
    let mut regs = Regs::new();
    let mut sub = in_op(&mut regs);
    let mut od = DiagOd::default();
    assert_eq!(history_entry(&od, 2), [0], "empty");
    regs.put(ecat_core::register::WATCHDOG_STATUS_PROCESS_DATA, &[0, 0]);
    regs.event |= AlEvent::WATCHDOG_PROCESS_DATA.bits();
    sub.handle_al_event(AlEvent(regs.event));
    regs.drive(&mut sub, T0);
    assert_eq!(sub.al_status_code(), AlStatusCode(0x001B));
    assert_eq!(sub.error_register(), 0x11);

    let t1 = Instant::from_micros(5);
    let sent = serve_with(&mut regs, &mut sub, t1, &mut od);
    assert_eq!(
        sent,
        [emergency_message(
            1,
            [0x00, 0x81, 0x11, 0x1B, 0x00, 0, 0, 0]
        )]
    );
    assert_only_message(
        &od,
        [
            0x00, 0xE0, 0x00, 0x00, // diag code
            0x12, 0x00, // error, local timestamp, no parameters
            0x1B, 0x00, // text ID: the AL status code
            0x88, 0x13, 0, 0, 0, 0, 0, 0, // 5 µs
        ],
    );
}

#[test]
fn stack_emergencies_are_rate_limited_per_code_and_diagnosis_emergencies_follow_0x10f3_05() {
    use ecat_core::diagnosis::{Message, Severity};
    use ecat_core::subdevice::EMERGENCY_PERIOD;
    let mut regs = Regs::new();
    let mut sub = in_preop(&mut regs);
    let mut od = DiagOd::default();
    // PREOP→SAFEOP refused by the application with 0x001D: 0xA000 with the code, logged.
    let refuse = |regs: &mut Regs, sub: &mut SubDevice<'_>| {
        request(regs, sub, 0x0014); // SAFEOP, acknowledging the previous error
        sub.complete_transition(
            up(AlState::PreOp, AlState::SafeOp),
            Err(AlStatusCode(0x001D)),
        );
        regs.drive(sub, T0);
    };
    refuse(&mut regs, &mut sub);
    let a000 = [0x00, 0xA0, 0x01, 0x1D, 0x00, 0, 0, 0];
    assert_eq!(
        serve_with(&mut regs, &mut sub, T0, &mut od),
        [emergency_message(1, a000)]
    );
    answer_read(&mut regs, &mut sub);
    // Again within the period: logged, no emergency; after it: one.
    refuse(&mut regs, &mut sub);
    let just_before = Instant::from_micros(EMERGENCY_PERIOD.as_micros() - 1);
    assert_eq!(
        serve_with(&mut regs, &mut sub, just_before, &mut od),
        Vec::<Vec<u8>>::new()
    );
    assert_eq!(history_entry(&od, 2), [7]);
    refuse(&mut regs, &mut sub);
    let at = Instant::from_micros(EMERGENCY_PERIOD.as_micros());
    assert_eq!(
        serve_with(&mut regs, &mut sub, at, &mut od),
        [emergency_message(2, a000)]
    );
    answer_read(&mut regs, &mut sub);
    assert_eq!(history_entry(&od, 2), [8]);

    // 0x10F3:05 bit 0: each new message is an emergency 0xFF00 with its text ID and flags, the
    // error register the current error's.
    use ecat_core::dictionary::ObjectDictionary;
    (DiagOd::object(0x10F3).unwrap().write)(&mut od, 5, &[1, 0]).unwrap();
    let warning = Message::new(Severity::Warning, 0x4001, at);
    assert!(sub.diagnose(&mut od, warning));
    assert_eq!(
        serve_with(&mut regs, &mut sub, at, &mut od),
        [emergency_message(
            3,
            [0x00, 0xFF, 0x01, 0x01, 0x40, 0x11, 0x00, 0x00]
        )]
    );
    assert_eq!(history_entry(&od, 2), [9]);
}

#[test]
fn a_refused_mailbox_request_is_logged_as_a_warning_in_the_diagnosis_history() {
    // ETG.1020 §13: the stack logs its own events, mailbox errors among them. An EoE request
    // (type 2), which the device does not serve, gets the error reply 0x0002 and the history a
    // warning whose text ID is 0x0100 + 0x0002 (the ESI names it); a request served normally
    // logs nothing.
    let mut regs = Regs::new();
    let mut sub = in_preop(&mut regs);
    let mut od = DiagOd::default();
    let receive = common::MAILBOX.receive.start;
    regs.put(receive, &[4, 0, 0, 0, 0, (1 << 4) | 2, 0, 0, 0, 0]);
    sub.handle_al_event(AlEvent::sync_manager(0));
    let t1 = Instant::from_micros(7);
    regs.drive(&mut sub, t1);
    let sent = serve_with(&mut regs, &mut sub, t1, &mut od);
    assert_eq!(sent, [vec![4, 0, 0, 0, 0, 0x10, 0x01, 0x00, 0x02, 0x00]]);
    assert_only_message(
        &od,
        [
            0x00, 0xE0, 0x00, 0x00, // diag code
            0x11, 0x00, // warning, local timestamp, no parameters
            0x02, 0x01, // text ID 0x0102
            0x58, 0x1B, 0, 0, 0, 0, 0, 0, // 7 µs
        ],
    );
    // The MainDevice reads the reply, then sends an upload (refused by an SDO abort, which is
    // an answer, not a mailbox error): nothing more is logged.
    sub.handle_al_event(AlEvent::sync_manager(1));
    regs.drive(&mut sub, t1);
    put_request(&mut regs, 2);
    sub.handle_al_event(AlEvent::sync_manager(0));
    regs.drive(&mut sub, t1);
    let sent = serve_with(&mut regs, &mut sub, t1, &mut od);
    assert_eq!(sent.len(), 1);
    assert_eq!(history_entry(&od, 2), [6], "still one message");
}
