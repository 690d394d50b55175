"""Tangential control on the MC405: TANG_DIRECTION and MOVETANG (TrioBASIC help pages).

- TANG_DIRECTION AXIS(n): the direction, in radians, of the path the interpolated group of
  axis n follows, from its first two axes (X, Y): atan2(X, Y), so +Y reads 0, +X PI/2,
  -X -PI/2, -Y PI (the page's table, C). Exact: the tangent of the path segment the group
  is on at this servo tick, whatever its speed. A single-axis move counts as X alone
  (D). At rest the direction of the last path the axis ended is kept (D); 0 at power-up.
- MOVETANG(position) AXIS(n): move axis n at its SPEED, ACCEL, DECEL to `position` the
  short way round, the axis's REP_DIST being half a turn (PI) (page, C); `position` must be
  within -REP_DIST..REP_DIST (page: -PI..PI in the axis's units; outside it and a
  REP_DIST that is not positive are refused, D). Called again while its move runs, the
  end moves to the new position from where the axis is, at the speed it has (page:
  "a tight loop which updates the end position"; re-planned as MOVEMODIFY, I). MTYPE 30
  while it moves (C: MTYPE page); the page keeps MTYPE 30 after the move ends, here it
  returns to 0 so WAIT IDLE ends (D). The link_axis form (the end copied from another
  axis's TANG_DIRECTION every servo cycle) is refused: a target moved every cycle is not
  a closed-form motion of the shared machine (D).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol

import numpy as np

from . import moves
from .runs import Run

MOVETANG = 30  # MTYPE (C: the MTYPE page)


class Host(moves.Host, Protocol):
    """What tangential control needs of the machine beyond the moves' Host."""

    tangents: dict[int, float]

    def dpos(self, axis: int) -> float: ...


def _tangent(run: Run, s: float | None) -> float | None:
    """atan2(X, Y) of the run's path at distance s (its end when s is None)."""
    if run.plan is None or run.profile is not None or not run.segments:
        if run.profile is not None:  # a single-axis move: X alone
            return math.pi / 2 if run.profile.final_offset >= 0 else -math.pi / 2
        return None
    plan = run.plan
    segment = plan.segment_at(plan.s_end if s is None else s)
    sigma = (plan.s_end if s is None else s) - segment.s0
    x = segment.slope(sigma, 0)
    y = segment.slope(sigma, 1) if len(run.axes) > 1 else 0.0
    if x == 0 and y == 0:
        return None
    return math.atan2(x, y)


def direction(m: Host, axis: int) -> float:
    """TANG_DIRECTION AXIS(axis)."""
    queue = m.queues[axis]
    run = queue[0] if queue else None
    if run is not None and run.started:
        s = None
        if run.plan is not None and run.profile is None:
            s_now, _v = run.distance_speed(np.array([m.tick]), m.period)
            s = float(s_now[0])
        found = _tangent(run, s)
        if found is not None:
            return found
    return m.tangents.get(axis, 0.0)


def finished(m: Host, run: Run) -> None:
    """A run ended: its axes keep the direction it ended with (TANG_DIRECTION at rest)."""
    found = _tangent(run, None)
    if found is not None:
        for a in run.axes:
            m.tangents[a] = found


def movetang(m: Host, axis: int, args: Sequence[float], min_rate: float) -> None:
    if len(args) != 1:
        raise ValueError("Parameter out of range")  # the link_axis form (D, see above)
    a = m.axes[axis]
    rep = a.params.get("REP_DIST", 0.0)
    if not rep > 0 or not -rep <= args[0] <= rep:
        raise ValueError("Parameter out of range")
    here = m.dpos(axis)
    turn = 2.0 * rep
    delta = (args[0] - here + rep) % turn - rep  # the short way round (half: forward)
    target = here + delta
    queue = m.queues[axis]
    run = queue[0] if queue else None
    if run is not None and run.started and set(run.kinds.values()) == {MOVETANG}:
        moves.movemodify(m, axis, target, min_rate)
        queue[0].kinds = dict.fromkeys(range(len(queue[0].deltas)), MOVETANG)
        return
    if not m.axis_idle(axis):
        raise ValueError("Parameter out of range")  # another move runs on it (D)
    m._load((axis,), [round(m._counts(axis, delta))], kind=MOVETANG)


__all__ = ["MOVETANG", "direction", "finished", "movetang"]
