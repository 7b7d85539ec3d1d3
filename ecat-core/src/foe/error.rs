//! FoE error codes (ETG.1000.6 §5.9, "FoE error codes"), carried by an error frame.

/// The code of an FoE error frame (ETG.1000.6 §5.9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct FoeError(pub u32);

impl FoeError {
    /// 0x8000: not defined (the error text says what).
    pub const NOT_DEFINED: Self = Self(0x8000);
    /// 0x8001: not found (no such file).
    pub const NOT_FOUND: Self = Self(0x8001);
    /// 0x8002: access denied.
    pub const ACCESS_DENIED: Self = Self(0x8002);
    /// 0x8003: disk full (the file does not fit).
    pub const DISK_FULL: Self = Self(0x8003);
    /// 0x8004: illegal (a frame the transfer did not expect).
    pub const ILLEGAL: Self = Self(0x8004);
    /// 0x8005: packet number wrong.
    pub const PACKET_NUMBER_WRONG: Self = Self(0x8005);
    /// 0x8006: already exists.
    pub const ALREADY_EXISTS: Self = Self(0x8006);
    /// 0x8007: no user.
    pub const NO_USER: Self = Self(0x8007);
    /// 0x8008: bootstrap only (the file is served in BOOT only).
    pub const BOOTSTRAP_ONLY: Self = Self(0x8008);
    /// 0x8009: not in bootstrap (the file is not served in BOOT).
    pub const NOT_IN_BOOTSTRAP: Self = Self(0x8009);
    /// 0x800A: no rights (e.g. a wrong password).
    pub const NO_RIGHTS: Self = Self(0x800A);
    /// 0x800B: program error.
    pub const PROGRAM_ERROR: Self = Self(0x800B);
}
