//! The device the firmware runs: 4 bytes of outputs, 4 bytes of inputs (the outputs inverted,
//! so the MainDevice checks every cycle's answer), and a dictionary with one long object, the
//! 1 KiB [`BLOB`] at 0x2000, that the MainDevice uploads segmented while process data runs.

use core::sync::atomic::{AtomicU32, Ordering};

use ecat_core::dictionary::OctetString;
use ecat_embassy::{Application, Config};

use crate::esc::ModelPdi;

/// Bytes of outputs and of inputs.
pub const IMAGE: usize = 4;

/// Mailboxes of 128 bytes at 0x1000/0x1080; 4 bytes of outputs, 4 bytes of inputs.
pub const DEVICE: Config<ModelPdi, IMAGE, IMAGE> = Config::standard();

/// Size of [`BLOB`].
pub const BLOB_LEN: usize = 1024;

/// Byte `i` of the blob: a pattern in which a lost, repeated or shifted segment shows.
pub const fn blob_byte(i: usize) -> u8 {
    (i.wrapping_mul(7).wrapping_add(i / 251)) as u8
}

/// 0x2000's value: [`blob_byte`] for every offset.
pub const BLOB: OctetString<BLOB_LEN> = {
    let mut bytes = [0; BLOB_LEN];
    let mut i = 0;
    while i < BLOB_LEN {
        bytes[i] = blob_byte(i);
        i += 1;
    }
    OctetString::new(&bytes)
};

/// The inputs answering `outputs`: every bit inverted.
pub const fn answer(outputs: u32) -> u32 {
    !outputs
}

/// The dictionary: no CoE communication area (`minimal`), the blob only.
pub struct Od {
    /// 0x2000, read-only.
    pub blob: OctetString<BLOB_LEN>,
}

ecat_core::dictionary! {
    minimal Od {
        0x2000 => var(blob, RO, "Blob", default = BLOB);
    }
}

/// The application: accepts every transition, answers the outputs.
pub struct App;

/// Cycles run while the state-machine runner was inside a chunked mailbox transfer.
static CYCLES_INSIDE_TRANSFERS: AtomicU32 = AtomicU32::new(0);

/// Cycles run so far while the state-machine runner was inside a chunked mailbox transfer:
/// the process-data runner took the PDI at a chunk boundary.
pub fn cycles_inside_transfers() -> u32 {
    CYCLES_INSIDE_TRANSFERS.load(Ordering::Relaxed)
}

impl Application<Od> for App {
    fn cycle(&mut self, _: &mut Od, outputs: Option<&[u8]>, inputs: &mut [u8]) {
        if crate::esc::inside_transfer() {
            CYCLES_INSIDE_TRANSFERS.fetch_add(1, Ordering::Relaxed);
        }
        let value = match outputs.and_then(|o| o.first_chunk::<4>()) {
            Some(o) => answer(u32::from_le_bytes(*o)),
            // SAFEOP: no outputs to answer.
            None => 0,
        };
        if let Some(i) = inputs.first_chunk_mut::<4>() {
            *i = value.to_le_bytes();
        }
    }
}
