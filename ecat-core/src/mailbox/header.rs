//! The mailbox header (ETG.1000.4 Table 29, "Mailbox header").

/// The protocol of a mailbox message (header byte 5, bits 0..3; ETG.1000.4 Table 29).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MailboxType {
    /// 0: mailbox error reply.
    Error,
    /// 1: ADS over EtherCAT.
    Aoe,
    /// 2: Ethernet over EtherCAT.
    Eoe,
    /// 3: CANopen over EtherCAT.
    Coe,
    /// 4: File access over EtherCAT.
    Foe,
    /// 5: Servo profile over EtherCAT.
    Soe,
    /// 15: vendor specific.
    Voe,
    /// Any other value.
    Unknown(u8),
}

impl MailboxType {
    /// The type of the 4-bit code `code`.
    pub const fn from_code(code: u8) -> Self {
        match code & 0x0F {
            0 => Self::Error,
            1 => Self::Aoe,
            2 => Self::Eoe,
            3 => Self::Coe,
            4 => Self::Foe,
            5 => Self::Soe,
            15 => Self::Voe,
            c => Self::Unknown(c),
        }
    }

    /// The 4-bit code.
    pub const fn code(self) -> u8 {
        match self {
            Self::Error => 0,
            Self::Aoe => 1,
            Self::Eoe => 2,
            Self::Coe => 3,
            Self::Foe => 4,
            Self::Soe => 5,
            Self::Voe => 15,
            Self::Unknown(c) => c & 0x0F,
        }
    }
}

/// The 6-byte header in front of every mailbox message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MailboxHeader {
    /// Bytes 0..1: length of the data after the header.
    pub length: u16,
    /// Bytes 2..3: station address of the originator (0 for the MainDevice).
    pub address: u16,
    /// Byte 4, bits 0..5: channel (0).
    pub channel: u8,
    /// Byte 4, bits 6..7: priority.
    pub priority: u8,
    /// Byte 5, bits 0..3: the protocol.
    pub kind: MailboxType,
    /// Byte 5, bits 4..6: the counter, 1..=7 (0: no counter).
    pub counter: u8,
}

impl MailboxHeader {
    /// Size on the wire.
    pub const SIZE: usize = 6;

    /// A header for `length` bytes of `kind` with `counter`.
    pub const fn new(kind: MailboxType, length: u16, counter: u8) -> Self {
        Self {
            length,
            address: 0,
            channel: 0,
            priority: 0,
            kind,
            counter,
        }
    }

    /// Parses the first six bytes; `None` when there are fewer.
    pub fn parse(bytes: &[u8]) -> Option<Self> {
        let [l0, l1, a0, a1, b4, b5] = *bytes.get(..Self::SIZE)? else {
            return None;
        };
        Some(Self {
            length: u16::from_le_bytes([l0, l1]),
            address: u16::from_le_bytes([a0, a1]),
            channel: b4 & 0x3F,
            priority: b4 >> 6,
            kind: MailboxType::from_code(b5),
            counter: (b5 >> 4) & 0x07,
        })
    }

    /// The six bytes on the wire (byte 5 bit 7 reserved, 0).
    pub const fn to_bytes(self) -> [u8; 6] {
        let [l0, l1, _, _, _, b5] = bytes(self.kind.code(), self.length, self.counter);
        let a = self.address.to_le_bytes();
        [
            l0,
            l1,
            a[0],
            a[1],
            (self.channel & 0x3F) | (self.priority << 6),
            b5,
        ]
    }
}

/// The header the SubDevice puts in front of its messages: type `code` (4 bits), `length`,
/// `counter`, address, channel and priority 0.
pub(crate) const fn bytes(code: u8, length: u16, counter: u8) -> [u8; 6] {
    let l = length.to_le_bytes();
    [l[0], l[1], 0, 0, 0, (code & 0x0F) | ((counter & 0x07) << 4)]
}

/// The type's 4-bit code of the header at the start of `bytes` (byte 5, bits 0..3; 0 when
/// there are fewer than six bytes): what the mailbox dispatches on, straight from the byte
/// (through [`MailboxType`] and back it costs the SDO upload 6 instructions).
pub(crate) const fn code(bytes: &[u8]) -> u8 {
    match bytes {
        [_, _, _, _, _, b5, ..] => *b5 & 0x0F,
        _ => 0,
    }
}

/// The mailbox counter sequence 1..=7 (0 is "no counter"; ETG.1000.4 §5.6.3).
pub const fn next_counter(counter: u8) -> u8 {
    match counter {
        1..=6 => counter + 1,
        // After 7 comes 1; without a counter yet (0) the sequence starts at 1.
        _ => 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_code_is_the_types_own_for_every_byte_5() {
        for b5 in 0..=u8::MAX {
            let bytes = [4, 0, 0, 0, 0, b5];
            let header = MailboxHeader::parse(&bytes).unwrap();
            assert_eq!(code(&bytes), header.kind.code(), "byte 5 {b5:#04x}");
            assert_eq!(code(&bytes), b5 & 0x0F);
        }
        assert_eq!(code(&[4, 0, 0, 0, 0]), 0);
    }
}
