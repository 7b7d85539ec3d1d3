//! Mailbox error replies (ETG.1000.4 Table 30, "Mailbox error reply"): mailbox type 0, two u16:
//! the service 0x0001 and a detail code.

/// The detail code of a mailbox error reply (ETG.1000.4 Table 30).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MailboxError(pub u16);

impl MailboxError {
    /// 0x0001: syntax of the 6-byte header wrong.
    pub const SYNTAX: Self = Self(0x0001);
    /// 0x0002: the mailbox protocol is not supported.
    pub const UNSUPPORTED_PROTOCOL: Self = Self(0x0002);
    /// 0x0003: channel field wrong.
    pub const INVALID_CHANNEL: Self = Self(0x0003);
    /// 0x0004: the service is not supported.
    pub const SERVICE_NOT_SUPPORTED: Self = Self(0x0004);
    /// 0x0005: the header is invalid (e.g. length 0).
    pub const INVALID_HEADER: Self = Self(0x0005);
    /// 0x0006: length of the received data too short.
    pub const SIZE_TOO_SHORT: Self = Self(0x0006);
    /// 0x0007: no more memory.
    pub const NO_MORE_MEMORY: Self = Self(0x0007);
    /// 0x0008: the length of the data is inconsistent.
    pub const INVALID_SIZE: Self = Self(0x0008);

    /// The meaning of the code as ETG.1000.4 Table 30 states it, `None` for a code it does not
    /// define: the text of the diagnosis message the stack logs for a refused request
    /// ([`crate::diagnosis::Message::mailbox_error`]).
    pub const fn name(self) -> Option<&'static str> {
        Some(match self.0 {
            0x0001 => "mailbox error: syntax of the mailbox header wrong",
            0x0002 => "mailbox error: mailbox protocol not supported",
            0x0003 => "mailbox error: channel field wrong",
            0x0004 => "mailbox error: service not supported",
            0x0005 => "mailbox error: mailbox protocol header wrong",
            0x0006 => "mailbox error: received data too short",
            0x0007 => "mailbox error: no more memory",
            0x0008 => "mailbox error: data length inconsistent",
            _ => return None,
        })
    }

    /// The 4-byte payload of the reply: service 0x0001, then the detail.
    pub(crate) const fn payload(self) -> [u8; 4] {
        let d = self.0.to_le_bytes();
        [0x01, 0x00, d[0], d[1]]
    }
}
