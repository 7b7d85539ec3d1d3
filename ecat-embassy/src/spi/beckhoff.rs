//! The Beckhoff ESC SPI slave protocol, spoken by the ET1100, ET1200, AX58100 and compatible
//! ESCs (ESC datasheet section II, "SPI Slave Interface": "Address Modes", "Commands",
//! "Read Access", "Write Access", "Read Wait State", "Read Termination").
//!
//! Every access is one SPI transaction: the address phase (2 address/command bytes below 0x2000,
//! 3 from 0x2000 on), for reads the wait state byte, then the data. While the SPI master sends the
//! address phase the ESC shifts out the AL event register (0x0220, 0x0221 and, with 3-byte
//! addressing, 0x0222): every access brings the AL event for free, sampled before the access.
//!
//! ```text
//! 2-byte addressing:  A[12:5]  A[4:0] CMD0[2:0]                          [0xFF wait]  D0 D1 …
//! 3-byte addressing:  A[12:5]  A[4:0] 110b      A[15:13] CMD1[2:0] 00b   [0xFF wait]  D0 D1 …
//! MISO meanwhile:     0x0220   0x0221           0x0222
//! ```
//!
//! During the data phase of a read the master sends 0x00 for every byte but the last, and the read
//! termination byte 0xFF with the last one: only then does the ESC stop prefetching (a prefetched
//! byte of a SyncManager buffer counts as read).
//!
//! An empty access is a NOP: the address phase alone, which brings the AL event and nothing else.
//!
//! [`BeckhoffSpi`] makes each access one transaction; [`BeckhoffSpiPerByte`] one per byte.

use ecat_core::AlEvent;
use ecat_core::chip::{Chip, SpiMode};

use crate::Pdi;
use crate::pdi::Data;
use crate::spi::port::{Part, Port};

/// The SPI commands CMD0/CMD1 (ESC datasheet section II, Table "SPI commands CMD0 and CMD1").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum Command {
    /// No operation: the address phase alone (and the AL event it shifts out).
    Nop = 0b000,
    /// Read, the first data byte following the address phase at once; the SPI clock must leave
    /// the ESC its internal read latency.
    Read = 0b010,
    /// Read with a wait state byte (0xFF) between the address phase and the data.
    ReadWithWaitState = 0b011,
    /// Write.
    Write = 0b100,
    /// Address extension: a third address/command byte follows, carrying `A[15:13]` and the command.
    AddressExtension = 0b110,
}

/// The SPI mode the bus must run in: the mode the SII image's configuration area writes into
/// the PDI configuration register (0x0150 bits 1:0) of the ET1100 and the AX58100
/// ([`ecat_core::chip::ConfigArea`]), taken from the same [`Chip`] constants so the two cannot
/// differ. A board configures its SPI peripheral with it.
pub const SPI_MODE: SpiMode = Chip::ET1100.spi_mode;

const _: () = assert!(Chip::AX58100.spi_mode as u8 == SPI_MODE as u8);

/// First address that needs 3-byte addressing: 2-byte addressing carries `A[12:0]` only.
pub const THREE_BYTE_ADDRESSING_FROM: u16 = 0x2000;
/// The wait state byte, sent between the address phase and the data of a read.
pub const WAIT_STATE: u8 = 0xFF;
/// Sent with the last data byte of a read: the read termination.
pub const READ_TERMINATION: u8 = 0xFF;
/// Sent with every other data byte of a read: the ESC prefetches the next byte.
pub const READ_CONTINUE: u8 = 0x00;

/// How reads wait for the ESC's internal read latency (ESC datasheet section II, "Read Wait State").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadLatency {
    /// Send a wait state byte (0xFF) after the address phase: works at any SPI clock the ESC
    /// supports, one byte per read.
    WaitStateByte,
    /// No wait state byte: the SPI clock must be slow enough for the ESC to fetch the first byte
    /// between the last address bit and the first data bit (the ET1200's usual mode).
    SlowClock,
}

/// The driver's configuration. The default suits an ET1100 or AX58100: the wait state byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// How reads wait for the ESC.
    pub read_latency: ReadLatency,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            read_latency: ReadLatency::WaitStateByte,
        }
    }
}

/// The address phase of one transaction, plus the wait state byte of a read.
struct AddressPhase {
    /// Sent, then overwritten with what the ESC shifted out.
    bytes: [u8; 4],
    /// Bytes in use: 2 or 3 address/command bytes, plus the wait state byte.
    len: u8,
    /// 3-byte addressing: the ESC shifts out 0x0222 as well.
    extended: bool,
}

impl AddressPhase {
    /// No transaction yet.
    const NONE: Self = Self {
        bytes: [0; 4],
        len: 0,
        extended: false,
    };

    /// The bytes that address `address` with `command`: 2-byte addressing below
    /// [`THREE_BYTE_ADDRESSING_FROM`], 3-byte addressing from there on.
    fn new(address: u16, command: Command) -> Self {
        let [high, low] = address.to_be_bytes();
        let a12_5 = (address >> 5) as u8;
        let a4_0 = low << 3;
        let extended = address >= THREE_BYTE_ADDRESSING_FROM;
        let mut bytes = if extended {
            let a15_13 = high & 0xE0;
            [
                a12_5,
                a4_0 | Command::AddressExtension as u8,
                a15_13 | (command as u8) << 2,
                0,
            ]
        } else {
            [a12_5, a4_0 | command as u8, 0, 0]
        };
        let mut len = if extended { 3 } else { 2 };
        if command == Command::ReadWithWaitState {
            if let Some(byte) = bytes.get_mut(usize::from(len)) {
                *byte = WAIT_STATE;
            }
            len += 1;
        }
        Self {
            bytes,
            len,
            extended,
        }
    }

