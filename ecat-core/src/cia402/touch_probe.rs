//! Touch probe (CiA 402-2 / ETG.6010 objects 0x60B8 touch probe function, 0x60B9 touch probe
//! status, 0x60BA/0x60BB touch probe 1 positive/negative edge position, 0x60BC/0x60BD touch
//! probe 2 positive/negative edge position; bit layout as Beckhoff's AX8000 object description
//! and CODESYS SoftMotion's `MC_TouchProbe` page restate it).
//!
//! 0x60B8, per probe (probe 1 in bits 0..7, probe 2 in bits 8..15):
//! bit 0 enable; bit 1 0 = trigger on the first event, 1 = continuous; bits 2..3 trigger source
//! 00 = the probe's input, 01 = the encoder's zero (index) pulse, 10 = 0x60D0 (not implemented:
//! treated as 00), 11 reserved (no trigger); bit 4 sample the positive edge; bit 5 sample the
//! negative edge; bits 6..7 user-defined (ignored).
//!
//! 0x60B9, per probe: bit 0 enabled; bit 1 positive edge stored; bit 2 negative edge stored;
//! bits 3..7 reserved/user-defined (0).
//!
//! Enabling (bit 0 rising) clears the stored bits; in first-event mode an edge is stored once
//! and further edges are ignored until the edge's enable bit (4 or 5) rises again or the probe
//! is re-enabled; in continuous mode every edge overwrites the position. Disabling clears the
//! probe's status byte; the positions keep their last value.
//!
//! The latched position is the application's: the actual position at the cycle of the edge, or
//! the position interpolated from the ESC's latch unit time stamps (0x09B0..0x09CF) for
//! sub-cycle resolution.

/// One probe's input this cycle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ProbeInput {
    /// The level of the probe's digital input (or the ESC's latch input).
    pub input: bool,
    /// The level of the encoder's zero pulse.
    pub index: bool,
    /// The position to store on an edge this cycle, counts.
    pub position: i32,
}

/// The probe's edge positions (0x60BA..0x60BD).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ProbePositions {
    /// 0x60BA / 0x60BC.
    pub positive: i32,
    /// 0x60BB / 0x60BD.
    pub negative: i32,
}

/// Two touch probes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TouchProbes {
    /// 0x60B8 of the previous cycle.
    function: u16,
    /// The source levels of the previous cycle.
    levels: [bool; 2],
    /// 0x60B9.
    status: u16,
    /// 0x60BA/0x60BB, 0x60BC/0x60BD.
    positions: [ProbePositions; 2],
}

impl TouchProbes {
    /// Both probes off.
    pub const fn new() -> Self {
        Self {
            function: 0,
            levels: [false; 2],
            status: 0,
            positions: [ProbePositions {
                positive: 0,
                negative: 0,
            }; 2],
        }
    }

    /// 0x60B9.
    pub const fn status(&self) -> u16 {
        self.status
    }

    /// 0x60BA/0x60BB (`probe` 0) or 0x60BC/0x60BD (`probe` 1).
    pub fn positions(&self, probe: usize) -> ProbePositions {
        self.positions.get(probe).copied().unwrap_or_default()
    }

    /// One cycle with 0x60B8 `function` and the two probes' inputs.
    pub fn update(&mut self, function: u16, inputs: [ProbeInput; 2]) {
        if function == 0 && self.function == 0 {
            // Both probes off (status 0 since they were switched off): only the input levels
            // are kept, for an edge in the cycle that enables a probe.
            self.levels = inputs.map(|i| i.input);
            return;
        }
        let before = self.function;
        self.function = function;
        for (n, ((input, level), positions)) in inputs
            .into_iter()
            .zip(self.levels.iter_mut())
            .zip(self.positions.iter_mut())
            .enumerate()
        {
            let shift = 8 * n as u32;
            let now = (function >> shift) as u8;
            let was = (before >> shift) as u8;
            let mut status = (self.status >> shift) as u8;
            let rose = now & !was;
            if now & 1 == 0 {
                status = 0;
            } else if rose & 1 != 0 {
                status = 1;
            }
            if rose & 0x10 != 0 {
                status &= !0x02;
            }
            if rose & 0x20 != 0 {
                status &= !0x04;
            }
            let source = match (now >> 2) & 3 {
                1 => Some(input.index),
                3 => None,
                _ => Some(input.input),
            };
            let continuous = now & 0x02 != 0;
            let level_now = source.unwrap_or(false);
            if status & 1 != 0 && source.is_some() {
                if level_now && !*level && now & 0x10 != 0 && (continuous || status & 0x02 == 0) {
                    positions.positive = input.position;
                    status |= 0x02;
                }
                if !level_now && *level && now & 0x20 != 0 && (continuous || status & 0x04 == 0) {
                    positions.negative = input.position;
                    status |= 0x04;
                }
            }
            *level = level_now;
            self.status = (self.status & !(0xFF << shift)) | (u16::from(status) << shift);
        }
    }
}
