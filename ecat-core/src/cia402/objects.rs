//! The standard objects of a CiA 402 drive (CiA 402-2 §6; IEC 61800-7-201 §6.2, Annex objects):
//! indices, data types and access, as a table a drive's dictionary is checked against.
//!
//! `dictionary!` takes one list per device, so this module cannot splice a fragment into it;
//! instead a drive declares the entries it needs with the types of [`ENTRIES`] (the record of
//! 0x607D is [`SoftwarePositionLimit`]) and proves the declaration in a test with [`check`]:
//!
//! ```text
//! 0x603F => var(error_code, RO | TXPDO, "Error code");
//! 0x6040 => var(controlword, RW | RXPDO, "Controlword");
//! 0x6041 => var(statusword, RO | TXPDO, "Statusword");
//! 0x605A => var(quick_stop_option, RW, "Quick stop option code", default = 2, min = 0, max = 8);
//! 0x605B => var(shutdown_option, RW, "Shutdown option code", default = 0, min = 0, max = 1);
//! 0x605C => var(disable_operation_option, RW, "Disable operation option code", default = 1, min = 0, max = 1);
//! 0x605E => var(fault_reaction_option, RW, "Fault reaction option code", default = 2, min = 0, max = 4);
//! 0x6060 => var(mode, RW | RXPDO, "Modes of operation");
//! 0x6061 => var(mode_display, RO | TXPDO, "Modes of operation display");
//! 0x607D => record(position_limit: SoftwarePositionLimit, "Software position limit") {
//!     1 => min, RW, "Min position limit";
//!     2 => max, RW, "Max position limit";
//! };
//! 0x6502 => var(supported_modes, RO, "Supported drive modes");
//! ```

use crate::dictionary::{DataType, ObjectDictionary};

/// 0x603F error code.
pub const ERROR_CODE: u16 = 0x603F;
/// 0x6040 controlword.
pub const CONTROLWORD: u16 = 0x6040;
/// 0x6041 statusword.
pub const STATUSWORD: u16 = 0x6041;
/// 0x6060 modes of operation.
pub const MODES_OF_OPERATION: u16 = 0x6060;
/// 0x6502 supported drive modes.
pub const SUPPORTED_DRIVE_MODES: u16 = 0x6502;

/// The record of 0x607D software position limit: positions outside `min..=max` are not
/// commanded (CiA 402-2 0x607D). The limits are active when `min < max`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SoftwarePositionLimit {
    /// SI1: min position limit.
    pub min: i32,
    /// SI2: max position limit.
    pub max: i32,
}

/// The record of 0x6099 homing speeds (CiA 402-2 0x6099).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HomingSpeeds {
    /// SI1: speed during search for switch, counts/s.
    pub switch_search: u32,
    /// SI2: speed during search for zero, counts/s.
    pub zero_search: u32,
}

/// How a standard entry may be mapped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mapping {
    /// Not required to be mappable.
    None,
    /// RxPDO-mappable (a command).
    Rx,
    /// TxPDO-mappable (an actual value).
    Tx,
}

/// One standard entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StandardEntry {
    /// The index.
    pub index: u16,
    /// The subindex.
    pub sub: u8,
    /// The name CiA 402-2 gives it.
    pub name: &'static str,
    /// The data type.
    pub data_type: DataType,
    /// Whether the MainDevice writes it (RW) or only reads it (RO).
    pub writable: bool,
    /// How it maps.
    pub mapping: Mapping,
    /// Whether every drive of this profile must declare it.
    pub required: bool,
}

const fn entry(
    index: u16,
    sub: u8,
    name: &'static str,
    data_type: DataType,
    writable: bool,
    mapping: Mapping,
    required: bool,
) -> StandardEntry {
    StandardEntry {
        index,
        sub,
        name,
        data_type,
        writable,
        mapping,
        required,
    }
}

