"""Paths of straight lines and circular arcs, and the speed planned along them.

A path is a list of segments (lines, or arcs given by a centre and an angle) that blend
without stopping. The speed is planned along the path length ``s``: each segment's speed
rises toward its end velocity (or stays at its start velocity and falls to a lower end
velocity) at the segment's acceleration, never above max(start, end) x override, on arcs
never above sqrt(A R) (so the centripetal acceleration stays within A too), and always
able to stop at the end of the known path. The result is pieces of constant acceleration
in time, so position and speed along the path are closed-form at any instant. Points are
computed from the geometry (arc points from the centre and angle, never accumulated), and
each axis follows its coordinate of the path as a motion with the shared `MotionPlan`
interface (`ContourMotion`), split into phases where that axis may turn round, so limit
searches, outputs tied to positions and the servo work on it unchanged.

Used by the MAXk's vector contouring; the same planner carries any controller's
interpolated path (the Trio's BASE group moves, the MM4005's trajectory). A path may also
be given in time rather than speed (`plan_timed`: each segment a displacement over a given
duration, the MM4005's time-based trajectory): the same segments and pieces, with the
speed along the path continuous across every seam and each segment ending exactly on its
duration.

Long module: the geometry, the speed plan (made whole, or lazily as far as it is looked
at) and each axis's view of it are one planner whose parts read each other's private
state (the plan's forward pass, the motion's end when the plan completes).
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

from maxk.firmware_model.profiles import RampShape

EPS = 1e-9  # path lengths closer than this are one point


# ---- definitions and geometry ---------------------------------------------------------
@dataclass(frozen=True, slots=True)
class SegmentDef:
    """A VP or VC as defined, with the VA/VV/VIO values in effect when it was sent."""

    kind: str  # "line", "arc" or "sphere"
    values: tuple[float | None, ...]  # line: one coordinate per contour axis; arc: centre
    # sphere (an arc anywhere in the space of the first three axes): centre (3), the unit
    # direction the arc leaves its start along (3), its end (3), then further axes' rises
    relative: bool
    angle: float  # arc: degrees, positive from the first axis toward the second
    v_start: float | None  # None: go on at the previous segment's end velocity
    v_end: float
    accel: float
    io: tuple[int, int | None, int] | None
    # its own top speed (a Trio move's SPEED or FORCE_SPEED): the segment cruises at it
    # whatever its ends are; v_end is then the seam speed alone, which may be above the
    # top (the segment ramps up to it at its end). None: max(v_start, v_end) (a VP/VV)
    v_top: float | None = None


def _snap(x: float) -> float:
    """Arc ends land on whole counts when the geometry says so (90-degree multiples)."""
    r = round(x)
    return float(r) if abs(x - r) < 1e-6 else x


class Segment:
    """A resolved segment: where it starts and ends on the path (s0, length)."""

    __slots__ = ("defn", "s0", "length", "start", "end", "unit", "cx", "cy", "radius",
                 "theta0", "turn", "v_start", "v_end", "accel", "ceiling", "arc_cap",
                 "frame", "topped")

    def __init__(self, defn: SegmentDef, start: tuple[float, ...], s0: float,
                 v_previous: float | None) -> None:
        self.defn = defn
        self.s0 = s0
        self.start = start
        self.accel = defn.accel
        self.v_end = defn.v_end
        self.v_start = defn.v_start if defn.v_start is not None else (
            v_previous if v_previous is not None else defn.v_end)
        self.topped = defn.v_top is not None
        self.ceiling = defn.v_top if defn.v_top is not None else max(self.v_start,
                                                                     self.v_end)
        self.arc_cap = math.inf
        self.unit: tuple[float, ...] = tuple(0.0 for _ in start)
        self.cx = self.cy = self.radius = self.theta0 = self.turn = 0.0
        self.frame: tuple[float, ...] = ()  # sphere: centre, e1 (start), e2 (way on)
        if defn.kind == "sphere":
            self.end = self._sphere(defn, start)
        elif defn.kind == "line":
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
                theta = self.theta0 + self.turn
                end = (_snap(self.cx + self.radius * math.cos(theta)),
                       _snap(self.cy + self.radius * math.sin(theta)), *start[2:])
            # a helix: values beyond the centre move further axes linearly along the
            # arc (relative); the path length stays the arc's (its speed is the circle's)
            rise = tuple(0.0 if v is None else v for v in defn.values[2:])
            if any(rise):
                end = (*end[:2], *(s + d for s, d in zip(start[2:], rise, strict=False)),
                       *start[2 + len(rise):])
            self.end = end

    def _sphere(self, defn: SegmentDef, start: tuple[float, ...]) -> tuple[float, ...]:
        """An arc in the space of axes 0..2 (MSPHERICAL): the circle through the start
        about the centre, leaving along e2; further axes rise in proportion."""
        v = [0.0 if x is None else float(x) for x in defn.values]
        centre, e2, end3, rise = v[0:3], v[3:6], v[6:9], v[9:]
        d = [start[i] - centre[i] for i in range(3)]
        self.radius = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        e1 = [x / self.radius for x in d] if self.radius > 0 else [1.0, 0.0, 0.0]
        self.frame = (*centre, *e1, *e2)
        self.turn = math.radians(defn.angle)
        self.length = self.radius * abs(self.turn)
        if self.radius > 0:
            self.arc_cap = math.sqrt(self.accel * self.radius)
        return (*end3, *(s + r for s, r in zip(start[3:], rise, strict=False)),
                *start[3 + len(rise):])

    @property
    def is_arc(self) -> bool:
        return self.defn.kind != "line"

    def coordinate(self, sigma: float, k: int) -> float:
        """Axis k's ideal position sigma counts along this segment."""
        if sigma >= self.length:
            return self.end[k]
        if not self.is_arc:
            return self.start[k] + self.unit[k] * sigma
        if self.frame and k < 3:
            f, theta = self.frame, sigma / self.radius
            return f[k] + self.radius * (math.cos(theta) * f[3 + k]
                                         + math.sin(theta) * f[6 + k])
        if k > 1 or self.frame:  # (a helix's further axes: in proportion to the arc)
            rise = self.end[k] - self.start[k]
            return self.start[k] + rise * sigma / self.length if rise else self.start[k]
        if self.radius == 0:
            return self.start[k]
        theta = self.theta0 + math.copysign(sigma / self.radius, self.turn)
        if k == 0:
            return self.cx + self.radius * math.cos(theta)
        return self.cy + self.radius * math.sin(theta)

    def slope(self, sigma: float, k: int) -> float:
        """d(axis k)/ds: the share of the vector velocity axis k carries."""
        if not self.is_arc:
            return self.unit[k]
        if self.frame and k < 3:
            f, theta = self.frame, sigma / self.radius
            return -math.sin(theta) * f[3 + k] + math.cos(theta) * f[6 + k]
        if k > 1 or self.frame:
            return (self.end[k] - self.start[k]) / self.length if self.length else 0.0
        if self.radius == 0:
            return 0.0
        sign = 1.0 if self.turn > 0 else -1.0
        theta = self.theta0 + sign * sigma / self.radius
        return -sign * math.sin(theta) if k == 0 else sign * math.cos(theta)

    def extremes(self, k: int, a: float, b: float) -> list[float]:
        """Where axis k turns round within (a, b) on an arc (it is monotonic between)."""
        if self.frame and k < 3 and self.radius > 0:
            f = self.frame  # d/dtheta = 0 where tan(theta) = e2[k] / e1[k]
            if f[3 + k] == 0 and f[6 + k] == 0:
                return []
            first = math.atan2(f[6 + k], f[3 + k])
            m = math.ceil((a / self.radius - first) / math.pi)
            found: list[float] = []
            while (first + m * math.pi) * self.radius < b:
                sigma = (first + m * math.pi) * self.radius
                if a + 1e-9 < sigma < b - 1e-9:
                    found.append(sigma)
                m += 1
            return found
        if not self.is_arc or k > 1 or self.radius == 0 or self.frame:
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
    j: float = 0.0  # jerk along the path (S-ramps, path_scurve.py): a cubic in time

    def s(self, tau: float) -> float:
        if self.j:
            return self.s0 + tau * (self.v0 + tau * (0.5 * self.a + tau * self.j / 6.0))
        return self.s0 + self.v0 * tau + 0.5 * self.a * tau * tau

    def v(self, tau: float) -> float:
        if self.j:
            return self.v0 + tau * (self.a + 0.5 * self.j * tau)
        return self.v0 + self.a * tau

    @property
    def s1(self) -> float:
        return self.s0 if math.isinf(self.duration) else self.s(self.duration)

    def tau_at(self, s: float) -> float:
        d = s - self.s0
        if d <= 0:
            return 0.0
        if self.j:  # a cubic: bisection (the speed is never negative within a piece)
            lo, hi = 0.0, self.duration
            if self.s(hi) <= s:
                return hi
            for _ in range(200):
                mid = (lo + hi) / 2.0
                if mid <= lo or mid >= hi:
                    break
                if self.s(mid) < s:
                    lo = mid
                else:
                    hi = mid
            return hi
        root = math.sqrt(max(0.0, self.v0 * self.v0 + 2.0 * self.a * d))
        denominator = self.v0 + root
        return min(2.0 * d / denominator, self.duration) if denominator > 0 else 0.0


