//! The figures of issue 21 point 4, measured while the run goes on (docs/performance.md):
//! - instructions from the ESC's IRQ (the MainDevice's outputs written, the line pended) to the
//!   inputs written over the PDI, in TIMER0 counts (25 MHz: 40 instructions each under
//!   `-icount shift=0`), with the part spent inside the ESC model (the stand-in for the PDI bus,
//!   not firmware) apart, and the stack measurement's own time left out;
//! - peak stack of each handler (stack painting: all handlers have one priority, so none nests
//!   in another and each starts at the base of the main stack, [`HANDLER_BASE`]; each scans the
//!   painted region below it when it returns, then paints what it used again), and of the
//!   thread executor's own stack ([`THREAD_STACK`], the process stack).

use core::ptr::{read_volatile, write_volatile};
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use core::cell::RefCell;

use critical_section::Mutex;

/// cortex-m-rt's paint (`paint-stack`), and ours for the thread stack.
pub const PAINT: u32 = 0xCCCC_CCCC;
/// Instructions per TIMER0 count under `-icount shift=0` (1 ns each, 25 MHz).
pub const INSTRUCTIONS_PER_COUNT: u32 = 40;

use crate::time_driver::count as now;

/// One distribution, in TIMER0 counts.
#[derive(Debug, Clone, Copy)]
pub struct Spread {
    /// Samples.
    pub n: u32,
    /// Smallest.
    pub min: u32,
    /// Largest.
    pub max: u32,
    /// Sum, for the mean.
    pub sum: u64,
}

impl Spread {
    const fn new() -> Self {
        Self {
            n: 0,
            min: u32::MAX,
            max: 0,
            sum: 0,
        }
    }

    fn add(&mut self, value: u32) {
        self.n += 1;
        self.min = self.min.min(value);
        self.max = self.max.max(value);
        self.sum += u64::from(value);
    }
}

impl core::fmt::Display for Spread {
    /// In instructions: min / mean / max over n.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let k = u64::from(INSTRUCTIONS_PER_COUNT);
        let mean = self.sum * k / u64::from(self.n.max(1));
        write!(
            f,
            "min {} / mean {} / max {} instructions over {} cycles",
            u64::from(self.min) * k,
            mean,
            u64::from(self.max) * k,
            self.n
        )
    }
}

/// The latency figures: total and outside the model, with the state-machine runner idle or
/// inside a chunked mailbox transfer.
#[derive(Debug, Clone, Copy)]
pub struct Latency {
    /// IRQ → inputs written, the state-machine runner between transfers.
    pub total_idle: Spread,
    /// The same less the time inside the ESC model.
    pub firmware_idle: Spread,
    /// IRQ → inputs written, the state-machine runner inside a chunked transfer.
    pub total_inside: Spread,
    /// The same less the time inside the ESC model.
    pub firmware_inside: Spread,
}

static LATENCY: Mutex<RefCell<Latency>> = Mutex::new(RefCell::new(Latency {
    total_idle: Spread::new(),
    firmware_idle: Spread::new(),
    total_inside: Spread::new(),
    firmware_inside: Spread::new(),
}));
/// A window is open: the IRQ was raised, the inputs not yet written.
static OPEN: AtomicBool = AtomicBool::new(false);
static RAISED_AT: AtomicU32 = AtomicU32::new(0);
/// Counts spent in the model inside the open window.
static IN_MODEL: AtomicU32 = AtomicU32::new(0);
/// Counts spent measuring stacks inside the open window: not counted at all.
static MEASURING: AtomicU32 = AtomicU32::new(0);

/// The MainDevice raised the ESC's IRQ with new outputs (OP): the window opens.
pub fn irq_raised() {
    IN_MODEL.store(0, Ordering::Relaxed);
    MEASURING.store(0, Ordering::Relaxed);
    RAISED_AT.store(now(), Ordering::Relaxed);
    OPEN.store(true, Ordering::Relaxed);
}

/// Runs a model access `f`, its time counted as the model's while the window is open.
pub fn in_model<R>(f: impl FnOnce() -> R) -> R {
    if !OPEN.load(Ordering::Relaxed) {
        return f();
    }
    let start = now();
    let result = f();
    IN_MODEL.fetch_add(now().wrapping_sub(start), Ordering::Relaxed);
    result
}

