//! The diagnosis history, object 0x10F3 (ETG.1020 §13 "Diagnosis history"): a ring of
//! diagnosis messages the MainDevice reads by SDO (TwinCAT's "Diag History" tab), with the
//! newest-message and acknowledge subindices and an emergency per new message on request.
//!
//! | SI | entry | type | access |
//! |---|---|---|---|
//! | 0 | highest subindex (5 + N) | UNSIGNED8 | RO |
//! | 1 | maximum messages (N) | UNSIGNED8 | RO |
//! | 2 | newest message: the SI of the newest, 0 when empty | UNSIGNED8 | RO |
//! | 3 | newest acknowledged message: written by the MainDevice, 0 deletes every message | UNSIGNED8 | RW |
//! | 4 | new messages available: messages newer than the acknowledged one | BOOLEAN | RO |
//! | 5 | flags ([`Flags`]) | UNSIGNED16 | RW (bits 0..4) |
//! | 6..5+N | diagnosis message ([`Message`]) | OCTET_STRING | RO |
//!
//! A message on the wire (ETG.1020 Table "Diagnosis message"): diag code UNSIGNED32, flags
//! UNSIGNED16 (bits 0..3 type: 0 info, 1 warning, 2 error; bit 4 the timestamp is the local
//! clock's; bits 8..15 the number of parameters), text ID UNSIGNED16, timestamp UNSIGNED64 (ns),
//! then per parameter its flags UNSIGNED16 (bits 12..15 = 0: bits 0..11 are the CoE data type
//! of the value that follows) and the value, little endian. The stack's own messages
//! ([`Message::al_status_code`]) take the AL status code as text ID, a refused mailbox request
//! ([`Message::mailbox_error`]) [`MAILBOX_ERROR_TEXT`] + its error code; the ESI names both
//! (`DiagMessages`, [`crate::esi`]).
//!
//! Modes (flags bit 4): in *overwrite* mode a new message replaces the oldest; in *acknowledge*
//! mode a message newer than the acknowledged one is never overwritten: when all N are
//! unacknowledged, a new one is discarded. Either way a message lost unacknowledged sets flags
//! bit 5 until the MainDevice next writes SI3.
//!
//! The ring is a fixed array in the dictionary struct ([`DiagnosisHistory<N>`], declared with
//! `dictionary!`'s `diagnosis` item at 0x10F3); its code ([`Log`]) is shared by every `N`.

pub use crate::history::{
    DIAG_CODE, DiagnosisHistory, Flags, History, Log, MAILBOX_ERROR_TEXT, MAX_PARAMETERS, Message,
    Parameter, Severity,
};
pub(crate) use crate::history::{FIRST_MESSAGE, MESSAGE_MAX};

use crate::abort::AbortCode;
use crate::coe::Emergency;
use crate::dictionary::{Access, At, DataType, EntryInfo, Limits, ObjectCode, ObjectInfo, Read};

/// The index of the diagnosis history.
pub(crate) const DIAGNOSIS_HISTORY: u16 = 0x10F3;
/// The emergency error code of a diagnosis message sent as emergency (CiA 301 0xFF00
/// "device specific"), with the text ID and the message flags in the data.
pub const EMERGENCY_CODE: u16 = 0xFF00;

impl Message {
    /// The emergency announcing this message (flags bit 0): [`EMERGENCY_CODE`], `register`
    /// (0x1001), the text ID and the flags in the data.
    pub const fn emergency(&self, register: u8) -> Emergency {
        let t = self.text_id.to_le_bytes();
        let f = self.flags().to_le_bytes();
        Emergency {
            code: EMERGENCY_CODE,
            register,
            data: [t[0], t[1], f[0], f[1], 0],
        }
    }
}

impl History<'_> {
    /// Stores `message` ([`Log::push`]). `None` when it was not stored; else `Some`, with the
    /// emergency to raise when 0x10F3:05 bit 0 asks for one ([`Message::emergency`], error
    /// register `register`).
    pub fn log(&mut self, message: Message, register: u8) -> Option<Option<Emergency>> {
        if !self.log.push(self.messages, message) {
            return None;
        }
        let announce = self.log.flags.has(Flags::EMERGENCY);
        Some(announce.then(|| message.emergency(register)))
    }
}

impl Log {
    /// Reads a subindex from an offset ([`At`]).
    pub fn read(&self, messages: &[Message], at: At, out: &mut [u8]) -> Result<Read, AbortCode> {
        let (sub, offset) = (at.sub(), at.offset());
        let capacity = messages.len();
        let byte: u8 = match sub {
            0 => FIRST_MESSAGE - 1 + capacity as u8,
            1 => capacity as u8,
            2 => self.newest(capacity),
            3 => self.acknowledged,
            4 => u8::from(self.unacked > 0),
            5 => return Ok(crate::dictionary::read_value(&self.flags.0, offset, out)),
            _ => {
                let slot = usize::from(sub - FIRST_MESSAGE);
                let message = messages.get(slot).ok_or(AbortCode::NO_SUBINDEX)?;
                if slot >= usize::from(self.stored) {
                    return Ok(Read::new(0, 0));
                }
                let (bytes, len) = message.encode();
                let bytes = bytes.get(..len).unwrap_or_default();
                let rest = bytes.get(offset..).unwrap_or_default();
                let copied = crate::bytes::copy(out, rest);
                return Ok(Read::new(copied, len));
            }
        };
        Ok(crate::dictionary::read_value(&byte, offset, out))
    }

