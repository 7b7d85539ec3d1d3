"""SOEM with distributed clocks: config_dc finds the ESCs' DC units, the axis runs DC SYNC0 at 1 ms.

A fresh MainDevice after test_soem.py's (which leaves the line in INIT): SOEM's own DC start-up
(ecx_configdc: receive-time latch, offsets, delays) and SYNC0 activation (ecx_dcsync0) in the
PREOP→SAFEOP hook, as SOEM's examples do it; the axis follows the ESC's SYNC0 activation because
SOEM writes no 0x1C32:01 (the SSC behaviour).
"""

import os
import struct
import time

import pysoem

LINE = os.environ.get("ECAT_LINE", "cia402,drive,dio,dio-update,sensor").split(",")
CYCLE_NS = 1_000_000
DC_SYNC0 = 0x02  # 0x1C32/0x1C33 SI1: synchronous with SYNC0
SYNC_ERROR_LIMIT = 60  # 0x10F1:02: 20 missed SYNC0 cycles in a row


def test_config_dc_finds_every_esc_with_a_dc_unit(master):
    assert master.config_init() == len(LINE)
    assert master.config_dc()
    for slave in master.slaves:
        # SOEM reads the feature register 0x0008 (bit 2: DC) into hasdc; the DC system time of
        # every ESC must be running after config_dc.
        time0 = struct.unpack("<Q", slave._fprd(0x0910, 8))[0]
        time.sleep(0.01)
        time1 = struct.unpack("<Q", slave._fprd(0x0910, 8))[0]
        assert time1 > time0


def test_the_axis_reaches_op_in_dc_mode_and_runs_thousands_of_cycles(master):
    axis = master.slaves[LINE.index("cia402")]

    def setup(slave_pos):
        # A PLC sends one frame per SYNC0 cycle, locked to the DC time. This MainDevice is a
        # Python loop on a shared, non-real-time machine: its frames come late now and then,
        # and each SYNC0 cycle without new outputs adds 3 to the sync error counter (SSC's
        # rule; at the default limit 4 two in a row end OP with 0x001A, as a real drive does
        # with a real PLC that misses frames: tests/tests/sync_error.rs checks that exactly).
        # Like a TwinCAT start-up list, the set-up writes the limit 0x10F1:02: a late frame now
        # and then is tolerated, a MainDevice that stops is not.
        axis.sdo_write(0x10F1, 2, struct.pack("<H", SYNC_ERROR_LIMIT))
        axis.dc_sync(True, CYCLE_NS)

    axis.config_func = setup
    master.config_map()
    assert master.state_check(pysoem.SAFEOP_STATE, 5_000_000) == pysoem.SAFEOP_STATE
    assert axis.sdo_read(0x1C33, 1)[0] == DC_SYNC0
    assert struct.unpack("<I", axis.sdo_read(0x1C32, 2))[0] == CYCLE_NS
    # Every half cycle, on a schedule (not a sleep after each exchange, which would add the
    # round trip to the period): most SYNC0 cycles find new outputs even when the interpreter
    # is late once.
    def run(cycles):
        bad = 0
        next_frame = time.monotonic()
        for _ in range(cycles):
            master.send_processdata()
            if master.receive_processdata(20_000) != master.expected_wkc:
                bad += 1
            next_frame += CYCLE_NS / 2e9
            time.sleep(max(0.0, next_frame - time.monotonic()))
        return bad

    run(10)
    master.state = pysoem.OP_STATE
    master.write_state()
    for _ in range(100):
        run(10)
        if master.read_state() == pysoem.OP_STATE:
            break
    master.read_state()
    states = {name: (hex(s.state), hex(s.al_status)) for name, s in zip(LINE, master.slaves)}
    assert all(s.state == pysoem.OP_STATE for s in master.slaves), states
    bad = run(6000)
    master.read_state()
    diag = {si: struct.unpack("<H", axis.sdo_read(0x1C32, si)[:2])[0] for si in (0x0B, 0x0C)}
    assert bad == 0, diag
    # Neither the sync error supervision nor the SYNC0 loss supervision fired; SYNC0 cycles
    # never overran (0x1C32:0C: the line delivers each pulse at its time).
    assert (axis.state, axis.al_status) == (pysoem.OP_STATE, 0), diag
    assert diag[0x0C] == 0, diag
    # The axis ran DC cycles: 0x1C32:0A shows the SYNC0 cycle time it follows.
    assert struct.unpack("<I", axis.sdo_read(0x1C32, 0x0A))[0] == CYCLE_NS


def test_a_sync_error_is_an_emergency_and_the_newest_diagnosis_message(master):
    """The MainDevice stops sending frames with the axis in OP in DC mode and the sync error
    counter limit low: the axis leaves OP with 0x001A (ETG.1020 §6.3), raises emergency 0x8700
    (error register 0x11, the AL status code in the data) and logs the code as the newest
    message of its diagnosis history 0x10F3 (ETG.1020 §13), read subindex by subindex as SOEM
    reads it (ec_SDOread)."""
    axis = master.slaves[LINE.index("cia402")]
    received = []
    axis.add_emergency_callback(received.append)
    # Limit 4: two SYNC0 cycles in a row without new outputs (3, 6). No frame is sent from
    # here on but mailbox ones: the next SYNC0 cycles trip the supervision.
    axis.sdo_write(0x10F1, 2, struct.pack("<H", 4))
    time.sleep(0.05)
    master.read_state()
    assert (axis.state, axis.al_status) == (pysoem.SAFEOP_STATE | pysoem.STATE_ERROR, 0x001A)
    newest = axis.sdo_read(0x10F3, 2)[0]
    assert 6 <= newest <= 6 + axis.sdo_read(0x10F3, 1)[0] - 1
    code, flags, text_id, _ns = struct.unpack("<IHHQ", axis.sdo_read(0x10F3, newest)[:16])
    # Diag code 0xE000, an error (type 2) with a local timestamp (bit 4), text ID 0x001A.
    assert (code, flags, text_id) == (0xE000, 0x0012, 0x001A)
    assert axis.sdo_read(0x10F3, 4) == b"\x01"
    got = [(e.error_code, e.error_reg, e.b1, e.w1, e.w2) for e in received]
    assert (0x8700, 0x11, 0x1A, 0, 0) in got, got
