//! The board around the ecat firmware: an STM32G474 (NUCLEO-G474RE) wired to an EtherCAT
//! SubDevice Controller (AX58100/ET1100 or LAN9252) over SPI1, and a 4-in/4-out digital I/O
//! application. Shared by the firmwares (`src/main.rs`: digital I/O, `src/bin/axis.rs`: the
//! CiA402 dummy axis) and the size baseline (`src/bin/baseline.rs`), which differ only in what
//! runs on top.
#![no_std]

pub mod board;
pub mod esc;
pub mod io;
