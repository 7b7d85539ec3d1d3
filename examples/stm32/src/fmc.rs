//! The ESC on the FMC (feature `fmc`): an AX58100 (or ET1100) with its 16-bit asynchronous
//! microcontroller interface as 16-bit SRAM on NOR/PSRAM bank 1 (NE1), BUSY on NWAIT
//! (`ecat_embassy::mcu`). The only `unsafe` of the firmware's PDI: the volatile bus cycles.
//!
//! Wiring (pins: README.md): FMC D\[15:0\] to the ESC's DATA\[15:0\]; with a 16-bit bus the FMC
//! puts HADDR\[n+1\] on A\[n\], so A\[14:0\] go to the ESC's ADR\[15:1\]; NBL0 to ADR\[0\] and NBL1
//! to BHE (both low for a word, one high for a byte write on the other lane); NE1 to CS, NOE to
//! RD, NWE to WR, BUSY to NWAIT. The FMC drives NBL\[1:0\] low on reads: reads are whole words, as
//! `Mcu16` expects.

use ecat_embassy::mcu::Bus16;
use embassy_stm32::Peri;
use embassy_stm32::gpio::{AfType, Flex, OutputType, Pin, Pull, Speed};
use embassy_stm32::pac;

/// NOR/PSRAM bank 1, sub-bank 1 (NE1): the ESC's address 0 in the microcontroller's map.
const BANK1: usize = 0x6000_0000;

/// The FMC's registers (RM0440, "FMC registers"). embassy-stm32 0.6 has no FMC register block for
/// the STM32G4 (its metadata lists the pins only), so the firmware writes them itself.
const FMC_BCR1: usize = 0xA000_0000;
const FMC_BTR1: usize = 0xA000_0004;

/// FMC_BCR1: bank enabled (MBKEN), SRAM (MTYP 00, not multiplexed), 16 bits wide (MWID 01),
/// writes enabled (WREN), NWAIT honoured (WAITEN) in asynchronous accesses too (ASYNCWAIT),
/// active low (WAITPOL 0: the ESC's BUSY as the SII image's PDI configuration sets it), mode 1
/// (EXTMOD 0: the same timings for reads and writes), the controller enabled (FMCEN); bit 7,
/// reserved, at its reset value (1).
const BCR1: u32 = 1 | 0b01 << 4 | 1 << 7 | 1 << 12 | 1 << 13 | 1 << 15 | 1 << 31;

/// Timings in HCLK cycles (170 MHz, 5.9 ns): address setup before RD/WR (ADDSET), the data phase
/// (DATAST; the ESC holds BUSY until its access is done and the FMC waits on NWAIT, so this is a
/// minimum), and the gap between two cycles with CS high (BUSTURN). To check on hardware against
/// the ESC's "µController interface" timing tables.
const ADDRESS_SETUP: u32 = 2;
const DATA_PHASE: u32 = 12;
const BUS_TURNAROUND: u32 = 4;
/// FMC_BTR1: ADDSET bits 3:0, DATAST bits 15:8, BUSTURN bits 19:16, ACCMOD 00 (mode A).
const BTR1: u32 = ADDRESS_SETUP | DATA_PHASE << 8 | BUS_TURNAROUND << 16;

/// The alternate function of every FMC pin used here (STM32G474 datasheet, "Alternate function").
pub const AF_FMC: u8 = 12;

/// The FMC bank the ESC sits on: a [`Bus16`] for `ecat_embassy::mcu::Mcu16`. One exists at most
/// ([`FmcBus::init`] is called once, by the board's start-up).
pub struct FmcBus {
    _private: (),
}

impl FmcBus {
    /// Clocks the FMC and configures bank 1 for the ESC ([`BCR1`], [`BTR1`]). The pins must be
    /// connected first (`fmc_pins!`). Called once, by the board's start-up.
    pub fn init() -> Self {
        pac::RCC.ahb3enr().modify(|w| w.set_fmcen(true));
        // SAFETY: FMC_BTR1 and FMC_BCR1 are the FMC's registers, clocked just above; nothing else
        // in the firmware touches the FMC. Timings first, then the bank on.
        unsafe {
            (FMC_BTR1 as *mut u32).write_volatile(BTR1);
            (FMC_BCR1 as *mut u32).write_volatile(BCR1);
        }
        Self { _private: () }
    }

    /// The bank address of the ESC's byte address `address`.
    fn at(address: u16) -> usize {
        BANK1 + usize::from(address)
    }
}

impl Bus16 for FmcBus {
    fn read(&mut self, address: u16) -> u16 {
        let word = Self::at(address & !1) as *const u16;
        // SAFETY: `word` is an even address in bank 1, which `new` configured as the ESC's 16-bit
        // SRAM and `FmcBus` owns (the FMC peripheral is taken): the read is one FMC bus cycle,
        // aligned, reading no memory Rust knows about.
        unsafe { word.read_volatile() }
    }

    fn write(&mut self, address: u16, value: u16) {
        let word = Self::at(address & !1) as *mut u16;
        // SAFETY: as in `read`: one aligned 16-bit bus cycle to the ESC, both byte lanes.
        unsafe { word.write_volatile(value) }
    }

    fn write_byte(&mut self, address: u16, value: u8) {
        let byte = Self::at(address) as *mut u8;
        // SAFETY: as in `read`; an 8-bit store makes the FMC drive only the addressed byte's lane
        // (NBL0 for even addresses, NBL1 for odd ones), the ESC writes that byte alone.
        unsafe { byte.write_volatile(value) }
    }
}

/// Connects `pin` to the FMC ([`AF_FMC`]): push-pull at full speed, or an input pulled up
/// (NWAIT). The pin stays connected for good.
pub fn connect(pin: Peri<'static, impl Pin>, input: bool) {
    let mut flex = Flex::new(pin);
    let af_type = if input {
        AfType::input(Pull::Up)
    } else {
        AfType::output(OutputType::PushPull, Speed::VeryHigh)
    };
    flex.set_as_af_unchecked(AF_FMC, af_type);
    // Dropping a `Flex` disconnects its pin.
    core::mem::forget(flex);
}

/// Connects the FMC's pins for the ESC (README.md, "FMC"): `fmc_pins!(p)` in the board's
/// start-up, `p` the HAL's peripherals. D0..D15, A0..A14 (the ESC's ADR1..ADR15), NBL0 (ADR0),
/// NBL1 (BHE), NE1 (CS), NOE (RD), NWE (WR), then NWAIT (BUSY), an input.
#[macro_export]
macro_rules! fmc_pins {
    ($p:ident) => {
        $crate::fmc_pins!($p;
            PD14, PD15, PD0, PD1, PE7, PE8, PE9, PE10, PE11, PE12, PE13, PE14, PE15, PD8, PD9, PD10,
            PF10, PF7, PF2, PF3, PF4, PF5, PF12, PF13, PF14, PF15, PG0, PG1, PG2, PG3, PG4,
            PE0, PE1, PD7, PD4, PD5);
        $crate::fmc::connect($p.PD6, true);
    };
    ($p:ident; $($pin:ident),*) => {
        $($crate::fmc::connect($p.$pin, false);)*
    };
}
