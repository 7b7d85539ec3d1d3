//! ethercrab, an independent MainDevice, against three sample SubDevices on a line of emulated
//! ESCs (frame level: datagrams, FMMUs, working counters, SII EEPROM), running the real runners:
//! discovery, identity and names from the SII images the core generated, SDO through ethercrab,
//! PREOP → SAFEOP → OP, cyclic LRW with the working counter asserted and the data checked end to
//! end, and a refused transition surfacing its AL status code at the MainDevice.

use ecat_emu::devices;
use ecat_emu::harness::{self, Spawn};
use ecat_emu::master::TestMaster;
use ecat_emu::real_master::{next_cycle, run_on_line, timeouts};
use ethercrab::subdevice_group::{DcConfiguration, Op, PreOp, SafeOp};
use ethercrab::{DcSupport, DcSync, DefaultLock, MainDevice, SubDeviceGroup, Timeouts};

const MAX: usize = 8;
const PDI: usize = 128;

fn three() -> Vec<Box<dyn Spawn>> {
    vec![
        Box::new(devices::drive().device),
        Box::new(devices::dio().device),
        Box::new(devices::sensor().device),
    ]
}

/// PREOP → SAFEOP, then OP while the cyclic frames run: a SubDevice enters OP only after valid
/// outputs (ETG.1000.6 §6.4.3), so ethercrab's `into_op`, which sends none while it waits, is not
/// the way; its `request_into_op` is (ethercrab's documentation says the same).
async fn to_op(
    main: &'static MainDevice<'static>,
    group: SubDeviceGroup<MAX, PDI, DefaultLock, PreOp>,
    masters: &[TestMaster],
) -> SubDeviceGroup<MAX, PDI, DefaultLock, Op> {
    let group = group.into_safe_op(main).await.expect("PREOP → SAFEOP");
    cycle_into_op(main, group, masters).await
}

/// SAFEOP → OP: requests OP, then runs the cycle until every SubDevice is in OP.
async fn cycle_into_op<DC>(
    main: &'static MainDevice<'static>,
    group: SubDeviceGroup<MAX, PDI, DefaultLock, SafeOp, DC>,
    masters: &[TestMaster],
) -> SubDeviceGroup<MAX, PDI, DefaultLock, Op, DC> {
    let group = group.request_into_op(main).await.expect("OP requested");
    for _ in 0..100 {
        let response = group.tx_rx(main).await.expect("cycle");
        next_cycle(masters).await;
        if response.all_op() {
            return group;
        }
    }
    panic!("not all SubDevices reached OP within 100 cycles");
}

/// ethercrab's `name()` is the SII order string (for a Beckhoff EK1100 "EK1100"), its
/// `description()` the SII name string.
#[test]
fn discovery_reads_identity_and_names_from_the_generated_sii() {
    let found = run_on_line(three(), timeouts(), async |main, _| {
        let group: SubDeviceGroup<MAX, PDI, DefaultLock, PreOp> = main
            .init_single_group(|| embassy_time::Instant::now().as_micros() * 1000)
            .await
            .expect("discovery");
        group
            .iter(main)
            .map(|s| {
                let id = s.identity();
                (
                    s.configured_address(),
                    s.name().to_owned(),
                    (id.vendor_id, id.product_id, id.revision, id.serial),
                )
            })
            .collect::<Vec<_>>()
    });
    let id = |i: ecat_core::device::Identity| (i.vendor_id, i.product_code, i.revision, i.serial);
    assert_eq!(
        found,
        vec![
            (0x1000, "ECAT-DRIVE".to_owned(), id(devices::DRIVE_IDENTITY)),
            (0x1001, "ECAT-DIO-16".to_owned(), id(devices::DIO_IDENTITY)),
            (
                0x1002,
                "ECAT-SENSOR".to_owned(),
                id(devices::SENSOR_IDENTITY)
            ),
        ]
    );
}