    /// The bytes to clock out; after the transfer, what the ESC shifted out meanwhile.
    fn as_mut_slice(&mut self) -> &mut [u8] {
        self.bytes
            .get_mut(..usize::from(self.len))
            .unwrap_or_default()
    }

    /// The AL event register as the ESC shifted it out during the address phase: 0x0220, 0x0221
    /// and, with 3-byte addressing, 0x0222 (the wait state byte carries nothing).
    fn al_event(&self) -> AlEvent {
        let [e0, e1, e2, _] = self.bytes;
        AlEvent::from_le_bytes([e0, e1, if self.extended { e2 } else { 0 }, 0])
    }
}

/// A [`Pdi`] over the Beckhoff ESC SPI protocol.
// `repr(C)`: small fields first (docs/performance.md, "Codegen rules").
#[repr(C)]
pub struct BeckhoffSpi<S> {
    config: Config,
    /// The address phase of the transaction in flight: kept here, once, rather than in the
    /// access future each runner holds; after it, what the ESC shifted out ([`Pdi::al_event`]).
    phase: AddressPhase,
    spi: S,
}

impl<S: Port> BeckhoffSpi<S> {
    /// The driver on `spi`, which must be set up for the ESC's SPI mode (PDI configuration
    /// register 0x0150, usually mode 3) with its chip-select line: an
    /// [`Exclusive`](crate::spi::port::Exclusive) bus, or any `SpiDevice`. The ESC needs no start-up
    /// sequence over SPI.
    pub const fn new(spi: S, config: Config) -> Self {
        Self {
            spi,
            config,
            phase: AddressPhase::NONE,
        }
    }

    /// The read command for the configured read latency.
    fn read_command(&self) -> Command {
        match self.config.read_latency {
            ReadLatency::WaitStateByte => Command::ReadWithWaitState,
            ReadLatency::SlowClock => Command::Read,
        }
    }
}

impl<S: Port> Pdi for BeckhoffSpi<S> {
    type Error = S::Error;

    /// The ET1100's SyncManagers and process RAM, which the AX58100 shares.
    const CHIP: Option<Chip> = Some(Chip::ET1100);

    /// One transaction: the address phase, then the data (a read's with the read termination on
    /// its last byte). An empty access is a NOP (2 bytes on the bus): the AL event alone.
    ///
    /// The port's future itself, the address phase built before it and the AL event decoded
    /// after it ([`Pdi::al_event`]): no future of the driver's own around the port's
    /// (docs/size-history.md, "Session 14: the PDI access one future less").
    fn access<'a>(
        &'a mut self,
        address: u16,
        data: Data<'a>,
    ) -> impl Future<Output = Result<(), S::Error>> {
        let (command, data) = match data {
            Data::Read(buf) => {
                buf.fill(READ_CONTINUE);
                let command = match buf.last_mut() {
                    Some(last) => {
                        *last = READ_TERMINATION;
                        self.read_command()
                    }
                    None => Command::Nop,
                };
                (command, Part::Exchange(buf))
            }
            Data::Write([]) => (Command::Nop, Part::Write(&[])),
            Data::Write(data) => (Command::Write, Part::Write(data)),
        };
        self.phase = AddressPhase::new(address, command);
        self.spi
            .transaction([Part::Exchange(self.phase.as_mut_slice()), data])
    }

    /// The AL event the last address phase shifted out.
    fn al_event(&self) -> AlEvent {
        self.phase.al_event()
    }
}

/// A [`Pdi`] over the Beckhoff ESC SPI protocol, one transaction per byte, each with its own
/// address phase: for SPI masters that cannot keep the clock running through a long transfer, or
/// boards where a higher-priority interrupt may stretch a transaction beyond what the ESC
/// tolerates (the Beckhoff sample code's byte-wise `HW_EscRead`). About three times the bytes of
/// [`BeckhoffSpi`].
pub struct BeckhoffSpiPerByte<S> {
    /// The AL event of the access's first address phase.
    event: AlEvent,
    driver: BeckhoffSpi<S>,
}

impl<S: Port> BeckhoffSpiPerByte<S> {
    /// The driver on `spi`, as [`BeckhoffSpi::new`].
    pub const fn new(spi: S, config: Config) -> Self {
        Self {
            event: AlEvent::NONE,
            driver: BeckhoffSpi::new(spi, config),
        }
    }
}

impl<S: Port> Pdi for BeckhoffSpiPerByte<S> {
    type Error = S::Error;

    /// The ET1100's SyncManagers and process RAM, which the AX58100 shares.
    const CHIP: Option<Chip> = Some(Chip::ET1100);

    /// One transaction per byte; [`Pdi::al_event`] is the first one's. An empty access is one
    /// NOP.
    async fn access(&mut self, mut address: u16, mut rest: Data<'_>) -> Result<(), S::Error> {
        let mut first = true;
        while first || !rest.is_empty() {
            let (piece, tail) = rest.split_at(1);
            rest = tail;
            self.driver.access(address, piece).await?;
            if core::mem::take(&mut first) {
                self.event = self.driver.al_event();
            }
            address = address.wrapping_add(1);
        }
        Ok(())
    }

    fn al_event(&self) -> AlEvent {
        self.event
    }
}