    /// Writes subindex 3 (acknowledge up to a message, 0: delete them all) or 5 (flags bits
    /// 0..4); the others are read-only.
    pub fn write(&mut self, messages: &[Message], sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        let capacity = messages.len();
        match (sub, data) {
            (3, [0]) => {
                *self = Self {
                    flags: Flags(self.flags.0 & !Flags::LOST),
                    ..Self::default()
                };
                Ok(())
            }
            (3, [si]) => {
                let slot = si
                    .checked_sub(FIRST_MESSAGE)
                    .ok_or(AbortCode::VALUE_RANGE)?;
                if slot >= self.stored {
                    return Err(AbortCode::VALUE_RANGE);
                }
                let newest = self.newest(capacity) - FIRST_MESSAGE;
                let capacity = capacity as u8;
                self.unacked = (newest + capacity - slot) % capacity;
                self.acknowledged = *si;
                self.flags.0 &= !Flags::LOST;
                Ok(())
            }
            (5, [lo, hi]) => {
                let value = u16::from_le_bytes([*lo, *hi]);
                self.flags.0 = value & Flags::WRITABLE | self.flags.0 & Flags::LOST;
                Ok(())
            }
            (3, _) | (5, _) => Err(AbortCode::LENGTH_MISMATCH),
            (0..=4, _) => Err(AbortCode::READ_ONLY),
            _ if usize::from(sub - FIRST_MESSAGE) < capacity => Err(AbortCode::READ_ONLY),
            _ => Err(AbortCode::NO_SUBINDEX),
        }
    }
}

/// The index of a `diagnosis` item: 0x10F3, else it does not compile.
#[doc(hidden)]
pub const fn index(index: u16) -> u16 {
    assert!(
        index == DIAGNOSIS_HISTORY,
        "the diagnosis history is object 0x10F3"
    );
    index
}

/// 0x10F3's highest subindex for a history of `N` messages (the `diagnosis` item).
#[doc(hidden)]
pub const fn max_sub_of<S, const N: usize>(_: fn(&S) -> &DiagnosisHistory<N>) -> u8 {
    FIRST_MESSAGE - 1 + N as u8
}

const fn entry(
    sub: u8,
    name: &'static str,
    data_type: DataType,
    bits: u16,
    access: Access,
) -> EntryInfo<&'static str> {
    EntryInfo {
        sub,
        name,
        data_type,
        bit_len: bits,
        access,
        limits: Limits(0),
    }
}

