//! `pd <case> <n>`: `n` process-data cycles through the core (unpack the outputs into the
//! dictionary, an application stub, pack the inputs), run under callgrind by
//! `bench/callgrind.sh`.
//!
//! Cases: `cia402` (RxPDO 0x6040 u16, 0x607A i32, 0x60FF i32, 0x6060 i8; TxPDO 0x6041 u16,
//! 0x6064 i32, 0x606C i32, 0x6061 i8: 11 + 11 bytes), `cia402-remapped` (the same entries
//! in another order, as a MainDevice may configure them), `io64` (64 bytes each way as 16 × u32),
//! `axis` (the `ecat-axis` dummy drive, enabled in CSV at 5 000 counts/s: its 13 + 19 bytes and
//! one `Axis::step`, the CiA 402 state machine and the simulated motor), and the axis in its
//! profile modes through the same image: `axis-pp` (profile position towards 10 000 000 counts at
//! 0x6081 = 100 000 counts/s: the trajectory generator's braking-distance check every cycle),
//! `axis-pv` (profile velocity to 50 000 counts/s: 50 cycles of ramp, then cruising), `axis-hm`
//! (homing method 1, searching the negative limit 100 000 counts away at 50 000 counts/s).

use ecat_axis::{Axis, AxisOd};
use ecat_core::pdo::image::{pack, unpack};
use ecat_core::pdo::layout::Layout;
use ecat_core::pdo::{Direction, MappingEntry, PdoAssignment, PdoMapping};
use ecat_emu::devices::{DRIVE_RX, DRIVE_TX, Drive};

struct Io {
    outputs: [u32; 16],
    inputs: [u32; 16],
    rx: PdoMapping<16>,
    tx: PdoMapping<16>,
    rx_assign: PdoAssignment<1>,
    tx_assign: PdoAssignment<1>,
}

const fn io_mapping(index: u16) -> [MappingEntry; 16] {
    let mut out = [MappingEntry(0); 16];
    let mut i = 0;
    while i < 16 {
        out[i] = MappingEntry::new(index, i as u8 + 1, 32);
        i += 1;
    }
    out
}

const IO_RX: [MappingEntry; 16] = io_mapping(0x7000);
const IO_TX: [MappingEntry; 16] = io_mapping(0x6000);

ecat_core::dictionary! {
    // The copy of 64 entries alone: no communication area.
    minimal Io {
        0x1600 => pdo(rx, RW_PREOP, "RxPDO", "Entry", default = PdoMapping::mapping(&IO_RX));
        0x1A00 => pdo(tx, RW_PREOP, "TxPDO", "Entry", default = PdoMapping::mapping(&IO_TX));
        0x1C12 => pdo(rx_assign, RW_PREOP, "SM2 assignment", "PDO", default = PdoAssignment::assignment(&[0x1600]));
        0x1C13 => pdo(tx_assign, RW_PREOP, "SM3 assignment", "PDO", default = PdoAssignment::assignment(&[0x1A00]));
        0x6000 => array(inputs, RO | TXPDO, "Inputs", "Input");
        0x7000 => array(outputs, RW | RXPDO, "Outputs", "Output");
    }
}

/// `n` cycles: `outputs(i, image)` writes cycle `i`'s outputs (the image starts as 0x5A bytes),
/// then unpack, `app`, pack.
fn cycles<D: ecat_core::dictionary::ObjectDictionary>(
    od: &mut D,
    n: usize,
    outputs_of: impl Fn(usize, &mut [u8]),
    mut app: impl FnMut(&mut D),
) {
    let rx = Layout::of(od, Direction::Rx)
        .ok()
        .flatten()
        .expect("RxPDO layout");
    let tx = Layout::of(od, Direction::Tx)
        .ok()
        .flatten()
        .expect("TxPDO layout");
    let mut outputs = vec![0x5Au8; usize::from(rx.bytes())];
    let mut inputs = vec![0u8; usize::from(tx.bytes())];
    for i in 0..n {
        outputs_of(i, &mut outputs);
        unpack(&rx, std::hint::black_box(&outputs), od);
        app(od);
        pack(&tx, od, &mut inputs);
        std::hint::black_box(&inputs);
    }
}

/// The CiA402-like application stub: the set-points back as actual values.
fn echo(d: &mut Drive) {
    d.statusword = d.controlword;
    d.position = d.target_position;
    d.velocity = d.target_velocity;
    d.mode_display = d.mode;
}

/// The first output byte is the cycle number.
fn vary_first_byte(i: usize, outputs: &mut [u8]) {
    outputs[0] = i as u8;
}

fn main() {
    let mut args = std::env::args().skip(1);
    let case = args.next().unwrap_or_else(|| "cia402".into());
    let n = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    match case.as_str() {
        "cia402" => cycles(&mut <Drive>::default(), n, vary_first_byte, echo),
        "cia402-remapped" => {
            let mut od = Drive {
                rx1: PdoMapping::mapping(&[DRIVE_RX[3], DRIVE_RX[2], DRIVE_RX[1], DRIVE_RX[0]]),
                tx1: PdoMapping::mapping(&[DRIVE_TX[1], DRIVE_TX[0], DRIVE_TX[3], DRIVE_TX[2]]),
                ..<Drive>::default()
            };
            cycles(&mut od, n, vary_first_byte, echo)
        }
        "io64" => cycles(&mut Io::default(), n, vary_first_byte, |d| {
            d.inputs = d.outputs
        }),
        "axis" | "axis-pp" | "axis-pv" | "axis-hm" => {
            let (mut axis, mut od) = (Axis::new(), AxisOd::default());
            od.homing_method = 1;
            for controlword in [0x00, 0x06] {
                od.controlword = controlword;
                axis.step(&mut od);
            }
            // Controlword, target position, target velocity, torque 0, mode.
            let image: [u8; 13] = match case.as_str() {
                // 0x000F, 0, 5 000 counts/s, CSV.
                "axis" => [0x0F, 0, 0, 0, 0, 0, 0x88, 0x13, 0, 0, 0, 0, 9],
                // 0x001F (new set-point), 10 000 000 counts, PP.
                "axis-pp" => [0x1F, 0, 0x80, 0x96, 0x98, 0, 0, 0, 0, 0, 0, 0, 1],
                // 0x000F, 50 000 counts/s, PV.
                "axis-pv" => [0x0F, 0, 0, 0, 0, 0, 0x50, 0xC3, 0, 0, 0, 0, 3],
                // 0x001F (homing start), HM.
                _ => [0x1F, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 6],
            };
            cycles(
                &mut od,
                n,
                |_, out| out.copy_from_slice(&image),
                |od| axis.step(od),
            );
        }
        other => panic!("unknown case {other}"),
    }
}
