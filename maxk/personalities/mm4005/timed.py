"""The time-based trajectory the EPICS MM4005 trajectory scan drives (NC, DC, UC, DT, DX,
MB/ME/MN, VC, RC, GC, EC, XC, NQ, TQ), with its pulses and the trace read back per pulse.

A definition is a list of elements, each a duration (``iDT``) and a displacement per
taking-part axis (``nDX``, controller units). EC runs it on the shared path planner
(`firmware_model.path.plan_timed`), as the XY trajectory runs: the elements are the
segments of one path through the taking-part axes' space (user units, from where they
stand), each lasting exactly its duration x the time scale. The speed along the path is
continuous across every seam, a speed change spread over up to UC seconds across it (D:
the seam speed is the lower of the two elements' mean speeds, scaled by the cosine of the
turn between them), and each element cruises at the one speed that makes it end exactly
on its sum of displacements at its end time: so at every element boundary every axis
stands exactly where the host put it. The run starts and ends at rest. Each axis follows
its coordinate in counts of its own TU (`path.ContourMotion`), so limit switches, MS,
TP/TH and the servo see an ordinary motion. VC's figures stay the host's: the elements'
mean speeds dx / dt and their steps (what GC bounds, RC reports, |dv| / UC the
acceleration).

Pulses (``MBs,MEe,MNn``): the controller "puts out one fewer pulse than requested"
(the scan sends n = pulses + 1): n - 1 pulses evenly spaced in time, the first at the
start of element s, spacing (end of e - start of s) / (n - 1) (D: so with one pulse per
element each pulse marks an element's start, the scan's trajectory point). Each pulse
fires on the first servo tick at or after its time (`outputs.EvenlySpaced` times through
`outputs.time_trigger_ticks`) and
records every axis's theoretical (TH) and actual (TP) position then: the trace NQ counts
and ``iTQ`` reads.
"""

from __future__ import annotations

import itertools
import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Final

from maxk.firmware_model.outputs import EvenlySpaced, time_trigger_ticks
from maxk.firmware_model.path import ContourMotion, PathPlan, plan_timed, timed_segments

from .errors import (
    PARAMETER,
    PULSE_ELEMENTS,
    PULSE_NUMBER,
    TRAJECTORY_ELEMENT,
    TRAJECTORY_EMPTY,
    TRAJECTORY_SPEED_CHANGE,
    TRAJECTORY_VELOCITY,
    MM4005Error,
)
from .execution import PulseRecord

if TYPE_CHECKING:
    from maxk.firmware_model.engine import Engine

    from .stage import MM4005Axis

Positions = Callable[[], tuple[tuple[float, ...], tuple[float, ...]]]


MAX_ELEMENTS: Final = 2000  # MM4005_trajectoryScan.st: "up to 2000 elements" (I)
MAX_PULSES: Final = 2000 + 1  # the scan's 2000 pulses, sent as MN2001 (I)
DEFAULT_ACCEL_TIME: Final = 0.5  # UC, seconds (D: the scan's Accel PV default)
TRACE_CAPACITY: Final = 20_000  # pulses kept (TQ, :pulses: ~5 MB); older ones dropped, counted
PULSE_BATCH: Final = 256
MIN_ELEMENT_TIME: Final = 0.0005  # one servo cycle (D)
MAX_ELEMENT_TIME: Final = 1e5  # seconds (D)


@dataclass(slots=True)
class TimedElement:
    """One element: its duration (s) and each taking-part axis's displacement."""

    duration: float = 0.0
    moves: dict[int, float] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class AxisFigures:
    """What VC found for one axis (RC1..RC6): element and value of the largest speed
    change between elements, of the largest velocity, of the largest acceleration."""

    change_element: int = 0
    change: float = 0.0
    velocity_element: int = 0
    velocity: float = 0.0
    accel_element: int = 0
    accel: float = 0.0

    def report(self, which: int) -> float:
        return (self.change_element, self.change, self.velocity_element, self.velocity,
                self.accel_element, self.accel)[which - 1]


