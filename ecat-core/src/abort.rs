//! SDO abort codes (ETG.1000.6 Table 41; CiA 301 §7.2.4.3.17).
//!
//! A leaf: the dictionary and the PDO rules refuse an access with a code, the CoE server
//! ([`coe`](crate::coe), which re-exports it) sends it; this module imports none of them.

/// Why an SDO transfer failed. Codes are data: any `u32` is a valid value.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct AbortCode(pub u32);

macro_rules! aborts {
    ($($(#[$doc:meta])* $name:ident = $value:literal, $text:literal;)*) => {
        impl AbortCode {
            $($(#[$doc])* pub const $name: Self = Self($value);)*

            /// The meaning as ETG.1000.6 Table 41 words it, `None` for other codes.
            pub const fn name(self) -> Option<&'static str> {
                match self.0 {
                    $($value => Some($text),)*
                    _ => None,
                }
            }
        }
    };
}

aborts! {
    /// 0x05030000: toggle bit not alternated.
    TOGGLE_BIT = 0x0503_0000, "toggle bit not changed";
    /// 0x05040000: SDO protocol timed out.
    TIMEOUT = 0x0504_0000, "SDO protocol timeout";
    /// 0x05040001: client/server command specifier not valid or unknown.
    COMMAND_SPECIFIER = 0x0504_0001, "client/server command specifier not valid or unknown";
    /// 0x05040005: out of memory.
    OUT_OF_MEMORY = 0x0504_0005, "out of memory";
    /// 0x06010000: unsupported access to an object.
    UNSUPPORTED_ACCESS = 0x0601_0000, "unsupported access to an object";
    /// 0x06010001: attempt to read a write-only object.
    WRITE_ONLY = 0x0601_0001, "attempt to read a write only object";
    /// 0x06010002: attempt to write a read-only object.
    READ_ONLY = 0x0601_0002, "attempt to write a read only object";
    /// 0x06010003: subindex cannot be written, SI0 must be 0 for write access.
    SI0_NOT_ZERO = 0x0601_0003, "subindex cannot be written, SI0 must be 0 for write access";
    /// 0x06010004: complete access not supported for variable-length objects.
    CA_VARIABLE_LENGTH = 0x0601_0004, "SDO complete access not supported for variable length objects";
    /// 0x06010005: object length exceeds mailbox size.
    EXCEEDS_MAILBOX = 0x0601_0005, "object length exceeds mailbox size";
    /// 0x06010006: object mapped to RxPDO, SDO download blocked.
    MAPPED_TO_RXPDO = 0x0601_0006, "object mapped to RxPDO, SDO download blocked";
    /// 0x06020000: the object does not exist in the dictionary.
    NO_OBJECT = 0x0602_0000, "the object does not exist in the object directory";
    /// 0x06040041: the object cannot be mapped into the PDO.
    NOT_MAPPABLE = 0x0604_0041, "the object can not be mapped into the PDO";
    /// 0x06040042: the mapped objects would exceed the PDO length.
    PDO_TOO_LONG = 0x0604_0042, "the number and length of the objects to be mapped would exceed the PDO length";
    /// 0x06040043: general parameter incompatibility.
    PARAMETER_INCOMPATIBLE = 0x0604_0043, "general parameter incompatibility reason";
    /// 0x06040047: general internal incompatibility in the device.
    INTERNAL_INCOMPATIBLE = 0x0604_0047, "general internal incompatibility in the device";
    /// 0x06060000: access failed due to a hardware error.
    HARDWARE_ERROR = 0x0606_0000, "access failed due to a hardware error";
    /// 0x06070010: data type does not match, length of service parameter does not match.
    LENGTH_MISMATCH = 0x0607_0010, "data type does not match, length of service parameter does not match";
    /// 0x06070012: data type does not match, length of service parameter too high.
    LENGTH_TOO_HIGH = 0x0607_0012, "data type does not match, length of service parameter too high";
    /// 0x06070013: data type does not match, length of service parameter too low.
    LENGTH_TOO_LOW = 0x0607_0013, "data type does not match, length of service parameter too low";
    /// 0x06090011: the subindex does not exist.
    NO_SUBINDEX = 0x0609_0011, "subindex does not exist";
    /// 0x06090030: value range of parameter exceeded.
    VALUE_RANGE = 0x0609_0030, "value range of parameter exceeded";
    /// 0x06090031: value of parameter written too high.
    VALUE_TOO_HIGH = 0x0609_0031, "value of parameter written too high";
    /// 0x06090032: value of parameter written too low.
    VALUE_TOO_LOW = 0x0609_0032, "value of parameter written too low";
    /// 0x06090036: maximum value is less than minimum value.
    MAX_BELOW_MIN = 0x0609_0036, "maximum value is less than minimum value";
    /// 0x08000000: general error.
    GENERAL = 0x0800_0000, "general error";
    /// 0x08000020: data cannot be transferred or stored to the application.
    CANNOT_STORE = 0x0800_0020, "data cannot be transferred or stored to the application";
    /// 0x08000021: ... because of local control.
    LOCAL_CONTROL = 0x0800_0021, "data cannot be transferred or stored to the application because of local control";
    /// 0x08000022: ... because of the present device (ESM) state.
    DEVICE_STATE = 0x0800_0022, "data cannot be transferred or stored to the application because of the present device state";
    /// 0x08000023: object dictionary not present or generation failed.
    NO_DICTIONARY = 0x0800_0023, "object dictionary dynamic generation fails or no object dictionary is present";
}

impl core::fmt::Debug for AbortCode {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.name() {
            Some(name) => write!(f, "AbortCode({:#010x}: {name})", self.0),
            None => write!(f, "AbortCode({:#010x})", self.0),
        }
    }
}
