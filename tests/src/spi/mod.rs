//! Fake SPI ESC chips in front of the emulated ESC (being written).
