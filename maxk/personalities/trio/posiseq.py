"""POSI_SEQ_MODE and POSI_SEQ_DELAY (TrioBASIC help POSI_SEQ_MODE, POSI_SEQ_DELAY): a
delay line on an axis's demand position.

The pages: the axis's final output position (DPOS) goes through a buffer of
POSI_SEQ_DELAY servo cycles; mode 1 puts out the value pushed that many cycles ago, mode
2 the mean of the newest value and that one, mode 0 nothing delayed; until the buffer is
full the demand is not delayed, and once it is the delayed values overwrite the demand.

The shared machine plans each motion in closed form between events and lets a plan go
when it ends, so the past demand is kept here: while an axis's filter is on, this source
takes an event every servo cycle and pushes the demand of that cycle into the axis's
buffer (bounded: POSI_SEQ_DELAY + 1 values, at most MAX_DELAY + 1). The delayed value
at any tick is then exact: from the buffer for a cycle already passed, from the closed
form for one still ahead (which the running motion describes up to the next event).

Decisions (D): the buffer starts filling when the mode or the delay is written (a change
empties it); DPOS reads the delayed value, as do MPOS of an axis without a servo loop, a
stepper's world motor (its limit switches and shaft encoder), a servo axis's loop (its
command: `MC405Machine.command_offset`, so FE is its error to the delayed value) and
BACKLASH's base; the
moves and links go on planning from the undelayed demand, and so does the search for a
limit switch on the axis's own move (the switch is found where the undelayed demand
meets it). The delay is a whole number of cycles, 0..MAX_DELAY (a fraction is cut).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

MAX_DELAY = 10000  # servo cycles (D: a bound on the buffer, 10 s at 1 ms)
MODES = (0, 1, 2)


@dataclass
class Line:
    """One axis's buffer: the demand of every cycle from `first` to `last`, the newest
    `delay + 1` kept."""

    mode: int
    delay: int
    first: int  # the tick the buffer started filling
    values: deque[float]
    last: int  # the last tick pushed (first - 1: none yet)


class DelayLine:
    """Every axis's POSI_SEQ buffer, as an event source of the machine."""

    def __init__(self, axis_count: int, tick: Callable[[], int],
                 params: Callable[[int], dict[str, float]],
                 demand: Callable[[int, np.ndarray], np.ndarray],
                 revision: Callable[[], int]) -> None:
        self._axis_count = axis_count
        self._tick = tick
        self._params = params
        self._demand = demand
        self._revision = revision  # the machine's count of changes (a parameter written)
        self.lines: dict[int, Line] = {}
        self._idle_at = -1  # the revision at which no filter was on (nothing to look at)

    def reset(self) -> None:
        self.lines = {}
        self._idle_at = -1

    def _line(self, axis: int) -> Line | None:
        """The axis's buffer, started afresh when its setting changed; None when off."""
        params = self._params(axis)
        mode = int(params.get("POSI_SEQ_MODE", 0.0))
        delay = int(params.get("POSI_SEQ_DELAY", 0.0))
        if mode == 0 or delay <= 0:
            self.lines.pop(axis, None)
            return None
        line = self.lines.get(axis)
        if line is None or (line.mode, line.delay) != (mode, delay):
            now = self._tick()
            line = Line(mode, delay, now, deque(maxlen=delay + 1), now - 1)
            self.lines[axis] = line
        return line

    # ---- the event source: one push a servo cycle while a filter is on -----------------
    def next_event(self) -> int | None:
        if not self.lines and self._idle_at == self._revision():
            return None  # (no filter on, and no parameter written since: the common case)
        now = self._tick()
        due = None
        for axis in range(self._axis_count):
            line = self._line(axis)
            if line is not None:
                tick = max(now, line.last + 1)
                due = tick if due is None else min(due, tick)
        if due is None:
            self._idle_at = self._revision()
        return due

    def on_event(self, now: int) -> None:
        for axis in range(self._axis_count):
            line = self._line(axis)
            if line is None or now <= line.last:
                continue
            ticks = np.arange(line.last + 1, now + 1)  # (every cycle: one, as a rule)
            line.values.extend(float(v) for v in self._demand(axis, ticks).tolist())
            line.last = now

    # ---- what reads the delayed demand ----------------------------------------------------
    def delayed(self, axis: int, ticks: np.ndarray, demand: np.ndarray) -> np.ndarray:
        """The output position at `ticks`, given the undelayed `demand` there."""
        line = self._line(axis)
        if line is None:
            return demand
        back = ticks - line.delay
        full = back >= line.first  # (the buffer had been filled by then)
        if not full.any():
            return demand
        kept = np.array(line.values, dtype=float)
        oldest = line.last - len(kept) + 1
        index = back - oldest
        stored = full & (back <= line.last) & (index >= 0)
        past = demand.astype(float)
        if len(kept) and stored.any():
            past = np.where(stored, kept[np.clip(index, 0, len(kept) - 1)], past)
        ahead = full & (back > line.last)  # a cycle not pushed yet: the closed form
        if ahead.any():
            past = np.where(ahead, self._demand(axis, np.maximum(back, line.last + 1)), past)
        out = past if line.mode == 1 else (demand + past) / 2.0
        return np.where(full, out, demand)


__all__ = ["MAX_DELAY", "MODES", "DelayLine"]