class _Forward:
    """Where the forward pass of a plan still being made stands (see PathPlan)."""

    __slots__ = ("allow", "i0", "j", "n", "s", "scale", "t", "v_in")

    def __init__(self, i0: int, n: int, scale: float, t: float, s: float,
                 v_in: float) -> None:
        self.i0 = i0  # the plan's first segment
        self.n = n  # how many segments from i0 it plans over
        self.scale = scale
        self.j = 0  # the next segment (from i0) to plan
        self.t = t  # where that segment starts: time, distance, speed
        self.s = s
        self.v_in = v_in
        self.allow: list[float] = []  # the speed caps at segment ends found so far


class PathPlan:
    """Where the path is at every time from the plan's start: pieces of constant
    acceleration, ending at rest (end_time) or held at speed 0 (end_time None).

    A plan may be made lazily (`plan_path(..., lazy=True)`): its pieces are made segment
    by segment as far as someone looks, with exactly the arithmetic of the whole pass,
    so what it answers never depends on how far it was made. `done` says whether it is
    complete; asking for `end_time`, `s_end` or the whole `pieces` completes it, and
    `on_complete` callbacks run when it completes."""

    def __init__(self, segments: list[Segment], pieces: list[Piece], s_start: float,
                 end_time: float | None, starts: list[float] | None = None,
                 count: int | None = None, s_end: float | None = None) -> None:
        self.segments = segments
        # the segments known when planned (the list may grow later: more VPs)
        self.count = len(segments) if count is None else count
        self.starts = [seg.s0 for seg in segments] if starts is None else starts
        self._pieces = pieces
        self._times = [p.t0 for p in pieces]
        self._ends = [p.s1 for p in pieces]
        self.s_start = s_start
        self._end_time = end_time
        self._s_end = s_end if s_end is not None else (pieces[-1].s1 if pieces
                                                       else s_start)
        self._memo: tuple[float, float, float] = (-1.0, s_start, 0.0)
        self._forward: _Forward | None = None
        self._sorted = True  # the piece ends made so far never decrease
        self.last_arc: int | None = None  # the last arc among the segments, if known
        self.jerked = False  # pieces with a jerk (path_scurve.py's plans)
        self.on_complete: list[Callable[[], None]] = []

    # ---- completeness (lazy plans) ---------------------------------------------------
    @property
    def done(self) -> bool:
        return self._forward is None

    @property
    def horizon(self) -> float:
        """The time up to which the pieces are made (the end time once done): the plan
        never ends before it."""
        forward = self._forward
        if forward is None:
            return self._end_time if self._end_time is not None else math.inf
        return forward.t

    def complete(self) -> None:
        forward = self._forward
        if forward is None:
            return
        first = len(self._pieces)
        ended = False
        while not ended:
            ended = self._step(forward)
        self._index(first)
        self._finish()

    @property
    def pieces(self) -> list[Piece]:
        self.complete()
        return self._pieces

    @property
    def times(self) -> list[float]:
        self.complete()
        return self._times

    @property
    def piece_ends(self) -> list[float]:
        self.complete()
        return self._ends

    @property
    def end_time(self) -> float | None:
        self.complete()
        return self._end_time

    @property
    def s_end(self) -> float:
        self.complete()
        return self._s_end

    def extend(self) -> None:
        """Plan one more segment."""
        forward = self._forward
        if forward is None:
            return
        first = len(self._pieces)
        ended = self._step(forward)
        self._index(first)
        if ended:
            self._finish()

    def _step(self, forward: _Forward) -> bool:
        """One step of the forward pass (one segment's pieces). True: the plan ended
        (at rest at the end of the known path, or held at speed 0)."""
        j = forward.j
        seg = self.segments[forward.i0 + j]
        s, v_in = forward.s, forward.v_in
        length = seg.s0 + seg.length - s
        a = seg.accel
        up = math.sqrt(v_in * v_in + 2.0 * a * max(0.0, length))
        down = math.sqrt(max(0.0, v_in * v_in - 2.0 * a * max(0.0, length)))
        allow = forward.allow
        cap = allow[j] if j < len(allow) else _allowed(self.segments, forward, j)
        v_out = max(min(cap, up), down)
        end = _segment_pieces(self._pieces, forward.t, s, length, v_in, v_out,
                              min(seg.ceiling * forward.scale, seg.arc_cap), a, seg.topped)
        if end is None:
            self._end_time = None
            return True
        forward.t, forward.v_in, forward.s = end, v_out, seg.s0 + seg.length
        forward.j = j + 1
        if forward.j == forward.n:
            self._end_time = end
            return True
        return False

    def _index(self, first: int) -> None:
        """Times and ends of the pieces from `first` on (and whether ends still rise)."""
        pieces, ends = self._pieces, self._ends
        new = [p.s1 for p in pieces[first:]]
        if new and self._sorted:
            last = ends[-1] if ends else new[0]
            for s1 in new:
                if s1 < last:
                    self._sorted = False
                    break
                last = s1
        self._times.extend(p.t0 for p in pieces[first:])
        ends.extend(new)

    def _finish(self) -> None:
        """The plan is complete: its end, then whoever waited for it."""
        self._forward = None
        self._s_end = self._pieces[-1].s1 if self._pieces else self.s_start
        callbacks, self.on_complete = self.on_complete, []
        for callback in callbacks:
            callback()

    def cover(self, s: float) -> None:
        """Make the plan far enough that every piece still to come lies beyond s (and
        one made reaches it), or complete it: then time_at(s) and the path's end as seen
        from s are what the complete plan says."""
        margin = 1e-6 + 1e-12 * abs(s)
        while self._forward is not None:
            if not self._sorted:
                self.complete()  # (rounding made piece ends step back: search them all)
                return
            if self._ends and self._ends[-1] >= s - EPS and self._forward.s > s + margin:
                return
            self.extend()

    # ---- where the path is ---------------------------------------------------------------
    def state(self, t: float) -> tuple[float, float]:
        """(s, speed) at t seconds into the plan."""
        memo = self._memo
        if memo[0] == t:
            return memo[1], memo[2]
        times = self._times
        while self._forward is not None and (not times or times[-1] <= t):
            self.extend()
        pieces = self._pieces
        if not pieces or (self._end_time is not None and t >= self._end_time):
            result = (self._s_end, 0.0)
        else:
            i = max(0, bisect.bisect_right(times, t) - 1)
            p = pieces[i]
            tau = min(t - p.t0, p.duration)
            result = (p.s(tau), max(0.0, p.v(tau)))
            if i + 1 < len(pieces):
                result = (min(result[0], pieces[i + 1].s0), result[1])
        self._memo = (t, result[0], result[1])
        return result

    def segment_at(self, s: float) -> Segment:
        i = max(0, bisect.bisect_right(self.starts, s, 0, self.count) - 1)
        while i > 0 and self.segments[i].length == 0 and self.segments[i].s0 >= s:
            i -= 1
        return self.segments[i]

    def time_at(self, s: float) -> float | None:
        """When the plan reaches s (None if it never does)."""
        if self._forward is not None:
            self.cover(s)
        if self._forward is None and s > self._s_end + EPS:
            return None
        i = bisect.bisect_left(self._ends, s - EPS)
        if i >= len(self._pieces):
            return self._end_time
        p = self._pieces[i]
        if math.isinf(p.duration):
            return p.t0 if s <= p.s0 + EPS else None
        return p.t0 + p.tau_at(s)

    def point(self, s: float, k: int) -> float:
        seg = self.segment_at(s)
        return seg.coordinate(s - seg.s0, k)


