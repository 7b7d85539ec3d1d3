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

from conftest import RECEIVE_US, safeop_to_op
from test_soem import IMAGE, PRODUCT_CODES, VENDOR_ID

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
    safeop_to_op(master, IMAGE, LINE)
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
