"""A verified trajectory running on the shared path planner, with its synchronized pulses.

The elements become the planner's segments (`firmware_model/path.py`: lines to absolute
end points, arcs by centre and sweep), in the trajectory's own coordinates (user units,
relative to where X and Y stood at ET). The speed is planned along the path at VV with
VS as the acceleration: from rest, blending every seam without stopping, down to rest at
the end of the last element (arcs are also held to sqrt(VS R), the planner's centripetal
rule). X and Y each follow their coordinate of the plan, in counts of their own TU (the
shared `ContourMotion` with a scale), so the two axes may have different resolutions and
the arcs stay circles in user units.

Pulses (manual 6.1.2): NN pulses at equal curvilinear distances from the start of
element NB to the end of element NE, each fired on the first update tick at which the
path has reached its distance (`outputs.path_trigger_ticks` over `EvenlySpaced`
distances, a batch at a time, so an MPN of a million pulses costs nothing until they are
due). Each pulse is logged with its tick and where X and Y stood then (whole counts).
"""

from __future__ import annotations

import bisect
import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Final, Protocol

from maxk.firmware_model.outputs import EvenlySpaced, path_trigger_ticks
from maxk.firmware_model.path import (
    ContourMotion,
    PathPlan,
    Segment,
    SegmentDef,
    plan_path,
    plan_stop,
)

from .geometry import Arc, Geometry
from .stage import MM4005Axis
from .trajectory import TrajectoryRun, path_extent

if TYPE_CHECKING:
    from maxk.firmware_model.engine import Engine

PULSE_BATCH: Final = 256  # pulse ticks computed ahead at a time


class PulseSink(Protocol):
    """Where fired pulses go: the machine's bounded pulse trace."""

    def begin(self) -> None: ...

    def add(self, record: PulseRecord) -> None: ...


def axis_motion(plan: PathPlan, k: int, resolution: float, origin: int,
                span: tuple[float, float]) -> ContourMotion:
    """One axis's coordinate of the plan (user units) in its own counts: the shared
    `ContourMotion` scaled by 1 / TU. ``origin`` is the whole counts the axis had already
    moved along this trajectory when the plan began (0 at ET, more after a stop re-plan);
    ``span`` the path's extent in user units, so limit searches skip switches the path
    never reaches."""
    scale = 1.0 / resolution
    motion = ContourMotion(plan, k, origin, scale)
    motion.reach = (span[0] * scale - origin - 1.0, span[1] * scale - origin + 1.0)
    return motion


def segment_defs(elements: tuple[Geometry, ...], velocity: float,
                 acceleration: float) -> list[SegmentDef]:
    """The elements as the planner's segments: every seam blended at VV, VS throughout."""
    defs = []
    for g in elements:
        if isinstance(g, Arc):
            defs.append(SegmentDef("arc", g.centre, False, g.sweep, None, velocity,
                                   acceleration, None))
        else:
            defs.append(SegmentDef("line", g.end, False, 0.0, None, velocity,
                                   acceleration, None))
    return defs


def resolve(defs: list[SegmentDef]) -> list[Segment]:
    segments: list[Segment] = []
    for defn in defs:
        if segments:
            last = segments[-1]
            segments.append(Segment(defn, last.end, last.s0 + last.length, last.v_end))
        else:
            segments.append(Segment(defn, (0.0, 0.0), 0.0, None))
    return segments


@dataclass(frozen=True, slots=True)
class PulseRecord:
    """One pulse on the auxiliary output: its number (0 first), the tick it fired on, the
    path distance it was planned at, the element it belongs to, and X/Y then (whole
    counts, and the same in user units)."""

    index: int
    tick: int
    distance: float
    element: int
    x_counts: int
    y_counts: int
    x: float
    y: float


