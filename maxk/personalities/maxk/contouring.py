"""Vector contouring: paths of straight lines and circular arcs at a vector velocity.

The manual's hole-cutting example (Appendix C) and the MAXv vector tasks the EPICS
trajectory scan drives (evidence 2.8) share one machine, modelled here:

- A *task* (1-8; the MAXk form without ``[n]`` is task 1) holds the definition state the
  commands set: vector acceleration (VA), start and end vector velocity (VV), the output
  action at segment starts (VIO), the velocity override (VO, or an analog input by VOA),
  hold (VH), done-on-finish (VID).
- A *contour* is what one task runs from its first VP or VC to its VE. The first VP names
  its axes. The contour takes one entry (its anchor) in each of its axes' queues, so it
  starts when every one of them is idle and has reached it, like an AA-mode GO, and the
  commands queued after it run when it has finished. Segments (VP/VC) are kept in the
  contour and hold one queue unit on each of its axes until the path has passed them
  (about 2559 segments fit, as the trajectory scan's comment says of the MAXv).
- The path is planned along its length ``s``: each segment's speed rises toward its end
  velocity (or stays at its start velocity and falls to a lower end velocity) at the
  segment's VA, never above max(start, end) x override, on arcs never above sqrt(VA R)
  (so the centripetal acceleration stays within VA too), and always able to stop at the
  end of the known path. Segments blend without stopping; the path is exact (arc points
  are computed from the centre and angle, never accumulated), each axis stands on the
  whole count its position has passed (under one count from the ideal path), and the
  contour ends on its last point exactly.
- Appending segments, changing the override, VH1 (hold) and stops re-plan from where the
  path is, at the speed it has: the path is never left, speed changes stay within VA.

Decisions (D) and inferences (I) are listed with the commands in the command table and in
docs/contouring.md.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from maxk.firmware_model.profiles import RampShape
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.axis import WAIT_REST_RETRY

if TYPE_CHECKING:
    from maxk.personalities.maxk.axis import Axis
    from maxk.personalities.maxk.board import Board

TASKS = range(1, 9)
DEFAULT_TASK = 1
MAX_VECTOR_VELOCITY = 4_194_303.0  # VV's range: the trajectory scan clamps to this
OVERRIDE_MAX = 200.0
DEFAULT_VOA_SPAN = 5.0  # volts from 0 V to 0% or 200% (VOA channel[,span])
PULSE_TICKS = 1  # a VIO pulse (off-mask given) lasts one update cycle
_EPS = 1e-9


# ---- definitions and geometry ---------------------------------------------------------
@dataclass(frozen=True, slots=True)
class SegmentDef:
    """A VP or VC as defined, with the VA/VV/VIO values in effect when it was sent."""

    kind: str  # "line" or "arc"
    values: tuple[float | None, ...]  # line: one coordinate per contour axis; arc: centre
    relative: bool
    angle: float  # arc: degrees, positive from the first axis toward the second
    v_start: float | None  # None: go on at the previous segment's end velocity
    v_end: float
    accel: float
    io: tuple[int, int | None, int] | None


def _snap(x: float) -> float:
    """Arc ends land on whole counts when the geometry says so (90-degree multiples)."""
    r = round(x)
    return float(r) if abs(x - r) < 1e-6 else x


class Segment:
    """A resolved segment: where it starts and ends on the path (s0, length)."""

    __slots__ = ("defn", "s0", "length", "start", "end", "unit", "cx", "cy", "radius",
                 "theta0", "turn", "v_start", "v_end", "accel", "ceiling", "arc_cap")

    def __init__(self, defn: SegmentDef, start: tuple[float, ...], s0: float,
                 v_previous: float | None) -> None:
        self.defn = defn
        self.s0 = s0
        self.start = start
        self.accel = defn.accel
        self.v_end = defn.v_end
        self.v_start = defn.v_start if defn.v_start is not None else (
            v_previous if v_previous is not None else defn.v_end)
        self.ceiling = max(self.v_start, self.v_end)
        self.arc_cap = math.inf
        self.unit: tuple[float, ...] = tuple(0.0 for _ in start)
        self.cx = self.cy = self.radius = self.theta0 = self.turn = 0.0
        if defn.kind == "line":
            end = tuple(
                (start[k] + v if defn.relative else v) if v is not None else start[k]
                for k, v in enumerate(defn.values))
            delta = [e - s for e, s in zip(end, start, strict=True)]
            self.length = math.sqrt(sum(d * d for d in delta))
            if self.length > 0:
                self.unit = tuple(d / self.length for d in delta)
            self.end = end
        else:
            self.cx, self.cy = defn.values[0], defn.values[1]  # type: ignore[assignment]
            dx, dy = start[0] - self.cx, start[1] - self.cy
            self.radius = math.hypot(dx, dy)
            self.theta0 = math.atan2(dy, dx)
            self.turn = math.radians(defn.angle)
            self.length = self.radius * abs(self.turn)
            if self.radius > 0:
                self.arc_cap = math.sqrt(self.accel * self.radius)
            if self.length > 0 and defn.angle % 360.0 == 0.0:
                end = start  # whole circles close exactly
            else:
                end = list(start)
                theta = self.theta0 + self.turn
                end[0] = _snap(self.cx + self.radius * math.cos(theta))
                end[1] = _snap(self.cy + self.radius * math.sin(theta))
                end = tuple(end)
            self.end = end

    @property
    def is_arc(self) -> bool:
        return self.defn.kind == "arc"

    def coordinate(self, sigma: float, k: int) -> float:
        """Axis k's ideal position sigma counts along this segment."""
        if sigma >= self.length:
            return self.end[k]
        if not self.is_arc:
            return self.start[k] + self.unit[k] * sigma
        if k > 1 or self.radius == 0:
            return self.start[k]
        theta = self.theta0 + math.copysign(sigma / self.radius, self.turn)
        if k == 0:
            return self.cx + self.radius * math.cos(theta)
        return self.cy + self.radius * math.sin(theta)

    def slope(self, sigma: float, k: int) -> float:
        """d(axis k)/ds: the share of the vector velocity axis k carries."""
        if not self.is_arc:
            return self.unit[k]
        if k > 1 or self.radius == 0:
            return 0.0
        sign = 1.0 if self.turn > 0 else -1.0
        theta = self.theta0 + sign * sigma / self.radius
        return -sign * math.sin(theta) if k == 0 else sign * math.cos(theta)

    def extremes(self, k: int, a: float, b: float) -> list[float]:
        """Where axis k turns round within (a, b) on an arc (it is monotonic between)."""
        if not self.is_arc or k > 1 or self.radius == 0:
            return []
        sign = 1.0 if self.turn > 0 else -1.0
        phase = 0.0 if k == 0 else math.pi / 2  # x turns at m*pi, y at pi/2 + m*pi
        th_a = self.theta0 + sign * a / self.radius
        th_b = self.theta0 + sign * b / self.radius
        lo, hi = min(th_a, th_b), max(th_a, th_b)
        m = math.ceil((lo - phase) / math.pi)
        out = []
        while phase + m * math.pi < hi:
            theta = phase + m * math.pi
            sigma = (theta - self.theta0) * sign * self.radius
            if a + 1e-9 < sigma < b - 1e-9:
                out.append(sigma)
            m += 1
        return sorted(out)


