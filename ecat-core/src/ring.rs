//! A fixed-capacity FIFO that never allocates and never panics: when full, a push drops the oldest
//! element and counts it.

/// A FIFO of at most `N` elements, `N` a power of two below 128.
#[derive(Debug, Clone, Copy)]
// `repr(C)`: the cursor first, within reach of 16-bit byte loads whatever the slots' size.
#[repr(C)]
pub struct Ring<T: Copy, const N: usize> {
    cursor: Cursor,
    /// The elements, as many as the cursor says from its head on (wrapping); the other slots
    /// hold stale values or the filler, never returned (no `Option` per slot: its tag is what
    /// the cursor says).
    slots: [T; N],
}

/// Where a ring's elements are: the part of a [`Ring`] that does not depend on the element
/// type or the capacity, so every ring shares its code.
#[derive(Debug, Clone, Copy)]
struct Cursor {
    /// The oldest element's slot and the element count: bytes, as the capacity is below 128
    /// (checked in [`Ring::new`]), so that their sum fits.
    head: u8,
    len: u8,
    /// Saturating: a diagnostic count, 16 bits like the other counters of the SubDevice.
    dropped: u16,
}

impl Cursor {
    /// The slot a new element goes to in a ring of `capacity` slots (a power of two); when the
    /// ring is full the oldest element is dropped and counted.
    #[inline(never)]
    fn push(&mut self, capacity: u8) -> usize {
        if self.len == capacity {
            self.dropped = self.dropped.saturating_add(1);
            self.pop(capacity);
        }
        self.len = self.len.wrapping_add(1);
        usize::from(self.head.wrapping_add(self.len.wrapping_sub(1)) & capacity.wrapping_sub(1))
    }

    /// The oldest element's slot, which it leaves (`capacity` a power of two).
    #[inline(never)]
    fn pop(&mut self, capacity: u8) -> Option<usize> {
        if self.len == 0 {
            return None;
        }
        let head = self.head;
        self.head = head.wrapping_add(1) & capacity.wrapping_sub(1);
        self.len -= 1;
        Some(usize::from(head))
    }
}

impl<T: Copy, const N: usize> Ring<T, N> {
    /// An empty queue whose slots hold `fill` until used (never returned).
    pub const fn new(fill: T) -> Self {
        const {
            assert!(
                N < 128 && N.is_power_of_two(),
                "a Ring holds a power of two below 128 elements (a slot is an index masked)"
            )
        };
        Self {
            slots: [fill; N],
            cursor: Cursor {
                head: 0,
                len: 0,
                dropped: 0,
            },
        }
    }

    /// Empties the queue and its drop count, as [`Ring::new`] does, leaving the slots as they
    /// are (never returned before a push writes them).
    pub fn clear(&mut self) {
        self.cursor = Cursor {
            head: 0,
            len: 0,
            dropped: 0,
        };
    }

    /// Appends `value`; when the queue is full the oldest element is dropped and counted.
    pub fn push(&mut self, value: T) {
        let i = self.cursor.push(N as u8);
        if let Some(slot) = self.slots.get_mut(i) {
            *slot = value;
        }
    }

    /// Removes and returns the oldest element.
    pub fn pop(&mut self) -> Option<T> {
        let i = self.cursor.pop(N as u8)?;
        self.slots.get(i).copied()
    }

    /// Number of queued elements.
    pub const fn len(&self) -> usize {
        self.cursor.len as usize
    }

    /// Whether nothing is queued.
    pub const fn is_empty(&self) -> bool {
        self.cursor.len == 0
    }

    /// How many elements were dropped because the queue was full (saturating at 65 535).
    pub const fn dropped(&self) -> u16 {
        self.cursor.dropped
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
        let mut r: Ring<u8, 4> = Ring::new(0);
        for v in 1..=6 {
            r.push(v);
        }
        assert_eq!(r.dropped(), 2);
        assert_eq!(
            (r.pop(), r.pop(), r.pop(), r.pop(), r.pop()),
            (Some(3), Some(4), Some(5), Some(6), None)
        );
    }

    #[test]
    fn clear_empties_and_resets_the_drop_count() {
        let mut r: Ring<u8, 2> = Ring::new(0);
        for v in 1..=3 {
            r.push(v);
        }
        r.clear();
        assert_eq!((r.len(), r.dropped(), r.pop()), (0, 0, None));
        r.push(7);
        assert_eq!((r.pop(), r.pop()), (Some(7), None));
    }
}
