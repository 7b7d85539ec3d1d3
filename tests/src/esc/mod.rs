//! The emulated ESC (being written).
