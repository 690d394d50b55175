"""Real time for the doors: the wall clock lives here and nowhere in the core.

A door attached to a host keeps its controller at "now": before it answers anything it
advances the engine to the tick that corresponds to the wall clock, and a background
pacer does the same every millisecond or so, so flags, notifications and shared memory
stay fresh between requests. The target tick is always computed from one fixed epoch,
never by adding up sleeps, so the engine cannot drift from the wall clock over hours.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Protocol

from maxk.firmware_model.engine import Engine


class _HasEngine(Protocol):
    @property
    def engine(self) -> Engine: ...


class Pacer:
    """Maps wall-clock time to a controller's ticks (optionally `speed` times faster)."""

    def __init__(self, controller: _HasEngine, speed: float = 1.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        if speed <= 0:
            raise ValueError("speed must be positive")
        self.controller = controller
        self.speed = speed
        self._clock = clock
        self._epoch = clock()
        self._time_at_epoch = controller.engine.time

    def target_tick(self) -> int:
        virtual = self._time_at_epoch + (self._clock() - self._epoch) * self.speed
        return self.controller.engine.tick_at(virtual)

    def sync(self) -> int:
        """Advance the engine to now; return how many ticks that was."""
        engine = self.controller.engine
        target = self.target_tick()
        if target > engine.tick:
            before = engine.tick
            engine.advance_to(target)
            return engine.tick - before
        return 0

    def lag(self) -> float:
        """Seconds the engine's virtual time is behind the (scaled) wall clock."""
        virtual = self._time_at_epoch + (self._clock() - self._epoch) * self.speed
        return virtual - self.controller.engine.time

    def set_speed(self, speed: float) -> None:
        """From now on `speed` times real time; 0 pauses (the engine stands still until
        the speed is set again). Virtual time carries on from where the engine stands."""
        if not (math.isfinite(speed) and speed >= 0):
            raise ValueError("speed must be a finite number >= 0")
        self._epoch = self._clock()
        self._time_at_epoch = self.controller.engine.time
        self.speed = speed
