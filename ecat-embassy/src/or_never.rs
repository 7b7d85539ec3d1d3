//! A future that may not be there: what the runners wait on when a source is switched off (no
//! deadline, the IRQ line held by the other runner, no SYNC0 in this mode).

use core::future::Future;
use core::pin::Pin;
use core::task::{Context, Poll};

/// `OrNever(Some(future))` completes with the future; `OrNever(None)` never completes.
///
/// A plain wrapper, not an `async` block (docs/performance.md, "Codegen rules"). A future that
/// is not `Unpin` goes in as `Pin<&mut F>`, pinned by the caller.
pub(crate) struct OrNever<F>(pub(crate) Option<F>);

impl<F: Future + Unpin> Future for OrNever<F> {
    type Output = F::Output;

    fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<F::Output> {
        match &mut self.0 {
            Some(future) => Pin::new(future).poll(cx),
            None => Poll::Pending,
        }
    }
}
