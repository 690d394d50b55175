"""Bit layout of the outbound doorbell register (ODBR) and the MAXnet flag word.

The MAXk manual (3.4) and the MAXnet notification map (evidence 3.2) agree: bits 0-7
done X..S, 8-15 overtravel X..S, 16-23 encoder slip X..S, 24 command error, 25/26 the
W/K notification bits. The MAXnet word spells W and K out in bits 25-30.
"""

from __future__ import annotations

DONE_SHIFT = 0
OVERTRAVEL_SHIFT = 8
SLIP_SHIFT = 16
COMMAND_ERROR = 1 << 24
W_NOTIFY = 1 << 25
K_NOTIFY = 1 << 26

# Per-axis status word bits used for W and K (shared memory 0xCC/0xD0) and internally.
AXIS_DONE = 0x1
AXIS_OVERTRAVEL = 0x2
AXIS_SLIP = 0x4

# MAXnet `%000 SSSSSSSS` word: W and K each have their own done/overtravel/slip bits.
MAXNET_W = {AXIS_DONE: 0x0200_0000, AXIS_OVERTRAVEL: 0x0800_0000, AXIS_SLIP: 0x2000_0000}
MAXNET_K = {AXIS_DONE: 0x0400_0000, AXIS_OVERTRAVEL: 0x1000_0000, AXIS_SLIP: 0x4000_0000}


def doorbell_word(axis_flags: list[int], command_error: bool) -> int:
    """The ODBR image for per-axis flag bits (index = axis number)."""
    word = COMMAND_ERROR if command_error else 0
    for index, bits in enumerate(axis_flags):
        if not bits:
            continue
        if index < 8:
            if bits & AXIS_DONE:
                word |= 1 << (DONE_SHIFT + index)
            if bits & AXIS_OVERTRAVEL:
                word |= 1 << (OVERTRAVEL_SHIFT + index)
            if bits & AXIS_SLIP:
                word |= 1 << (SLIP_SHIFT + index)
        else:
            word |= W_NOTIFY if index == 8 else K_NOTIFY
    return word


def maxnet_word(axis_flags: list[int], command_error: bool) -> int:
    """The MAXnet notification word (evidence 3.2): like the ODBR but W/K in full."""
    word = doorbell_word(axis_flags[:8], command_error)
    for index, table in ((8, MAXNET_W), (9, MAXNET_K)):
        if index < len(axis_flags):
            for bit, mask in table.items():
                if axis_flags[index] & bit:
                    word |= mask
    return word


def describe_doorbell(word: int, axis_letters: str) -> str:
    """Human-readable flag names for the REPL's status line."""
    parts: list[str] = []
    shifts = (("done", DONE_SHIFT), ("overtravel", OVERTRAVEL_SHIFT), ("slip", SLIP_SHIFT))
    for name, shift in shifts:
        letters = "".join(
            letter for i, letter in enumerate(axis_letters[:8]) if word & (1 << (shift + i))
        )
        if letters:
            parts.append(f"{name} {letters}")
    if word & W_NOTIFY:
        parts.append("W notify")
    if word & K_NOTIFY:
        parts.append("K notify")
    if word & COMMAND_ERROR:
        parts.append("command error")
    return ", ".join(parts) if parts else "none"


def maxnet_event_bits(index: int, bit: int) -> int:
    """The MAXnet word bits for one axis flag (what a notification for that event says)."""
    flags = [0] * (index + 1)
    flags[index] = bit
    return maxnet_word(flags, False)


# Firmware state flags (shared memory 0x048, Table 3-4).
FIRMWARE_INITIALIZING = 0xFFFF_FFFF  # the whole word, until power-up initialization ends
FIRMWARE_RUNNING = 1 << 2  # application code running
ARCHIVE_CHECKSUM_ERROR = 1 << 12  # power-up default parameter archive
ARCHIVE_PROGRAMMING_ERROR = 1 << 13  # storing the power-up default parameter archive
ALTERNATE_CHECKSUM_ERROR = 1 << 14  # (the alternate archive is not modelled)
ALTERNATE_PROGRAMMING_ERROR = 1 << 15
USER_DEFAULTS_LOADED = 1 << 16  # power-up default parameter set in working memory
ALTERNATE_LOADED = 1 << 17
FACTORY_DEFAULTS_LOADED = 1 << 18
