"""The slot buffer: 128 slots of signed pulse counts, one column per axis.

Entries are stored already decoded (direction bit -> sign), so a stretch of slots can be
consumed as one numpy block. The host never learns the free space directly on a fill:
the engine answers with the number of slots it accepted (seed v1, 'Fill buffer command').
"""

from __future__ import annotations

import numpy as np

from .constants import BUFFER_DEPTH


class SlotBuffer:
    def __init__(self, axes: int, max_pulses: int, depth: int = BUFFER_DEPTH) -> None:
        self.depth = depth
        self.axes = axes
        self.max_pulses = max_pulses
        self.clipped = np.zeros(axes, dtype=np.int64)  # pulses beyond max_pulses, per axis
        self._rows = np.zeros((depth, axes), dtype=np.int32)
        self._head = 0
        self.count = 0

    @property
    def free(self) -> int:
        return self.depth - self.count

    def accept(self, entries: np.ndarray, raw_column: int | None = None) -> int:
        """Append as many leading entries (rows of up to `axes` columns) as fit; return
        how many were taken. Columns beyond the entries' width are zero. A slot never
        carries more than max_pulses: the excess is dropped here and counted. A raw
        column (synced output bits, not pulses) is kept as it is."""
        take = min(len(entries), self.free)
        if take <= 0:
            return 0
        width = entries.shape[1]
        taken = entries[:take]
        m = self.max_pulses
        clipped = taken
        if np.abs(taken).max() > m:
            clipped = np.clip(taken, -m, m)
            if raw_column is not None and raw_column < width:
                clipped[:, raw_column] = taken[:, raw_column]
            self.clipped[:width] += np.abs(taken - clipped).sum(axis=0)
        idx = (self._head + self.count + np.arange(take)) % self.depth
        self._rows[idx] = 0
        self._rows[idx, :width] = clipped
        self.count += take
        return take

    def peek(self, n: int) -> np.ndarray:
        """The next n entries (n <= count) without consuming them."""
        if self._head + n <= self.depth:
            return self._rows[self._head:self._head + n]
        idx = (self._head + np.arange(n)) % self.depth
        return self._rows[idx]

    def pop(self, n: int) -> np.ndarray:
        n = min(n, self.count)
        rows = self.peek(n).copy()
        self._head = (self._head + n) % self.depth
        self.count -= n
        return rows

    def clear(self) -> None:
        self._head = 0
        self.count = 0