#[test]
fn three_subdevices_reach_op_and_exchange_10000_cycles() {
    let cycles = 10_000u32;
    let report = run_on_line(three(), timeouts(), async move |main, masters| {
        let group: SubDeviceGroup<MAX, PDI, DefaultLock, PreOp> = main
            .init_single_group(|| embassy_time::Instant::now().as_micros() * 1000)
            .await
            .expect("discovery");
        let drive = group.subdevice(main, 0).unwrap();
        let vendor: u32 = drive.sdo_read(0x1018, 1).await.expect("SDO read 0x1018:01");
        drive
            .sdo_write(0x607A, 0, 1234i32)
            .await
            .expect("SDO write 0x607A");
        let target: i32 = drive.sdo_read(0x607A, 0).await.expect("SDO read 0x607A");
        let group = to_op(main, group, &masters).await;
        let sizes: Vec<(usize, usize)> = group
            .iter(main)
            .map(|s| (s.outputs_raw().len(), s.inputs_raw().len()))
            .collect();
        let mut wrong_wkc = 0;
        let mut last_value = None;
        let mut echo_ok = 0;
        for cycle in 0..cycles {
            let (drive, dio) = (
                group.subdevice(main, 0).unwrap(),
                group.subdevice(main, 1).unwrap(),
            );
            {
                let mut o = drive.outputs_raw_mut();
                o[2..6].copy_from_slice(&(cycle as i32).to_le_bytes());
            }
            dio.outputs_raw_mut()
                .copy_from_slice(&(cycle as u16).to_le_bytes());
            let response = group.tx_rx(main).await.expect("cycle");
            if response.working_counter != 3 + 3 + 1 {
                wrong_wkc += 1;
            }
            next_cycle(&masters).await;
            // The inputs of this frame carry the SubDevices' answer to the previous one.
            let drive_in = drive.inputs_raw();
            let dio_in = dio.inputs_raw();
            let sensor = group.subdevice(main, 2).unwrap();
            let sensor_in = sensor.inputs_raw();
            if cycle > 0 {
                let expected = (cycle - 1) as i32;
                let position = i32::from_le_bytes(drive_in[2..6].try_into().unwrap());
                let io = u16::from_le_bytes(dio_in[..2].try_into().unwrap());
                if position == expected && io == (cycle - 1) as u16 {
                    echo_ok += 1;
                }
            }
            let value = i32::from_le_bytes(sensor_in[..4].try_into().unwrap());
            if let Some(last) = last_value {
                assert!(value > last, "the sensor counts: {last} then {value}");
            }
            last_value = Some(value);
        }
        (vendor, target, sizes, wrong_wkc, echo_ok)
    });
    let (vendor, target, sizes, wrong_wkc, echo_ok) = report;
    assert_eq!(vendor, devices::VENDOR_ID, "SDO upload through ethercrab");
    assert_eq!(target, 1234, "SDO download then upload through ethercrab");
    assert_eq!(
        sizes,
        vec![(11, 11), (2, 2), (0, 6)],
        "(outputs, inputs) per SubDevice"
    );
    assert_eq!(wrong_wkc, 0, "LRW working counter 3 + 3 + 1 every cycle");
    assert_eq!(
        echo_ok,
        cycles - 1,
        "outputs reached the applications, inputs came back"
    );
}

/// Refuses PREOP→SAFEOP as a device whose inputs are misconfigured would.
struct RefuseSafeOp;

impl<D> ecat_embassy::Application<D> for RefuseSafeOp {
    fn on_transition(
        &mut self,
        t: ecat_core::Transition,
    ) -> impl Future<Output = Result<(), ecat_core::AlStatusCode>> + use<D> {
        let answer = match t.to {
            ecat_core::AlState::SafeOp => Err(ecat_core::AlStatusCode::INVALID_INPUT_CONFIG),
            _ => Ok(()),
        };
        async move { answer }
    }
}

