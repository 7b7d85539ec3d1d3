//! A SubDevice in PREOP over a plain-memory register file, and the MainDevice side of one
//! mailbox exchange: what the benchmarks run, so that what they count is the core's work (the
//! "PDI" is a `memcpy`).

use ecat_core::coe::AbortCode;
use ecat_core::device::Identity;
use ecat_core::device::{MailboxConfig, ProcessDataSizes};
use ecat_core::dictionary::{
    Communication, DeviceInfo, Domain, ObjectDictionary, ObjectHooks, VisibleString,
};
use ecat_core::mailbox::Handlers;
use ecat_core::{
    AlEvent, AlState, DeviceConfig, Instant, RegisterAccess, SubDevice, Transition, register,
};

/// The benchmark device: `MBX`-byte mailboxes at 0x1000, no process data.
pub const fn device(mailbox: u16) -> DeviceConfig {
    DeviceConfig::new(
        MailboxConfig::contiguous(0x1000, mailbox),
        ProcessDataSizes {
            outputs: 0,
            inputs: 0,
        },
    )
}

/// 0x1018.
pub const IDENTITY: Identity = Identity {
    vendor_id: 0xE000_0001,
    product_code: 0x0000_0402,
    revision: 1,
    serial: 0x1234_5678,
};

/// The communication area of the benchmark device.
pub const INFO: DeviceInfo = DeviceInfo {
    device_type: 0x0002_0192,
    name: "ecat bench",
    hardware_version: "1",
    software_version: "1",
    identity: IDENTITY,
};

/// The benchmark dictionary: the communication area and a 1 KiB string.
pub struct Od {
    /// The communication area (0x1018 is the expedited upload's object).
    pub area: Communication,
    /// 0x2000, 1 KiB.
    pub text: VisibleString<1024>,
    /// 0x2001, streamed to [`Sink`].
    pub blob: Domain,
}

ecat_core::dictionary! {
    // No process data: no PDO assignments.
    minimal Od {
        communication(area, INFO);
        0x2000 => var(text, RW, "Text");
        0x2001 => var(blob, RW, "Blob");
    }
}

/// Application hooks that take DOMAIN downloads and count the bytes.
#[derive(Default)]
pub struct Sink {
    /// Bytes received.
    pub bytes: usize,
}

impl ObjectHooks<Od> for Sink {
    fn domain_write(
        &mut self,
        _: u16,
        _: u8,
        _: u32,
        data: &[u8],
        _: bool,
    ) -> Result<(), AbortCode> {
        self.bytes += data.len();
        Ok(())
    }
}

/// The ESC as plain memory.
pub struct Bench<'c, const MBX: usize> {
    /// The SubDevice.
    pub sub: SubDevice<'c, MBX>,
    /// Registers and process RAM.
    pub mem: Vec<u8>,
    /// The pending AL event bits.
    pub event: u32,
    mailbox: u16,
    counter: u8,
}

impl<'c, const MBX: usize> Bench<'c, MBX> {
    /// A SubDevice in PREOP.
    pub fn new(config: &'c DeviceConfig) -> Self {
        let mailbox = config.mailbox.receive.length;
        let mut bench = Self {
            sub: SubDevice::new::<()>(config),
            mem: vec![0; 0x1_0000],
            event: 0,
            mailbox,
            counter: 0,
        };
        bench.drive();
        let sm = |start: u16, control: u8| {
            let [s0, s1] = start.to_le_bytes();
            let [l0, l1] = mailbox.to_le_bytes();
            [s0, s1, l0, l1, control, 0, 1, 0]
        };
        put(
            &mut bench.mem,
            register::sync_manager(0),
            &sm(config.mailbox.receive.start, 0x26),
        );
        put(
            &mut bench.mem,
            register::sync_manager(1),
            &sm(config.mailbox.send.start, 0x22),
        );
        put(&mut bench.mem, register::AL_CONTROL, &[2, 0]);
        bench.sub.handle_al_event(AlEvent(0x11));
        bench.drive();
        bench.sub.complete_transition(
            Transition {
                from: AlState::Init,
                to: AlState::PreOp,
            },
            Ok(()),
        );
        bench.drive();
        assert_eq!(bench.sub.state(), AlState::PreOp);
        bench
    }

