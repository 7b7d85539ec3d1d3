//! The entry point: [`Config`] describes the device and sizes its buffers, [`Resources`] holds
//! everything the runners share (in one `StaticCell`), [`Resources::split`] hands out the two
//! runners and a [`Control`] (or [`Resources::run`] runs both in one task).

use core::cell::RefCell;
use core::marker::PhantomData;

use ecat_core::device::{MailboxConfig, ProcessDataSizes};
use ecat_core::dictionary::ObjectDictionary;
use ecat_core::{DeviceConfig, SubDevice};
use embassy_sync::blocking_mutex::Mutex as BlockingMutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embedded_hal_async::digital::Wait;

use crate::esm_runner::StateMachineRunner;
use crate::pd_runner::{Error, ProcessDataRunner};
use crate::shared::{SharedEsc, Status};
use crate::{Application, Pdi};

/// The device's description on the ESC behind the PDI driver `P` (whose SyncManager count and
/// process RAM it takes, [`Pdi::CHIP`]), with the sizes of the runners' buffers checked against
/// it: output and input images of exactly `OUT` and `IN` bytes, mailboxes of at most `MBX` bytes
/// (the SubDevice's mailbox buffers). Built in a `const` item, a mismatch is a compile error, and
/// the description stays in flash ([`Resources::new`] takes a `&'static`).
pub struct Config<P, const OUT: usize, const IN: usize, const MBX: usize = 128> {
    device: DeviceConfig,
    pdi: PhantomData<fn() -> P>,
}

impl<P: Pdi, const OUT: usize, const IN: usize, const MBX: usize> Config<P, OUT, IN, MBX> {
    /// The usual device: both mailboxes of `MBX` bytes, at 0x1000 and right after it; `OUT`
    /// bytes of outputs, `IN` bytes of inputs; free-run and SM-synchronous.
    pub const fn standard() -> Self {
        Self::new(DeviceConfig::new(
            MailboxConfig::contiguous(0x1000, MBX as u16),
            ProcessDataSizes {
                outputs: OUT as u16,
                inputs: IN as u16,
            },
        ))
    }

    /// `device` on this ESC, which must then pass [`DeviceConfig::validate`], whose process
    /// images must be `OUT` and `IN` bytes and whose mailboxes must fit in `MBX` bytes. Panics
    /// otherwise: in a `const` item, at compile time.
    pub const fn new(device: DeviceConfig) -> Self {
        let sizes = device.process_data;
        assert!(
            sizes.outputs as usize == OUT,
            "`OUT` is not the output image's size"
        );
        assert!(
            sizes.inputs as usize == IN,
            "`IN` is not the input image's size"
        );
        let config = Self::at_most(device);
        assert!(
            config.device.validate().is_ok(),
            "the device description is invalid"
        );
        config
    }

    /// The description as the SubDevice gets it: the chip's SyncManagers and process RAM in.
    pub const fn device(&self) -> &DeviceConfig {
        &self.device
    }

    /// `device` on this ESC, whose process images fit in `OUT` and `IN` bytes (a runner given a
    /// larger image by the MainDevice stops with [`Error::BufferTooSmall`]) and whose mailboxes
    /// fit in `MBX` bytes, not validated: for a host that runs devices of many sizes, some of
    /// them wrong on purpose. Panics otherwise.
    pub const fn at_most(device: DeviceConfig) -> Self {
        let sizes = device.process_data;
        assert!(
            sizes.outputs as usize <= OUT,
            "the output image exceeds `OUT`"
        );
        assert!(sizes.inputs as usize <= IN, "the input image exceeds `IN`");
        let mailbox = device.mailbox;
        assert!(
            mailbox.receive.length as usize <= MBX && mailbox.send.length as usize <= MBX,
            "a mailbox exceeds `MBX`"
        );
        Self {
            device: match P::CHIP {
                Some(chip) => chip.fit(device),
                None => device,
            },
            pdi: PhantomData,
        }
    }
}

