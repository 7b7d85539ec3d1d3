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
import pytest

IFACE = os.environ.get("ECAT_IFACE", "")
LINE = os.environ.get("ECAT_LINE", "cia402,drive,dio,sensor").split(",")
CYCLE_NS = 1_000_000
DC_SYNC0 = 0x02  # 0x1C32/0x1C33 SI1: synchronous with SYNC0


@pytest.fixture(scope="module")
def master():
    assert IFACE, "ECAT_IFACE names the MainDevice's interface (run .ci/soem)"
    m = pysoem.Master()
    m.open(IFACE)
    yield m
    m.state = pysoem.INIT_STATE
    m.write_state()
    m.close()


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
        axis.dc_sync(True, CYCLE_NS)

    axis.config_func = setup
    master.config_map()
    assert master.state_check(pysoem.SAFEOP_STATE, 5_000_000) == pysoem.SAFEOP_STATE
    assert axis.sdo_read(0x1C33, 1)[0] == DC_SYNC0
    assert struct.unpack("<I", axis.sdo_read(0x1C32, 2))[0] == CYCLE_NS
    master.send_processdata()
    master.receive_processdata(20_000)
    master.state = pysoem.OP_STATE
    master.write_state()
    for _ in range(500):
        master.send_processdata()
        master.receive_processdata(20_000)
        if master.state_check(pysoem.OP_STATE, 1000) == pysoem.OP_STATE:
            break
        time.sleep(0.001)
    master.read_state()
    states = {name: (hex(s.state), hex(s.al_status)) for name, s in zip(LINE, master.slaves)}
    assert master.state_check(pysoem.OP_STATE, 50_000) == pysoem.OP_STATE, states
    # A PLC sends one frame per SYNC0 cycle, locked to the DC time; this loop runs on a
    # non-real-time Python interpreter, so it sends every half cycle: each SYNC0 cycle then
    # finds new outputs even when the interpreter is late once. A SYNC0 cycle without new
    # outputs counts +3 against the sync error limit (SSC's rule, 0x10F1:02 = 4 by default):
    # two in a row take the axis to SAFEOP with 0x001A, which is what a real drive does.
    bad = 0
    for _ in range(6000):
        master.send_processdata()
        if master.receive_processdata(20_000) != master.expected_wkc:
            bad += 1
        time.sleep(0.0005)
    master.read_state()
    diag = {si: struct.unpack("<H", axis.sdo_read(0x1C32, si)[:2])[0] for si in (0x0B, 0x0C)}
    assert bad == 0, diag
    # Neither the sync error supervision nor the SYNC0 loss supervision fired.
    assert (axis.state, axis.al_status) == (pysoem.OP_STATE, 0), diag
    # The axis ran DC cycles: 0x1C32:0A shows the SYNC0 cycle time it follows.
    assert struct.unpack("<I", axis.sdo_read(0x1C32, 0x0A))[0] == CYCLE_NS
