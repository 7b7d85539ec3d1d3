"""SOEM (through pysoem) against a line of every catalog device served by ecat-virtual-slave.

SOEM is the second independent MainDevice (ethercrab is the first): what it reads, how it
configures the process data and what it records on its error list are its own, so a SubDevice
that passes here passes for a reason that is not ecat's. Run by `.ci/soem`, which starts the
virtual slave on one end of a veth pair and sets ECAT_IFACE to the other end, ECAT_LINE to the
devices in order. The tests run in file order on one MainDevice, as a master's start-up does.
"""

import os
import struct
import time

import pysoem

from conftest import RECEIVE_US, safeop_to_op

LINE = os.environ.get("ECAT_LINE", "cia402,drive,dio,dio-update,sensor").split(",")

VENDOR_ID = 0xE000_0001
PRODUCT_CODES = {
    "cia402": 0x0001_0402,
    "drive": 0x0000_0402,
    "dio": 0x0000_1001,
    "dio-update": 0x0000_1001,  # the dio with a firmware update in BOOT (test_soem_foe.py)
    "sensor": 0x0000_2001,
}
# (output bytes, input bytes) of the default PDO configuration of each device.
IMAGE = {"cia402": (13, 19), "drive": (11, 11), "dio": (2, 2), "dio-update": (2, 2), "sensor": (0, 6)}

# The ESC's reset values as SOEM leaves them (it writes no watchdog registers without
# config_dc): divider 2498 + 2 = 2500 × 40 ns = 100 µs, process-data watchdog 1000 → 100 ms.
WATCHDOG_S = 0.100

AL_STATUS = 0x0130
AL_STATUS_CODE = 0x0134


def u32(data):
    return struct.unpack("<I", data[:4])[0]


def errors(master):
    """SOEM's error list since the last call (SDO aborts, SDO Info and mailbox errors)."""
    return [str(e) for e in master._collect_mailbox_errors()]


def cycle(master, count, period=0.001, check=None):
    """`count` process-data cycles; returns (cycle, working counter) of those that differ from
    the expected (-1: no frame came back within RECEIVE_US)."""
    expected = master.expected_wkc
    bad = []
    for i in range(count):
        if check is not None:
            check(i)
        master.send_processdata()
        wkc = master.receive_processdata(RECEIVE_US)
        if wkc != expected:
            bad.append((i, wkc))
        time.sleep(period)
    return bad


def test_scan_finds_the_line_with_the_identity_of_0x1018(master):
    assert master.config_init() == len(LINE)
    assert len(master.slaves) == len(LINE)
    for name, slave in zip(LINE, master.slaves):
        # From the SII image (SOEM reads the EEPROM's identity words).
        assert (slave.man, slave.id) == (VENDOR_ID, PRODUCT_CODES[name]), name
        # The same from the object dictionary.
        assert u32(slave.sdo_read(0x1018, 1)) == slave.man, name
        assert u32(slave.sdo_read(0x1018, 2)) == slave.id, name
        assert u32(slave.sdo_read(0x1018, 3)) == slave.rev, name
    assert errors(master) == []


def test_the_whole_dictionary_reads_through_sdo_information_without_errors(master):
    errors(master)
    for name, slave in zip(LINE, master.slaves):
        objects = slave.od
        indices = [o.index for o in objects]
        for mandatory in (0x1000, 0x1008, 0x1018, 0x1C00):
            assert mandatory in indices, f"{name}: 0x{mandatory:04X} missing"
        for obj in objects:
            assert obj.name, f"{name}: 0x{obj.index:04X} has no name"
            for entry in obj.entries:  # every subindex 0..max, as SOEM's ecx_readOE asks
                entry.name, entry.data_type, entry.bit_length, entry.obj_access
        assert errors(master) == [], name


def test_complete_access_and_segmented_sdo_both_ways_in_preop(master):
    drive = master.slaves[LINE.index("drive")]
    # Complete access upload of the assignment: SI0 as one byte + one pad byte, then the entries.
    assert drive.sdo_read(0x1C12, 0, ca=True) == bytes([1, 0]) + struct.pack("<H", 0x1600)
    assert drive.sdo_read(0x1600, 0, ca=True)[:2] == bytes([4, 0])
    # The device name: a normal (non-expedited) upload.
    name = drive.sdo_read(0x1008, 0)
    assert name.rstrip(b"\0") == b"ecat sample drive"
    # 0x2000, 128 bytes: more than one message of a 128-byte mailbox carries (112), so SOEM
    # downloads and uploads it in segments.
    pattern = bytes((i * 7 + 3) & 0xFF for i in range(128))
    drive.sdo_write(0x2000, 0, pattern)
    assert drive.sdo_read(0x2000, 0) == pattern
    # Complete access both ways: the mapping written back as it was read (SI0 + four entries).
    mapping = drive.sdo_read(0x1600, 0, ca=True)
    drive.sdo_write(0x1600, 0, mapping, ca=True)
    assert drive.sdo_read(0x1600, 0, ca=True) == mapping
    assert errors(master) == []


