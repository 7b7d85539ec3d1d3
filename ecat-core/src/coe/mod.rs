//! CANopen over EtherCAT (CoE, ETG.1000.6 §5.6).

mod abort;

pub use abort::AbortCode;
