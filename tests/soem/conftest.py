"""What the SOEM tests share: the MainDevice on ECAT_IFACE and the SAFEOP→OP start-up."""

import os

import pysoem
import pytest

# How long SOEM waits for its process-data frame to come back (µs). Generous: the virtual slave
# shares this machine with the test; a late frame is a failure all the same (-1 working counter).
RECEIVE_US = 20_000


@pytest.fixture(scope="module")
def master():
    """One MainDevice per test module on ECAT_IFACE, left in INIT and closed at the end."""
    iface = os.environ.get("ECAT_IFACE", "")
    assert iface, "ECAT_IFACE names the MainDevice's interface (run .ci/soem)"
    m = pysoem.Master()
    m.open(iface)
    yield m
    m.state = pysoem.INIT_STATE
    m.write_state()
    m.close()


def safeop_to_op(master, image, line):
    """From SAFEOP (after config_map) to OP: checks the LRW's expected working counter for the
    line's `image` (+2 per device with outputs, +1 per device with inputs), then cycles until
    every SubDevice is in OP (SAFEOP→OP completes only once valid outputs arrived)."""
    assert master.state_check(pysoem.SAFEOP_STATE, 5_000_000) == pysoem.SAFEOP_STATE
    outputs = sum(1 for name in line if image[name][0])
    inputs = sum(1 for name in line if image[name][1])
    assert master.expected_wkc == 2 * outputs + inputs
    master.send_processdata()
    master.receive_processdata(RECEIVE_US)
    assert to_op(master)


def to_op(master):
    """Requests OP and cycles until every SubDevice is there (SAFEOP→OP completes only once
    valid outputs arrived); whether they are."""
    master.state = pysoem.OP_STATE
    master.write_state()
    for _ in range(200):
        master.send_processdata()
        master.receive_processdata(RECEIVE_US)
        if master.state_check(pysoem.OP_STATE, 1000) == pysoem.OP_STATE:
            break
    return master.state_check(pysoem.OP_STATE, 50_000) == pysoem.OP_STATE
