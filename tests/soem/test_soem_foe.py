"""SOEM's FoE (pysoem foe_write, foe_read) against the virtual slave's dio-update: a firmware
update in BOOT as SOEM's firm_update tool makes it.

INIT, SM0/SM1 moved to the bootstrap mailbox the SII describes (words 0x14..0x17), BOOT, the
update file written (`ecat_emu::update`: a 12-byte header, magic ECFW, the image's length and
CRC-32, then the image), INIT. The device streamed the image into the DFU partition of its
flash, verified it and marked it for the bootloader on leaving BOOT; reading the file back in
BOOT gives the image as the flash holds it. A wrong password writes nothing.
"""

import os
import struct
import zlib

import pysoem

LINE = os.environ.get("ECAT_LINE", "cia402,drive,dio,dio-update,sensor").split(",")
FILE_NAME = "firmware.bin"
PASSWORD = 0x16
TIMEOUT_US = 2_000_000
# The SII words of the bootstrap mailbox: receive offset/size (0x14), send offset/size (0x16).
SII_BOOT_RECEIVE = 0x14
SII_BOOT_SEND = 0x16


def update_file(image):
    return b"ECFW" + struct.pack("<II", len(image), zlib.crc32(image)) + image


def image(version, length):
    """A host image: its version, then bytes that differ from version to version."""
    body = bytes((i * 31 + version * 7 + i // 251) & 0xFF for i in range(length - 4))
    return struct.pack("<I", version) + body


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


def test_the_sii_describes_the_bootstrap_mailbox(master):
    assert master.config_init() == len(LINE)
    slave = master.slaves[LINE.index("dio-update")]
    assert bootstrap_mailbox(slave) == ((0x1800, 256), (0x1900, 256))


def test_foe_write_in_boot_then_init_then_read_back(master):
    slave = master.slaves[LINE.index("dio-update")]
    new = image(2, 20_000)  # 82 segments of 244 bytes
    to_boot(slave)
    assert slave.foe_write(FILE_NAME, PASSWORD, update_file(new), TIMEOUT_US) > 0
    to_state(slave, pysoem.INIT_STATE)
    to_boot(slave)
    assert slave.foe_read(FILE_NAME, PASSWORD, 65_536, TIMEOUT_US) == new
    to_state(slave, pysoem.INIT_STATE)


def test_a_wrong_password_writes_nothing(master):
    slave = master.slaves[LINE.index("dio-update")]
    to_boot(slave)
    assert slave.foe_write(FILE_NAME, PASSWORD + 1, update_file(image(3, 1_000)), TIMEOUT_US) <= 0
    # The image of the previous test is still the one received.
    assert slave.foe_read(FILE_NAME, PASSWORD, 65_536, TIMEOUT_US) == image(2, 20_000)
    to_state(slave, pysoem.INIT_STATE)
