"""CLUTCH_RATE: a running CONNECT takes a new ratio at a rate, not at once.

The CLUTCH_RATE and CONNECT pages of the TrioBASIC help: a second CONNECT on the same
link axis changes the ratio at the base axis's CLUTCH_RATE (ratio per second, default
1,000,000: so fast it is at once), without cancelling the first; the CONNECT page's
example starts with CONNECT(0, link) to avoid the step a fresh CONNECT makes, so a fresh
CONNECT takes its ratio at once (C: the example's words).

How each servo cycle moves the axis (D: the pages give the rate, not the cycle's
arithmetic): in the k-th servo cycle after the change the ratio is the old one plus
k x CLUTCH_RATE x the servo period, capped at the new ratio, and the axis moves that
ratio times the link axis's demand change over the cycle. So from the old ratio r0 to
r1 at rate c the ramp lasts ceil(|r1 - r0| / (c T)) cycles, and a link at a constant v
counts a cycle carries the axis sum(r_k) x v over it.

The sum of ratio x link step is not a closed form of the link's position, so while a
ratio ramps the CONNECT is folded at every servo tick (`ClutchWatch`, an event source):
its origin moves to that tick's position and its ratio to that cycle's. Between folds
the position at any tick is the sum over the link's demand at every tick from the fold
(`ramped_counts`), which the folds keep to one or two ticks. The rate is read at each
cycle from the axis's CLUTCH_RATE, so a new rate acts from the next cycle (D). A ratio
change that one cycle's step covers is taken at once, as before this module (C: the
default rate).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Protocol

import numpy as np

from .link_kinds import Connect
from .runs import TrioAxis


class Host(Protocol):
    axes: list[TrioAxis]
    tick: int
    period: float

    def changed(self) -> None: ...
    def _now(self) -> np.ndarray: ...
    def demand_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...
    def own_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...


def step_of(axis: TrioAxis, period: float) -> float:
    """The most a ratio may change in one servo cycle on this axis."""
    return max(float(axis.params.get("CLUTCH_RATE", 1e6)), 0.0) * period


def ratio_after(link: Connect, cycles: np.ndarray, step: float) -> np.ndarray:
    """The ratio of the `cycles`-th servo cycle after the fold (1 the first)."""
    assert link.ramp_from is not None
    gap = link.ratio - link.ramp_from
    return link.ramp_from + math.copysign(1.0, gap) * np.minimum(cycles * step, abs(gap))


def ramped_counts(link: Connect, ticks: np.ndarray, leader: Callable[[np.ndarray], np.ndarray],
                  step: float) -> np.ndarray:
    """The base axis's demand (counts) at `ticks` while its ratio ramps: the origin at the
    fold tick plus, cycle by cycle, that cycle's ratio times the link's demand change. A
    tick before the fold is taken back at the fold's ratio (VP_SPEED reads the cycle
    before now)."""
    ticks = np.asarray(ticks)
    if step == 0:  # CLUTCH_RATE 0: the ratio holds where it is (a plain gearing)
        assert link.ramp_from is not None
        at_fold = float(leader(np.array([link.since]))[0])
        return link.origin + link.ramp_from * (leader(ticks) - at_fold)
    assert link.ramp_from is not None
    since = link.since
    # the ramp's last cycle: beyond it the ratio is the new one, a plain gearing again
    # (so a search far ahead sums only the ramp's cycles)
    last = since + math.ceil(abs(link.ratio - link.ramp_from) / step - 1e-12)
    low = min(int(np.min(ticks)), since)
    high = min(max(int(np.max(ticks)), since), last)
    span = np.arange(low, high + 1)
    lead = leader(span)
    at_fold = float(lead[since - low])
    after = lead[since - low:]
    n = len(after) - 1
    ratios = ratio_after(link, np.arange(1, n + 1, dtype=float), step)
    ahead = np.concatenate(([0.0], np.cumsum(ratios * np.diff(after))))
    behind = link.ramp_from * (lead[:since - low] - at_fold)
    moved = np.concatenate((behind, ahead))
    inside = np.minimum(ticks, high) - low
    out = link.origin + moved[inside]
    beyond = ticks > high
    if np.any(beyond):  # past the ramp: its end plus the new ratio x the link's change
        out = np.where(beyond, link.origin + moved[-1]
                       + link.ratio * (leader(np.maximum(ticks, high)) - float(lead[-1])),
                       out)
    return out


def change_ratio(m: Host, axis: int, link: Connect, ratio: float) -> None:
    """A second CONNECT on the same link axis: from the ratio it has now towards `ratio`
    at the axis's CLUTCH_RATE (at once if one cycle's step covers the change)."""
    now = m._now()
    here = float(m.own_counts(axis, now)[0])
    current = link.ratio if link.ramp_from is None else float(
        ratio_after(link, np.array([float(m.tick - link.since)]),
                    step_of(m.axes[axis], m.period))[0])
    link.origin, link.link_origin = here, float(m.demand_counts(link.link, now)[0])
    link.since, link.ratio = m.tick, ratio
    step = step_of(m.axes[axis], m.period)
    link.ramp_from = None if abs(ratio - current) <= step else current
    m.changed()


class ClutchWatch:
    """The engine's event source for ramping CONNECT ratios: a fold at every servo tick
    while one ramps (see the module docstring)."""

    def __init__(self, machine: Host) -> None:
        self.machine = machine

    def _ramping(self) -> list[tuple[int, Connect]]:
        return [(i, a.link) for i, a in enumerate(self.machine.axes)
                if isinstance(a.link, Connect) and a.link.ramp_from is not None]

    def next_event(self) -> int | None:
        m = self.machine
        due = [link.since + 1 for i, link in self._ramping()
               if step_of(m.axes[i], m.period) > 0]  # (at rate 0 nothing changes)
        return max(min(due), m.tick) if due else None

    def new_rate(self, axis: int) -> None:
        """CLUTCH_RATE is about to change on the axis: its ramp is folded to now at the
        old rate first (a rate of 0 is not folded at every tick)."""
        link = self.machine.axes[axis].link
        if isinstance(link, Connect) and link.ramp_from is not None:
            self.fold([(axis, link)], self.machine.tick)

    def on_event(self, now: int) -> None:
        self.fold([(i, link) for i, link in self._ramping() if link.since < now], now)

    def fold(self, ramps: list[tuple[int, Connect]], now: int) -> None:
        m = self.machine
        if not ramps:
            return
        for axis, link in ramps:
            step = step_of(m.axes[axis], m.period)
            here = float(m.own_counts(axis, np.array([now]))[0])
            cycles = float(now - link.since)
            assert link.ramp_from is not None
            done = cycles * step >= abs(link.ratio - link.ramp_from)
            ratio = float(ratio_after(link, np.array([cycles]), step)[0])
            link.origin = here
            link.link_origin = float(m.demand_counts(link.link, np.array([now]))[0])
            link.since = now
            link.ramp_from = None if done else ratio
        m.changed()


__all__ = ["ClutchWatch", "change_ratio", "ramped_counts", "step_of"]