def _end_cap(segments: list[Segment], forward: _Forward, j: int) -> float:
    """The cap on the speed at the end of segment j (from i0): its VV end velocity, its
    own and the next segment's speed ceilings (x override, sqrt(A R) on arcs); the
    known path ends at rest."""
    if j == forward.n - 1:
        return 0.0
    scale = forward.scale
    seg = segments[forward.i0 + j]
    after = segments[forward.i0 + j + 1]
    return min(seg.v_end * scale, _seam_cap(seg, scale), _seam_cap(after, scale))


def _seam_cap(seg: Segment, scale: float) -> float:
    """What a segment's own speed allows at its seams: its ceiling (x override, sqrt(A R)
    on arcs); a segment with its own top speed only its arc's cap (its seam speed may be
    above its top: it ramps up to it at its end)."""
    if seg.topped:
        return seg.arc_cap
    return min(seg.ceiling * scale, seg.arc_cap)


def _allowed(segments: list[Segment], forward: _Forward, j: int) -> float:
    """The backward pass's speed cap at the end of segment j (from i0), looking ahead
    only as far as braking needs.

    The backward pass sets allow[m] = min(end cap m, sqrt(allow[m+1]^2 + 2 A L) of the
    segment after m); allow[m+1] >= 0, so where the end cap is at most sqrt(2 A L) of
    the next segment (that segment alone is long enough to stop in from it), allow[m]
    is its end cap whatever follows, in floating point too (x + c >= c for x >= 0 and
    sqrt are monotonic). From the first such m at or after j the backward pass runs
    down to j with the very operations of the whole pass."""
    allow = forward.allow
    if j < len(allow):
        return allow[j]
    n, i0 = forward.n, forward.i0
    m = j
    value = _end_cap(segments, forward, m)
    while m < n - 1:
        after = segments[i0 + m + 1]
        if value <= math.sqrt(2.0 * after.accel * after.length):
            break
        m += 1
        value = _end_cap(segments, forward, m)
    found = [value]
    for x in range(m - 1, len(allow) - 1, -1):
        seg = segments[i0 + x + 1]
        value = min(_end_cap(segments, forward, x),
                    math.sqrt(value ** 2 + 2.0 * seg.accel * seg.length))
        found.append(value)
    found.reverse()
    allow.extend(found)
    return allow[j]