class TimedTrajectory:
    """The definition, its verification figures and the pulse set-up (no motion)."""

    def __init__(self, axis_count: int) -> None:
        self.axis_count = axis_count
        self.accel_time = DEFAULT_ACCEL_TIME
        self.speed_error_limits = [0.0] * axis_count  # GC; 0: not checked (D)
        self.axes: set[int] = set()
        self.elements: list[TimedElement] = []
        self.current = 0  # the element the last DT named (DX applies to it)
        self.pulse_start = 1
        self.pulse_end = 1
        self.pulse_request = 0  # MN: 0 no pulses
        self.verified = False
        self.figures: dict[int, AxisFigures] = {}

    def new(self) -> None:
        """NC: forget elements, axes and pulses; UC and GC stay (D)."""
        self.axes.clear()
        self.elements.clear()
        self.current = 0
        self.pulse_start = self.pulse_end = 1
        self.pulse_request = 0
        self.verified = False
        self.figures = {}

    def take_part(self, axis: int, moves: bool) -> None:
        (self.axes.add if moves else self.axes.discard)(axis)
        self.verified = False

    def set_duration(self, number: int, seconds: float) -> None:
        """``iDT``: element i's duration; i may name an element already defined or the
        next one (D), which it then creates."""
        if not 1 <= number <= min(len(self.elements) + 1, MAX_ELEMENTS):
            raise MM4005Error(TRAJECTORY_ELEMENT, f"element {number}")
        if not MIN_ELEMENT_TIME <= seconds <= MAX_ELEMENT_TIME:
            raise MM4005Error(PARAMETER, "element time out of range")
        if number > len(self.elements):
            self.elements.append(TimedElement())
        self.elements[number - 1].duration = seconds
        self.current = number
        self.verified = False

    def set_displacement(self, axis: int, units: float) -> None:
        """``nDX``: axis n's displacement in the element the last DT named."""
        if self.current == 0:
            raise MM4005Error(TRAJECTORY_EMPTY, "DX before any DT")
        self.elements[self.current - 1].moves[axis] = units
        self.verified = False

    def set_pulses(self, start: int | None = None, end: int | None = None,
                   count: int | None = None) -> None:
        if count is not None and not 0 <= count <= MAX_PULSES:
            raise MM4005Error(PULSE_NUMBER, f"MN{count}")
        for value in (start, end):
            if value is not None and not 1 <= value <= MAX_ELEMENTS:
                raise MM4005Error(PULSE_ELEMENTS, f"element {value}")
        if start is not None:
            self.pulse_start = start
        if end is not None:
            self.pulse_end = end
        if count is not None:
            self.pulse_request = count
        self.verified = False

    # ---- verification -------------------------------------------------------------------
    def velocities(self, axis: int) -> list[float]:
        return [e.moves.get(axis, 0.0) / e.duration for e in self.elements]

    def _figures(self, axis: int) -> AxisFigures:
        v = self.velocities(axis)
        best_change = (0, 0.0)
        best_velocity = (0, 0.0)
        best_accel = (0, 0.0)
        previous = 0.0
        for i, vi in enumerate(v, start=1):
            change = abs(vi - previous)
            if i > 1 and change > best_change[1]:
                best_change = (i, change)
            if abs(vi) > best_velocity[1]:
                best_velocity = (i, abs(vi))
            accel = change / self.accel_time if self.accel_time > 0 else 0.0
            if accel > best_accel[1]:
                best_accel = (i, accel)
            previous = vi
        return AxisFigures(*best_change, *best_velocity, *best_accel)

    def verify(self, max_speed: Callable[[int], float]) -> None:
        """VC: compute each axis's figures (kept for RC even when VC refuses), then check,
        in this order: elements and axes defined (K), every element timed (L), each
        velocity within the axis's VU (H), each speed change within GC when GC > 0 (G),
        the pulse elements (N) and count (P)."""
        self.verified = False
        self.figures = {a: self._figures(a) for a in sorted(self.axes)}
        if not self.elements or not self.axes:
            raise MM4005Error(TRAJECTORY_EMPTY, "no element or no axis")
        for number, element in enumerate(self.elements, start=1):
            if not element.duration > 0.0:
                raise MM4005Error(TRAJECTORY_ELEMENT, f"element {number} has no time")
        for axis, figures in self.figures.items():
            if figures.velocity > max_speed(axis):
                raise MM4005Error(TRAJECTORY_VELOCITY,
                                  f"axis {axis} element {figures.velocity_element}")
            limit = self.speed_error_limits[axis - 1]
            if limit > 0.0 and figures.change > limit:
                raise MM4005Error(TRAJECTORY_SPEED_CHANGE,
                                  f"axis {axis} element {figures.change_element}")
        if self.pulse_request:
            n = len(self.elements)
            if not 1 <= self.pulse_start <= self.pulse_end <= n:
                raise MM4005Error(PULSE_ELEMENTS, f"MB{self.pulse_start} ME{self.pulse_end}")
            if self.pulse_request < 2:
                raise MM4005Error(PULSE_NUMBER, f"MN{self.pulse_request}")
        self.verified = True

    def times(self, scale: float) -> list[float]:
        """Each element's start time, scaled, and the end (len + 1 values)."""
        out = [0.0]
        for e in self.elements:
            out.append(out[-1] + e.duration * scale)
        return out