/// The default largest chunk of a state-machine access, in bytes ([`Resources::with_chunk`]).
pub const DEFAULT_CHUNK: u16 = 32;

/// Locks the application with its dictionary: the one place the runners and the [`Control`]s
/// borrow them (one borrow check and one panic location for all; the lock makes the borrow
/// always free).
pub(crate) struct AppCell<A, D>(BlockingMutex<CriticalSectionRawMutex, RefCell<Parts<A, D>>>);

/// The application and its dictionary, the dictionary first.
// `repr(C)`: docs/performance.md, "Codegen rules".
#[repr(C)]
struct Parts<A, D> {
    od: D,
    app: A,
}

impl<A, D> AppCell<A, D> {
    /// Runs `f` on the application and the dictionary, locked.
    pub(crate) fn lock<R>(&self, f: impl FnOnce(&mut A, &mut D) -> R) -> R {
        self.0.lock(|cell| {
            let Parts { od, app } = &mut *cell.borrow_mut();
            f(app, od)
        })
    }
}

/// What both runners and every [`Control`] reach: the ESC with its routing and the application
/// with its dictionary, in one place so that a handle holds one reference for both.
pub(crate) struct Common<P, A, D> {
    pub(crate) esc: SharedEsc<P>,
    pub(crate) app: AppCell<A, D>,
}

/// Everything the two runners share, in one value for a `StaticCell`: the PDI driver `P` with
/// the routing of its AL events, the application `A` with its dictionary `D`, the device's
/// description and the process-data buffers (`OUT`, `IN` bytes; `MBX`: the mailbox buffers of
/// the state-machine runner, see [`Config`]).
pub struct Resources<P, A, D, const OUT: usize, const IN: usize, const MBX: usize = 128>
where
    D: ObjectDictionary,
{
    common: Common<P, A, D>,
    outputs: [u8; OUT],
    inputs: [u8; IN],
    /// The SubDevice, made with the rest (in INIT) and lent to the state-machine runner; its
    /// segmented-download buffer sized by the dictionary (`D::Download`), not the mailbox.
    sub: SubDevice<'static, MBX, D::Download>,
}