# ---- speed along the path -------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class Piece:
    """A stretch of the path at constant acceleration along it."""

    t0: float
    duration: float  # math.inf: held at speed 0 (override 0%)
    s0: float
    v0: float
    a: float

    def s(self, tau: float) -> float:
        return self.s0 + self.v0 * tau + 0.5 * self.a * tau * tau

    def v(self, tau: float) -> float:
        return self.v0 + self.a * tau

    @property
    def s1(self) -> float:
        return self.s0 if math.isinf(self.duration) else self.s(self.duration)

    def tau_at(self, s: float) -> float:
        d = s - self.s0
        if d <= 0:
            return 0.0
        root = math.sqrt(max(0.0, self.v0 * self.v0 + 2.0 * self.a * d))
        denominator = self.v0 + root
        return min(2.0 * d / denominator, self.duration) if denominator > 0 else 0.0


class PathPlan:
    """Where the path is at every time from the plan's start: pieces of constant
    acceleration, ending at rest (end_time) or held at speed 0 (end_time None)."""

    def __init__(self, segments: list[Segment], pieces: list[Piece], s_start: float,
                 end_time: float | None) -> None:
        self.segments = segments
        self.starts = [seg.s0 for seg in segments]
        self.pieces = pieces
        self.times = [p.t0 for p in pieces]
        self.piece_ends = [p.s1 for p in pieces]
        self.s_start = s_start
        self.end_time = end_time
        self.s_end = pieces[-1].s1 if pieces else s_start
        self._memo: tuple[float, float, float] = (-1.0, s_start, 0.0)

    def state(self, t: float) -> tuple[float, float]:
        """(s, speed) at t seconds into the plan."""
        memo = self._memo
        if memo[0] == t:
            return memo[1], memo[2]
        if not self.pieces or (self.end_time is not None and t >= self.end_time):
            result = (self.s_end, 0.0)
        else:
            i = max(0, bisect.bisect_right(self.times, t) - 1)
            p = self.pieces[i]
            tau = min(t - p.t0, p.duration)
            result = (p.s(tau), max(0.0, p.v(tau)))
            if i + 1 < len(self.pieces):
                result = (min(result[0], self.pieces[i + 1].s0), result[1])
        self._memo = (t, result[0], result[1])
        return result

    def segment_at(self, s: float) -> Segment:
        i = max(0, bisect.bisect_right(self.starts, s) - 1)
        while i > 0 and self.segments[i].length == 0 and self.segments[i].s0 >= s:
            i -= 1
        return self.segments[i]

    def time_at(self, s: float) -> float | None:
        """When the plan reaches s (None if it never does)."""
        if s > self.s_end + _EPS:
            return None
        i = bisect.bisect_left(self.piece_ends, s - _EPS)
        if i >= len(self.pieces):
            return self.end_time
        p = self.pieces[i]
        if math.isinf(p.duration):
            return p.t0 if s <= p.s0 + _EPS else None
        return p.t0 + p.tau_at(s)

    def point(self, s: float, k: int) -> float:
        seg = self.segment_at(s)
        return seg.coordinate(s - seg.s0, k)


