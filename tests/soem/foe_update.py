"""A firmware update with SOEM (pysoem), as SOEM's firm_update tool makes it, then the device's
restart into the new image: what `examples/host/foe-update.sh` runs against the virtual axis;
test_soem_foe.py uses its steps.

    python foe_update.py IFACE FILE

Scans the line on IFACE and updates its first SubDevice with FILE (an update file, as
`ecat-firmware` writes it): INIT, SM0/SM1 moved to the bootstrap mailbox its SII describes
(words 0x14..0x17), BOOT, FILE written as firmware.bin (password 0x16) with foe_write, INIT.
Taken out of BOOT with a verified image, the device marks it for its bootloader and restarts;
the line is scanned again until the device is back with another revision. Then PREOP (where the
new image confirms itself), 0x1018:03 over SDO, SAFEOP and OP with process data. Prints the
revision before and after; exit status 1 when it is not the version the file's image carries.
"""

import os
import struct
import sys
import time

import pysoem

from conftest import RECEIVE_US, to_op

FILE_NAME = "firmware.bin"
PASSWORD = 0x16
TIMEOUT_US = 2_000_000
# The SII words of the bootstrap mailbox: receive offset/size (0x14), send offset/size (0x16).
SII_BOOT_RECEIVE = 0x14
SII_BOOT_SEND = 0x16
# The update file's header: magic, the image's length and CRC-32; the image follows.
HEADER = 12
# How long a restart may take: the bootloader's swap, the new image's start.
RESTART_S = 10.0


def to_state(slave, state):
    slave.state = state
    slave.write_state()
    assert slave.state_check(state, TIMEOUT_US) == state


def bootstrap_mailbox(slave):
    receive = struct.unpack("<HH", slave.eeprom_read(SII_BOOT_RECEIVE))
    send = struct.unpack("<HH", slave.eeprom_read(SII_BOOT_SEND))
    return receive, send


def to_boot(slave):
    """INIT, the bootstrap mailbox, BOOT (SOEM's firm_update)."""
    to_state(slave, pysoem.INIT_STATE)
    (rx_start, rx_len), (tx_start, tx_len) = bootstrap_mailbox(slave)
    slave.amend_mbx("out", rx_start, rx_len)
    slave.amend_mbx("in", tx_start, tx_len)
    to_state(slave, pysoem.BOOT_STATE)


def leave_boot(slave):
    """INIT, without waiting for it: a device with a new image restarts at once (its ESC too:
    the station address SOEM would ask it at is gone)."""
    slave.state = pysoem.INIT_STATE
    slave.write_state()


def rescan(master, count, position, before):
    """Scans the line until its `count` devices answer and the one at `position` reports a
    revision (SII) other than `before`; that device, or None after RESTART_S."""
    deadline = time.monotonic() + RESTART_S
    while time.monotonic() < deadline:
        if master.config_init() == count and master.slaves[position].rev != before:
            return master.slaves[position]
        time.sleep(0.1)
    return None


def revision_over_sdo(slave):
    return struct.unpack("<I", slave.sdo_read(0x1018, 3))[0]


def revisions(slave):
    """The revision the SII and 0x1018:03 give, and in words with the device's name (0x1008)."""
    sii, sdo = slave.rev, revision_over_sdo(slave)
    where = "SII and 0x1018:03" if sii == sdo else f"SII; 0x1018:03: {sdo}"
    name = slave.sdo_read(0x1008, 0).rstrip(b"\0").decode()
    return (sii, sdo), f"{name}, revision {sii} ({where})"


def run_op(master, cycles=100):
    """SAFEOP with the process data mapped, OP, then `cycles` cycles of 1 ms: whether the line
    reached OP, and how many cycles came back with a working counter other than the expected."""
    master.config_map()
    if not to_op(master):
        return False, cycles
    missed = 0
    for _ in range(cycles):
        master.send_processdata()
        missed += master.receive_processdata(RECEIVE_US) != master.expected_wkc
        time.sleep(0.001)
    return True, missed


def main(iface, path):
    with open(path, "rb") as f:
        data = f.read()
    version = struct.unpack("<I", data[HEADER:HEADER + 4])[0]
    name = os.path.basename(path)
    master = pysoem.Master()
    master.open(iface)
    try:
        count = master.config_init()
        if count < 1:
            print(f"no SubDevice on {iface}")
            return 1
        slave = master.slaves[0]
        (before, _), text = revisions(slave)
        print(f"before: {text}")
        to_boot(slave)
        start = time.monotonic()
        if slave.foe_write(FILE_NAME, PASSWORD, data, TIMEOUT_US) <= 0:
            print(f"BOOT: foe_write of {name} failed")
            return 1
        took = time.monotonic() - start
        print(f"BOOT: {name} ({len(data)} bytes) written as {FILE_NAME} by FoE in {took:.2f} s")
        leave_boot(slave)
        start = time.monotonic()
        slave = rescan(master, count, 0, before)
        if slave is None:
            print(f"INIT: the device did not come back with another revision in {RESTART_S} s")
            return 1
        print(f"INIT: the device restarted into the new image (found again after "
              f"{time.monotonic() - start:.2f} s)")
        after, text = revisions(slave)
        in_op, missed = run_op(master)
        print(f"after: {text}; " + (f"OP, {missed} of 100 cycles with a wrong working counter"
                                    if in_op else "not in OP"))
        if after != (version, version) or not in_op or missed:
            print(f"expected: revision {version} (the file's image) in OP")
            return 1
        return 0
    finally:
        master.state = pysoem.INIT_STATE
        master.write_state()
        master.close()


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
