"""COMPENSATE_XY: a correction from a 2D grid in TABLE, superimposed on an axis.

From the COMPENSATE_XY and MTYPE pages of the TrioBASIC help (C unless marked):
- COMPENSATE_XY(table, opt, x_axis, x_div, x_dist, x_offset, y_axis, y_div, y_dist,
  y_offset) AXIS(n) puts a correction on axis n, read from a grid of x_div by y_div
  TABLE values from `table`, laid out X fastest (X0Y0, X1Y0, ... then X0Y1, ...), the
  values evenly spread over x_dist from x_offset (the end points count in x_div) and
  the same for Y; the grid is interpolated linearly in both dimensions; outside the
  working area the nearest value inside it applies (so each coordinate is clamped to
  its edge). Distances are in the X and Y axes' units, the TABLE values in the axis's.
- When it is given, the correction at the present position is taken as an offset, so
  the axis does not jump: the axis moves by the change of the correction from there.
- It is a motion of the axis (MTYPE 26), ended by CANCEL; the page's layout drives
  the axis from virtual axes by ADDAX, the correction adding to what ADDAX adds.

Decided here (D):
- It is a linked move: it waits in the axis's buffer behind moves loaded before it
  (as CONNPATH and CAMBOX) and moves loaded after it wait for its CANCEL.
- opt bit 0 chooses MPOS (0) or DPOS (1) of the X and Y axes: both follow the axes'
  demand here, the machine's convention for every link (CONNECT's MPOS mode too); the
  two agree on the page's virtual axes, steppers and other axes whose MPOS is their
  demand. The X and Y axes may not be the axis itself, nor follow it (a correction
  following itself has no position): 'Invalid axis number' / 'Parameter out of range'.
- The grid is read from TABLE when the command is given (a later TABLE write takes
  effect at the next COMPENSATE_XY) and the axis's UNITS then scale it to counts.
- A division count must be a whole number from 1 (one value: the correction does not
  vary along that axis), a distance above 0, the grid inside TABLE, opt 0 or 1; else
  'Parameter out of range', nothing loaded.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

MTYPE = 26  # MTYPE page: COMPENSATE_XY


@dataclass
class Compensation:
    """One COMPENSATE_XY: the grid and its working area; `link` and `link_y` the X and
    Y axes it follows (the name the machine's link checks look for)."""

    grid: np.ndarray  # shape (y_div, x_div), the axis's user units
    link: int  # the X axis
    link_y: int  # the Y axis
    x_offset: float
    x_dist: float
    y_offset: float
    y_dist: float
    units: float  # the axis's counts per user unit when it was given
    origin: float = 0.0  # the axis's own demand (counts) when it took effect
    start: float = 0.0  # the correction (user units) there, taken as the offset

    def value(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """The correction (the axis's user units) at X and Y positions (their units)."""
        y_div, x_div = self.grid.shape
        i, fx = _cell(x, self.x_offset, self.x_dist, x_div)
        j, fy = _cell(y, self.y_offset, self.y_dist, y_div)
        i1 = np.minimum(i + 1, x_div - 1)
        j1 = np.minimum(j + 1, y_div - 1)
        g = self.grid
        low = g[j, i] * (1.0 - fx) + g[j, i1] * fx
        high = g[j1, i] * (1.0 - fx) + g[j1, i1] * fx
        return np.asarray(low * (1.0 - fy) + high * fy, dtype=float)

    def begin(self, x: float, y: float) -> None:
        """It takes effect with the axes at x and y: the correction there is the offset."""
        self.start = float(self.value(np.array([x]), np.array([y]))[0])

    def counts(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """The axis's own demand (counts) with the X and Y axes at x and y."""
        return self.origin + (self.value(x, y) - self.start) * self.units


def _cell(position: np.ndarray, offset: float, dist: float, div: int
          ) -> tuple[np.ndarray, np.ndarray]:
    """The grid index below each position and the fraction of the way to the next,
    clamped to the working area (the nearest value inside it applies outside)."""
    if div == 1:
        zero = np.zeros(np.shape(position), dtype=int)
        return zero, np.zeros(np.shape(position))
    u = np.clip((np.asarray(position, dtype=float) - offset) / dist, 0.0, 1.0) * (div - 1)
    index = np.minimum(np.floor(u).astype(int), div - 2)
    return index, u - index


def _whole(value: float, low: int) -> int:
    if value != int(value) or value < low or not math.isfinite(value):
        raise ValueError("Parameter out of range")
    return int(value)


def compensation_from(args: Sequence[float], check_axis: Callable[[float], int],
                      read_run: Callable[[int, int], list[float]], table_size: int,
                      units: float) -> Compensation:
    """The COMPENSATE_XY of the arguments (every one checked before anything loads)."""
    if len(args) != 10:
        raise ValueError("Syntax error")
    table, opt, x_axis, x_div, x_dist, x_offset, y_axis, y_div, y_dist, y_offset = args
    x = check_axis(x_axis)
    y = check_axis(y_axis)
    if opt not in (0, 1) or not x_dist > 0 or not y_dist > 0:
        raise ValueError("Parameter out of range")
    start = _whole(table, 0)
    nx, ny = _whole(x_div, 1), _whole(y_div, 1)
    if start + nx * ny > table_size:
        raise ValueError("Parameter out of range")
    values = np.array(read_run(start, start + nx * ny - 1), dtype=float).reshape(ny, nx)
    return Compensation(values, x, y, x_offset, x_dist, y_offset, y_dist, units)


__all__ = ["MTYPE", "Compensation", "compensation_from"]
