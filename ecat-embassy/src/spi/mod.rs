//! PDI drivers over SPI (being written).
