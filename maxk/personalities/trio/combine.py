"""COMBINE_AXES and COMBINE_CONTROL: an axis whose DPOS is computed from two others
(TrioBASIC help COMBINE_AXES, COMBINE_CONTROL; newer than the MC405's token table,
helpwords.NEWER_WORDS).

From the pages (C unless marked):
- COMBINE_AXES(axis_a, axis_b) AXIS(n) makes axis n's DPOS a function of axis_a's and
  axis_b's positions, the function COMBINE_CONTROL(mode, ...) AXIS(n) sets: mode 0 the sum,
  1 the difference (a - b), 3 the average, each source times numerator / denominator;
  mode 2 sqrt((a + offset_1)^2 + (b + offset_2)^2), COMBINE_CONTROL(2, offset_1, offset_2).

Decided here (D):
- It is a linked move of axis n, as COMPENSATE_XY (compensate.py): it waits behind the
  moves buffered before it, CANCEL ends it, MTYPE reads 26 (no page gives its MTYPE).
- DPOS is the function itself (absolute: the axis steps to it when it starts).
- The sources follow the axes' demand (DPOS), the machine's convention for links; the
  MPOS choice (source 1) is the demand too, as COMPENSATE_XY's opt (the two agree on
  steppers, virtual axes and any axis whose MPOS is its demand).
- COMBINE_CONTROL before COMBINE_AXES is kept for it; after, it changes the running one
  at once. With none given: mode 0 with ratios 1 (the sum). A denominator of 0, a mode
  other than 0..3 or the wrong count of arguments: 'Parameter out of range', nothing set.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from .compensate import Compensation

SUM = (0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0)  # mode, source_1, source_2, n1, d1, n2, d2


@dataclass
class Combination(Compensation):
    """One COMBINE_AXES: `link` axis_a, `link_y` axis_b (the names the machine's link
    checks look for); `control` its COMBINE_CONTROL, shared with the axis's setting."""

    control: list[float] = field(default_factory=lambda: list(SUM))
    datum: float = 0.0  # the axis's DEFPOS offset (counts) when it started

    def value(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """DPOS (the axis's user units) with axis_a at x and axis_b at y."""
        c = self.control
        if c[0] == 2:
            return np.asarray(np.hypot(x + c[1], y + c[2]), dtype=float)
        a, b = x * c[3] / c[4], y * c[5] / c[6]
        if c[0] == 1:
            return np.asarray(a - b, dtype=float)
        return np.asarray((a + b) / 2 if c[0] == 3 else a + b, dtype=float)

    def begin(self, x: float, y: float) -> None:
        """Absolute: the own demand is DPOS less the datum, so `start` takes the origin."""
        self.start = (self.origin + self.datum) / self.units


class Combinations:
    """Each axis's COMBINE_CONTROL setting (kept for its next COMBINE_AXES)."""

    def __init__(self) -> None:
        self.controls: dict[int, list[float]] = {}

    def reset(self) -> None:
        self.controls.clear()

    def control(self, axis: int, args: Sequence[float]) -> list[float]:
        """COMBINE_CONTROL(mode, ...) AXIS(n): checked whole, then kept (and returned, so
        a running combination takes it)."""
        mode = args[0] if args else -1
        if mode == 2 and len(args) == 3:
            setting = [2.0, float(args[1]), float(args[2]), 1.0, 1.0, 1.0, 1.0]
        elif mode in (0, 1, 3) and len(args) in (3, 7):
            ratios = list(args[3:]) if len(args) == 7 else [1.0, 1.0, 1.0, 1.0]
            if ratios[1] == 0 or ratios[3] == 0 or args[1] not in (0, 1) \
                    or args[2] not in (0, 1):
                raise ValueError("Parameter out of range")
            setting = [float(mode), float(args[1]), float(args[2]), *map(float, ratios)]
        else:
            raise ValueError("Parameter out of range")
        kept = self.controls.setdefault(axis, list(SUM))
        kept[:] = setting
        return kept

    def combination(self, axis: int, args: Sequence[float], check: Callable[[float], int],
                    units: float, datum: float) -> Combination:
        """COMBINE_AXES(axis_a, axis_b) AXIS(n): the link it loads."""
        if len(args) != 2:
            raise ValueError("Syntax error")
        first, second = check(args[0]), check(args[1])
        return Combination(grid=np.zeros((1, 1)), link=first, link_y=second, x_offset=0.0,
                           x_dist=1.0, y_offset=0.0, y_dist=1.0, units=units,
                           control=self.controls.setdefault(axis, list(SUM)), datum=datum)