/// The description of 0x10F3 (its `max_sub` set by the `diagnosis` item): a RECORD whose last
/// entry, SI6, describes every message.
#[doc(hidden)]
pub const OBJECT: ObjectInfo<&'static str> = ObjectInfo {
    index: DIAGNOSIS_HISTORY,
    code: ObjectCode::Record,
    name: "Diagnosis history",
    max_sub: FIRST_MESSAGE,
    entries: &[
        EntryInfo::subindex_count("Highest sub-index supported"),
        entry(1, "Maximum messages", DataType::Unsigned8, 8, Access::RO),
        entry(2, "Newest message", DataType::Unsigned8, 8, Access::RO),
        entry(
            3,
            "Newest acknowledged message",
            DataType::Unsigned8,
            8,
            Access::RW,
        ),
        entry(
            4,
            "New messages available",
            DataType::Boolean,
            1,
            Access::RO,
        ),
        entry(5, "Flags", DataType::Unsigned16, 16, Access::RW),
        entry(
            6,
            "Diagnosis message",
            DataType::OctetString,
            8 * MESSAGE_MAX as u16,
            Access::RO,
        ),
    ],
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::Instant;

    fn read(h: &DiagnosisHistory<3>, sub: u8) -> Vec<u8> {
        let mut out = [0u8; 64];
        let r = h.log.read(&h.messages, At::start(sub), &mut out).unwrap();
        out[..r.size()].to_vec()
    }

    fn write(h: &mut DiagnosisHistory<3>, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        h.log.write(&h.messages, sub, data)
    }

    fn msg(text: u16) -> Message {
        Message::al_status_code(text, Instant::from_micros(u64::from(text)))
    }

    extern crate std;
    use std::{vec, vec::Vec};

    #[test]
    fn a_message_on_the_wire() {
        let m = Message::new(Severity::Warning, 0x1234, Instant::from_micros(2))
            .with(Parameter::u8(0x3C))
            .with(Parameter::u16(0x0189))
            .with(Parameter::u32(7));
        let (bytes, len) = m.encode();
        assert_eq!(
            &bytes[..len],
            &[
                0x00, 0xE0, 0x00, 0x00, // diag code 0xE000
                0x11, 0x02, // warning, local timestamp, 2 parameters (the third ignored)
                0x34, 0x12, // text ID
                0xD0, 0x07, 0, 0, 0, 0, 0, 0, // 2 µs = 2000 ns
                0x05, 0x00, 0x3C, // UNSIGNED8
                0x06, 0x00, 0x89, 0x01, // UNSIGNED16
            ]
        );
        assert_eq!(
            msg(0x001A).emergency(0x11).to_bytes(),
            [0x00, 0xFF, 0x11, 0x1A, 0x00, 0x12, 0x00, 0x00]
        );
    }

    #[test]
    fn overwrite_mode_keeps_the_newest_n() {
        let mut h = DiagnosisHistory::<3>::new();
        assert_eq!(read(&h, 0), [8]);
        assert_eq!(read(&h, 1), [3]);
        assert_eq!(read(&h, 2), [0], "empty");
        assert_eq!(read(&h, 4), [0]);
        assert_eq!(read(&h, 6), [0u8; 0], "an empty slot reads empty");
        for code in 1..=4 {
            assert!(h.push(msg(code)));
        }
        // Slots 0, 1, 2, then 0 again: the newest is SI6, holding code 4.
        assert_eq!(read(&h, 2), [6]);
        assert_eq!(read(&h, 6)[6..8], [4, 0]);
        assert_eq!(read(&h, 7)[6..8], [2, 0]);
        assert_eq!(read(&h, 4), [1]);
        assert_eq!(read(&h, 5), [0x20, 0], "message 1 lost unacknowledged");
        assert_eq!(write(&mut h, 9, &[0]), Err(AbortCode::NO_SUBINDEX));
        assert_eq!(write(&mut h, 6, &[0]), Err(AbortCode::READ_ONLY));
    }

    #[test]
    fn acknowledge_mode_discards_when_all_are_unacknowledged() {
        let mut h = DiagnosisHistory::<3>::new();
        write(&mut h, 5, &[0x10, 0]).unwrap();
        for code in 1..=3 {
            assert!(h.push(msg(code)));
        }
        assert!(!h.push(msg(4)), "no room: discarded");
        assert_eq!(read(&h, 5), [0x30, 0]);
        assert_eq!(read(&h, 2), [8]);
        // The MainDevice acknowledges up to SI7 (code 2): one left, room for two.
        write(&mut h, 3, &[7]).unwrap();
        assert_eq!(
            (read(&h, 3), read(&h, 4), read(&h, 5)),
            (vec![7], vec![1], vec![0x10, 0])
        );
        assert!(h.push(msg(5)));
        assert!(h.push(msg(6)));
        assert!(!h.push(msg(7)));
        assert_eq!(read(&h, 2), [7]);
        assert_eq!(read(&h, 7)[6..8], [6, 0]);
        // Up to the newest: nothing new.
        write(&mut h, 3, &[7]).unwrap();
        assert_eq!(read(&h, 4), [0]);
        assert_eq!(write(&mut h, 3, &[9]), Err(AbortCode::VALUE_RANGE));
        assert_eq!(write(&mut h, 3, &[5]), Err(AbortCode::VALUE_RANGE));
        assert_eq!(write(&mut h, 3, &[7, 0]), Err(AbortCode::LENGTH_MISMATCH));
        // 0 deletes them all; the mode stays.
        write(&mut h, 3, &[0]).unwrap();
        assert_eq!(
            (read(&h, 2), read(&h, 5), read(&h, 6)),
            (vec![0], vec![0x10, 0], vec![])
        );
    }

    #[test]
    fn log_returns_the_emergency_flags_bit_0_asks_for() {
        let mut h = DiagnosisHistory::<1>::new();
        assert_eq!(h.history().log(msg(0x1A), 0x11), Some(None));
        h.log.flags = Flags(Flags::EMERGENCY | Flags::ACKNOWLEDGE_MODE);
        h.log.write(&h.messages, 3, &[0]).unwrap();
        let e = h.history().log(msg(0x1B), 0x11).unwrap().unwrap();
        assert_eq!(
            e.to_bytes(),
            [0x00, 0xFF, 0x11, 0x1B, 0x00, 0x12, 0x00, 0x00]
        );
        assert_eq!(
            h.history().log(msg(0x1C), 0x11),
            None,
            "full, unacknowledged"
        );
    }

    #[test]
    fn disabled_types_are_not_stored_and_bit_5_is_read_only() {
        let mut h = DiagnosisHistory::<3>::new();
        write(&mut h, 5, &[0x2E, 0xFF]).unwrap();
        assert_eq!(read(&h, 5), [0x0E, 0]);
        assert!(!h.push(msg(1)));
        assert!(!h.push(Message::new(Severity::Info, 1, Instant::from_micros(0))));
        assert!(!h.push(Message::new(Severity::Warning, 1, Instant::from_micros(0))));
        assert_eq!(read(&h, 2), [0]);
    }
}
