"""Real time for the doors: the wall clock lives here and nowhere in the core.

A door attached to a host keeps its controller at "now": before it answers anything it
advances the engine to the tick that corresponds to the wall clock, and a background
pacer does the same every millisecond or so, so flags, notifications and shared memory
stay fresh between requests. The target tick is always computed from one fixed epoch,
never by adding up sleeps, so the engine cannot drift from the wall clock over hours.

A door serving several controllers on one loop gives each a bounded turn (`budget`
seconds of work a sync): a controller whose work takes longer than real time (a MAX
queue loop of a thousand commands, a busy TrioBASIC program) then falls behind the wall
clock on its own, and every other controller's door goes on answering. Its lag is kept
within `max_lag` seconds: beyond that its clock slips (runs slow) rather than racing
to catch up later, and `engine.behind` says by how much it stands behind (once that is
more than BEHIND, a few update periods' jitter of a bounded turn being no lag).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Protocol

from maxk.firmware_model.engine import Engine

MAX_LAG = 0.25
"""Wall seconds a controller may stand behind real time before its clock slips (runs
slow) instead: a burst of heavy work is caught up, a hog never builds a backlog (D)."""
BEHIND = 0.05
"""Wall seconds behind real time from which a controller is said to run behind (D)."""


class _HasEngine(Protocol):
    @property
    def engine(self) -> Engine: ...


class Pacer:
    """Maps wall-clock time to a controller's ticks (optionally `speed` times faster)."""

    def __init__(self, controller: _HasEngine, speed: float = 1.0,
                 clock: Callable[[], float] = time.monotonic,
                 work_clock: Callable[[], float] = time.perf_counter,
                 max_lag: float = MAX_LAG) -> None:
        if speed <= 0:
            raise ValueError("speed must be positive")
        self.controller = controller
        self.speed = speed
        self._clock = clock
        self._work_clock = work_clock  # what a sync's budget is measured on
        self.max_lag = max_lag
        self._epoch = clock()
        self._time_at_epoch = controller.engine.time
        self.slipped = 0.0  # virtual seconds the clock has slipped (lag beyond max_lag)

    def _virtual_now(self) -> float:
        return self._time_at_epoch + (self._clock() - self._epoch) * self.speed

    def target_tick(self) -> int:
        return self.controller.engine.tick_at(self._virtual_now())

    def sync(self, budget: float | None = None) -> int:
        """Advance the engine to now; return how many ticks that was. With a `budget`
        (seconds of work), stop once it is spent, after the event at hand: the engine
        then stands behind now, and `engine.behind` says by how much."""
        engine = self.controller.engine
        target = self.target_tick()
        before = engine.tick
        if target > before:
            if budget is None:
                engine.advance_to(target)
            else:
                clock = self._work_clock
                deadline = clock() + budget
                engine.advance_to(target, lambda: clock() >= deadline)
        self._note_lag(target)
        return engine.tick - before

    def _note_lag(self, target: int) -> None:
        engine = self.controller.engine
        if engine.tick >= target:
            engine.behind = 0.0
            return
        lag = self._virtual_now() - engine.time
        limit = self.max_lag * self.speed
        if lag > limit:  # the clock slips: real time the controller could not keep up with
            self._time_at_epoch -= lag - limit
            self.slipped += lag - limit
            lag = limit
        engine.behind = lag if lag >= BEHIND * self.speed else 0.0

    def lag(self) -> float:
        """Seconds the engine's virtual time is behind the (scaled) wall clock."""
        return self._virtual_now() - self.controller.engine.time