def _caps(segments: list[Segment], i0: int, scale: float) -> tuple[list[float], list[float]]:
    """Per segment from i0: its speed ceiling, and the cap on the speed at its end."""
    ceilings = [min(seg.ceiling * scale, seg.arc_cap) for seg in segments[i0:]]
    ends = []
    n = len(ceilings)
    for j, seg in enumerate(segments[i0:]):
        if j == n - 1:
            ends.append(0.0)  # the known path ends at rest
        else:
            ends.append(min(seg.v_end * scale, ceilings[j], ceilings[j + 1]))
    return ceilings, ends


def _segment_pieces(out: list[Piece], t: float, s: float, length: float, v_in: float,
                    v_out: float, ceiling: float, accel: float) -> float | None:
    """Append one segment's pieces (ramp to the top speed, cruise, ramp to v_out).
    Returns the time at its end, or None if the path is held at speed 0 inside it."""
    if length <= 0:
        return t
    if v_out > ceiling + 1e-9:  # a lowered override: slow down over the whole segment
        a = (v_out * v_out - v_in * v_in) / (2.0 * length)
        duration = (v_out - v_in) / a if a else length / max(v_in, _EPS)
        out.append(Piece(t, duration, s, v_in, a))
        return t + duration
    peak = min(ceiling, math.sqrt(max(0.0, (v_in * v_in + v_out * v_out) / 2.0
                                      + accel * length)))
    peak = max(peak, v_out)
    d1 = abs(peak * peak - v_in * v_in) / (2.0 * accel)
    d3 = (peak * peak - v_out * v_out) / (2.0 * accel)
    cruise = length - d1 - d3
    if cruise < 0:  # rounding at a triangle's tip
        d1 = max(0.0, d1 + cruise)
        cruise = 0.0
    if abs(peak - v_in) > 1e-12:
        a = accel if peak > v_in else -accel
        duration = abs(peak - v_in) / accel
        out.append(Piece(t, duration, s, v_in, a))
        t += duration
        s += d1
    if cruise > 1e-9:
        if peak <= 0:
            out.append(Piece(t, math.inf, s, 0.0, 0.0))
            return None
        out.append(Piece(t, cruise / peak, s, peak, 0.0))
        t += cruise / peak
        s += cruise
    if peak - v_out > 1e-12:
        duration = (peak - v_out) / accel
        out.append(Piece(t, duration, s, peak, -accel))
        t += duration
    return t