    /// Performs every access the core asks for.
    pub fn drive(&mut self) {
        while let Some(access) = self.sub.poll_access() {
            let event = AlEvent(self.event);
            match access {
                RegisterAccess::Read { address, buf, .. } => {
                    let a = usize::from(address);
                    buf.copy_from_slice(&self.mem[a..a + buf.len()]);
                }
                RegisterAccess::Write { address, data, .. } => put(&mut self.mem, address, data),
                RegisterAccess::Send {
                    address,
                    data,
                    last,
                    ..
                } => {
                    put(&mut self.mem, address, data);
                    if let Some(last) = last {
                        self.mem[usize::from(last)] = 0;
                    }
                }
            }
            self.sub.access_done(Instant::from_micros(0), event);
        }
    }

    /// One mailbox round trip: the MainDevice writes a CoE `payload` into SM0, the SubDevice
    /// reads it, serves it and writes SM1 ([`Bench::serve`]), the MainDevice reads SM1. Returns
    /// the answer's mailbox data (CoE header on).
    pub fn exchange<D: ObjectDictionary, H: ObjectHooks<D>>(
        &mut self,
        od: &mut D,
        hooks: &mut H,
        payload: &[u8],
    ) -> &[u8] {
        self.exchange_with(od, hooks, &mut (), COE, payload)
    }

    /// [`Bench::exchange`] for a message of the mailbox type `kind` (4 bits), served by CoE or
    /// one of `handlers` (the mailbox protocols beside CoE, e.g. `(Foe::new(files),)`).
    pub fn exchange_with<D: ObjectDictionary, H: ObjectHooks<D>, P: Handlers>(
        &mut self,
        od: &mut D,
        hooks: &mut H,
        handlers: &mut P,
        kind: u8,
        payload: &[u8],
    ) -> &[u8] {
        self.counter = self.counter % 7 + 1;
        let len = payload.len() as u16;
        let [l0, l1] = len.to_le_bytes();
        put(
            &mut self.mem,
            0x1000,
            &[l0, l1, 0, 0, 0, (self.counter << 4) | kind],
        );
        put(&mut self.mem, 0x1006, payload);
        self.serve(od, hooks, handlers);
        let send = 0x1000 + usize::from(self.mailbox);
        let length = usize::from(u16::from_le_bytes([self.mem[send], self.mem[send + 1]]));
        &self.mem[send + 6..send + 6 + length]
    }

    /// The SubDevice's side of one exchange, what the firmware does: the AL event of the
    /// request, the accesses the core asks for (performed by the memory driver) and the mailbox
    /// service. Out of line so that `bench/callgrind.sh` can count it alone
    /// (`--toggle-collect`), the figure comparable to a SubDevice stack's own count.
    #[inline(never)]
    pub fn serve<D: ObjectDictionary, H: ObjectHooks<D>, P: Handlers>(
        &mut self,
        od: &mut D,
        hooks: &mut H,
        handlers: &mut P,
    ) {
        // The MainDevice read the previous answer: SM1's read event is latched in the AL event
        // register and arrives with the SM0 event of this request, as in the real rhythm.
        self.sub
            .handle_al_event(AlEvent::sync_manager(0) | AlEvent::sync_manager(1));
        // What the state-machine runner does after an AL event (`run_esm`): the process-data
        // configuration refreshed, the accesses, the mailbox served until it has nothing more.
        self.sub.refresh_process_data(od);
        self.drive();
        while self
            .sub
            .service_mailbox_with(Instant::from_micros(0), od, hooks, handlers)
        {
            self.drive();
        }
    }
}

/// The mailbox type of CoE (ETG.1000.4 Table 29).
pub const COE: u8 = 3;
/// The mailbox type of FoE.
pub const FOE: u8 = 4;

/// Writes `data` into the register file `mem` at `address`.
#[inline]
fn put(mem: &mut [u8], address: u16, data: &[u8]) {
    let a = usize::from(address);
    mem[a..a + data.len()].copy_from_slice(data);
}
