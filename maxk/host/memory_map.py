"""The MAXk PCI shared-memory map (Table 3-1), in one place. Big-endian throughout.

Offsets from the manual are marked (T3-1). Where the manual is silent the choice is
ours and marked (D); docs/shared-memory.md explains each:

- Offset 0: the manual says it holds the dip-switch image (bits 0-2: controller number)
  and also the X motor position. We keep the X motor position there (every host reads
  positions; none reads the dip switches) and put the board number in BOARD_NUMBER.
- The outbound doorbell and message registers are PCI registers on the real board, not
  shared memory. A file has no registers, so their images live in the reserved region
  from 0xD000: the board writes ODBR, the host writes ones to ODBR_CLEAR to clear
  doorbell bits (write-one-to-clear, applied by the board, which then zeroes
  ODBR_CLEAR), OMR0 becomes 1 when a text response is waiting and OMR1 bit 1 when
  capture data is.
"""

from __future__ import annotations

SIZE = 0xE010  # (T3-1) 57,360 bytes

MOTOR_XS = 0x000  # 8 x int32, X..S (T3-1)
ENCODER_XS = 0x020  # (T3-1)
LIMIT_WORD = 0x040  # (T3-2)
HOME_WORD = 0x044  # (T3-3)
FIRMWARE_FLAGS = 0x048  # (T3-4); 0xFFFFFFFF until power-up initialization completes
DIRECT_MAILBOX = 0x04C  # (T3-1) direct command, bypassing the text buffer
POSITION_REQUEST = 0x050  # (T3-1) host asks for a coherent snapshot
SNAP_MOTOR_XS = 0x054  # (T3-1)
SNAP_ENCODER_XS = 0x074  # (T3-1)
MESSAGE_SEMAPHORE = 0x094  # (T3-1) coordinates text responses; (D) unread response bytes
IO_WORD = 0x09C  # (T3-1) 16 general purpose bits
MOTOR_WK = 0x0AC  # (T3-1)
ENCODER_WK = 0x0B4
SNAP_MOTOR_WK = 0x0BC
SNAP_ENCODER_WK = 0x0C4
STATUS_WK = 0x0CC  # (T3-1) W and K axis status flags; (D) bit 0 done, 1 overtravel, 2 slip
CMD_INSERT = 0x0F0  # (T3-1) host writes
CMD_PROCESS = 0x0F4  # (T3-1) board writes
RESP_INSERT = 0x0F8  # (T3-1) board writes
RESP_PROCESS = 0x0FC  # (T3-1) host writes
CMD_RING = 0x100  # (T3-1) 1024 bytes
RESP_RING = 0x500  # (T3-1) 1024 bytes
RING_SIZE = 1024
UTILITY = 0x900  # (T3-1) 2048 bytes, unused here
CAPTURE = 0x1540  # (T3-5) 552 bytes
DAC_XS = 0x2E80  # (T3-1)
SNAP_DAC_XS = 0x2EA0  # (T3-1) coherent servo DAC output X..S
SNAP_DAC_WK = 0x2EC0  # (T3-1)
DAC_WK = 0x2EC8  # (T3-1)
ABSOLUTE_ENCODERS = 0x3520  # (T3-1) 10 x int32, X..K

# ---- our choices in the reserved region (D) -------------------------------------------
ODBR = 0xD000  # outbound doorbell register image (board writes)
ODBR_CLEAR = 0xD004  # host writes ones here to clear doorbell bits; board zeroes it
OMR0 = 0xD008  # outbound message register 0: 1 while a text response is waiting
OMR1 = 0xD00C  # outbound message register 1: bit 1 (0x2) capture data available
TICK = 0xD010  # the board's update-cycle counter (a heartbeat for hosts)
BOARD_NUMBER = 0xD014  # J5 board number, 1..16
LAYOUT = 0xD018  # b"MXK1": this layout's version

LAYOUT_MAGIC = b"MXK1"

# Direct command mailbox codes (D): the host writes one, the board acts on the next
# update cycle and writes 0 back (or 0xFFFFFFFF for a code it does not know).
DIRECT_KILL_ALL = 1  # kill all motion (manual 3.3: Direct Commands = {Kill all motion})
DIRECT_DONE = 0
DIRECT_UNKNOWN = 0xFFFF_FFFF

DIRECT_RESET = 2  # reset the controller (the DLL's ResetOmsController), decision D


def motor_offset(axis: int) -> int:
    return MOTOR_XS + 4 * axis if axis < 8 else MOTOR_WK + 4 * (axis - 8)


def encoder_offset(axis: int) -> int:
    return ENCODER_XS + 4 * axis if axis < 8 else ENCODER_WK + 4 * (axis - 8)


def snapshot_motor_offset(axis: int) -> int:
    return SNAP_MOTOR_XS + 4 * axis if axis < 8 else SNAP_MOTOR_WK + 4 * (axis - 8)


def snapshot_encoder_offset(axis: int) -> int:
    return SNAP_ENCODER_XS + 4 * axis if axis < 8 else SNAP_ENCODER_WK + 4 * (axis - 8)


def dac_offset(axis: int) -> int:
    return DAC_XS + 4 * axis if axis < 8 else DAC_WK + 4 * (axis - 8)


def snapshot_dac_offset(axis: int) -> int:
    return SNAP_DAC_XS + 4 * axis if axis < 8 else SNAP_DAC_WK + 4 * (axis - 8)
