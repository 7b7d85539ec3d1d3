//! SDO Information (ETG.1000.6 §5.6.3): being written.