def _allow_all(segments: list[Segment], forward: _Forward) -> None:
    """The whole backward pass at once (a plan made whole): the values _allowed gives,
    from the end of the path (where every anchor's value comes from anyway)."""
    scale, i0, n = forward.scale, forward.i0, forward.n
    ceilings = [_seam_cap(seg, scale) for seg in segments[i0:i0 + n]]
    allow = [min(seg.v_end * scale, ceilings[j], ceilings[j + 1])
             for j, seg in enumerate(segments[i0:i0 + n - 1])]
    allow.append(0.0)  # the known path ends at rest
    for j in range(n - 1, 0, -1):  # backward: every later cap can still be met
        seg = segments[i0 + j]
        allow[j - 1] = min(allow[j - 1],
                           math.sqrt(allow[j] ** 2 + 2.0 * seg.accel * seg.length))
    forward.allow = allow
def _segment_pieces(out: list[Piece], t: float, s: float, length: float, v_in: float,
                    v_out: float, ceiling: float, accel: float,
                    topped: bool = False) -> float | None:
    """Append one segment's pieces (ramp to the top speed, cruise, ramp to v_out).
    Returns the time at its end, or None if the path is held at speed 0 inside it."""
    if length <= 0:
        return t
    if topped and v_out > ceiling + 1e-9:
        return _rising_end_pieces(out, t, s, length, v_in, v_out, ceiling, accel)
    if v_out > ceiling + 1e-9:  # a lowered override: slow down over the whole segment
        a = (v_out * v_out - v_in * v_in) / (2.0 * length)
        duration = (v_out - v_in) / a if a else length / max(v_in, EPS)
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


