//! The first byte of every SDO message: command specifier and flags (ETG.1000.6 Tables 33–40;
//! CiA 301 §7.2.4.3).

/// Bit 4 of an initiate request (upload or download) and of its response: complete access.
pub(crate) const COMPLETE: u8 = 0x10;

/// An upload request: both kinds copy the value's bytes from the transfer's offset into the
/// answer (one path in the server).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Upload {
    /// ccs 2: initiate upload (complete access: bit 4, [`COMPLETE`]).
    Initiate,
    /// ccs 3: upload segment with toggle `toggle`.
    Segment { toggle: bool },
}

/// A download request: both kinds store bytes at the transfer's offset (one path in the
/// server).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Download {
    /// ccs 1: initiate download. `expedited` with `size` given or not (complete access: bit
    /// 4, [`COMPLETE`]).
    Initiate {
        expedited: bool,
        size_indicated: bool,
        unused: u8,
    },
    /// ccs 0: download segment with toggle `toggle`, `unused` bytes of the 7, `last`.
    Segment {
        toggle: bool,
        unused: u8,
        last: bool,
    },
}

/// A request from the SDO client (the MainDevice), decoded from its command byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Request {
    /// ccs 1 or 0: a download's initiate or segment.
    Download(Download),
    /// ccs 2 or 3: an upload's initiate or segment.
    Upload(Upload),
    /// ccs 4: abort transfer.
    Abort,
    /// Any other specifier.
    Unknown,
}

impl Request {
    /// Decodes a command byte.
    pub(crate) const fn from_byte(b: u8) -> Self {
        let toggle = b & 0x10 != 0;
        match b >> 5 {
            1 => Self::Download(Download::Initiate {
                expedited: b & 0x02 != 0,
                size_indicated: b & 0x01 != 0,
                unused: (b >> 2) & 0x03,
            }),
            0 => Self::Download(Download::Segment {
                toggle,
                unused: (b >> 1) & 0x07,
                last: b & 0x01 != 0,
            }),
            2 => Self::Upload(Upload::Initiate),
            3 => Self::Upload(Upload::Segment { toggle }),
            4 => Self::Abort,
            _ => Self::Unknown,
        }
    }
}

/// Server command bytes.
pub(crate) mod response {
    /// scs 3: download initiate response (plus the complete-access bit).
    pub(crate) const fn download(complete: bool) -> u8 {
        0x60 | complete_bit(complete)
    }

    /// scs 1: download segment response with toggle.
    pub(crate) const fn download_segment(toggle: bool) -> u8 {
        0x20 | toggle_bit(toggle)
    }

    /// scs 2, expedited, size indicated: `size` of 1..=4 bytes.
    pub(crate) const fn upload_expedited(size: usize, complete: bool) -> u8 {
        let unused = (4usize.saturating_sub(size) as u8) & 0x03;
        0x43 | (unused << 2) | complete_bit(complete)
    }

    /// scs 2, normal, size indicated.
    pub(crate) const fn upload_normal(complete: bool) -> u8 {
        0x41 | complete_bit(complete)
    }

    /// scs 0: upload segment with toggle, `unused` bytes of the 7, `last`.
    pub(crate) const fn upload_segment(toggle: bool, unused: u8, last: bool) -> u8 {
        toggle_bit(toggle) | ((unused & 0x07) << 1) | (last as u8)
    }

    /// Abort transfer.
    pub(crate) const ABORT: u8 = 0x80;

    const fn toggle_bit(toggle: bool) -> u8 {
        if toggle { 0x10 } else { 0 }
    }

    const fn complete_bit(complete: bool) -> u8 {
        if complete { super::COMPLETE } else { 0 }
    }
}
