"""Real-time position capture (manual 3.7, Tables 3-5 and 3-6).

The firmware records the encoder position of an axis when a chosen event happens: an
edge of its home switch, an encoder index mark (the "encoder home event"), or an edge of
a general purpose input. Entries go into a 55-entry ring in shared memory: the board
writes at the insert index and advances it; if it then equals the host's removal index,
the board advances that too and the oldest entry is lost (the host was too slow).

The MAX command reference pages that configure capture were not in our sources, so
capture is configured from Python, command scripts and the REPL (docs/io.md), not by a
controller command. Capture needs an incremental encoder on the axis (PSE or PSM).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from maxk.personalities.maxk.config import wrap32

RING_ENTRIES = 55
ENTRY_SIZE = 10
RING_BYTES = 2 + RING_ENTRIES * ENTRY_SIZE  # 552 bytes at shared memory 0x1540

HOME_RISING = 0x01
ENCODER_HOME = 0x02
HOME_FALLING = 0x04

EDGES = ("rising", "falling", "both")


@dataclass(frozen=True)
class CaptureEntry:
    encoder: int  # signed 32-bit encoder position
    axis: int  # X = 0, Y = 1, ...
    home_events: int = 0  # HOME_RISING | ENCODER_HOME | HOME_FALLING
    io_rising: int = 0  # input bits that rose
    io_falling: int = 0  # input bits that fell

    def to_bytes(self) -> bytes:
        """Table 3-6, big-endian (the board is a PowerPC)."""
        return struct.pack(">iBBHH", self.encoder, self.axis, self.home_events,
                           self.io_rising, self.io_falling)


@dataclass
class CaptureConfig:
    """What one axis captures."""

    home: str | None = None  # "rising", "falling" or "both" home switch edges
    index: bool = False  # every encoder index mark
    io_rising: int = 0  # input bits whose rising edges capture
    io_falling: int = 0  # input bits whose falling edges capture

    @property
    def on_position(self) -> bool:
        return self.home is not None or self.index

    @property
    def on_inputs(self) -> bool:
        return bool(self.io_rising or self.io_falling)


class CaptureRing:
    """The 55-entry ring with the board's insert index and the host's removal index."""

    def __init__(self) -> None:
        self.slots: list[CaptureEntry | None] = [None] * RING_ENTRIES
        self.insert = 0
        self.removal = 0
        self.lost = 0  # entries overwritten before the host removed them
        self.signal = False  # outbound message register 1, bit 1: data available

    def push(self, entry: CaptureEntry) -> None:
        self.slots[self.insert] = entry
        self.insert = (self.insert + 1) % RING_ENTRIES
        if self.insert == self.removal:
            self.removal = (self.removal + 1) % RING_ENTRIES
            self.lost += 1
        self.signal = True

    def __len__(self) -> int:
        return (self.insert - self.removal) % RING_ENTRIES

    def read(self) -> list[CaptureEntry]:
        """What a host does: take every entry from the removal index up to the insert
        index, advancing the removal index, and clear the signal."""
        out: list[CaptureEntry] = []
        while self.removal != self.insert:
            entry = self.slots[self.removal]
            if entry is not None:
                out.append(entry)
            self.removal = (self.removal + 1) % RING_ENTRIES
        self.signal = False
        return out

    def to_bytes(self) -> bytes:
        """The 552 bytes at shared memory 0x1540 (Table 3-5)."""
        body = b"".join(
            (slot.to_bytes() if slot is not None else bytes(ENTRY_SIZE)) for slot in self.slots
        )
        return bytes([self.insert, self.removal]) + body


def encoder_at(steps: int, encoder_offset: int) -> int:
    return wrap32(steps + encoder_offset)