def trajectory_plan(trajectory: TimedTrajectory, scale: float) -> PathPlan:
    """The definition as the shared planner's path through the taking-part axes (in the
    order of their numbers), element times x ``scale``, speed changes over UC."""
    axes = sorted(trajectory.axes)
    displacements = [[e.moves.get(a, 0.0) for a in axes] for e in trajectory.elements]
    return plan_timed(timed_segments(displacements),
                      [e.duration * scale for e in trajectory.elements], trajectory.accel_time)


def axis_motion(plan: PathPlan, k: int, resolution: float) -> ContourMotion:
    """Axis k of the plan in its own counts (1 / TU per user unit). Its reach is the
    extremes of its element boundaries: along each straight element it only moves one
    way, so limit searches skip switches it never gets to."""
    scale = 1.0 / resolution
    motion = ContourMotion(plan, k, 0.0, scale)
    motion.snap = 1e-12  # (the host's whole-count points are whole counts: TP reads them)
    ends = [0.0] + [seg.end[k] * scale for seg in plan.segments]
    motion.reach = (min(ends) - 1.0, max(ends) + 1.0)
    return motion


@dataclass(frozen=True, slots=True)
class TracePoint:
    """One pulse of a time-based run: its number (1 first), tick, element, and every
    installed axis's theoretical and actual position (user units)."""

    number: int
    tick: int
    element: int
    theoretical: tuple[float, ...]
    actual: tuple[float, ...]


