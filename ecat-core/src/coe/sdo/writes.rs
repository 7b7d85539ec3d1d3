//! What SDO writes changed of the process-data configuration, noted by the SDO server for the
//! SubDevice: the MainDevice's sync choices in 0x1C32 (ETG.1020 §6.2) and whether a mapping,
//! assignment or sync parameter object was written (its layout is computed again).

use crate::pdo::configures_process_data;
use crate::sync_parameters::Chosen;

/// What SDO writes changed of the process-data configuration: noted by the SDO server at each
/// successful write ([`Context::writes`](super::Context::writes)), in the SubDevice's own record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Writes {
    /// The MainDevice's choices in 0x1C32 (sync mode, cycle time).
    pub chosen: Chosen,
    /// A mapping, assignment or sync parameter object was written
    /// ([`configures_process_data`]): the layout and the sync mode are computed again.
    pub configured: bool,
}

impl Writes {
    /// Notes a successful SDO write of `data` into `index:sub`.
    pub fn note(&mut self, index: u16, sub: u8, data: &[u8]) {
        self.chosen.note(index, sub, data);
        self.configured |= configures_process_data(index);
    }
}
