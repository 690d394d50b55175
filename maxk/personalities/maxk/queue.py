"""Per-axis FIFO command queue with LS/LE loops (manual 6.2, theory of operation).

The firmware keeps a command queue of addresses and an argument queue; LS pushes its
count and its own address on a loop stack, LE decrements and jumps back. Entries inside
a loop cannot be released until the outermost loop ends, so the queue is a list with a
program counter; consumed entries are dropped (and their units freed) only when no loop
is open.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from maxk.personalities.maxk.models import QUEUE_CAPACITY
from maxk.personalities.maxk.waits import Wait

QUEUE_COMMANDS_PER_UPDATE = 32
"""Queue entries one axis executes in one update cycle at most; the rest wait for the
next update. The manual gives no execution rate: the update-cycle process "calculates
the desired velocity at the selected update rate" as the PowerPC's highest-priority
process (theory of operation, 6.2), so queue work shares what each 122 us cycle leaves,
and a loop body of a thousand commands cannot run every cycle. 32 an axis per update is
our decision (D): no sequence of commands a host sends between two waits in the
reference programs comes near it (a GO with its VL, AC, MR and a handful of I/O
commands is under ten), so their timing is unchanged, while a queue loop's cost per
update is bounded."""

Action = Callable[[Any, Any], Wait | None]
"""A queued command's effect, called with (axis, board): None when finished, or a wait
(see Axis.run_queue). The axis and board are the MAXk's `Axis` and `Board`, which sit
above the queue; they are not named here so that the queue imports neither."""


@dataclass(slots=True)
class QueueEntry:
    mnemonic: str
    units: int
    action: Action
    text: str = ""  # the command as the host sent it, for traces and the REPL
    sync: Any = None  # an AA GO's StartGroup or an MT/ML LinearMove: a flush withdraws
    applied_at_stop: bool = False  # an AC/DC just before ST/SA acts first (evidence E4)


class QueueFull(Exception):
    """The command does not fit: the board refuses it with a command error."""


class CommandQueue:
    __slots__ = ("capacity", "entries", "pc", "loops", "used_units")

    def __init__(self, capacity: int = QUEUE_CAPACITY) -> None:
        self.capacity = capacity
        self.entries: deque[QueueEntry] = deque()
        self.pc = 0
        self.loops: list[list[int]] = []  # [loop body start index, remaining count]
        self.used_units = 0

    @property
    def free_units(self) -> int:
        return self.capacity - self.used_units

    def __len__(self) -> int:
        return len(self.entries) - self.pc

    def push(self, entry: QueueEntry) -> None:
        if entry.units > self.free_units:
            raise QueueFull(f"queue full ({self.free_units} units free, {entry.units} needed)")
        self.entries.append(entry)
        self.used_units += entry.units

    def peek(self) -> QueueEntry | None:
        pc, entries = self.pc, self.entries
        return entries[pc] if pc < len(entries) else None

    def advance(self) -> None:
        """Move past the entry just executed; release consumed entries outside loops."""
        if self.pc >= len(self.entries):  # the entry flushed its own queue
            self.pc = len(self.entries)
            return
        self.pc += 1
        if not self.loops:
            self._release()

    def _release(self) -> None:
        entries = self.entries
        while self.pc:
            self.used_units -= entries.popleft().units
            self.pc -= 1

    def loop_start(self, count: int) -> None:
        """LS: remember where the body starts (the entry after LS) and how often to run it."""
        self.loops.append([self.pc + 1, count])

    def loop_end(self) -> bool:
        """LE: jump back while the count lasts. Returns True when it jumped."""
        if not self.loops:
            return False  # an LE without LS is a no-op, like a jump target that is gone
        frame = self.loops[-1]
        frame[1] -= 1
        if frame[1] > 0:
            self.pc = frame[0] - 1  # advance() will step onto the body start
            return True
        self.loops.pop()
        return False

    def flush(self) -> None:
        """FL / ST / KL: drop every pending entry and any open loop."""
        self.entries.clear()
        self.pc = 0
        self.loops.clear()
        self.used_units = 0

    def pending(self) -> list[QueueEntry]:
        """Entries not yet executed (inside an open loop, the ones after the pc)."""
        return [self.entries[i] for i in range(self.pc, len(self.entries))]
