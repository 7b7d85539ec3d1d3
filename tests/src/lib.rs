//! # ecat-emu: run ecat SubDevices on a PC
//!
//! Everything a firmware author needs to test an ecat SubDevice without hardware:
//!
//! | module | what |
//! |---|---|
//! | [`esc`] | an emulated EtherCAT SubDevice Controller: PDI port, EtherCAT port, SyncManagers, AL events (crate `ecat-esc`, `no_std`, shared with the QEMU firmware) |
//! | [`emulator`] | the emulated ESC as the async runners see it: a `Pdi`, an IRQ pin, its RUN/ERR LED outputs in virtual time |
//! | [`coe_client`] | a spec-correct SDO client for the test MainDevice |
//! | [`foe_client`] | an FoE client for the test MainDevice: file writes and reads, the mailbox repeat |
//! | [`devices`] | sample device dictionaries (a CiA402-like drive) |
//! | [`flash`] | a device's NOR flash in the bootloader's layout, with the power cut at any erase or write |
//! | [`frame`] | EtherCAT frames: parsing, building, passing them through one ESC |
//! | [`fuzz`] | a SubDevice session driven by arbitrary bytes: the fuzz target of the core |
//! | [`fuzz_foe`] | the FoE parser and server driven by arbitrary bytes: the fuzz target of FoE |
//! | [`fuzz_parameters`] | the stored-parameter record (0x1010) loaded from arbitrary bytes: its fuzz target |
//! | [`line`](mod@line) | emulated ESCs on one cable, processing frames as a real line does |
//! | [`master`] | a scripted MainDevice with virtual time |
//! | [`spi`] | fake SPI ESC chips that decode the byte stream as the real chip would |
//! | [`mcu`] | a fake 16-bit asynchronous microcontroller bus to the ESC (the ET1100/AX58100 parallel PDI) |
//! | [`harness`] | runs the real runners with the mock time driver, the process-data runner at interrupt level |
//! | [`update`] | a device's firmware update: FoE files into the flash's DFU partition, the bootloader's reset |
//! | [`restart`] | a device that restarts while its line runs (after an update): booted anew, its ESC power-cycled |
//! | [`scheduler`] | the harness's executor: a pended interrupt's priority on one host thread |
pub mod coe_client;
pub mod devices;
pub mod emulator;
pub use ecat_esc as esc;
pub mod flash;
pub mod foe_client;
pub mod frame;
pub mod fuzz;
pub mod fuzz_foe;
pub mod fuzz_parameters;
pub mod harness;
pub mod line;
pub mod master;
pub mod mcu;
pub mod pcap;
pub mod real_master;
pub mod restart;
pub mod scheduler;
pub mod spi;
pub mod update;
