//! # ecat-emu: run ecat SubDevices on a PC
//!
//! - [`esc`]: an emulated EtherCAT SubDevice Controller with a PDI port and an EtherCAT port.
pub mod esc;