/// The process-data runner wrote the inputs: the window closes.
pub fn inputs_written(inside_transfer: bool) {
    if !OPEN.swap(false, Ordering::Relaxed) {
        return;
    }
    let total = now()
        .wrapping_sub(RAISED_AT.load(Ordering::Relaxed))
        .saturating_sub(MEASURING.load(Ordering::Relaxed));
    let firmware = total.saturating_sub(IN_MODEL.load(Ordering::Relaxed));
    critical_section::with(|cs| {
        let mut latency = LATENCY.borrow_ref_mut(cs);
        let latency = &mut *latency;
        let (t, f) = if inside_transfer {
            (&mut latency.total_inside, &mut latency.firmware_inside)
        } else {
            (&mut latency.total_idle, &mut latency.firmware_idle)
        };
        t.add(total);
        f.add(firmware);
    });
}

/// The latency figures so far.
pub fn latency() -> Latency {
    critical_section::with(|cs| *LATENCY.borrow_ref(cs))
}

/// The main stack pointer when the thread moved to its own stack: where every handler's stack
/// starts.
pub static HANDLER_BASE: AtomicU32 = AtomicU32::new(0);

/// Peak stack of a kind of handler: bytes below [`HANDLER_BASE`], its exception entry and
/// prologue included, looked for within a window (the scan's time grows with it, and it runs
/// in the handler: a wide window would change the timing it measures).
pub struct Peak {
    peak: AtomicU32,
    window: usize,
}

impl Peak {
    /// None yet; use looked for down to `window` bytes below the base.
    pub const fn new(window: usize) -> Self {
        Self {
            peak: AtomicU32::new(0),
            window,
        }
    }

    /// The peak so far, and whether it reached the window (then the real peak may be larger).
    pub fn get(&self) -> (u32, bool) {
        let peak = self.peak.load(Ordering::Relaxed);
        (peak, peak as usize >= self.window)
    }

    /// Runs the handler body `f`, then finds the deepest word written below [`HANDLER_BASE`]
    /// and paints what lies below the current stack pointer again for the next handler.
    #[inline(always)]
    pub fn measure(&self, f: impl FnOnce()) {
        f();
        let top = HANDLER_BASE.load(Ordering::Relaxed) as usize;
        if top == 0 {
            return;
        }
        let start = now();
        let bottom = top - self.window;
        let mut p = bottom;
        // SAFETY: [bottom, top) is RAM of the main stack region, read only.
        unsafe {
            while p < top && read_volatile(p as *const u32) == PAINT {
                p += 4;
            }
        }
        self.peak.fetch_max((top - p) as u32, Ordering::Relaxed);
        // Below the current stack pointer nothing lives: no handler nests in this one.
        let sp = cortex_m::register::msp::read() as usize & !3;
        let end = top.min(sp);
        let mut q = p;
        while q < end {
            // SAFETY: a word of the main stack below the stack pointer, dead (see above).
            unsafe { write_volatile(q as *mut u32, PAINT) };
            q += 4;
        }
        if OPEN.load(Ordering::Relaxed) {
            MEASURING.fetch_add(now().wrapping_sub(start), Ordering::Relaxed);
        }
    }
}

/// The interrupt executor's handler (the process-data runner).
pub static EXECUTOR: Peak = Peak::new(2048);
/// The ESC IRQ's handler (wakes the runner).
pub static ESC_IRQ: Peak = Peak::new(1024);
/// The time driver's handlers.
pub static TIMERS: Peak = Peak::new(1024);
/// The MainDevice (test code, not firmware).
pub static MAIN_DEVICE: Peak = Peak::new(3072);

impl core::fmt::Display for Peak {
    /// `N B`, `≥ N B` when the use reached the window.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.get() {
            (peak, false) => write!(f, "{peak} B"),
            (peak, true) => write!(f, ">= {peak} B"),
        }
    }
}

/// Bytes of the thread executor's stack (the process stack).
pub const THREAD_STACK_BYTES: usize = 16 * 1024;

/// The thread executor's stack: painted, then used as the process stack (`main.rs`).
pub static mut THREAD_STACK: [u32; THREAD_STACK_BYTES / 4] = [0; THREAD_STACK_BYTES / 4];

/// Bytes of the thread stack ever used: from its top to the deepest word not painted.
pub fn thread_stack_peak() -> usize {
    let base = &raw const THREAD_STACK as usize;
    let mut p = base;
    // SAFETY: reads of the thread stack's words (a static), volatile: the thread may run.
    unsafe {
        while p < base + THREAD_STACK_BYTES && read_volatile(p as *const u32) == PAINT {
            p += 4;
        }
    }
    base + THREAD_STACK_BYTES - p
}
