"""Where the MC405's axes are, in closed form, at any servo tick: on arrays of ticks.

A mixin of the machine: the demand position and VP_SPEED of every kind of axis (a run's
path or profile, a CONNPATH or CAMBOX link, at rest) as a function of the tick, valid
from now to the machine's next event, so a single reading and a trace of a whole stretch
are one evaluation; and the tick a CAMBOX completes.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from maxk.firmware_model.sampling import profile_offset_speed

from . import clutch
from .compensate import Compensation
from .frames import Frames
from .link_kinds import Cambox, Connect, Connpath, Movelink
from .links import LinkedMoves
from .runs import Run, TrioAxis


class Kinematics:
    """Positions and speeds of the machine's axes (see the module docstring)."""

    axes: list[TrioAxis]
    queues: list[deque[Run]]
    distance_done: list[float]
    links: LinkedMoves
    frames: Frames
    tick: int
    period: float

    # ---- positions and speeds, on arrays of ticks -----------------------------------------------
    def _now(self) -> np.ndarray:
        return np.array([self.tick])

    def demand_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """The exact demand position (physical counts, DEFPOS not applied) at ticks
        between now and the next event: the axis's own, and what ADDAX adds."""
        return self.links.superimpose(axis, ticks, self.own_counts(axis, ticks))

    def motor_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """The motor's demand (physical counts): `demand_counts`, or with a FRAME on the
        axis the frame's inverse transform of the world demand (frames.py)."""
        return self.frames.motor_counts(axis, ticks)

    def own_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """The demand of the axis's own moves and links (ADDAX's part not included)."""
        a = self.axes[axis]
        link = a.link
        if isinstance(link, Connect) and link.ramp_from is not None:  # CLUTCH_RATE
            leader = link.link
            return clutch.ramped_counts(link, ticks,
                                        lambda at: self.demand_counts(leader, at),
                                        clutch.step_of(a, self.period))
        if isinstance(link, Connect | Movelink):
            return link.counts(self.demand_counts(link.link, ticks))
        if isinstance(link, Connpath):
            travelled = self.path_distance(link.base, ticks) - link.distance0
            return link.origin + link.ratio * travelled * a.units
        if isinstance(link, Cambox):
            return link.counts(self.dpos_at(link.link, ticks))
        if isinstance(link, Compensation):  # COMPENSATE_XY (compensate.py)
            return link.counts(self.dpos_at(link.link, ticks), self.dpos_at(link.link_y, ticks))
        m = a.motion
        if m is None:
            return np.full(ticks.shape, a.steps + a.fraction)
        run = self.queues[axis][0]
        if run.profile is not None:
            offset, _speed = profile_offset_speed(run.profile,
                                                  (ticks - a.motion_start) * self.period)
            position = a.steps + offset
        else:
            assert run.arrays is not None
            s, _v = run.arrays.state((ticks - run.plan_tick) * self.period)
            k = run.axes.index(axis)
            if run.arcs and run.plan is not None:  # MOVECIRC: the planner's own geometry
                plan = run.plan
                position = np.array([plan.point(float(x), k) for x in np.ravel(s)])
            else:
                position = run.arrays.point(s, k)
        if a.motion_end is not None:
            position = np.where(ticks >= a.motion_end, float(a.steps + m.final_offset),
                                position)
        return position

    def dpos_at(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        a = self.axes[axis]
        return (self.demand_counts(axis, ticks) + a.datum) / a.units

    def path_distance(self, base: int, ticks: np.ndarray) -> np.ndarray:
        """The path distance (base user units) every run based on `base` has made."""
        done = self.distance_done[base]
        queue = self.queues[base]
        run = queue[0] if queue else None
        if run is None or not run.started or run.base != base:
            return np.full(ticks.shape, done)
        s, _v = run.distance_speed(ticks, self.period)
        return done + s / run.units

    def vp_speed_at(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """VP_SPEED: the path speed of the run the axis takes part in (every axis of an
        interpolated group reads the group's path speed, I), in the base's user units."""
        a = self.axes[axis]
        link = a.link
        if isinstance(link, Connect | Movelink | Compensation) or axis in self.links.addax:
            # the demand's change over the servo cycle before each tick (D)
            change = self.demand_counts(axis, ticks) - self.demand_counts(axis, ticks - 1)
            return np.abs(change) / (self.period * a.units)
        if isinstance(link, Connpath):
            return abs(link.ratio) * self.path_speed(link.base, ticks)
        if isinstance(link, Cambox):
            slope = link.slope(self.dpos_at(link.link, ticks))
            return np.abs(slope) * self.vp_speed_at(link.link, ticks) / a.units
        queue = self.queues[axis]
        run = queue[0] if queue else None
        if run is None or not run.started:
            return np.zeros(ticks.shape)
        s, v = run.distance_speed(ticks, self.period)
        if run.interp and run.segments:  # INTERP_FACTOR: the interpolated axes' speed
            ends = np.array([seg.s0 + seg.length for seg in run.segments[:-1]])
            index = np.searchsorted(ends, s + 1e-9, side="right")
            share = np.array([run.interp.get(j, 1.0) for j in range(len(run.segments))])
            v = v * share[index]
        return v / run.units

    def path_speed(self, base: int, ticks: np.ndarray) -> np.ndarray:
        queue = self.queues[base]
        run = queue[0] if queue else None
        if run is None or not run.started or run.base != base:
            return np.zeros(ticks.shape)
        return run.distance_speed(ticks, self.period)[1] / run.units

    def demand(self, axis: int) -> float:
        return float(self.demand_counts(axis, self._now())[0])

    def framed(self, axis: int) -> bool:
        """Is a FRAME on the axis (its motor no longer follows DPOS 1:1)?"""
        return self.frames.framed(axis)

    def motor(self, axis: int, tick: int | None = None) -> float:
        """The motor's demand now (or at `tick`, between now and the next event)."""
        ticks = self._now() if tick is None else np.array([tick])
        return float(self.motor_counts(axis, ticks)[0])

    def own_demand(self, axis: int) -> float:
        return float(self.own_counts(axis, self._now())[0])

    def dpos(self, axis: int) -> float:
        return float(self.dpos_at(axis, self._now())[0])

    def vp_speed(self, axis: int) -> float:
        return float(self.vp_speed_at(axis, self._now())[0])

    def counts_at(self, axis: int, tick: int) -> int:
        """Whole counts the axis has made (what PWM_ENCODER counts)."""
        a = self.axes[axis]
        if a.link is not None or self.links.shift[axis] or axis in self.links.addax:
            return math.floor(float(self.demand_counts(axis, np.array([tick]))[0]))
        return a.steps_at_tick(tick, self.period)

    def cambox_end_tick(self, axis: int) -> int | None:
        """The tick the link axis has travelled the CAMBOX's link distance."""
        link = self.axes[axis].link
        assert isinstance(link, Cambox)
        target = link.end_position()  # link axis DPOS, user units
        if target is None or self.links.ends_here(link):
            return None  # on a linked (or ADDAX) link axis: links.py finds its end
        here = self.dpos(link.link)
        if link.follow is not None:  # forward-only links: where the link itself must be
            here = float(link.follow.effective(np.array([here]))[0])
            if here >= target - 1e-9:
                return self.tick
            target = link.follow.raw(target)
        if here >= target - 1e-9:
            return self.tick
        la = self.axes[link.link]
        position = target * la.units - la.datum  # link axis demand, counts
        inner = la.link
        if isinstance(inner, Connpath):
            queue = self.queues[inner.base]
            run = queue[0] if queue else None
            if run is None or not run.started or run.plan is None or inner.ratio <= 0:
                return None
            needed = ((position - inner.origin) / (inner.ratio * la.units)
                      + inner.distance0 - self.distance_done[inner.base]) * run.units
            plan = run.plan
            if needed > plan.s_end and needed <= plan.s_end + 1e-9 * max(1.0, plan.s_end):
                needed = plan.s_end  # the path's end, within rounding
            t = plan.time_at(needed)
            if t is None:
                return None
            return max(self.tick, run.plan_tick + math.ceil(t / self.period - 1e-9))
        if inner is not None or la.motion is None:
            return None  # (a CAMBOX linked to a CAMBOX axis ends when next looked at: D)
        return la.tick_reaching(math.ceil(position - 1e-9), 1, self)  # type: ignore[arg-type]
