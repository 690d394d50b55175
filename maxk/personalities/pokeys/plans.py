"""Each axis's motion as the shared machine's `MotionPlan` (firmware_model/motion.py).

A pulse-engine axis runs one of two kinds of motion:

- its internal controller's (also homing and probing): a chain of closed-form profile
  segments from `firmware_model.profiles`, each begun at a slot boundary
  (`SlotMotion`), seen here as one `SegmentPlan`;
- the slot buffer's: pulses per 1 ms time slot, the PoKeys buffer mode, seen as a
  step function over the buffered slots (`PulsePlan`): the pulses of slot k count at
  its end, so the offset at every slot boundary is exactly what the engine will emit.

Plans are views made on demand (the slot loop itself runs on the buffer's numpy rows
and on `SlotMotion`); times are seconds from the plan's first slot, offsets pulses from
the axis's counter there. What a plan does not know: switches, soft limits and the
probe, which may cut it short in the slot loop.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ...firmware_model.motion import MotionPlan
from ...firmware_model.profiles import RampShape
from .constants import SLOT_SECONDS
from .motion import SlotMotion, whole_pulses

_SNAP = 1e-6  # the slack whole_pulses allows: offsets this close to a whole pulse are one


@dataclass(frozen=True, slots=True)
class PlanPhase:
    """One monotonic stretch (the `MotionPhase` protocol)."""

    t0: float
    duration: float
    direction: int
    v1: float
    v2: float
    polynomial: bool
    shape: RampShape


class AxisPlan(NamedTuple):
    """An axis's planned motion: from slot `start`, the counter at `origin` there."""

    start: int
    origin: int
    plan: MotionPlan


class SegmentPlan:
    """An internal-controller motion (a chain of profile segments) as one plan."""

    def __init__(self, motion: SlotMotion) -> None:
        self.motion = motion
        first = motion.segments[0]
        self.start, self.origin = first.start, first.origin
        phases: list[PlanPhase] = []
        segments = motion.segments
        for i, seg in enumerate(segments):
            shift = (seg.start - self.start) * SLOT_SECONDS
            cut = (segments[i + 1].start - seg.start) * SLOT_SECONDS if i + 1 < len(
                segments) else math.inf
            for ph in seg.motion.phases:
                if ph.t0 >= cut:
                    break
                duration = min(ph.duration, cut - ph.t0)
                v2 = ph.v2 if duration == ph.duration else ph.speed(duration)
                phases.append(PlanPhase(ph.t0 + shift, duration, ph.direction, ph.v1, v2,
                                        ph.polynomial, ph.shape))
        self.phases: Sequence[PlanPhase] = phases
        last = segments[-1]
        end = last.motion.end_time
        self.end_time = None if end is None else (last.start - self.start) * SLOT_SECONDS + end
        self.final_offset = last.origin - self.origin + last.motion.final_offset
        self.ramp_end_time = ((last.start - self.start) * SLOT_SECONDS
                              + last.motion.ramp_end_time)
        directions = {p.direction for p in phases if max(p.v1, p.v2) > 0}
        self.monotonic = len(directions) <= 1
        self.direction = phases[0].direction if phases else 1

    def _segment(self, t: float) -> tuple[float, int, object]:
        slot = self.start + t / SLOT_SECONDS
        seg = self.motion.segments[0]
        for s in self.motion.segments[1:]:
            if s.start <= slot + 1e-9:
                seg = s
        return (seg.start - self.start) * SLOT_SECONDS, seg.origin - self.origin, seg.motion

    def offset(self, t: float) -> float:
        """The closed-form offset, so that its whole part (truncated toward zero, as
        `MotionAxis` counts) is the engine's count: each segment counts whole pulses
        from its own origin, so a fraction that would cross a whole pulse toward zero
        (a return move starting on the far side) is left out."""
        t0, base, motion = self._segment(t)
        x = motion.offset(max(0.0, t - t0))  # type: ignore[attr-defined]
        whole = base + whole_pulses(x)
        residual = x - whole_pulses(x)
        if abs(residual) < _SNAP or residual * whole < 0:
            return float(whole)
        return whole + residual

    def velocity(self, t: float) -> float:
        t0, _base, motion = self._segment(t)
        return float(motion.velocity(max(0.0, t - t0)))  # type: ignore[attr-defined]

    def phase_at(self, t: float) -> PlanPhase | None:
        found = None
        for ph in self.phases:
            if ph.t0 <= t:
                found = ph
        return found

    def whole_offset(self, slot: int) -> int:
        """The pulses emitted from the plan's start to slot `slot` (as the engine counts)."""
        return self.motion.position_at(slot) - self.origin


class PulsePlan:
    """Buffered pulses per slot as a step function: exact at every slot boundary."""

    def __init__(self, pulses: np.ndarray) -> None:
        self.pulses = np.asarray(pulses, dtype=np.int64)
        self.cumulative = np.concatenate(([0], np.cumsum(self.pulses)))
        n = len(self.pulses)
        self.end_time: float | None = n * SLOT_SECONDS
        self.ramp_end_time = n * SLOT_SECONDS
        self.final_offset = int(self.cumulative[-1])
        self.phases: Sequence[PlanPhase] = _stretches(self.pulses)
        self.monotonic = len({p.direction for p in self.phases}) <= 1
        self.direction = self.phases[0].direction if self.phases else 1

    def _slot(self, t: float) -> int:
        return min(max(0, math.floor(t / SLOT_SECONDS + 1e-9)), len(self.pulses))

    def offset(self, t: float) -> float:
        return float(self.cumulative[self._slot(t)])

    def velocity(self, t: float) -> float:
        k = self._slot(t)
        return float(self.pulses[k]) / SLOT_SECONDS if k < len(self.pulses) else 0.0

    def phase_at(self, t: float) -> PlanPhase | None:
        found = None
        for ph in self.phases:
            if ph.t0 <= t + 1e-12:
                found = ph
        return found


def _stretches(pulses: np.ndarray) -> list[PlanPhase]:
    """Monotonic stretches: a new one wherever the direction of travel turns (slots
    without pulses belong to the stretch they are in)."""
    moving = np.flatnonzero(pulses)
    if not len(moving):
        return []
    signs = np.sign(pulses[moving])
    turns = moving[np.flatnonzero(np.diff(signs)) + 1]
    starts = [0, *turns.tolist()]
    ends = [*turns.tolist(), len(pulses)]
    out = []
    for a, b in zip(starts, ends, strict=True):
        chunk = np.abs(pulses[a:b])
        direction = int(np.sign(pulses[a:b][np.flatnonzero(pulses[a:b])[0]]))
        out.append(PlanPhase(a * SLOT_SECONDS, (b - a) * SLOT_SECONDS, direction,
                             float(chunk.min()) / SLOT_SECONDS,
                             float(chunk.max()) / SLOT_SECONDS, False, RampShape.LINEAR))
    return out


def segment_plan(motion: SlotMotion) -> AxisPlan:
    plan = SegmentPlan(motion)
    return AxisPlan(plan.start, plan.origin, plan)


def pulse_plan(slot: int, counter: int, pulses: np.ndarray) -> AxisPlan | None:
    return AxisPlan(slot, counter, PulsePlan(pulses)) if len(pulses) else None


__all__ = ["AxisPlan", "PlanPhase", "PulsePlan", "SegmentPlan", "pulse_plan",
           "segment_plan", "whole_pulses"]