class TrajectoryExecution:
    """ET's run: the plan, the axes following it, the pulses, AT. An event source."""

    def __init__(self, run: TrajectoryRun, x: MM4005Axis, y: MM4005Axis,
                 engine: Engine, pulses: PulseSink) -> None:
        self.run = run
        self.axes = (x, y)
        self.engine = engine
        self.segments = resolve(segment_defs(run.elements, run.velocity, run.acceleration))
        self.starts = [seg.s0 for seg in self.segments]
        x0, x1, y0, y1 = path_extent(run.elements)
        self._spans = ((x0, x1), (y0, y1))
        self.start_counts = (x.counts(engine), y.counts(engine))
        self._moved_origin = (x.steps, y.steps)  # physical steps at ET
        self.plan: PathPlan = plan_path(self.segments, 0, 0.0, 0.0, 1.0)
        self.plan_tick = engine.tick
        self.end_tick: int | None = None
        self.finished = False
        self.stopping = False
        self.pulses = pulses
        pulses.begin()
        self._pulse_distances: EvenlySpaced | None = None
        self._pulse_end = 0.0
        self._next_pulse = 0  # index of the first pulse not yet scheduled or fired
        self._due: list[tuple[int, int]] = []  # (tick, index), the next one last
        plan = run.pulses
        if plan is not None:
            first = self.segments[plan.start_element - 1].s0
            last_seg = self.segments[plan.end_element - 1]
            self._pulse_end = last_seg.s0 + last_seg.length
            self._pulse_distances = EvenlySpaced(
                first, (self._pulse_end - first) / (plan.count - 1), plan.count)
        self._begin()

    # ---- planning --------------------------------------------------------------------
    def _begin(self) -> None:
        engine = self.engine
        plan = self.plan
        self.end_tick = None if plan.end_time is None else (
            self.plan_tick + math.ceil(plan.end_time / engine.period - 1e-9))
        for k, axis in enumerate(self.axes):
            moved = axis.steps - self._moved_origin[k]
            motion = axis_motion(plan, k, axis.resolution, moved, self._spans[k])
            axis.begin(motion, engine)  # type: ignore[arg-type]
            axis.target_counts = self.start_counts[k] + moved + motion.final_offset
        self._due = []
        self._schedule_pulses()

    def _distances(self) -> Iterator[tuple[float, int]]:
        """The pulses not yet scheduled; the last one lands exactly on the end of NE."""
        spaced = self._pulse_distances
        assert spaced is not None
        end = self._pulse_end
        for distance, index in spaced.from_index(self._next_pulse):
            yield (end if index == spaced.count - 1 else min(distance, end)), index

    def _schedule_pulses(self) -> None:
        if self._pulse_distances is None or self._due:
            return
        batch = path_trigger_ticks(self.plan, self.plan_tick, self.engine.period,
                                   itertools.islice(self._distances(), PULSE_BATCH))
        self._due = batch[::-1]
        if batch:
            self._next_pulse = batch[-1][1] + 1

    def stop(self) -> None:
        """ST, a limit: ramp down along the path at VS; later pulses are not reached."""
        if self.finished or self.stopping:
            return
        engine = self.engine
        t = (engine.tick - self.plan_tick) * engine.period
        s, v = self.plan.state(t)
        for axis in self.axes:
            axis.freeze(engine)
        self.stopping = True
        self.plan = plan_stop(self.segments, self.segment_index(s), s, v, 1.0)
        self.plan_tick = engine.tick
        self._next_pulse = self._due[-1][1] if self._due else self._next_pulse
        self._begin()

    def abort(self) -> None:
        """Motor power off: both axes stop where they are, at once."""
        engine = self.engine
        for axis in self.axes:
            axis.freeze(engine)
            axis.target_counts = axis.counts(engine)
        self._finish()

    def _finish(self) -> None:
        self.finished = True
        self._due = []
        self._pulse_distances = None
        for axis in self.axes:
            axis.in_trajectory = False

    # ---- where the path is -------------------------------------------------------------
    def distance(self, tick: int | None = None) -> float:
        engine = self.engine
        now = engine.tick if tick is None else tick
        s, _v = self.plan.state((now - self.plan_tick) * engine.period)
        return s

    def segment_index(self, s: float) -> int:
        i = max(0, bisect.bisect_right(self.starts, s) - 1)
        return min(i, len(self.segments) - 1)

    def element(self) -> int:
        """AT: the element under execution (1-based), 0 once the run has ended."""
        if self.finished:
            return 0
        return self.segment_index(self.distance()) + 1

    # ---- events ------------------------------------------------------------------------
    def next_event(self) -> int | None:
        if self.finished:
            return None
        best = self.end_tick
        due = self._due
        if due and (best is None or due[-1][0] < best):
            best = due[-1][0]
        return best

    def on_event(self, now: int) -> None:
        due = self._due
        while due and due[-1][0] <= now:
            tick, index = due.pop()
            self._fire(index, tick)
            if not due:
                self._schedule_pulses()
                due = self._due
        if self.end_tick is not None and now >= self.end_tick:
            self._finish()

    def _fire(self, index: int, tick: int) -> None:
        spaced = self._pulse_distances
        plan = self.run.pulses
        assert spaced is not None and plan is not None
        last = index == spaced.count - 1
        distance = self._pulse_end if last else spaced.start + index * spaced.step
        x, y = self.axes
        xc, yc = self._counts_at(tick)
        self.pulses.add(PulseRecord(index, tick, distance, plan.points.element(index),
                                       xc, yc, xc * x.resolution, yc * y.resolution))

    def _counts_at(self, tick: int) -> tuple[int, int]:
        """X and Y counts at a tick of the running plan: what `counts_at` gives, with the
        path located once for both axes (the pulse hot path)."""
        x, y = self.axes
        period = self.engine.period
        mx, my = x.motion, y.motion
        if (not isinstance(mx, ContourMotion) or not isinstance(my, ContourMotion)
                or mx.plan is not self.plan or my.plan is not self.plan
                or x.motion_end is None or tick >= x.motion_end):
            return x.counts_at(tick, period), y.counts_at(tick, period)
        s, _v = self.plan.state((tick - x.motion_start) * period)
        seg = self.plan.segment_at(s)
        sigma = s - seg.s0
        return (x.steps + int(seg.coordinate(sigma, 0) * mx.scale - mx.origin) + x.counter_offset,
                y.steps + int(seg.coordinate(sigma, 1) * my.scale - my.origin) + y.counter_offset)