def test_an_emergency_reaches_soem(master):
    drive = master.slaves[LINE.index("drive")]
    received = []
    drive.add_emergency_callback(received.append)
    # The sample drive reports the CiA 301 error code written to 0x2001 in an emergency.
    drive.sdo_write(0x2001, 0, struct.pack("<H", 0x5000))
    # SOEM takes the emergency from SM1 while it waits for its next SDO answer.
    assert u32(drive.sdo_read(0x1018, 1)) == VENDOR_ID
    got = [(e.slave_pos, e.error_code, e.error_reg, e.b1, e.w1, e.w2) for e in received]
    assert got == [(LINE.index("drive") + 1, 0x5000, 0x01, 0, 0, 0)]
    errors(master)  # SOEM also lists the emergency as an error of its own kind


def test_config_map_reads_every_pdo_configuration_without_errors(master):
    size = master.config_map()  # reads 0x1C00, 0x1C12/0x1C13 and the mappings; requests SAFEOP
    assert size == sum(sum(IMAGE[name]) for name in LINE)
    for name, slave in zip(LINE, master.slaves):
        assert (len(slave.output), len(slave.input)) == IMAGE[name], name
    assert errors(master) == []


def test_safeop_then_op_with_the_expected_working_counter(master):
    safeop_to_op(master, IMAGE, LINE)
    master.read_state()  # the group check reads the ORed AL status; this reads each SubDevice's
    for name, slave in zip(LINE, master.slaves):
        assert (slave.state, slave.al_status) == (pysoem.OP_STATE, 0), name


def test_thousands_of_cycles_in_op_with_data_through_the_devices(master):
    dio = master.slaves[LINE.index("dio")] if "dio" in LINE else None
    drive = master.slaves[LINE.index("drive")] if "drive" in LINE else None
    seen = []

    def check(i):
        if dio is not None:
            dio.output = struct.pack("<H", i & 0xFFFF)
            seen.append(struct.unpack("<H", bytes(dio.input))[0])
        if drive is not None:
            # controlword, target position, target velocity, mode
            drive.output = struct.pack("<HiiB", 0x000F, i, -i, 8)

    bad = cycle(master, 3000, check=check)
    assert bad == []
    master.read_state()
    for name, slave in zip(LINE, master.slaves):
        assert slave.state == pysoem.OP_STATE, name
    if dio is not None:
        # The dio's inputs are its outputs: every value written comes back, in order, a cycle
        # or two later.
        assert seen[-1] in (2997, 2998), seen[-5:]
        echoed = [v for v in seen if v]
        assert echoed == sorted(echoed)
    if drive is not None:
        status, position, velocity, mode = struct.unpack("<HiiB", bytes(drive.input))
        assert (status, mode) == (0x000F, 8)
        assert velocity == -position and position in (2998, 2999)


def test_process_data_stopped_means_safeop_with_error_0x001b_within_the_watchdog_time(master):
    assert cycle(master, 50) == []  # the watchdog restarts with every output buffer
    start = time.monotonic()
    expired = {}
    while time.monotonic() - start < 5 * WATCHDOG_S:
        master.read_state()
        now = time.monotonic() - start
        for name, slave in zip(LINE, master.slaves):
            if name not in expired and slave.state == pysoem.SAFEOP_STATE | pysoem.STATE_ERROR:
                expired[name] = now
        time.sleep(0.005)
    for name, slave in zip(LINE, master.slaves):
        if IMAGE[name][0]:  # a device with outputs has an SM watchdog
            assert name in expired, f"{name} still in state {slave.state:#x}"
            assert 0.8 * WATCHDOG_S <= expired[name] <= 2 * WATCHDOG_S, (name, expired[name])
            assert slave.al_status == 0x001B, name
        else:
            assert slave.state == pysoem.OP_STATE, name


def test_an_invalid_transition_is_refused_with_0x0011(master):
    slave = master.slaves[LINE.index("dio")]
    # Acknowledge the watchdog error into INIT, then ask INIT -> SAFEOP directly.
    slave.state = pysoem.INIT_STATE | pysoem.STATE_ACK
    slave.write_state()
    assert slave.state_check(pysoem.INIT_STATE, 2_000_000) == pysoem.INIT_STATE
    slave.state = pysoem.SAFEOP_STATE
    slave.write_state()
    slave.state_check(pysoem.INIT_STATE | pysoem.STATE_ERROR, 2_000_000)
    master.read_state()
    assert slave.state == pysoem.INIT_STATE | pysoem.STATE_ERROR
    assert slave.al_status == 0x0011
