//! # ecat-core: the sans-IO EtherCAT SubDevice protocol core
//!
//! This crate owns every protocol decision of an EtherCAT SubDevice (slave) and nothing else:
//! it performs no register access, reads no clock and needs no executor. The driver (for example
//! the runners in `ecat-embassy`) feeds it the bytes it read from the EtherCAT SubDevice
//! Controller (ESC), performs the register accesses it asks for, and passes the current time in.
//!
//! The contract, in the shape of `quinn-proto` and `smoltcp`:
//! - **deterministic**: the same inputs at the same instants give the same outputs;
//! - **no panics** on any input: malformed or hostile register contents become AL status codes;
//! - **bounded work** per call, no heap, no global state.
//!
//! ## Layers
//! | module | spec concept |
//! |---|---|
//! | [`register`] | ESC register map (ETG.1000.4 DL registers, ETG.1000.6 AL registers) |
//! | [`al`] | AL control, AL status, AL status code, AL event (ETG.1000.6 Tables 9–12) |
//! | [`sync_manager`] | SyncManager channel registers and the checks a SubDevice applies to them |
//! | [`esm`] | the EtherCAT state machine transition rules (ETG.1000.6 §6.4) |
//! | [`dictionary`](mod@dictionary) | the CoE object dictionary: metadata, typed values, the `dictionary!` declaration (ETG.1000.6 §5.6.3) |
//! | [`coe`] | CANopen over EtherCAT: SDO abort codes, … (ETG.1000.6 §5.6) |
//! | [`mailbox`] | the mailbox: header, counters, repeat, error replies, flow control, dispatch to protocol handlers (ETG.1000.4 §5.6) |
//! | [`foe`] | File access over EtherCAT: the FoE frame, error codes, the server over the application's files (ETG.1000.6 §5.9) |
//! | [`pdo`] | PDO mapping and assignment objects, the process-image layout, pack/unpack (ETG.1000.6 §5.6.7) |
//! | [`device`] | the static description of a device: mailbox, process-data sizes, BOOT support |
//! | [`chip`] | ESC chips (ET1100, AX58100, LAN9252): DL information, SPI PDI, the EEPROM configuration area (ETG.1000.6 §5.4) |
//! | [`sii`] | the SII EEPROM image generated from the description (ETG.1000.6 §5.4, ETG.2010) |
//! | [`esi`] | the ESI XML file generated from the same description (ETG.2000) |
//! | [`subdevice`] | the sans-IO SubDevice: AL events in, register accesses and application events out |
//! | [`process_data`] | where the process-data image lives and what triggers its exchange |
//! | [`sync_mode`] | the synchronisation modes (free-run, SM-synchronous, DC SYNC0) and the modes a device supports (0x1C32:01, 0x1C32:04) |
//! | [`sync_parameters`] | the 0x1C32/0x1C33 parameter objects, the DC settings and their checks |
//! | [`diagnosis`] | the diagnosis history 0x10F3: messages, acknowledge and overwrite modes (ETG.1020 §13) |
//! | [`sync_error`] | sync error supervision: the SM/SYNC-event-missed counter against 0x10F1:02 → SAFEOP + 0x001A (ETG.1020 §6.3) |
//! | [`time`] | instants and durations passed in by the driver |
//! | [`ring`] | the heap-free FIFO behind every bounded queue |
//! | [`indicator`] | the RUN and ERR indicators: patterns, the ESC's LED codes (0x0138/0x0139), AL state/code → pattern, next edge (ETG.1300) |
//! | [`cia402`] | the CiA 402 drive profile: PDS state machine, option codes, statusword, modes (IEC 61800-7-201 §6.2) |
#![no_std]
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented
    )
)]

pub mod abort;
pub mod al;
mod bytes;
pub mod chip;
pub mod cia402;
pub mod coe;
mod declaration;
pub mod device;
pub mod diagnosis;
pub mod dictionary;
pub mod esi;
pub mod esm;
pub mod foe;
mod history;
pub mod indicator;
pub mod mailbox;
pub mod pdo;
pub mod process_data;
pub mod register;
pub mod ring;
pub mod sii;
pub mod subdevice;
pub mod sync_error;
pub mod sync_manager;
pub mod sync_mode;
pub mod sync_parameters;
pub mod time;

pub use al::{AlControl, AlEvent, AlState, AlStatus, AlStatusCode};
pub use device::DeviceConfig;
pub use esm::Transition;
pub use subdevice::{Event, RegisterAccess, SubDevice};
pub use time::{Duration, Instant};
