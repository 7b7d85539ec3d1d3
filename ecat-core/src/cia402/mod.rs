//! The CiA 402 drive profile (IEC 61800-7-201, profile type 1, and CiA 402-2): the power drive
//! system (PDS) state machine, the option codes that decide how a drive stops, the statusword
//! and the modes of operation.
//!
//! The profile *decides*, the application *moves*: every cycle the application hands
//! [`PowerDriveSystem::update`] the controlword and whether its motor stands still, and gets a
//! [`Motion`] back (follow the mode, stop with a ramp, hold, or power off). It then builds the
//! statusword with [`statusword()`] from the state and the flags only it knows.
//!
//! | module | spec concept |
//! |---|---|
//! | [`state`] | the PDS states and their statusword patterns (IEC 61800-7-201 §6.2.1, Table 30) |
//! | [`controlword`] | the device control commands (§6.2.1.2, Table 28) |
//! | [`option_code`] | 0x605A/0x605B/0x605C/0x605E: the stop ramps and the state after them (§6.2.3) |
//! | [`pds`] | the state machine with transitions 0..16 (§6.2.1.1, Figure 19, Table 27) |
//! | [`statusword`](mod@statusword) | the statusword bits (§6.2.1.3, Table 29) |
//! | [`mode`] | modes of operation 0x6060/0x6061/0x6502 (§6.2.2, Tables 31–33) |
//! | [`objects`] | the standard objects a drive declares, and a check of a dictionary against them |
//! | [`profile`] | the trapezoidal profile generator and the limits 0x607D/0x607F/0x6072 |
//! | [`pp`] | profile position: set-point handshake, set of set-points, absolute/relative (§6.3) |
//! | [`pv`] | profile velocity: velocity window, speed-zero threshold (§6.5) |
//! | [`homing`] | homing methods 1–14, 17–30, 33–35, 37 (§6.4) |
//! | [`touch_probe`] | touch probe 0x60B8..0x60BD |
//! | [`inputs`] | digital inputs 0x60FD |

pub mod controlword;
pub mod homing;
pub mod inputs;
pub mod mode;
pub mod objects;
pub mod option_code;
pub mod pds;
pub mod pp;
pub mod profile;
pub mod pv;
pub mod state;
pub mod statusword;
pub mod touch_probe;

pub use controlword::Command;
pub use mode::Mode;
pub use objects::SoftwarePositionLimit;
pub use option_code::{OptionCodes, Ramp, Reaction, halt};
pub use pds::{Motion, PowerDriveSystem, Step, Transitions};
pub use state::State;
pub use statusword::{StatusFlags, statusword};
