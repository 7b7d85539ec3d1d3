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
    assert master.state_check(pysoem.OP_STATE, 50_000) == pysoem.OP_STATE
    bad = 0
    for _ in range(3000):
        master.send_processdata()
        if master.receive_processdata(20_000) != master.expected_wkc:
            bad += 1
        time.sleep(0.001)
    assert bad == 0
    master.read_state()
    assert axis.state == pysoem.OP_STATE
    # The SYNC0 loss supervision did not fire: the axis saw SYNC0 pulses every cycle.
    assert axis.al_status == 0
