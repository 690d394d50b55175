"""The one motion contract of the shared machine.

Every kind of motion an axis can run has this interface: the closed-form profiles of
`profiles.py` (moves, jogs, stops, and linear interpolation as a scaled profile), one
axis's share of a planned path (`path.ContourMotion`), and pulses given per time slot.
The engine, the limit and trigger searches (`MotionAxis.tick_reaching`) and the servo
loop use nothing else of a motion.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

from maxk.firmware_model.profiles import RampShape


class Clock(Protocol):
    """Where time stands: the tick and the update period (an `Engine`, or any controller
    that says so), which is all a motion needs to be evaluated."""

    tick: int
    period: float


class MotionPhase(Protocol):
    """One monotonic stretch of a motion: it starts at `t0` (s from the motion's start),
    lasts `duration` (inf for a slew without end) and travels `direction` at speeds
    between `v1` and `v2`."""

    @property
    def t0(self) -> float: ...
    @property
    def duration(self) -> float: ...
    @property
    def direction(self) -> int: ...
    @property
    def v1(self) -> float: ...
    @property
    def v2(self) -> float: ...
    @property
    def polynomial(self) -> bool: ...  # position is a polynomial in time (servo jumps)
    @property
    def shape(self) -> RampShape: ...  # the ramp's shape (an S-curve is two polynomials)


class MotionPlan(Protocol):
    """A planned motion relative to an integer origin, in closed form."""

    @property
    def phases(self) -> Sequence[MotionPhase]: ...
    @property
    def end_time(self) -> float | None: ...  # None: slews until told otherwise
    @property
    def final_offset(self) -> int: ...  # the whole steps it ends on
    @property
    def ramp_end_time(self) -> float: ...  # when its last speed change completes
    @property
    def direction(self) -> int: ...
    @property
    def monotonic(self) -> bool: ...

    def offset(self, t: float) -> float:
        """Signed offset from the origin at `t` seconds after the start (exact float)."""
        ...

    def velocity(self, t: float) -> float:
        """Signed velocity at `t`, steps/s."""
        ...

    def phase_at(self, t: float) -> MotionPhase | None:
        """The phase running at `t` (None for a motion without phases)."""
        ...
