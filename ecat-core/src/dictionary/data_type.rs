//! CoE data types (ETG.1000.6 Table 64, "Basic data type area" 0x0001..0x0037).

/// The data type index of an entry, as SDO Information and the ESI file report it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)] // every basic type's index is below 0x100: one byte in a description
pub enum DataType {
    /// BOOL, 1 bit.
    Boolean = 0x0001,
    /// SINT.
    Integer8 = 0x0002,
    /// INT.
    Integer16 = 0x0003,
    /// DINT.
    Integer32 = 0x0004,
    /// USINT.
    Unsigned8 = 0x0005,
    /// UINT.
    Unsigned16 = 0x0006,
    /// UDINT.
    Unsigned32 = 0x0007,
    /// REAL.
    Real32 = 0x0008,
    /// STRING(n), ISO 8859-1.
    VisibleString = 0x0009,
    /// ARRAY OF BYTE.
    OctetString = 0x000A,
    /// WSTRING(n), UTF-16LE.
    UnicodeString = 0x000B,
    /// Application-defined byte stream.
    Domain = 0x000F,
    /// LREAL.
    Real64 = 0x0011,
    /// LINT.
    Integer64 = 0x0015,
    /// ULINT.
    Unsigned64 = 0x001B,
    /// BIT1 … BIT8.
    Bit1 = 0x0030,
    /// BIT2.
    Bit2 = 0x0031,
    /// BIT3.
    Bit3 = 0x0032,
    /// BIT4.
    Bit4 = 0x0033,
    /// BIT5.
    Bit5 = 0x0034,
    /// BIT6.
    Bit6 = 0x0035,
    /// BIT7.
    Bit7 = 0x0036,
    /// BIT8.
    Bit8 = 0x0037,
}

impl DataType {
    /// The data type index.
    pub const fn code(self) -> u16 {
        self as u8 as u16
    }

    /// Whether values have a variable length (strings, domains): complete access refuses them.
    pub const fn is_variable_length(self) -> bool {
        matches!(
            self,
            Self::VisibleString | Self::OctetString | Self::UnicodeString | Self::Domain
        )
    }

    /// Whether the type may be mapped into a PDO.
    pub const fn is_pdo_mappable(self) -> bool {
        !matches!(
            self,
            Self::VisibleString | Self::UnicodeString | Self::Domain
        )
    }

    /// The BITn type of `bits` bits (1..=8).
    pub const fn bits(bits: u8) -> Option<Self> {
        Some(match bits {
            1 => Self::Bit1,
            2 => Self::Bit2,
            3 => Self::Bit3,
            4 => Self::Bit4,
            5 => Self::Bit5,
            6 => Self::Bit6,
            7 => Self::Bit7,
            8 => Self::Bit8,
            _ => return None,
        })
    }
}
