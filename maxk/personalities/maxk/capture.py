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
from typing import Protocol

from maxk.firmware_model.outputs import (
    PositionTrigger,
    next_periodic_marks,
    periodic_marks_passed,
    trigger_ticks,
)
from maxk.personalities.maxk.axis import Axis, AxisHost
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


# ---- capturing: position triggers from the shared outputs mechanism ---------------------
class CaptureHost(AxisHost, Protocol):
    """What capture asks of the board: its configuration, ring and inputs' last levels."""

    capture_config: list[CaptureConfig]
    capture_ring: CaptureRing
    _input_levels: int


def capture_triggers(board: CaptureHost, axis: Axis) -> list[tuple[int, PositionTrigger[int]]]:
    """The next home-switch edges and index mark each way ahead of the axis, as position
    triggers (payload: the home bits of the entry), each with the tick the running motion
    reaches it."""
    config = board.capture_config[axis.index]
    if not config.on_position or not axis.has_encoder:
        return []
    world = board.world.axes[axis.index]
    triggers: list[PositionTrigger[int]] = []
    if config.home is not None:
        rising = config.home in ("rising", "both")
        falling = config.home in ("falling", "both")
        for position, active_above in world.home.transitions():
            # Crossing upward into `position` turns the switch to active_above;
            # crossing downward out of it (to position - 1) does the opposite.
            if (rising and active_above) or (falling and not active_above):
                triggers.append(PositionTrigger(
                    position, 1, HOME_RISING if active_above else HOME_FALLING))
            if (rising and not active_above) or (falling and active_above):
                triggers.append(PositionTrigger(
                    position - 1, -1, HOME_FALLING if active_above else HOME_RISING))
    if config.index and world.index_period > 0:
        up, down = next_periodic_marks(axis.steps_now(board), world.index_offset,
                                       world.index_period, world.index_width)
        triggers.append(PositionTrigger(up, 1, ENCODER_HOME))
        triggers.append(PositionTrigger(down, -1, ENCODER_HOME))
    return trigger_ticks(axis, board, triggers)


def fire_captures(board: CaptureHost, axis: Axis) -> None:
    """Record every edge reached by now. Only the next index mark each way was
    scheduled, so the marks after it passed within the same update cycle are added
    here: every mark is captured, like every home-switch transition."""
    now = board.tick
    here = axis.steps_now(board)
    period = board.world.axes[axis.index].index_period
    due: list[tuple[int, int]] = []  # (bits, position)
    for tick, trigger in axis.capture_pending:
        if tick > now:
            continue
        position = int(trigger.position)
        if trigger.payload == ENCODER_HOME and period > 0:
            due.extend((ENCODER_HOME, mark) for mark in
                       periodic_marks_passed(position, period, here))
        else:
            due.append((trigger.payload, position))
    direction = axis.travel_direction(board)
    for bits, position in sorted(due, key=lambda d: d[1] * direction):
        board.capture_ring.push(CaptureEntry(
            encoder_at(axis.encoder_counts(position, board), axis.encoder_offset),
            axis.index, bits))


def read_inputs(board: CaptureHost) -> int:
    """The levels of the lines configured as inputs."""
    io = board.io
    return sum(1 << b for b in range(io.lines)
               if not io.direction >> b & 1 and board.world.digital_level(b, board))


def capture_inputs(board: CaptureHost) -> None:
    """Record input edges for every axis that captures on them."""
    levels = read_inputs(board)
    changed = levels ^ board._input_levels
    board._input_levels = levels
    if not changed:
        return
    rose, fell = changed & levels, changed & ~levels
    for axis, config in zip(board.axes, board.capture_config, strict=True):
        r, f = rose & config.io_rising, fell & config.io_falling
        if (r or f) and axis.has_encoder:
            board.capture_ring.push(CaptureEntry(axis.encoder_position(board), axis.index,
                                                 0, r, f))
