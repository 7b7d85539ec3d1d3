//! The application's say in transitions: refusal with a code, pending answers, the timeout, and
//! a MainDevice that changes its mind while the application thinks.

mod common;

use std::cell::RefCell;
use std::rc::Rc;

use common::walk_to;
use ecat_core::{AlState, AlStatusCode, Duration as CoreDuration, Transition};
use ecat_embassy::Application;
use ecat_emu::harness::{self, Device, Loopback};
use embassy_time::{Duration, Timer};

/// How the test application answers a given transition.
#[derive(Clone, Copy)]
enum Answer {
    Accept,
    Refuse(u16),
    After(u64),
    Never,
}

/// An application whose answer to PREOP→SAFEOP is scripted, recording what it was told.
#[derive(Clone, Default)]
struct Scripted {
    log: Rc<RefCell<Vec<String>>>,
    answer: Rc<RefCell<Option<Answer>>>,
}

struct DropFlag(Rc<RefCell<Vec<String>>>);

impl Drop for DropFlag {
    fn drop(&mut self) {
        self.0.borrow_mut().push("dropped".into());
    }
}

impl<D> Application<D> for Scripted {
    /// The future does not borrow the application: it takes its own handles on the log and the
    /// scripted answer, and starts when first polled (as an `async fn`'s body would).
    fn on_transition(
        &mut self,
        t: Transition,
    ) -> impl Future<Output = Result<(), AlStatusCode>> + use<D> {
        let (log, answer) = (self.log.clone(), self.answer.clone());
        async move {
            log.borrow_mut().push(format!("ask {}->{}", t.from, t.to));
            let answer = if t.to == AlState::SafeOp {
                answer.borrow().unwrap_or(Answer::Accept)
            } else {
                Answer::Accept
            };
            let _flag = DropFlag(log.clone());
            match answer {
                Answer::Accept => Ok(()),
                Answer::Refuse(code) => Err(AlStatusCode(code)),
                Answer::After(ms) => {
                    Timer::after(Duration::from_millis(ms)).await;
                    Ok(())
                }
                Answer::Never => core::future::pending().await,
            }
        }
    }

    fn on_state_change(&mut self, t: Transition) {
        self.log.borrow_mut().push(format!("{}->{}", t.from, t.to));
    }
}

/// The last `n` entries of the application's log.
fn tail(log: &Rc<RefCell<Vec<String>>>, n: usize) -> Vec<String> {
    let log = log.borrow();
    log[log.len().saturating_sub(n)..].to_vec()
}

fn device(app: Scripted) -> Device<Scripted, Loopback> {
    let mut config = common::drive();
    config.transition_timeout = CoreDuration::from_millis(300);
    Device::new(config, app, Loopback)
}

#[test]
fn application_refuses_with_its_own_code() {
    let app = Scripted::default();
    *app.answer.borrow_mut() = Some(Answer::Refuse(0x0026));
    harness::run(device(app), |master| async move {
        walk_to(&master, AlState::PreOp).await;
        assert_eq!(master.request(0x04).await, (0x12, 0x0026));
    });
}

#[test]
fn pending_transition_completes_when_the_application_is_done() {
    let app = Scripted::default();
    *app.answer.borrow_mut() = Some(Answer::After(200));
    let log = app.log.clone();
    harness::run(device(app), move |master| async move {
        walk_to(&master, AlState::PreOp).await;
        assert_eq!(
            master.request(0x04).await,
            (0x02, 0),
            "pending: PREOP, no error"
        );
        master.advance(Duration::from_millis(199)).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x02, 0),
            "still pending at 199 ms"
        );
        master.advance(Duration::from_millis(1)).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x04, 0),
            "done at 200 ms"
        );
        assert_eq!(
            tail(&log, 3),
            ["ask PREOP->SAFEOP", "dropped", "PREOP->SAFEOP"]
        );
    });
}

#[test]
fn pending_transition_times_out_with_0x0001() {
    let app = Scripted::default();
    *app.answer.borrow_mut() = Some(Answer::Never);
    let log = app.log.clone();
    harness::run(device(app), move |master| async move {
        walk_to(&master, AlState::PreOp).await;
        master.request(0x04).await;
        master.advance(Duration::from_millis(299)).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x02, 0),
            "pending until the deadline"
        );
        master.advance(Duration::from_millis(1)).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x12, 0x0001),
            "answered at 300 ms"
        );
        assert_eq!(
            tail(&log, 1),
            ["dropped"],
            "the application's future is dropped"
        );
    });
}

#[test]
fn init_request_while_pending_drops_the_application_future() {
    let app = Scripted::default();
    *app.answer.borrow_mut() = Some(Answer::Never);
    let log = app.log.clone();
    harness::run(device(app), move |master| async move {
        walk_to(&master, AlState::PreOp).await;
        master.request(0x04).await;
        master.advance(Duration::from_millis(50)).await;
        assert_eq!(master.request(0x01).await, (0x01, 0));
        assert_eq!(
            tail(&log, 3),
            ["ask PREOP->SAFEOP", "dropped", "PREOP->INIT"]
        );
        master.advance(Duration::from_millis(500)).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x01, 0),
            "no late timeout"
        );
    });
}

#[test]
fn state_changes_are_reported_in_order() {
    let app = Scripted::default();
    let log = app.log.clone();
    harness::run(device(app), move |master| async move {
        walk_to(&master, AlState::Op).await;
        master.request(0x02).await;
        let log = log.borrow();
        let changes: Vec<&str> = log
            .iter()
            .filter(|l| !l.starts_with("ask") && *l != "dropped")
            .map(String::as_str)
            .collect();
        assert_eq!(
            changes,
            ["INIT->PREOP", "PREOP->SAFEOP", "SAFEOP->OP", "OP->PREOP"]
        );
    });
}

#[test]
fn safeop_to_op_waits_for_the_first_outputs() {
    let app = Scripted::default();
    harness::run(device(app), |master| async move {
        walk_to_without_outputs(&master).await;
        assert_eq!(
            master.request(0x08).await,
            (0x04, 0),
            "no outputs yet: pending"
        );
        master.advance(Duration::from_millis(100)).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x04, 0),
            "still pending"
        );
        common::send_outputs(&master).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x08, 0),
            "outputs arrived: OP"
        );
    });
}

#[test]
fn safeop_to_op_without_outputs_is_answered_with_0x001b() {
    let app = Scripted::default();
    harness::run(device(app), |master| async move {
        walk_to_without_outputs(&master).await;
        master.request(0x08).await;
        master.advance(Duration::from_millis(299)).await;
        assert_eq!((master.al_status(), master.al_status_code()), (0x04, 0));
        master.advance(Duration::from_millis(1)).await;
        assert_eq!(
            (master.al_status(), master.al_status_code()),
            (0x14, 0x001B),
            "SM watchdog: no outputs"
        );
    });
}

/// SAFEOP, reached without a single output frame.
async fn walk_to_without_outputs(master: &ecat_emu::master::TestMaster) {
    walk_to(master, AlState::PreOp).await;
    assert_eq!(master.request(0x04).await, (0x04, 0));
}