def _rising_end_pieces(out: list[Piece], t: float, s: float, length: float, v_in: float,
                       v_out: float, top: float, accel: float) -> float:
    """A segment with its own top speed whose end is faster than it: to the top speed,
    cruise, and up to v_out at the end; entered faster than its top too, down to the
    top (or as far down as its length allows) and up again."""
    low = top
    if v_in > top:
        valley = (v_in * v_in + v_out * v_out) / 2.0 - accel * length
        if valley > top * top:
            low = math.sqrt(valley)
    d1 = abs(low * low - v_in * v_in) / (2.0 * accel)
    d3 = (v_out * v_out - low * low) / (2.0 * accel)
    cruise = length - d1 - d3
    if cruise < 0:  # rounding
        d1 = max(0.0, d1 + cruise)
        cruise = 0.0
    if abs(low - v_in) > 1e-12:
        duration = abs(low - v_in) / accel
        out.append(Piece(t, duration, s, v_in, accel if low > v_in else -accel))
        t += duration
        s += d1
    if cruise > 1e-9:
        out.append(Piece(t, cruise / low, s, low, 0.0))
        t += cruise / low
        s += cruise
    duration = (v_out - low) / accel
    out.append(Piece(t, duration, s, low, accel))
    return t + duration


def plan_path(segments: list[Segment], i0: int, s_now: float, v_now: float | None,
              scale: float, *, lazy: bool = False,
              starts: list[float] | None = None, last_arc: int | None = None) -> PathPlan:
    """Plan from s_now (inside segment i0) at speed v_now (None: from rest, taking the
    segment's start velocity at once, as a stepper takes its base velocity).

    Each segment's end speed is capped so that every later cap can still be met (the
    backward pass, looking ahead as far as braking needs: `_allowed`); the pieces follow
    segment by segment (the forward pass, `PathPlan.extend`). Lazy, the plan is made as
    far as it is looked at, so a re-plan costs what the next few segments cost, not
    what the whole path ahead costs; `starts` (the segments' s0, kept by the caller as
    the path grows) and `last_arc` (the index of the last arc, -1: none) spare looking
    through them all again."""
    forward = _Forward(i0, len(segments) - i0, scale, 0.0, s_now, 0.0)
    if not lazy:
        _allow_all(segments, forward)
    first = segments[i0]
    if v_now is None:
        remaining = max(0.0, first.s0 + first.length - s_now)
        reachable = math.sqrt(_allowed(segments, forward, 0) ** 2
                              + 2.0 * first.accel * remaining)
        v_now = min(first.v_start * scale, min(first.ceiling * scale, first.arc_cap),
                    reachable)
    forward.v_in = v_now
    plan = PathPlan(segments, [], s_now, None, starts)
    plan.last_arc = last_arc
    plan._forward = forward
    if not lazy:
        plan.complete()
    return plan