def plan_path(segments: list[Segment], i0: int, s_now: float, v_now: float | None,
              scale: float) -> PathPlan:
    """Plan from s_now (inside segment i0) at speed v_now (None: from rest, taking the
    segment's start velocity at once, as a stepper takes its base velocity)."""
    ceilings, ends = _caps(segments, i0, scale)
    n = len(ceilings)
    allow = list(ends)
    for j in range(n - 1, 0, -1):  # backward: every later cap can still be met
        seg = segments[i0 + j]
        allow[j - 1] = min(allow[j - 1],
                           math.sqrt(allow[j] ** 2 + 2.0 * seg.accel * seg.length))
    first = segments[i0]
    remaining = max(0.0, first.s0 + first.length - s_now)
    reachable = math.sqrt(allow[0] ** 2 + 2.0 * first.accel * remaining)
    if v_now is None:
        v_now = min(first.v_start * scale, ceilings[0], reachable)
    pieces: list[Piece] = []
    t, v_in, s = 0.0, v_now, s_now
    for j in range(n):
        seg = segments[i0 + j]
        length = seg.s0 + seg.length - s
        a = seg.accel
        up = math.sqrt(v_in * v_in + 2.0 * a * max(0.0, length))
        down = math.sqrt(max(0.0, v_in * v_in - 2.0 * a * max(0.0, length)))
        v_out = max(min(allow[j], up), down)
        end = _segment_pieces(pieces, t, s, length, v_in, v_out, ceilings[j], a)
        if end is None:
            return PathPlan(segments, pieces, s_now, None)
        t, v_in, s = end, v_out, seg.s0 + seg.length
    return PathPlan(segments, pieces, s_now, t)


def plan_stop(segments: list[Segment], i0: int, s_now: float, v_now: float,
              scale: float) -> PathPlan:
    """Ramp down along the path at the present segment's VA (VH1, ST, a soft limit)."""
    accel = segments[i0].accel
    distance = v_now * v_now / (2.0 * accel)
    if s_now + distance >= segments[-1].s0 + segments[-1].length:
        return plan_path(segments, i0, s_now, v_now, scale)  # it stops at the end anyway
    if v_now <= 0:
        return PathPlan(segments, [], s_now, 0.0)
    duration = v_now / accel
    return PathPlan(segments, [Piece(0.0, duration, s_now, v_now, -accel)], s_now, duration)


# ---- what each axis follows -------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class ContourPhase:
    """A stretch over which one axis moves one way (the Motion phase interface)."""

    t0: float
    duration: float
    v1: float
    v2: float
    direction: int
    polynomial: bool  # lines: a quadratic in time; arcs are not
    shape: RampShape = RampShape.LINEAR
    s0: float = 0.0
    mirrored: bool = False


class ContourMotion:
    """One axis's share of a path plan, with the interface of profiles.Motion."""

    contour = True

    def __init__(self, plan: PathPlan, k: int, origin: float) -> None:
        self.plan = plan
        self.k = k
        self.origin = origin  # the axis's motor counter when the plan started
        self.end_time = plan.end_time
        self.ramp_end_time = plan.end_time if plan.end_time is not None else 0.0
        self.final_offset = 0
        if plan.end_time is not None:
            self.final_offset = round(plan.point(plan.s_end, k)) - round(origin)
        self._phases: list[ContourPhase] | None = None  # made when first asked for
        self._times: list[float] = []
        self.direction, self.monotonic = self._directions()
        self.peak_speed = 0.0  # (only MT/ML scaling reads it)

    @property
    def phases(self) -> list[ContourPhase]:
        """Stretches where this axis moves one way (limit searches, the servo)."""
        if self._phases is None:
            self._phases = _axis_phases(self.plan, self.k)
            self._times = [p.t0 for p in self._phases]
        return self._phases

    def _directions(self) -> tuple[int, bool]:
        """The way the axis first moves, and whether it only ever moves that way: from
        the segments' slopes for straight lines (cheap: no phases), else the phases."""
        plan, k = self.plan, self.k
        first = max(0, bisect.bisect_right(plan.starts, plan.s_start) - 1)
        signs = set()
        direction = 0
        for seg in plan.segments[first:]:
            if seg.s0 >= plan.s_end - _EPS and seg.length > 0 and signs:
                break
            if seg.is_arc:
                moving = [p for p in self.phases if p.v1 or p.v2]
                d = moving[0].direction if moving else 1
                return d, all(p.direction == d for p in moving)
            u = seg.unit[k] if seg.length > 0 else 0.0
            if u:
                sign = 1 if u > 0 else -1
                direction = direction or sign
                signs.add(sign)
            if seg.s0 + seg.length >= plan.s_end - _EPS:
                break
        return direction or 1, len(signs) <= 1

    def _phase_at(self, t: float) -> ContourPhase | None:
        phases = self.phases
        if not phases:
            return None
        return phases[max(0, bisect.bisect_right(self._times, t) - 1)]

    def offset(self, t: float) -> float:
        if self.end_time is not None and t >= self.end_time:
            return float(self.final_offset)
        s, _v = self.plan.state(t)
        return self.plan.point(s, self.k) - self.origin

    def velocity(self, t: float) -> float:
        if self.end_time is not None and t >= self.end_time:
            return 0.0
        s, v = self.plan.state(t)
        seg = self.plan.segment_at(s)
        return v * seg.slope(s - seg.s0, self.k)


