"""Outputs tied to motion: one mechanism for everything that must happen at the exact
tick motion reaches a place, or that is computed from the motion every update.

Three kinds, each exact to the tick without stepping through ticks where the motion is
closed form:

- **Position triggers**: an output changed when an axis passes a position, travelling a
  given way (the MAXk's position capture at home-switch edges and encoder index marks;
  the Trio's position-gated PWM FIFO). The tick is found by bisection over the motion's
  monotonic phases (`MotionAxis.tick_reaching`), as limit switches are. Marks that repeat
  every period (index marks) are scheduled one ahead each way; the ones an axis passes
  within one update cycle are all reported (`periodic_marks_passed`).
- **Path triggers**: outputs at distances along a planned path (the MAXk's VIO at segment
  starts; the MM4005's pulses every NI along the trajectory between two elements). The
  tick is the path plan's inverse in closed form (`PathPlan.time_at`); evenly spaced
  distances are generated lazily, so a million pulses cost nothing until they are due.
  Outputs at given times along a plan (the MM4005's time-based pulses, evenly spaced in
  time) fire on the first update tick at or after their time (`time_trigger_ticks`).
- **Computed outputs**: a value recomputed every update from the path speed and another
  axis's position (the Trio's speed-linked PWM mark), evaluated at any tick in closed
  form from the motions it depends on.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Generic, TypeVar

if TYPE_CHECKING:
    from maxk.firmware_model.axis import MotionAxis
    from maxk.firmware_model.motion import Clock
    from maxk.firmware_model.path import PathPlan

Payload = TypeVar("Payload")


# ---- position triggers ----------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class PositionTrigger(Generic[Payload]):
    """Fire when the axis reaches `position` (physical steps) travelling `direction`."""

    position: float
    direction: int  # +1: met moving up, -1: met moving down
    payload: Payload


def trigger_ticks(axis: MotionAxis, engine: Clock,
                  triggers: Iterable[PositionTrigger[Payload]]
                  ) -> list[tuple[int, PositionTrigger[Payload]]]:
    """The tick at which the running motion first meets each trigger ahead of it (in its
    direction, strictly beyond where the axis stands now); triggers it never meets are
    left out."""
    here = axis.steps_now(engine)
    out: list[tuple[int, PositionTrigger[Payload]]] = []
    for trigger in triggers:
        if trigger.direction * (trigger.position - here) <= 0:
            continue
        tick = axis.tick_reaching(trigger.position, trigger.direction, engine)
        if tick is not None:
            out.append((tick, trigger))
    return out


def next_periodic_marks(here: int, offset: int, period: int, width: int) -> tuple[int, int]:
    """The next mark each way from `here` of marks `width` counts wide every `period`
    counts, one starting at `offset`: moving up a mark is met at its first count, moving
    down at its last. Returns (position met moving up, position met moving down)."""
    ahead = (offset - here) % period
    behind = (here - (offset + width - 1)) % period
    return here + (ahead or period), here - (behind or period)


def periodic_marks_passed(first: int, period: int, here: int) -> Iterator[int]:
    """`first` and every further mark `period` apart up to `here`, in the direction from
    `first` to `here`: what an axis passed within one update cycle."""
    direction = 1 if here >= first else -1
    mark = first
    while direction * (here - mark) >= 0:
        yield mark
        mark += direction * period


# ---- path triggers -----------------------------------------------------------------------
def path_tick(plan: PathPlan, plan_tick: int, period: float, distance: float) -> int | None:
    """The first tick at or after which the plan (started at `plan_tick`) has reached
    `distance` along the path; None if it never does."""
    t = plan.time_at(distance)
    if t is None:
        return None
    return plan_tick + math.ceil(t / period - 1e-9)


def path_trigger_ticks(plan: PathPlan, plan_tick: int, period: float,
                       distances: Iterable[tuple[float, Payload]]
                       ) -> list[tuple[int, Payload]]:
    """Ticks of increasing distances along the path, up to the first the plan does not
    reach (it stops short of the rest too)."""
    out: list[tuple[int, Payload]] = []
    for distance, payload in distances:
        tick = path_tick(plan, plan_tick, period, distance)
        if tick is None:
            break
        out.append((tick, payload))
    return out


def time_trigger_ticks(plan_tick: int, period: float, times: Iterable[tuple[float, Payload]]
                       ) -> list[tuple[int, Payload]]:
    """Each output at `t` seconds after the plan's start (tick `plan_tick`) fires on the
    first update tick at or after it (a time a rounding error past a tick stays on it)."""
    return [(plan_tick + math.ceil(t / period - 1e-9), payload) for t, payload in times]


@dataclass(frozen=True, slots=True)
class EvenlySpaced:
    """`count` positions along a path or times along a plan: `start`, then every `step`
    (the MM4005's NB..NE pulses at NI, its MB..ME pulses in time); generated lazily."""

    start: float
    step: float
    count: int

    def __iter__(self) -> Iterator[tuple[float, int]]:
        for k in range(self.count):
            yield self.start + k * self.step, k

    def from_index(self, k: int) -> Iterator[tuple[float, int]]:
        for j in range(k, self.count):
            yield self.start + j * self.step, j


# ---- computed outputs -------------------------------------------------------------------
class ComputedOutput:
    """A value recomputed every update from the motion: `compute(speed, position)` of a
    speed source and a position source, each a function of the tick (closed form: a path
    plan's speed, an axis's position). Nothing is stepped: the value at any tick is asked
    for when it is read, traced or plotted."""

    __slots__ = ("compute", "position", "speed")

    def __init__(self, compute: Callable[[float, float], float],
                 speed: Callable[[int], float], position: Callable[[int], float]) -> None:
        self.compute = compute
        self.speed = speed
        self.position = position

    def value_at(self, tick: int) -> float:
        return self.compute(self.speed(tick), self.position(tick))

    def values(self, first: int, last: int) -> list[float]:
        """Every update's value from `first` to `last` inclusive (traces and plots)."""
        return [self.value_at(t) for t in range(first, last + 1)]


def axis_speed(axis: MotionAxis, engine: Clock) -> Callable[[int], float]:
    """An axis's speed (steps/s, unsigned) at any tick of its running motion."""

    def speed(tick: int) -> float:
        m = axis.motion
        if m is None or (axis.motion_end is not None and tick >= axis.motion_end):
            return 0.0
        return abs(m.velocity((tick - axis.motion_start) * engine.period))

    return speed


def axis_position(axis: MotionAxis, engine: Clock) -> Callable[[int], float]:
    """An axis's physical position (whole steps) at any tick of its running motion."""
    return lambda tick: float(axis.steps_at_tick(tick, engine.period))