/// The standard entries this profile uses, by index.
pub const ENTRIES: &[StandardEntry] = {
    use DataType::*;
    use Mapping::*;
    &[
        entry(0x603F, 0, "Error code", Unsigned16, false, Tx, true),
        entry(0x6040, 0, "Controlword", Unsigned16, true, Rx, true),
        entry(0x6041, 0, "Statusword", Unsigned16, false, Tx, true),
        entry(
            0x605A,
            0,
            "Quick stop option code",
            Integer16,
            true,
            None,
            false,
        ),
        entry(
            0x605B,
            0,
            "Shutdown option code",
            Integer16,
            true,
            None,
            false,
        ),
        entry(
            0x605C,
            0,
            "Disable operation option code",
            Integer16,
            true,
            None,
            false,
        ),
        entry(0x605D, 0, "Halt option code", Integer16, true, None, false),
        entry(
            0x605E,
            0,
            "Fault reaction option code",
            Integer16,
            true,
            None,
            false,
        ),
        entry(0x6060, 0, "Modes of operation", Integer8, true, Rx, true),
        entry(
            0x6061,
            0,
            "Modes of operation display",
            Integer8,
            false,
            Tx,
            true,
        ),
        entry(
            0x6064,
            0,
            "Position actual value",
            Integer32,
            false,
            Tx,
            false,
        ),
        entry(
            0x6065,
            0,
            "Following error window",
            Unsigned32,
            true,
            None,
            false,
        ),
        entry(0x6067, 0, "Position window", Unsigned32, true, None, false),
        entry(
            0x6068,
            0,
            "Position window time",
            Unsigned16,
            true,
            None,
            false,
        ),
        entry(
            0x606C,
            0,
            "Velocity actual value",
            Integer32,
            false,
            Tx,
            false,
        ),
        entry(0x606D, 0, "Velocity window", Unsigned16, true, None, false),
        entry(
            0x606E,
            0,
            "Velocity window time",
            Unsigned16,
            true,
            None,
            false,
        ),
        entry(
            0x606F,
            0,
            "Velocity threshold",
            Unsigned16,
            true,
            None,
            false,
        ),
        entry(
            0x6070,
            0,
            "Velocity threshold time",
            Unsigned16,
            true,
            None,
            false,
        ),
        entry(0x6071, 0, "Target torque", Integer16, true, Rx, false),
        entry(0x6072, 0, "Max torque", Unsigned16, true, None, false),
        entry(
            0x6077,
            0,
            "Torque actual value",
            Integer16,
            false,
            Tx,
            false,
        ),
        entry(0x607A, 0, "Target position", Integer32, true, Rx, false),
        entry(0x607C, 0, "Home offset", Integer32, true, None, false),
        entry(
            0x607D,
            1,
            "Min position limit",
            Integer32,
            true,
            None,
            false,
        ),
        entry(
            0x607D,
            2,
            "Max position limit",
            Integer32,
            true,
            None,
            false,
        ),
        entry(
            0x607F,
            0,
            "Max profile velocity",
            Unsigned32,
            true,
            None,
            false,
        ),
        entry(0x6081, 0, "Profile velocity", Unsigned32, true, Rx, false),
        entry(
            0x6083,
            0,
            "Profile acceleration",
            Unsigned32,
            true,
            Rx,
            false,
        ),
        entry(
            0x6084,
            0,
            "Profile deceleration",
            Unsigned32,
            true,
            None,
            false,
        ),
        entry(
            0x6085,
            0,
            "Quick stop deceleration",
            Unsigned32,
            true,
            None,
            false,
        ),
        entry(0x6098, 0, "Homing method", Integer8, true, None, false),
        entry(
            0x6099,
            1,
            "Speed during search for switch",
            Unsigned32,
            true,
            None,
            false,
        ),
        entry(
            0x6099,
            2,
            "Speed during search for zero",
            Unsigned32,
            true,
            None,
            false,
        ),
        entry(
            0x609A,
            0,
            "Homing acceleration",
            Unsigned32,
            true,
            None,
            false,
        ),
        entry(0x60B1, 0, "Velocity offset", Integer32, true, Rx, false),
        entry(0x60B2, 0, "Torque offset", Integer16, true, Rx, false),
        entry(
            0x60B8,
            0,
            "Touch probe function",
            Unsigned16,
            true,
            Rx,
            false,
        ),
        entry(
            0x60B9,
            0,
            "Touch probe status",
            Unsigned16,
            false,
            Tx,
            false,
        ),
        entry(
            0x60BA,
            0,
            "Touch probe 1 positive edge",
            Integer32,
            false,
            Tx,
            false,
        ),
        entry(
            0x60BB,
            0,
            "Touch probe 1 negative edge",
            Integer32,
            false,
            Tx,
            false,
        ),
        entry(
            0x60BC,
            0,
            "Touch probe 2 positive edge",
            Integer32,
            false,
            Tx,
            false,
        ),
        entry(
            0x60BD,
            0,
            "Touch probe 2 negative edge",
            Integer32,
            false,
            Tx,
            false,
        ),
        entry(
            0x60F4,
            0,
            "Following error actual value",
            Integer32,
            false,
            Tx,
            false,
        ),
        entry(0x60FD, 0, "Digital inputs", Unsigned32, false, Tx, false),
        entry(0x60FF, 0, "Target velocity", Integer32, true, Rx, false),
        entry(
            0x6502,
            0,
            "Supported drive modes",
            Unsigned32,
            false,
            None,
            true,
        ),
    ]
};

/// How a dictionary's entry differs from [`ENTRIES`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mismatch {
    /// A required entry is not declared.
    Missing,
    /// The data type differs.
    DataType,
    /// RW where RO is expected or the other way round.
    Access,
    /// Not mappable in the expected direction.
    Mapping,
}

/// Checks every entry of [`ENTRIES`] that `D` declares (and that the required ones exist):
/// the first difference as `(index, sub, what)`.
pub fn check<D: ObjectDictionary>() -> Result<(), (u16, u8, Mismatch)> {
    ENTRIES.iter().try_for_each(|standard| {
        let found = D::object(standard.index).and_then(|o| o.info.entry(standard.sub));
        check_entry(standard, found).map_err(|m| (standard.index, standard.sub, m))
    })
}

fn check_entry(
    standard: &StandardEntry,
    found: Option<&crate::dictionary::EntryInfo>,
) -> Result<(), Mismatch> {
    let Some(found) = found else {
        return if standard.required {
            Err(Mismatch::Missing)
        } else {
            Ok(())
        };
    };
    if found.data_type != standard.data_type {
        return Err(Mismatch::DataType);
    }
    if found.access.writable() != standard.writable {
        return Err(Mismatch::Access);
    }
    let mappable = match standard.mapping {
        Mapping::None => true,
        Mapping::Rx => found.access.rxpdo(),
        Mapping::Tx => found.access.txpdo(),
    };
    if mappable {
        Ok(())
    } else {
        Err(Mismatch::Mapping)
    }
}
