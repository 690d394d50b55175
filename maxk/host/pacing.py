"""Real time for the doors: the wall clock lives here and nowhere in the core.

A door attached to a host keeps its board at "now": before it answers anything it
advances the board to the tick that corresponds to the wall clock, and a background
pacer does the same every millisecond or so, so flags, notifications and shared memory
stay fresh between requests. The target tick is always computed from one fixed epoch,
never by adding up sleeps, so the board cannot drift from the wall clock over hours.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from maxk.controllers.maxk import MAXk


class Pacer:
    """Maps wall-clock time to the board's ticks (optionally `speed` times faster)."""

    def __init__(self, maxk: MAXk, speed: float = 1.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        if speed <= 0:
            raise ValueError("speed must be positive")
        self.maxk = maxk
        self.speed = speed
        self._clock = clock
        self._epoch = clock()
        self._time_at_epoch = maxk.board.time

    def target_tick(self) -> int:
        board = self.maxk.board
        virtual = self._time_at_epoch + (self._clock() - self._epoch) * self.speed
        return board.tick_at(virtual)

    def sync(self) -> int:
        """Advance the board to now; return how many ticks that was."""
        board = self.maxk.board
        target = self.target_tick()
        if target > board.tick:
            before = board.tick
            board.advance_to(target)
            return board.tick - before
        return 0

    def lag(self) -> float:
        """Seconds the board's virtual time is behind the (scaled) wall clock."""
        virtual = self._time_at_epoch + (self._clock() - self._epoch) * self.speed
        return virtual - self.maxk.board.time