impl<P, A, D, const OUT: usize, const IN: usize, const MBX: usize> Resources<P, A, D, OUT, IN, MBX>
where
    P: Pdi,
    A: Application<D>,
    D: ObjectDictionary,
{
    /// The device `config` on the ESC behind `pdi`, with the application `app` over the
    /// dictionary `od`, and the SubDevice in INIT. State-machine accesses move in chunks of
    /// [`DEFAULT_CHUNK`] bytes ([`Resources::with_chunk`]).
    ///
    /// Built in its static's place: `CELL.init_with(|| Resources::new(…))`, which writes the
    /// SubDevice straight into the static rather than copying it there (docs/performance.md,
    /// "Codegen rules"). Not `const`: [`SubDevice::new`] is not.
    pub fn new(config: &'static Config<P, OUT, IN, MBX>, pdi: P, app: A, od: D) -> Self {
        Self {
            common: Common {
                esc: SharedEsc::with_chunk(pdi, DEFAULT_CHUNK),
                app: AppCell(BlockingMutex::new(RefCell::new(Parts { od, app }))),
            },
            outputs: [0; OUT],
            inputs: [0; IN],
            sub: SubDevice::new::<D>(&config.device),
        }
    }

    /// The same, with state-machine accesses (mailbox messages, registers) in chunks of at most
    /// `chunk` bytes (0: each access whole, as one transaction), which the driver may cut
    /// smaller at its own boundaries ([`Pdi::chunk`]). The process-data runner takes the PDI at
    /// the next chunk boundary: smaller chunks bound its wait more tightly and cost more bus
    /// overhead per mailbox byte (an address phase per chunk on the Beckhoff SPI, a PRAM command
    /// on the LAN9252; docs/performance.md). A SyncManager's mailbox buffer is released when its
    /// last byte is read and marked full when its last byte is written, so a mailbox message
    /// moved in order, chunk by chunk, is handed over exactly as a whole one.
    pub fn with_chunk(mut self, chunk: u16) -> Self {
        self.common.esc.set_chunk(chunk);
        self
    }

    /// The two runners and a control handle: the state-machine runner for the thread executor,
    /// the process-data runner for an `InterruptExecutor` above it, the [`Control`] for any task.
    /// Split once per start: the SubDevice is made by [`Resources::new`], and a second call
    /// hands out the same one, in the state the first runner left it (not INIT).
    #[allow(clippy::type_complexity)] // the three parts, each named in full
    pub fn split(
        &mut self,
    ) -> (
        StateMachineRunner<'_, P, A, D, MBX>,
        ProcessDataRunner<'_, P, A, D>,
        Control<'_, P, A, D>,
    ) {
        let Self {
            common,
            outputs,
            inputs,
            sub,
        } = self;
        let common = &*common;
        (
            StateMachineRunner::new(common, sub),
            ProcessDataRunner::new(common, outputs, inputs),
            Control { common },
        )
    }

    /// Both runners in one task, for a first device in one executor: the process-data exchange
    /// then waits for the state machine's work in progress, at most one chunk of mailbox traffic
    /// ([`Resources::with_chunk`]). `irq` is the ESC's IRQ pin; no SYNC0. Returns when a runner
    /// stopped, with its error. With a [`Control`] beside: [`StateMachineRunner::run_with`].
    /// Called again after an error, it goes on with the SubDevice as the runners left it (the
    /// one [`Resources::split`] hands out), not from INIT: a restarted PDI meets the AL state,
    /// mailbox and requests in flight of before.
    pub async fn run<I: Wait>(&mut self, irq: I) -> Error<P::Error, I::Error> {
        let (state_machine, process_data, _) = self.split();
        state_machine.run_with(process_data, irq).await
    }
}

/// A handle on the application, `Copy`: any task of either executor locks the application with
/// its dictionary, raises emergencies, or follows the AL status ([`Control::status`]).
pub struct Control<'a, P, A, D = ()> {
    common: &'a Common<P, A, D>,
}

impl<P, A, D> Clone for Control<'_, P, A, D> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<P, A, D> Copy for Control<'_, P, A, D> {}

impl<'a, P: Pdi, A, D> Control<'a, P, A, D> {
    /// Runs `f` on the application and the dictionary, locked (a critical section: keep it
    /// short, no `.await` inside).
    pub fn lock<R>(self, f: impl FnOnce(&mut A, &mut D) -> R) -> R {
        self.common.app.lock(f)
    }

    /// [`Status::raise_emergency`].
    pub fn raise_emergency(self, emergency: ecat_core::coe::Emergency) {
        self.status().raise_emergency(emergency);
    }

    /// Adds `message` to the dictionary's diagnosis history (0x10F3, `dictionary!`'s
    /// `diagnosis` item) and raises its emergency when 0x10F3:05 bit 0 asks for one. Returns
    /// whether it was stored (not without a history, nor with its type disabled or, in
    /// acknowledge mode, no room).
    pub fn diagnose(self, message: ecat_core::diagnosis::Message) -> bool
    where
        D: ecat_core::dictionary::ObjectDictionary,
    {
        let indication = self.status().indication();
        let register = match (indication.status(), indication.code()) {
            (Some(status), code) => ecat_core::coe::Emergency::error_register(status, code),
            (None, _) => 0,
        };
        let logged = self
            .common
            .app
            .lock(|_, od| od.diagnosis()?.log(message, register));
        if let Some(Some(emergency)) = logged {
            self.raise_emergency(emergency);
        }
        logged.is_some()
    }

    /// The AL status side alone, whatever the application: for the indicator task.
    pub fn status(self) -> Status<'a, P> {
        Status(&self.common.esc)
    }
}
