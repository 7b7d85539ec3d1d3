"""SOEM against a line in segments: ecat-virtual-slave instances chained with --out/--chained.

Run by `.ci/virtual-slave-chain`, which sets ECAT_SEGMENTS to the devices of each instance in
cable order, segments separated by "|" (e.g. "cia402,cia402|cia402,cia402"). Skipped without it
(`.ci/soem` serves one instance). SOEM must see one line of all the segments' SubDevices: their
number (a BRD's working counter), their identities in cable order (position addressing through
the joint), the DL status of the ESCs at the joint and at the end (ESC datasheet, 0x0110), the
process image and working counter of one line, OP, and cycles with every frame back in time.
"""

import os
import struct
import time

import pysoem
import pytest

from test_soem import IMAGE, PRODUCT_CODES, RECEIVE_US, VENDOR_ID

IFACE = os.environ.get("ECAT_IFACE", "")
SEGMENTS = [s.split(",") for s in os.environ.get("ECAT_SEGMENTS", "").split("|") if s]

pytestmark = pytest.mark.skipif(not SEGMENTS, reason="ECAT_SEGMENTS names a chain's segments")

DL_STATUS = 0x0110
# Bits 0, 1 PDI operational and watchdog; 4, 5 link on ports 0, 1; 9, 11 communication on
# ports 0, 1; 12, 14 loops of ports 2, 3 closed: port 1 leads on (to the next ESC, in this
# segment or the next one).
PORT_1_OPEN = 0x5A33
# Bit 10: the loop of port 1 closed, no link there: the end of the line.
PORT_1_CLOSED = 0x5613


LINE = [name for segment in SEGMENTS for name in segment]
CYCLES = int(os.environ.get("ECAT_CYCLES", "2000"))


@pytest.fixture(scope="module")
def master():
    assert IFACE, "ECAT_IFACE names the MainDevice's interface (run .ci/virtual-slave-chain)"
    m = pysoem.Master()
    m.open(IFACE)
    yield m
    m.state = pysoem.INIT_STATE
    m.write_state()
    m.close()


def test_the_segments_are_one_line_in_cable_order(master):
    # config_init counts the SubDevices by a BRD's working counter, then addresses them by
    # position (APWR) and reads their SII: all through every segment.
    assert master.config_init() == len(LINE)
    for name, slave in zip(LINE, master.slaves):
        assert (slave.man, slave.id) == (VENDOR_ID, PRODUCT_CODES[name]), name


def test_only_the_last_esc_of_the_line_closes_port_1(master):
    status = [struct.unpack("<H", s._fprd(DL_STATUS, 2, RECEIVE_US))[0] for s in master.slaves]
    expected = [PORT_1_OPEN] * (len(LINE) - 1) + [PORT_1_CLOSED]
    assert [hex(s) for s in status] == [hex(s) for s in expected]


def test_op_and_cycles_with_the_working_counter_of_one_line(master):
    assert master.config_map() == sum(sum(IMAGE[name]) for name in LINE)
    assert master.state_check(pysoem.SAFEOP_STATE, 5_000_000) == pysoem.SAFEOP_STATE
    outputs = sum(1 for name in LINE if IMAGE[name][0])
    inputs = sum(1 for name in LINE if IMAGE[name][1])
    # LRW: +2 per device whose outputs it writes, +1 per device whose inputs it reads.
    assert master.expected_wkc == 2 * outputs + inputs
    master.send_processdata()
    master.receive_processdata(RECEIVE_US)
    master.state = pysoem.OP_STATE
    master.write_state()
    for _ in range(200):  # SAFEOP→OP completes only once valid outputs arrived
        master.send_processdata()
        master.receive_processdata(RECEIVE_US)
        if master.state_check(pysoem.OP_STATE, 1000) == pysoem.OP_STATE:
            break
    assert master.state_check(pysoem.OP_STATE, 50_000) == pysoem.OP_STATE
    bad = []
    for i in range(CYCLES):
        master.send_processdata()
        wkc = master.receive_processdata(RECEIVE_US)
        if wkc != master.expected_wkc:
            bad.append((i, wkc))
        time.sleep(0.001)
    assert bad == []
    master.read_state()
    for name, slave in zip(LINE, master.slaves):
        assert slave.state == pysoem.OP_STATE, name