def _axis_phases(plan: PathPlan, k: int) -> list[ContourPhase]:
    """Split the plan where axis k may turn round: segment boundaries, arc extremes."""
    phases: list[ContourPhase] = []
    for p in plan.pieces:
        if math.isinf(p.duration):
            phases.append(ContourPhase(p.t0, math.inf, 0.0, 0.0, 1, True))
            continue
        s_a, s_b = p.s0, p.s1
        cuts = [s_a]
        i = max(0, bisect.bisect_right(plan.starts, s_a) - 1)
        while i < len(plan.segments) and plan.segments[i].s0 < s_b - _EPS:
            seg = plan.segments[i]
            lo, hi = max(s_a, seg.s0), min(s_b, seg.s0 + seg.length)
            if hi > lo:
                if seg.s0 > s_a + _EPS:
                    cuts.append(seg.s0)
                cuts.extend(seg.s0 + e for e in seg.extremes(k, lo - seg.s0, hi - seg.s0))
            i += 1
        cuts.append(s_b)
        for a, b in zip(cuts, cuts[1:], strict=False):
            if b - a <= _EPS:
                continue
            ta, tb = p.tau_at(a), p.tau_at(b)
            mid = plan.segment_at((a + b) / 2)
            sm = (a + b) / 2 - mid.s0
            slope = mid.slope(sm, k)
            if abs(slope) < 1e-12:
                phases.append(ContourPhase(p.t0 + ta, tb - ta, 0.0, 0.0, 1, True))
                continue
            direction = 1 if slope > 0 else -1
            v1 = abs(mid.slope(a - mid.s0, k)) * p.v(ta)
            v2 = abs(mid.slope(b - mid.s0, k)) * p.v(tb)
            phases.append(ContourPhase(p.t0 + ta, tb - ta, v1, v2, direction,
                                       not mid.is_arc))
    return phases


