"""The MC405's FLASH system parameters: kept across a restart (EX), reset by CLEAR_PARAMS.

Their help pages type them "MC_CONFIG / FLASH": SERVO_PERIOD (taking effect at the
restart), and the Ethernet port's IP_ADDRESS, IP_NETMASK and IP_GATEWAY (their pages and
ETHERNET's: a new address applies after EX(1) or a power cycle). The other FLASH words of
the pages (AXIS_OFFSET, MODULE_IO_MODE, CANIO_*, REMOTE_PROC, PCMCAT_PROC) configure
modules and buses the emulated MC405 has none of, so they are not kept here (D).

The VRs are kept too (EX's page: they remain in memory; FLASHVR's: the MC4xx keeps
them in flash itself): `MC405Machine.restart` carries them over the power-up. FLASH_DATA
= 1 (set by MC_CONFIG, its page) makes TABLE the MC4xx's automatic backup, its first
`AUTO_BACKUP` values, so those come back at the power-up as well.

A new run of the emulator on the same archive is a power cycle too: these, with the
FLASHTABLE pages and FLASHVR(-1)'s TABLE, are kept in the archive by
maxk/controllers/trio/archive.py.
"""

from __future__ import annotations

FLASH_PARAMETERS = frozenset({"SERVO_PERIOD", "IP_ADDRESS", "IP_NETMASK", "IP_GATEWAY"})
AUTO_BACKUP = 4096  # FLASH_DATA's page: an MC4x backs up only the first 4096 elements


def dotted(value: float) -> str:
    """A 32-bit address as its four octets, ``192.168.0.250``."""
    number = int(value) & 0xFFFFFFFF
    return ".".join(str(number >> shift & 0xFF) for shift in (24, 16, 8, 0))


def mac_text(value: float) -> str:
    """A 48-bit MAC address as six hexadecimal octets, ``00:06:70:00:00:F9``."""
    number = int(value) & 0xFFFFFFFFFFFF
    return ":".join(f"{number >> shift & 0xFF:02X}" for shift in range(40, -1, -8))
