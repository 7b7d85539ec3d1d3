//! A runner's error as a future's output. The runner loops never complete (a future that cannot
//! return has no "resumed after completion" panic path, docs/performance.md, "Codegen rules"):
//! they hand their error to a `stopped` callback and then pend for good. The `run` methods
//! that return the error wait for that hand-over.

use core::cell::Cell;
use core::future::{Future, poll_fn};
use core::pin::pin;
use core::task::Poll;

/// Polls `runner` until it has put its error into `error` (its `stopped` callback), then
/// returns that error.
pub(crate) async fn handed_over<E>(error: &Cell<Option<E>>, runner: impl Future<Output = ()>) -> E {
    let mut runner = pin!(runner);
    poll_fn(|cx| {
        let _ = runner.as_mut().poll(cx);
        error.take().map_or(Poll::Pending, Poll::Ready)
    })
    .await
}
