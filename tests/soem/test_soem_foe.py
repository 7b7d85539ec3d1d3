"""SOEM's FoE (pysoem foe_write, foe_read) against the virtual slave's dio-update: a firmware
update in BOOT as SOEM's firm_update tool makes it (the steps of foe_update.py), and the
device's restart into the new image.

INIT, SM0/SM1 moved to the bootstrap mailbox the SII describes (words 0x14..0x17), BOOT, the
update file written (`ecat_emu::update`: a 12-byte header, magic ECFW, the image's length and
CRC-32, then the image). The device streamed the image into the DFU partition of its flash and
verified it; reading the file back in BOOT gives the image as the flash holds it, and a wrong
password writes nothing. Leaving BOOT marks the image for the bootloader and restarts the
device: a new scan finds it with the image's version as its revision, the rest of the line as
it was.
"""

import os
import struct
import zlib

from foe_update import FILE_NAME, PASSWORD, TIMEOUT_US, bootstrap_mailbox, leave_boot, rescan
from foe_update import revision_over_sdo, to_boot, to_state
import pysoem

LINE = os.environ.get("ECAT_LINE", "cia402,drive,dio,dio-update,sensor").split(",")


def update_file(image):
    return b"ECFW" + struct.pack("<II", len(image), zlib.crc32(image)) + image


def image(version, length):
    """A host image: its version, then bytes that differ from version to version."""
    body = bytes((i * 31 + version * 7 + i // 251) & 0xFF for i in range(length - 4))
    return struct.pack("<I", version) + body


def test_the_sii_of_the_updatable_devices_describes_the_bootstrap_mailbox(master):
    assert master.config_init() == len(LINE)
    for name in ("cia402", "dio-update"):
        slave = master.slaves[LINE.index(name)]
        assert bootstrap_mailbox(slave) == ((0x1800, 256), (0x1900, 256)), name


def test_foe_write_in_boot_reads_back_and_a_wrong_password_writes_nothing(master):
    slave = master.slaves[LINE.index("dio-update")]
    new = image(2, 20_000)  # 82 segments of 244 bytes
    to_boot(slave)
    assert slave.foe_write(FILE_NAME, PASSWORD, update_file(new), TIMEOUT_US) > 0
    assert slave.foe_read(FILE_NAME, PASSWORD, 65_536, TIMEOUT_US) == new
    assert slave.foe_write(FILE_NAME, PASSWORD + 1, update_file(image(3, 1_000)), TIMEOUT_US) <= 0
    assert slave.foe_read(FILE_NAME, PASSWORD, 65_536, TIMEOUT_US) == new


def test_leaving_boot_restarts_the_device_into_the_new_image(master):
    position = LINE.index("dio-update")
    identities = [(s.id, s.rev) for s in master.slaves]
    leave_boot(master.slaves[position])
    slave = rescan(master, len(LINE), position, 1)
    assert slave is not None, "no restart"
    assert slave.rev == 2
    assert revision_over_sdo(slave) == 2
    identities[position] = (slave.id, 2)
    assert [(s.id, s.rev) for s in master.slaves] == identities
    to_state(slave, pysoem.INIT_STATE)
