//! A future that may not be there: what the runners wait on when a source is switched off (no
//! deadline, the IRQ line held by the other runner, no SYNC0 in this mode).

use core::future::Future;
use core::pin::Pin;
use core::task::{Context, Poll};

/// `Some(future)` completes with it; `None` never completes.
///
/// A plain wrapper instead of an `async` block: no state machine of its own around the future.
/// A future that is not `Unpin` goes in as `Pin<&mut F>`, pinned by the caller.
pub(crate) struct Maybe<F>(pub(crate) Option<F>);

impl<F: Future + Unpin> Future for Maybe<F> {
    type Output = F::Output;

    fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<F::Output> {
        match &mut self.0 {
            Some(future) => Pin::new(future).poll(cx),
            None => Poll::Pending,
        }
    }
}