#[test]
fn a_refused_transition_surfaces_its_al_status_code_at_the_maindevice() {
    let sample = devices::dio();
    let refusing = harness::Device::new(sample.device.config, RefuseSafeOp, devices::DioLoop)
        .with_dictionary(devices::Dio::default())
        .with_eeprom(sample.eeprom());
    let timeouts = Timeouts {
        state_transition: std::time::Duration::from_millis(200),
        ..timeouts()
    };
    let (result, status, code) =
        run_on_line(vec![Box::new(refusing)], timeouts, async |main, _| {
            let group: SubDeviceGroup<MAX, PDI, DefaultLock, PreOp> = main
                .init_single_group(|| embassy_time::Instant::now().as_micros() * 1000)
                .await
                .expect("discovery");
            let result = group
                .into_safe_op(main)
                .await
                .map(|_| ())
                .map_err(|e| e.to_string());
            let read = |register| ethercrab::Command::fprd(0x1000, register).receive::<u16>(main);
            let status = read(0x0130).await.expect("AL status");
            let code = read(0x0134).await.expect("AL status code");
            (result, status, code)
        });
    assert!(result.is_err(), "ethercrab gives up on SAFEOP");
    assert_eq!(status, 0x0012, "PREOP with the error indication");
    assert_eq!(
        code, 0x001E,
        "invalid input configuration, as the application said"
    );
}

/// A device with an explicit device ID advertises it in its SII General category (flag bit 3,
/// IdentALSts, which ethercrab knows as `IDENT_AL_STATUS`): ethercrab reads the image as any
/// other, and the ID request (AL control bit 5) shows the ID in 0x0134 with AL status bit 5.
#[test]
fn ethercrab_reads_an_image_advertising_an_explicit_device_id() {
    let mut sample = devices::dio();
    sample.device.config.explicit_device_id = true;
    sample.device.device_id = 0x0A5C;
    sample.device.eeprom = sample.eeprom();
    let (status, code) = run_on_line(
        vec![Box::new(sample.device)],
        timeouts(),
        async |main, masters| {
            let _group: SubDeviceGroup<MAX, PDI, DefaultLock, PreOp> = main
                .init_single_group(|| embassy_time::Instant::now().as_micros() * 1000)
                .await
                .expect("discovery");
            ethercrab::Command::fpwr(0x1000, 0x0120)
                .send(main, 0x0022u16)
                .await
                .expect("AL control: PREOP, device ID requested");
            let read = |register| ethercrab::Command::fprd(0x1000, register).receive::<u16>(main);
            let mut status = 0;
            for _ in 0..100 {
                status = read(0x0130).await.expect("AL status");
                if status & 0x20 != 0 {
                    break;
                }
                next_cycle(&masters).await;
            }
            (status, read(0x0134).await.expect("AL status code"))
        },
    );
    assert_eq!((status, code), (0x0022, 0x0A5C));
}

/// A DC-capable drive and sensor (ESCs with 64-bit DC, the emulated chip's default, devices
/// supporting DC SYNC0). Their SII images are written for DC SYNC0: the configuration area turns
/// the ESC's SYNC out unit on, without which no SYNC0 pulse would leave the ESC.
fn dc_line() -> Vec<Box<dyn Spawn>> {
    let (mut drive, mut sensor) = (devices::drive_dc(), devices::sensor_dc());
    drive.device.eeprom = drive.eeprom();
    sensor.device.eeprom = sensor.eeprom();
    vec![Box::new(drive.device), Box::new(sensor.device)]
}

