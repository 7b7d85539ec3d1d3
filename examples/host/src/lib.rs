//! Host programs around ecat: demos, the virtual slave, the ESI/SII writer. The modules here are
//! what those programs share.

pub mod axis;
pub mod bridge;
pub mod catalog;
pub mod cia402;
pub mod demo;
pub mod description;
pub mod net;
pub mod plot;
