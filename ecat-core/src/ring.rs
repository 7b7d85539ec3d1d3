//! A fixed-capacity FIFO that never allocates and never panics: when full, a push drops the oldest
//! element and counts it.

/// A FIFO of at most `N` elements.
#[derive(Debug, Clone, Copy)]
pub struct Ring<T: Copy, const N: usize> {
    /// The elements, `len` of them from `head` on (wrapping); the other slots hold stale values
    /// or the filler, never returned (no `Option` per slot: its tag is what `len` says).
    slots: [T; N],
    /// The oldest element's slot and the element count: bytes, as `N` < 128 (checked in `new`),
    /// so that their sum fits.
    head: u8,
    len: u8,
    /// Saturating: a diagnostic count, 16 bits like the other counters of the SubDevice.
    dropped: u16,
}

impl<T: Copy, const N: usize> Ring<T, N> {
    /// An empty queue whose slots hold `fill` until used (never returned).
    pub const fn new(fill: T) -> Self {
        const { assert!(N < 128, "a Ring holds fewer than 128 elements") };
        Self {
            slots: [fill; N],
            head: 0,
            len: 0,
            dropped: 0,
        }
    }

    /// Appends `value`; when the queue is full the oldest element is dropped and counted.
    pub fn push(&mut self, value: T) {
        if N == 0 {
            self.dropped = self.dropped.saturating_add(1);
            return;
        }
        if self.len == N as u8 {
            self.pop();
            self.dropped = self.dropped.saturating_add(1);
        }
        let tail = usize::from((self.head + self.len) % N as u8);
        if let Some(slot) = self.slots.get_mut(tail) {
            *slot = value;
            self.len += 1;
        }
    }

    /// Removes and returns the oldest element.
    pub fn pop(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        let value = self.slots.get(usize::from(self.head)).copied();
        self.head = (self.head + 1) % N as u8;
        self.len -= 1;
        value
    }

    /// Number of queued elements.
    pub const fn len(&self) -> usize {
        self.len as usize
    }

    /// Whether nothing is queued.
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// How many elements were dropped because the queue was full (saturating at 65 535).
    pub const fn dropped(&self) -> u16 {
        self.dropped
    }
}

impl<T: Copy + Default, const N: usize> Default for Ring<T, N> {
    fn default() -> Self {
        Self::new(T::default())
    }
}

#[cfg(test)]
mod tests {
    use super::Ring;

    #[test]
    fn fifo_order_and_oldest_dropped_when_full() {
        let mut r: Ring<u8, 3> = Ring::new(0);
        for v in 1..=5 {
            r.push(v);
        }
        assert_eq!(r.dropped(), 2);
        assert_eq!(
            (r.pop(), r.pop(), r.pop(), r.pop()),
            (Some(3), Some(4), Some(5), None)
        );
    }
}