# ---- tasks and contours ---------------------------------------------------------------
@dataclass
class ContourTask:
    """One vector task's definition state and its contours (the running one first)."""

    index: int
    accel: float | None = None  # VA; None: the first contour axis's AC
    v_start: float | None = None  # VV start; None: go on at the previous end velocity
    v_end: float | None = None  # VV end; None: the first contour axis's VL
    io: tuple[int, int | None, int] | None = None  # VIO on, off, mask
    hold: bool = False  # VH0: the next contour waits for VG
    done_on_finish: bool = False  # VID1
    override: float = 100.0  # VO, percent
    override_input: tuple[int, float] | None = None  # VOA channel, span (volts)
    contours: list[Contour] = field(default_factory=list)
    pulse: tuple[int, int, int] | None = None  # a VIO pulse's end: (tick, off bits, mask)

    @property
    def defining(self) -> Contour | None:
        """The contour that VP/VC/VE add to (opened by a VP, closed by VE)."""
        if self.contours and not self.contours[-1].closed:
            return self.contours[-1]
        return None

    @property
    def running(self) -> Contour | None:
        head = self.contours[0] if self.contours else None
        return head if head is not None and head.state != "waiting" else None

    def scale(self, board: Board) -> float:
        """The override as a factor: VO, or VOA's input with 0 V at 100% and the span
        either side reaching 0% and 200% (D)."""
        if self.override_input is None:
            return self.override / 100.0
        channel, span = self.override_input
        volts = board.world.analog_volts(channel, board)
        percent = 100.0 * (1.0 + volts / span)
        return min(OVERRIDE_MAX, max(0.0, percent)) / 100.0

    def next_event(self, board: Board) -> int | None:
        head = self.running
        best = head.next_event(board) if head is not None else None
        if self.pulse is not None and (best is None or self.pulse[0] < best):
            best = self.pulse[0]
        return best

    def on_event(self, board: Board) -> list[Axis]:
        if self.pulse is not None and self.pulse[0] <= board.tick:
            _tick, off, mask = self.pulse
            self.pulse = None
            Contour.drive(board, off, mask)
        head = self.running
        return head.on_event(board) if head is not None else []

    def override_changed(self, board: Board) -> None:
        head = self.running
        if head is not None and head.state == "running" and not head.stopping:
            head.replan(board)

    def go(self, board: Board) -> None:
        """VG: start the waiting contour, or resume a held one."""
        self.hold = False
        if not self.contours:
            return
        head = self.contours[0]
        if head.state == "held" or (head.state == "running" and head.stopping
                                    and not head.aborted):
            head.resume(board)  # (also during the VH1 ramp-down: it goes on from there)
        else:
            head.maybe_start(board)

    def hold_now(self, board: Board) -> None:
        """VH1: a running contour ramps down on its path and waits for VG."""
        self.hold = True
        head = self.running
        if head is not None and head.state == "starved":
            head.state = "held"  # at rest already: it waits for VG, segments or not
        elif head is not None and head.state == "running" and not head.stopping:
            head.hold(board)


class ContourWait:
    """The queue wait of a contour axis standing at the contour's anchor."""

    __slots__ = ("contour",)

    def __init__(self, contour: Contour) -> None:
        self.contour = contour

    def ready(self, board: Board) -> bool:
        return self.contour.state == "finished"