def plan_stop(segments: list[Segment], i0: int, s_now: float, v_now: float,
              scale: float, *, lazy: bool = False, starts: list[float] | None = None,
              last_arc: int | None = None, accel: float | None = None) -> PathPlan:
    """Ramp down along the path at the present segment's VA (VH1, ST, a soft limit), or
    at `accel` (the MC405's FASTDEC)."""
    if accel is None:
        accel = segments[i0].accel
    distance = v_now * v_now / (2.0 * accel)
    if s_now + distance >= segments[-1].s0 + segments[-1].length:
        # it stops at the end anyway
        return plan_path(segments, i0, s_now, v_now, scale, lazy=lazy, starts=starts,
                         last_arc=last_arc)
    if v_now <= 0:
        return PathPlan(segments, [], s_now, 0.0, starts)
    duration = v_now / accel
    return PathPlan(segments, [Piece(0.0, duration, s_now, v_now, -accel)], s_now, duration,
                    starts)


# ---- paths of given durations -----------------------------------------------------------
def timed_segments(displacements: Sequence[Sequence[float]]) -> list[Segment]:
    """Lines from the origin, one per displacement (one value per axis of the path). They
    carry no speed or acceleration of their own: `plan_timed` gives their times."""
    segments: list[Segment] = []
    start = tuple(0.0 for _ in displacements[0]) if displacements else ()
    s0 = 0.0
    for delta in displacements:
        end = tuple(a + d for a, d in zip(start, delta, strict=True))
        seg = Segment(SegmentDef("line", end, False, 0.0, None, 0.0, 0.0, None), start, s0,
                      None)
        segments.append(seg)
        start, s0 = seg.end, s0 + seg.length
    return segments


def seam_speed(before: Segment, v_before: float, after: Segment, v_after: float) -> float:
    """The path speed at the seam of two timed segments: the lower of their mean speeds,
    scaled by the cosine of the turn between them (0 for a turn of 90 degrees or more, or
    a dwell), so that no axis reverses at speed and the segments' own speeds bound it."""
    if before.length <= 0 or after.length <= 0:
        return 0.0
    turn = sum(a * b for a, b in zip(before.unit, after.unit, strict=True))
    return min(v_before, v_after) * max(0.0, min(1.0, turn))