/// ethercrab configures DC SYNC0 the way it does for any DC SubDevice (the ESC's SYNC unit;
/// it never writes 0x1C32:01): the SubDevices follow SYNC0, one cycle per pulse.
#[test]
fn ethercrab_dc_sync0_drives_the_cycle() {
    let (support, sync_in, cycle_ns, counted) =
        run_on_line(dc_line(), timeouts(), async |main, masters| {
            let mut group: SubDeviceGroup<MAX, PDI, DefaultLock, PreOp> = main
                .init_single_group(|| embassy_time::Instant::now().as_micros() * 1000)
                .await
                .expect("discovery");
            let support: Vec<_> = group.iter(main).map(|s| s.dc_support()).collect();
            for mut sub in group.iter_mut(main) {
                sub.set_dc_sync(DcSync::Sync0);
            }
            let group = group.into_pre_op_pdi(main).await.expect("PREOP with PDI");
            let group = group
                .configure_dc_sync(
                    main,
                    DcConfiguration {
                        start_delay: std::time::Duration::from_millis(5),
                        sync0_period: std::time::Duration::from_millis(1),
                        sync0_shift: std::time::Duration::ZERO,
                    },
                )
                .await
                .expect("DC SYNC0 configured");
            let group = group.into_safe_op(main).await.expect("SAFEOP");
            let group = cycle_into_op(main, group, &masters).await;
            let drive = group.subdevice(main, 0).unwrap();
            let sync_in: u16 = drive.sdo_read(0x1C33, 1).await.expect("0x1C33:01");
            let cycle_ns: u32 = drive.sdo_read(0x1C32, 2).await.expect("0x1C32:02");
            let sensor = group.subdevice(main, 1).unwrap();
            let value = |s: &ethercrab::SubDeviceRef<'_, _>| {
                i32::from_le_bytes(s.inputs_raw()[..4].try_into().unwrap())
            };
            group.tx_rx(main).await.expect("cycle");
            let before = value(&sensor);
            for _ in 0..50 {
                next_cycle(&masters).await;
            }
            group.tx_rx(main).await.expect("cycle");
            (support, sync_in, cycle_ns, value(&sensor) - before)
        });
    assert_eq!(support, vec![DcSupport::Bits64, DcSupport::Bits64]);
    assert_eq!(sync_in, 2, "the SubDevice runs DC SYNC0");
    assert_eq!(cycle_ns, 1_000_000, "0x1C32:02 is the SYNC0 cycle");
    assert_eq!(
        counted, 50,
        "one sensor cycle per SYNC0 pulse, none without"
    );
}

/// A SubDevice that falls back to PREOP deactivates SM2 and SM3 over its PDI (0x0807 + 8n bit
/// 0); its ESC then keeps the MainDevice out of their buffers and counts no LRW access to them
/// (ESC datasheet section I, "SyncManager deactivation by the PDI"): the working counter drops
/// by the drive's 3 (read + write) from 7 to 4, which is how a MainDevice detects the fallback.
#[test]
fn a_subdevice_back_in_preop_drops_out_of_the_lrw_working_counter() {
    let counters = run_on_line(three(), timeouts(), async move |main, masters| {
        let group: SubDeviceGroup<MAX, PDI, DefaultLock, PreOp> = main
            .init_single_group(|| embassy_time::Instant::now().as_micros() * 1000)
            .await
            .expect("discovery");
        let group = to_op(main, group, &masters).await;
        let mut counters = std::collections::BTreeMap::<(&str, u16), u32>::new();
        for _ in 0..100 {
            let response = group.tx_rx(main).await.expect("cycle");
            *counters
                .entry(("OP", response.working_counter))
                .or_default() += 1;
            next_cycle(&masters).await;
        }
        // The drive alone goes back to PREOP (a local fallback, or a request for it alone).
        masters[0].write_al_control(0x02);
        masters[0].settle().await;
        assert_eq!(masters[0].al_status(), 0x02, "the drive in PREOP");
        for _ in 0..200 {
            let response = group.tx_rx(main).await.expect("cycle");
            *counters
                .entry(("PREOP", response.working_counter))
                .or_default() += 1;
            next_cycle(&masters).await;
        }
        counters.into_iter().collect::<Vec<_>>()
    });
    assert_eq!(
        counters,
        vec![(("OP", 3 + 3 + 1), 100), (("PREOP", 3 + 1), 200)],
        "(state of the drive, LRW working counter) → cycles"
    );
}