class Contour:
    """One contour of a task: its axes, its segments and where its path is."""

    def __init__(self, task: ContourTask, axes: tuple[int, ...]) -> None:
        self.task = task
        self.axes = axes
        self.defs: list[SegmentDef] = []
        self.closed = False
        # waiting (for its axes or VG) -> running / starved / held -> finished
        self.state = "waiting"
        self.arrived: set[int] = set()
        self.segments: list[Segment] = []
        self.current = 0  # the segment the path is in
        self.plan: PathPlan | None = None
        self.plan_tick = 0
        self.plan_end_tick: int | None = None
        self.from_rest = False
        self.stopping = False  # a hold or an abort ramp-down is running
        self.aborted = False
        self.boundaries: list[tuple[int, int]] = []  # (tick, segment index), ascending
        self.reserved: dict[int, int] = {}  # queue units held per axis
        self.done_flag = False
        self.scale_used = 1.0  # the override the present plan was made with
        self._origin: tuple[float, ...] = ()
        self.next_poll: int | None = None  # next reading of a time-varying VOA input

    # ---- definition ------------------------------------------------------------------
    def add(self, defn: SegmentDef, board: Board) -> None:
        """A VP/VC. Every one after the first holds a unit on each axis's queue."""
        if self.defs:
            for i in self.axes:
                board.axes[i].queue.used_units += 1
                self.reserved[i] = self.reserved.get(i, 0) + 1
        self.defs.append(defn)
        if self.state == "waiting":
            return
        self._resolve_more()  # held or ramping down too: resume will plan with them
        if self.state == "starved":
            self.state = "running"
            self.replan(board, from_rest=True)
        elif self.state == "running" and not self.stopping:
            self.replan(board)
        else:
            return
        self._refuse_if_blocked(board)

    def close(self, board: Board) -> None:
        """VE: no more segments. A contour starved at the end of its path is done."""
        self.closed = True
        if self.state == "starved":
            self.finish(board)

    def _resolve_more(self) -> None:
        while len(self.segments) < len(self.defs):
            defn = self.defs[len(self.segments)]
            if self.segments:
                last = self.segments[-1]
                seg = Segment(defn, last.end, last.s0 + last.length, last.v_end)
            else:
                seg = Segment(defn, self._origin, 0.0, None)
            self.segments.append(seg)

    # ---- start -----------------------------------------------------------------------
    def arrive(self, axis: Axis, board: Board) -> object:
        """The anchor's queue action: wait for rest, then for the other axes."""
        if axis.motion is not None:
            return WAIT_REST_RETRY
        if self.state == "finished":
            return None
        self.arrived.add(axis.index)
        self.maybe_start(board)
        return ContourWait(self)

    def maybe_start(self, board: Board) -> None:
        task = self.task
        if (self.state != "waiting" or task.hold or not self.defs
                or task.contours[0] is not self or len(self.arrived) < len(self.axes)):
            return
        axes = [board.axes[i] for i in self.axes]
        self._origin = tuple(float(a.steps_now(board) + a.counter_offset) for a in axes)
        self._resolve_more()
        self.done_flag = task.done_on_finish
        if self.done_flag:
            for axis in axes:
                board.clear_axis_flags(axis, F.AXIS_DONE)
        self.state = "running"
        self.replan(board, from_rest=True)
        if self._refuse_if_blocked(board):
            return
        for axis in axes:
            axis.linked = [a for a in axes if a is not axis]
        self._segment_start(board, 0, board.tick)
        self._enter_segments(board, board.tick)

    # ---- planning --------------------------------------------------------------------
    def where(self, board: Board) -> tuple[float, float]:
        """(s, speed) of the path now (speed 0 once its axes were killed)."""
        if self.plan is None:
            return 0.0, 0.0
        s, v = self.plan.state((board.tick - self.plan_tick) * board.period)
        return (s, v) if self.followed(board) else (s, 0.0)

    def followed(self, board: Board) -> bool:
        """Does any axis still follow the present plan? (KS/KL kill them off it.)"""
        plan = self.plan
        return any(getattr(board.axes[i].motion, "plan", None) is plan for i in self.axes)

    def _index_at(self, s: float) -> int:
        i = self.current
        while (i + 1 < len(self.segments)
               and self.segments[i].s0 + self.segments[i].length <= s + _EPS):
            i += 1
        return i

    def replan(self, board: Board, *, from_rest: bool = False, stop: bool = False) -> None:
        s, v = self.where(board)
        if self.plan is not None and self.plan_tick == board.tick and self.from_rest:
            from_rest = True  # nothing has moved yet: plan the start again
        i = self._index_at(s)
        scale = self.task.scale(board)
        self.scale_used = scale
        if stop:
            plan = plan_stop(self.segments, i, s, v, scale)
        else:
            plan = plan_path(self.segments, i, s, None if from_rest else v, scale)
        self.plan = plan
        self.plan_tick = board.tick
        self.from_rest = from_rest and not stop
        period = board.period
        self.plan_end_tick = None if plan.end_time is None else (
            board.tick + math.ceil(plan.end_time / period - 1e-9))
        for k, index in enumerate(self.axes):
            axis = board.axes[index]
            axis._rebase(board)
            motion = ContourMotion(plan, k, float(axis.steps + axis.counter_offset))
            axis.start_motion(motion, board, stopping=True)  # type: ignore[arg-type]
        self.boundaries = []
        for j in range(self.current + 1, len(self.segments)):
            t = plan.time_at(self.segments[j].s0)
            if t is None:
                break
            self.boundaries.append((board.tick + math.ceil(t / period - 1e-9), j))

    def _refuse_if_blocked(self, board: Board) -> bool:
        """A path that would start an axis into a pressed limit is refused whole (as an
        MT/ML move is): the axes stay, the overtravel flag is set, the contour ends."""
        axes = [board.axes[i] for i in self.axes]
        # the cheap test first: only an axis standing on a pressed switch needs its phases
        blocked = [a for a in axes if a.motion is not None
                   and board.limit_blocks(a, a.motion.direction)
                   and a.motion.phases and a.motion.phases[0].t0 == 0.0]
        if not blocked:
            return False
        for axis in axes:
            axis.kill(board)
        for axis in blocked:
            board.refuse_into_limit(axis)
        self.aborted = True
        self.closed = True
        self.finish(board)
        return True

    def hold(self, board: Board) -> None:
        self.stopping = True
        self.replan(board, stop=True)

    def resume(self, board: Board) -> None:
        moving = self.state == "running" and self.where(board)[1] > 0
        self.stopping = False
        self.state = "running"
        self.replan(board, from_rest=not moving)
        if self._refuse_if_blocked(board):
            return
        self._enter_segments(board, board.tick)

    # ---- events ----------------------------------------------------------------------
    def next_event(self, board: Board) -> int | None:
        if self.aborted and self.state == "running" and not self.followed(board):
            return board.tick  # killed: finish now
        best = self.plan_end_tick if self.state == "running" else None
        if self.boundaries and (best is None or self.boundaries[0][0] < best):
            best = self.boundaries[0][0]
        if self.state == "running" and self.task.override_input is not None \
                and callable(board.world.analog.get(self.task.override_input[0])):
            if self.next_poll is None or self.next_poll < board.tick:
                self.next_poll = board.tick + 1  # the analog override, every update cycle
            if best is None or self.next_poll < best:
                best = self.next_poll
        return best

    def on_event(self, board: Board) -> list[Axis]:
        now = board.tick
        if self.aborted and self.state == "running" and not self.followed(board):
            self.finish(board)
            return [board.axes[i] for i in self.axes]
        self._enter_segments(board, now)
        if self.state == "running" and self.plan_end_tick is not None \
                and now >= self.plan_end_tick:
            self.plan_end_tick = None
            s, _v = self.where(board)
            at_end = self.segments and s >= self.segments[-1].s0 + self.segments[-1].length - 1e-6
            if self.aborted or (at_end and self.closed):
                self.finish(board)
            elif self.stopping:
                self.state = "held"
            else:
                self.state = "starved"  # waiting for more segments (or VE)
            return [board.axes[i] for i in self.axes]
        if self.next_poll is not None and self.next_poll <= now:
            self.next_poll = None
            if self.state == "running" and not self.stopping \
                    and abs(self.task.scale(board) - self.scale_used) > 1e-12:
                self.replan(board)
        return []

    def _enter_segments(self, board: Board, now: int) -> None:
        """Every segment start reached by now: VIO actions, queue units."""
        while self.boundaries and self.boundaries[0][0] <= now:
            _tick, j = self.boundaries.pop(0)
            for _passed in range(self.current, j):
                self._release_unit(board)
            self.current = j
            self._segment_start(board, j, now)

    def _segment_start(self, board: Board, j: int, now: int) -> None:
        io = self.segments[j].defn.io if j < len(self.segments) else None
        if io is None:
            return
        on, off, mask = io
        self.drive(board, on, mask)
        if off is not None:
            self.task.pulse = (now + PULSE_TICKS, off, mask)

    @staticmethod
    def drive(board: Board, bits: int, mask: int) -> None:
        io = board.io
        io.latch((io.outputs & ~mask) | (bits & mask), board.tick)
        board.cross_axis_event = True  # an SW may wait on an output level

    def _release_unit(self, board: Board) -> None:
        """The path has passed a segment: its queue unit is free again."""
        for i, n in self.reserved.items():
            if n > 0:
                self.reserved[i] = n - 1
                queue = board.axes[i].queue
                queue.used_units = max(0, queue.used_units - 1)

    # ---- the end -----------------------------------------------------------------------
    def withdraw(self, axis: Axis, board: Board) -> None:
        """A member's queue was flushed (ST, SA, FL, KS, SI, a limit, a reset): the
        contour is abandoned. Running, it ramps down on its path at VA (a kill after
        this stops the axes at once); not yet started, it is dropped."""
        self.reserved.pop(axis.index, None)  # the flush empties that queue's units
        if self.state == "finished" or self.aborted:
            return
        self.aborted = True
        self.closed = True  # later VPs open a new contour
        if self.state == "running":
            if not self.stopping:
                self.stopping = True
                self.replan(board, stop=True)
            board.cross_axis_event = True
            return
        self.finish(board)

    def finish(self, board: Board) -> None:
        self.state = "finished"
        self.plan_end_tick = None
        self.boundaries = []
        for i, n in self.reserved.items():
            queue = board.axes[i].queue
            queue.used_units = max(0, queue.used_units - n)
        self.reserved = {}
        axes = [board.axes[i] for i in self.axes]
        for axis in axes:
            axis.linked = []
        if self.done_flag and not self.aborted:
            for axis in axes:
                board.set_axis_flag(axis, F.AXIS_DONE)
        task = self.task
        if self in task.contours:
            task.contours.remove(self)
        board.cross_axis_event = True
        if task.contours:
            task.contours[0].maybe_start(board)