def plan_timed(segments: list[Segment], durations: Sequence[float],
               blend: float) -> PathPlan:
    """A path whose segments last given durations, from rest to rest.

    Each segment starts and ends at its seam speeds (`seam_speed`; 0 at the path's two
    ends) and changes speed over a ramp of min(blend, duration) / 2 at each end, at
    constant acceleration; between the ramps it cruises at the one speed that covers its
    length in exactly its duration. So the path stands exactly on every seam at the sum
    of the durations before it, the speed along the path is continuous (a speed change
    between segments is spread over up to `blend` seconds across the seam), and it never
    runs backwards: the seam speeds are at most the segment's mean speed, so the cruise
    is at least that mean (at most twice it, a segment starting and ending at rest)."""
    n = len(segments)
    if n != len(durations) or n == 0:
        raise ValueError("one duration per segment, at least one segment")
    means = [seg.length / duration for seg, duration in zip(segments, durations, strict=True)]
    seams = [0.0] + [seam_speed(segments[i], means[i], segments[i + 1], means[i + 1])
                     for i in range(n - 1)] + [0.0]
    pieces: list[Piece] = []
    end_times: list[float] = []
    t = 0.0
    for i, (seg, duration) in enumerate(zip(segments, durations, strict=True)):
        length = seg.length
        w_in, w_out = seams[i], seams[i + 1]
        ramp = min(blend, duration) / 2.0
        if length <= 0:
            pieces.append(Piece(t, duration, seg.s0, 0.0, 0.0))
            t += duration
            end_times.append(t)
            continue
        cruise = (length - (w_in + w_out) * ramp / 2.0) / (duration - ramp)
        ramp_in = ramp if cruise != w_in else 0.0  # (a ramp at one speed is cruise)
        ramp_out = ramp if cruise != w_out else 0.0
        if ramp_in > 0:
            pieces.append(Piece(t, ramp_in, seg.s0, w_in, (cruise - w_in) / ramp_in))
        middle = duration - ramp_in - ramp_out
        if middle > 0:
            pieces.append(Piece(t + ramp_in, middle,
                                seg.s0 + (w_in + cruise) * ramp_in / 2.0, cruise, 0.0))
        if ramp_out > 0:  # placed from the segment's end, so that it ends exactly on it
            pieces.append(Piece(t + duration - ramp_out, ramp_out,
                                seg.s0 + length - (cruise + w_out) * ramp_out / 2.0, cruise,
                                (w_out - cruise) / ramp_out))
        t += duration
        end_times.append(t)
    return TimedPlan(segments, pieces, end_times)


