//! The ARM EABI memory helpers ecat's zeroing and moves call, made small: the word-aligned ones as
//! tail calls to the byte-aligned ones, and `__aeabi_memclr` as a byte loop.
//!
//! LLVM calls `__aeabi_memclr4`/`8` and `__aeabi_memcpy4`/`8` when it knows a destination is
//! aligned (zeroing or moving a struct that holds a `u32` or `u64`). `compiler_builtins` gives each
//! of the four its own copy of the loop (156 to 174 bytes each, weak symbols); `__aeabi_memclr`
//! and `__aeabi_memcpy` take any alignment. The aligned entry points are hints the callee may
//! ignore (ARM EABI run-time ABI, §4.3.4), so these definitions only trade a few cycles per call
//! for 0.6 KB of flash. `__aeabi_memcpy` stays `compiler_builtins`' (every firmware of this board
//! links it anyway); `__aeabi_memclr` is replaced (below).

unsafe extern "aapcs" {
    fn __aeabi_memcpy(dest: *mut u8, src: *const u8, n: usize);
}

/// Zeroes `n` bytes at `dest`, a byte at a time: `compiler_builtins`' version is a word-wise
/// `memset` of 208 bytes that only ecat's zeroing calls (`SubDevice` at start-up, a `Mailbox`
/// when the mailbox starts or stops on a state change: its buffers, 384 bytes with 128-byte
/// mailboxes, about 1.5 k cycles; the read buffers the Beckhoff driver fills with 0x00, the
/// input image). The stores are volatile so that LLVM does not recognise the loop and turn it
/// back into a call to this very function.
///
/// # Safety
/// `dest` is valid for `n` bytes of writes.
#[unsafe(no_mangle)]
pub unsafe extern "aapcs" fn __aeabi_memclr(dest: *mut u8, n: usize) {
    for i in 0..n {
        // SAFETY: `i < n`, and the caller guarantees `dest` is valid for `n` bytes of writes.
        unsafe { dest.add(i).write_volatile(0) }
    }
}

/// `__aeabi_memclr` for a 4-byte aligned `dest`.
///
/// # Safety
/// As `__aeabi_memclr`: `dest` is valid for `n` bytes of writes.
#[unsafe(no_mangle)]
pub unsafe extern "aapcs" fn __aeabi_memclr4(dest: *mut u8, n: usize) {
    // SAFETY: the caller's contract is `__aeabi_memclr`'s.
    unsafe { __aeabi_memclr(dest, n) }
}

/// `__aeabi_memclr` for an 8-byte aligned `dest`.
///
/// # Safety
/// As `__aeabi_memclr`: `dest` is valid for `n` bytes of writes.
#[unsafe(no_mangle)]
pub unsafe extern "aapcs" fn __aeabi_memclr8(dest: *mut u8, n: usize) {
    // SAFETY: the caller's contract is `__aeabi_memclr`'s.
    unsafe { __aeabi_memclr(dest, n) }
}

/// `__aeabi_memcpy` for 4-byte aligned `dest` and `src`.
///
/// # Safety
/// As `__aeabi_memcpy`: `dest` is valid for `n` bytes of writes, `src` for `n` bytes of reads,
/// and they do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "aapcs" fn __aeabi_memcpy4(dest: *mut u8, src: *const u8, n: usize) {
    // SAFETY: the caller's contract is `__aeabi_memcpy`'s.
    unsafe { __aeabi_memcpy(dest, src, n) }
}

/// `__aeabi_memcpy` for 8-byte aligned `dest` and `src`.
///
/// # Safety
/// As `__aeabi_memcpy`: `dest` is valid for `n` bytes of writes, `src` for `n` bytes of reads,
/// and they do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "aapcs" fn __aeabi_memcpy8(dest: *mut u8, src: *const u8, n: usize) {
    // SAFETY: the caller's contract is `__aeabi_memcpy`'s.
    unsafe { __aeabi_memcpy(dest, src, n) }
}