class TimedExecution:
    """EC's run: every taking-part axis on its motion, the pulses, XC. An event source."""

    def __init__(self, trajectory: TimedTrajectory, axes: list[MM4005Axis], machine: Engine,
                 positions: Positions, scale: float, trace: PulseTrace) -> None:
        self.machine = machine
        self.positions = positions  # (TH, TP) of every installed axis now
        self.axes = axes
        self.starts = trajectory.times(scale)
        self.start_tick = machine.tick
        period = machine.period
        self.end_tick = self.start_tick + math.ceil(self.starts[-1] / period - 1e-9)
        self.finished = False
        self.stopped_tick: int | None = None  # where AB, ST, MF or a limit ended it
        self.trace = trace
        self._spaced: EvenlySpaced | None = None
        self._next = 0
        self._due: list[tuple[int, int]] = []
        self.plan = trajectory_plan(trajectory, scale)
        for k, axis in enumerate(self.axes):
            motion = axis_motion(self.plan, k, axis.resolution)
            axis.pending_target = None
            axis.homing = None
            axis.in_trajectory = True
            axis.target_counts = axis.counts(machine) + motion.final_offset
            axis.begin(motion, machine)
        if trajectory.pulse_request >= 2:
            t0 = self.starts[trajectory.pulse_start - 1]
            t1 = self.starts[trajectory.pulse_end]
            count = trajectory.pulse_request - 1
            self._spaced = EvenlySpaced(t0, (t1 - t0) / count, count)
        trace.begin()
        self._schedule()
        self.on_event(machine.tick)  # a pulse due at the start fires at once

    def _schedule(self) -> None:
        spaced = self._spaced
        if spaced is None or self._due:
            return
        batch = time_trigger_ticks(self.start_tick, self.machine.period,
                                   itertools.islice(spaced.from_index(self._next), PULSE_BATCH))
        if batch:
            self._next = batch[-1][1] + 1
        self._due = batch[::-1]

    def element_at(self, tick: int) -> int:
        """The element under execution at a tick (1-based)."""
        t = (tick - self.start_tick) * self.machine.period
        lo, hi = 0, len(self.starts) - 2
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if self.starts[mid] <= t:
                lo = mid
            else:
                hi = mid - 1
        return lo + 1

    def elements_done(self) -> int:
        """XC: the elements completed so far (up to where an abort or stop ended it)."""
        tick = self.machine.tick if self.stopped_tick is None else self.stopped_tick
        t = (min(tick, self.end_tick) - self.start_tick) * self.machine.period
        return sum(1 for end in self.starts[1:] if end <= t + 1e-12)

    def next_event(self) -> int | None:
        if self.finished:
            return None
        if self._due and self._due[-1][0] < self.end_tick:
            return self._due[-1][0]
        return self.end_tick

    def on_event(self, now: int) -> None:
        due = self._due
        while due and due[-1][0] <= now:
            _tick, index = due.pop()
            self._fire(index, now)
            if not due:
                self._schedule()
                due = self._due
        if now >= self.end_tick:
            self._end()

    def _fire(self, index: int, tick: int) -> None:
        th, tp = self.positions()
        self.trace.add(TracePoint(index + 1, tick, self.element_at(tick), th, tp))

    def _end(self) -> None:
        self.finished = True
        self._due = []
        for axis in self.axes:
            axis.in_trajectory = False

    def abort_braking(self) -> None:
        """ST or a limit: the run ends here (its axes then brake); later pulses never
        fire."""
        self.stopped_tick = self.machine.tick
        self.finished = True
        self._due = []
        self._spaced = None
        for axis in self.axes:
            axis.in_trajectory = False

    def abort(self) -> None:
        """AB, MF: every axis stops where it is; later pulses never fire."""
        if self.finished:
            return
        self.stopped_tick = self.machine.tick
        for axis in self.axes:
            if axis.motion is not None:
                axis.freeze(self.machine)
            axis.target_counts = axis.counts(self.machine)
        self.finished = True
        self._due = []
        self._spaced = None
        for axis in self.axes:
            axis.in_trajectory = False


class PulseTrace:
    """The pulse log as a bounded ring: the newest ``capacity`` records are kept (TQ,
    :pulses), older ones dropped and counted; a sink, when set, is given every record
    as it fires (the whole log streamed to a file: `--trace`, `:pulses-csv`)."""

    def __init__(self, capacity: int = TRACE_CAPACITY) -> None:
        self.capacity = capacity
        self.records: deque[PulseRecord | TracePoint] = deque(maxlen=capacity)
        self.total = 0
        self.sink: Callable[[PulseRecord | TracePoint], None] | None = None

    @property
    def dropped(self) -> int:
        return self.total - len(self.records)

    def begin(self) -> None:
        """A new run: its pulses are numbered from 1 again."""
        self.records.clear()
        self.total = 0

    def add(self, record: PulseRecord | TracePoint) -> None:
        self.records.append(record)
        self.total += 1
        if self.sink is not None:
            self.sink(record)

    def get(self, number: int) -> PulseRecord | TracePoint | None:
        """Pulse ``number`` (1 first) if the ring still holds it."""
        first = self.total - len(self.records) + 1
        if not first <= number <= self.total:
            return None
        return self.records[number - first]