class TimedPlan(PathPlan):
    """A `plan_timed` plan: at a time within a rounding error of a segment's end time the
    path stands exactly on that end (a tick whose time is the sum of the durations, to
    the last bit or not, finds the axes on the element's end point)."""

    def __init__(self, segments: list[Segment], pieces: list[Piece],
                 end_times: list[float]) -> None:
        super().__init__(segments, pieces, 0.0, end_times[-1])
        self._s_end = segments[-1].s0 + segments[-1].length
        self._end_times = end_times  # each segment's end time (increasing)
        self._end_s = [seg.s0 + seg.length for seg in segments]

    def state(self, t: float) -> tuple[float, float]:
        s, v = super().state(t)
        ends = self._end_times
        i = bisect.bisect_left(ends, t - 1e-9 - 1e-12 * abs(t))
        if i < len(ends) and abs(ends[i] - t) <= 1e-9 + 1e-12 * abs(t):
            return self._end_s[i], v
        return s, v


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
    """One axis's share of a path plan, with the interface of profiles.Motion.

    On a plan still being made (lazy), the motion slews (end_time None) until the plan
    completes: then it takes the end the complete plan gives (`on_end` callbacks tell
    whoever scheduled the axis). Its direction is the one the complete plan gives."""

    contour = True
    # the offsets the motion stays within, if its user knows them (switch searches
    # skip the switches outside: cheaper than making every phase of a long path)
    reach: tuple[float, float] | None = None
    # an offset within this share of itself (+1) of a whole count is that count (0: never):
    # a path whose points are whole counts (a timed path's element ends) stands on them
    # where the axis's whole steps are counted, not a rounding error short of them
    snap = 0.0

    def __init__(self, plan: PathPlan, k: int, origin: float, scale: float = 1.0) -> None:
        self.plan = plan
        self.k = k
        self.origin = origin  # the axis's counter when the plan started, in its counts
        # the axis's counts per plan unit: a plan in user units (the MM4005's trajectory,
        # its axes of different resolutions) drives each axis in its own counts
        self.scale = scale
        self._phases: list[ContourPhase] | None = None  # made when first asked for
        self._times: list[float] = []
        self.peak_speed = 0.0  # (only MT/ML scaling reads it)
        self.end_time: float | None = None
        self.ramp_end_time = 0.0
        self.final_offset = 0
        self.monotonic = False
        self._final = False
        direction = None if plan.done else self._first_direction()
        if direction is None:  # complete (or completed to find the direction)
            self._set_end()
        else:
            self.direction = direction
            plan.on_complete.append(self._set_end)

    def _set_end(self) -> None:
        """The plan is complete: the end, the final whole counts, monotonic or not."""
        if self._final:
            return
        self._final = True
        plan, k = self.plan, self.k
        self.end_time = plan.end_time
        self.ramp_end_time = plan.end_time if plan.end_time is not None else 0.0
        if plan.end_time is not None:
            self.final_offset = round(plan.point(plan.s_end, k) * self.scale) - round(self.origin)
        self.direction, self.monotonic = self._directions()

    @property
    def phases(self) -> list[ContourPhase]:
        """Stretches where this axis moves one way (limit searches, the servo)."""
        if self._phases is None:
            phases = _axis_phases(self.plan, self.k)
            scale = self.scale
            if scale != 1.0:
                phases = [replace(p, v1=p.v1 * scale, v2=p.v2 * scale) for p in phases]
            self._phases = phases
            self._times = [p.t0 for p in phases]
        return self._phases

    def _directions(self) -> tuple[int, bool]:
        """The way the axis first moves, and whether it only ever moves that way: from
        the segments' slopes for straight lines (cheap: no phases), else the phases."""
        plan, k = self.plan, self.k
        first = max(0, bisect.bisect_right(plan.starts, plan.s_start, 0, plan.count) - 1)
        signs: set[int] = set()
        direction = 0
        for seg in plan.segments[first:]:
            if seg.s0 >= plan.s_end - EPS and seg.length > 0 and signs:
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
            if seg.s0 + seg.length >= plan.s_end - EPS:
                break
        return direction or 1, len(signs) <= 1

    def _first_direction(self) -> int | None:
        """_directions' direction on a plan still being made, made only as far as the
        first segment that moves this axis (None: the plan had to be completed).

        Over straight lines the direction is the first nonzero slope before the path's
        end; covering each segment's end shows the end lies beyond it. An arc anywhere
        ahead (the direction then comes from the phases) completes the plan."""
        plan, k = self.plan, self.k
        count = plan.count
        segments = plan.segments
        i = max(0, bisect.bisect_right(plan.starts, plan.s_start, 0, count) - 1)
        last_arc = plan.last_arc
        if last_arc is None:
            last_arc = max((x for x in range(count) if segments[x].is_arc), default=-1)
        if last_arc >= i:
            plan.complete()
            return None
        while i < count:
            seg = segments[i]
            plan.cover(seg.s0 + seg.length)
            if plan.done:
                return None
            u = seg.unit[k] if seg.length > 0 else 0.0
            if u:
                return 1 if u > 0 else -1
            i += 1
        plan.complete()
        return None

    def phase_at(self, t: float) -> ContourPhase | None:
        phases = self.phases
        if not phases:
            return None
        return phases[max(0, bisect.bisect_right(self._times, t) - 1)]

    def offset(self, t: float) -> float:
        if not self._final:
            self.plan.state(t)  # (may complete the plan, and so set the end)
        if self.end_time is not None and t >= self.end_time:
            return float(self.final_offset)
        s, _v = self.plan.state(t)
        x = self.plan.point(s, self.k) * self.scale - self.origin
        if self.snap:
            whole = round(x)
            if abs(x - whole) <= self.snap * (1.0 + abs(x)):
                return float(whole)
        return x

    def velocity(self, t: float) -> float:
        if not self._final:
            self.plan.state(t)
        if self.end_time is not None and t >= self.end_time:
            return 0.0
        s, v = self.plan.state(t)
        seg = self.plan.segment_at(s)
        return v * seg.slope(s - seg.s0, self.k) * self.scale


def _axis_phases(plan: PathPlan, k: int) -> list[ContourPhase]:
    """Split the plan where axis k may turn round: segment boundaries, arc extremes."""
    phases: list[ContourPhase] = []
    for p in plan.pieces:
        if math.isinf(p.duration):
            phases.append(ContourPhase(p.t0, math.inf, 0.0, 0.0, 1, True))
            continue
        s_a, s_b = p.s0, p.s1
        cuts = [s_a]
        i = max(0, bisect.bisect_right(plan.starts, s_a, 0, plan.count) - 1)
        while i < len(plan.segments) and plan.segments[i].s0 < s_b - EPS:
            seg = plan.segments[i]
            lo, hi = max(s_a, seg.s0), min(s_b, seg.s0 + seg.length)
            if hi > lo:
                if seg.s0 > s_a + EPS:
                    cuts.append(seg.s0)
                cuts.extend(seg.s0 + e for e in seg.extremes(k, lo - seg.s0, hi - seg.s0))
            i += 1
        cuts.append(s_b)
        for a, b in zip(cuts, cuts[1:], strict=False):
            if b - a <= EPS:
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


