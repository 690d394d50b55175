"""Closed-form motions evaluated on arrays of times (numpy): a path plan's distance,
speed and points, a profile's offset and speed, at many times at once and exactly as
the one-at-a-time evaluations give them. A trace of every servo cycle of a stretch, or
a computed output loaded each cycle, costs a few array operations instead of a Python
call a tick."""

from __future__ import annotations

import math

import numpy as np

from .path import PathPlan, Segment
from .profiles import Motion, RampShape


class PlanArrays:
    """A path plan's pieces and segments as arrays: (s, speed) and the points of the
    path at many times at once, exactly as `PathPlan.state` and `PathPlan.point` give
    them one at a time."""

    def __init__(self, plan: PathPlan, previous: PlanArrays | None = None) -> None:
        self.plan = plan
        pieces = plan.pieces
        self.t0 = np.array([p.t0 for p in pieces], dtype=float)
        self.duration = np.array([p.duration for p in pieces], dtype=float)
        self.s0 = np.array([p.s0 for p in pieces], dtype=float)
        self.v0 = np.array([p.v0 for p in pieces], dtype=float)
        self.a = np.array([p.a for p in pieces], dtype=float)
        jerks = [p.j for p in pieces]
        self.j = np.array(jerks, dtype=float) if any(jerks) else None  # S-ramps
        nxt = [pieces[i + 1].s0 for i in range(len(pieces) - 1)] + [math.inf]
        self.next_s0 = np.array(nxt if pieces else [], dtype=float)
        segs = plan.segments
        table: _SegmentTable | None = previous.table if previous is not None else None
        if table is None or not table.extends(segs):
            table = _SegmentTable(segs)
        self.table: _SegmentTable = table
        n = table.add(segs)
        self.seg_s0 = table.s0[:n]
        self.seg_length = table.length[:n]
        self.seg_start = table.start[:n]
        self.seg_end = table.end[:n]
        self.seg_unit = table.unit[:n]

    def state(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        plan = self.plan
        if t.size == 1:  # one reading: the plan's own (memoised) evaluation
            s1, v1 = plan.state(float(t.flat[0]))
            return np.full(t.shape, s1), np.full(t.shape, v1)
        if not plan.pieces:
            return np.full(t.shape, plan.s_end), np.zeros(t.shape)
        i = np.maximum(np.searchsorted(self.t0, t, side="right") - 1, 0)
        tau = np.minimum(t - self.t0[i], self.duration[i])
        if self.j is None:
            s = self.s0[i] + self.v0[i] * tau + 0.5 * self.a[i] * tau * tau
            v = np.maximum(0.0, self.v0[i] + self.a[i] * tau)
        else:  # (Piece.s and Piece.v with their jerk, on arrays)
            j = self.j[i]
            cubic = self.s0[i] + tau * (self.v0[i] + tau * (0.5 * self.a[i] + tau * j / 6.0))
            s = np.where(j != 0, cubic,
                         self.s0[i] + self.v0[i] * tau + 0.5 * self.a[i] * tau * tau)
            v = np.maximum(0.0, np.where(j != 0, self.v0[i] + tau * (self.a[i] + 0.5 * j * tau),
                                         self.v0[i] + self.a[i] * tau))
        s = np.minimum(s, self.next_s0[i])
        if plan.end_time is not None:
            done = t >= plan.end_time
            s = np.where(done, plan.s_end, s)
            v = np.where(done, 0.0, v)
        return s, v

    def point(self, s: np.ndarray, k: int) -> np.ndarray:
        """Axis k's coordinate at path distances s (straight segments: MOVE, MOVEABS)."""
        j = np.maximum(np.searchsorted(self.seg_s0, s, side="right") - 1, 0)
        # (PathPlan.segment_at steps back over zero-length segments: they add nothing here,
        # a zero-length segment's start and end are the same point)
        sigma = s - self.seg_s0[j]
        inside = self.seg_start[j, k] + self.seg_unit[j, k] * sigma
        return np.where(sigma >= self.seg_length[j], self.seg_end[j, k], inside)


class _SegmentTable:
    """A path's segments as arrays, grown as moves merge into it (its list only grows,
    the segments already there never change place): a re-plan of a chain of thousands of
    merged moves adds the new rows instead of converting the whole path again."""

    def __init__(self, segments: list[Segment]) -> None:
        self.segments = segments
        self.count = 0
        self._last: Segment | None = None
        width = len(segments[0].start) if segments else 0
        capacity = max(16, len(segments))
        self.s0 = np.zeros(capacity)
        self.length = np.zeros(capacity)
        self.start = np.zeros((capacity, width))
        self.end = np.zeros((capacity, width))
        self.unit = np.zeros((capacity, width))

    def extends(self, segments: list[Segment]) -> bool:
        """The same path list, its rows so far unchanged (only appended to)."""
        n = self.count
        return (segments is self.segments and n > 0 and len(segments) >= n
                and segments[n - 1] is self._last)

    def add(self, segments: list[Segment]) -> int:
        """Rows for the segments not yet in the table; the row count."""
        n, total = self.count, len(segments)
        if total > len(self.s0):
            capacity = max(total, 2 * len(self.s0))
            for name in ("s0", "length", "start", "end", "unit"):
                old = getattr(self, name)
                grown = np.zeros((capacity, *old.shape[1:]))
                grown[:n] = old[:n]
                setattr(self, name, grown)
        if total > n:
            new = segments[n:]
            self.s0[n:total] = [g.s0 for g in new]
            self.length[n:total] = [g.length for g in new]
            self.start[n:total] = [g.start for g in new]
            self.end[n:total] = [g.end for g in new]
            self.unit[n:total] = [g.unit for g in new]
            self._last = segments[-1]
            self.count = total
        return total


def profile_offset_speed(motion: Motion, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A profile's signed offset and speed (unsigned) at many times: linear ramps as
    arrays; any other ramp shape one time at a time through the profile's own exact
    evaluation (S-ramps, parabolic ramps: their pieces are not array formulas here)."""
    phases = motion.phases
    if not phases:
        return np.full(t.shape, float(motion.final_offset)), np.zeros(t.shape)
    if any(p.shape is not RampShape.LINEAR and p.v1 != p.v2 for p in phases):
        flat = np.ravel(t)
        offset = np.array([motion.offset(float(x)) for x in flat]).reshape(t.shape)
        speed = np.array([abs(motion.velocity(float(x))) for x in flat]).reshape(t.shape)
        return offset, speed
    t0 = np.array([p.t0 for p in phases])
    i = np.maximum(np.searchsorted(t0, t, side="right") - 1, 0)
    dur = np.array([p.duration for p in phases])[i]
    s0 = np.array([p.s0 for p in phases])[i]
    v1 = np.array([p.v1 for p in phases])[i]
    v2 = np.array([p.v2 for p in phases])[i]
    direction = np.array([p.direction for p in phases], dtype=float)[i]
    tau = t - t0[i]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.clip(np.where(dur > 0, tau / dur, 0.0), 0.0, 1.0)
    ramp = v1 != v2
    distance = np.where(ramp, v1 * tau + (v2 - v1) * dur * (u * u / 2.0), v1 * tau)
    speed = np.where(ramp & (dur > 0), v1 + (v2 - v1) * u, v1)
    offset = s0 + direction * distance
    if motion.end_time is not None:
        done = t >= motion.end_time
        offset = np.where(done, float(motion.final_offset), offset)
        speed = np.where(done, 0.0, speed)
    return offset, speed
