"""Moves of the MC405 on the shared machine: runs of buffered moves, and linked axes.

A *run* is what one BASE group does from rest to rest: one interpolated path on the
shared path planner (`firmware_model/path.py`) whose segments are the group's moves,
joined without stopping while MERGE is ON, or one single-axis move as a closed-form
profile (`profiles.plan_move`). Each axis of a path run follows its coordinate of the
path as a `ContourMotion`, a single-axis run its profile, through `MotionAxis.begin`,
so positions, limit and trigger searches work on them unchanged.

A *linked* axis has no motion of its own: CONNPATH moves it by the path distance of a
group, CAMBOX by a TABLE profile over another axis's travel. Its demand position is a
closed-form function of the tick through the motions it follows.

Everything here evaluates on arrays of ticks (numpy, the shared machine's
`firmware_model/sampling.py`), so a trace of every servo cycle of a stretch costs a few
array operations; a single reading is an array of one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from maxk.firmware_model.axis import MotionAxis
from maxk.firmware_model.path import (
    ContourMotion,
    PathPlan,
    Segment,
    SegmentDef,
    plan_path,
    plan_stop,
)
from maxk.firmware_model.profiles import Motion, RampShape, plan_move
from maxk.firmware_model.sampling import PlanArrays, profile_offset_speed
from maxk.firmware_model.servo import Gains

from .geometry import sphere_definition
from .profiles_sp import jerk_ramp, seam

Ticks = np.ndarray  # integer servo ticks
SHAPE = RampShape.LINEAR  # the MC405's ramps are linear (trapezoid) (D: S-ramps not modelled)


# ---- runs -----------------------------------------------------------------------------
@dataclass
class Run:
    """Buffered moves of one BASE group that run from rest to rest."""

    axes: tuple[int, ...]  # axes[0] is the base axis: its SPEED/ACCEL/UNITS drive the path
    deltas: list[tuple[int, ...]]  # per move, counts per axis
    speeds: list[float]  # per move, vector speed, counts/s
    accels: list[float]  # per move, counts/s^2
    decel: float  # the base axis's DECEL (single-axis profiles), counts/s^2
    units: float  # the base axis's UNITS when loaded: VP_SPEED is in its user units
    single: bool  # one axis, MERGE OFF: a closed-form profile, nothing merges into it
    sramp: float = 0.0  # SRAMP when loaded, seconds: the acceleration's rise (S-ramps)
    scale: float = 1.0  # the path's speed scale (feed hold: FHSPEED's share, feedhold.py)
    jerk: float = 0.0  # VP_MODE 5/6: the jerk limit when loaded, counts/s^3 (0: none)
    preset: Motion | None = None  # a CAM's own profile (in time), made when loaded
    table: int | None = None  # a CAM's first TABLE index (TABLE_POINTER)
    cam: tuple[int, float] | None = None  # a CAM's last TABLE index, multiplier (recam)
    started: bool = False
    stopping: bool = False  # CANCEL/RAPIDSTOP: ramping down, takes no more moves
    start_tick: int = 0
    plan: PathPlan | None = None
    arrays: PlanArrays | None = None
    plan_tick: int = 0
    end_tick: int = 0
    profile: Motion | None = None  # single-axis runs
    segments: list[Segment] = field(default_factory=list)
    arcs: dict[int, tuple[float, ...]] = field(default_factory=dict)
    # move index -> an arc's centre (counts from the move's start) and turn (degrees);
    # MSPHERICAL's: its centre, way on and end, then turn (geometry.py)
    kinds: dict[int, int] = field(default_factory=dict)  # move index -> MTYPE (1: MOVE)
    counted: int = -1  # the last move MOVE_COUNT has counted (moves.count_moves)
    sp: dict[int, tuple[float, float]] = field(default_factory=dict)
    # an SP move's index -> its (STARTMOVE_SPEED, ENDMOVE_SPEED), counts/s (-1: unused)

    @property
    def base(self) -> int:
        return self.axes[0]

    @property
    def mergeable(self) -> bool:
        return not self.single and not self.stopping

    def definitions(self) -> list[SegmentDef]:
        """Each move a relative straight segment at its own speed (its top); the first
        starts from rest (v_start 0), each hands over to the next at the seam speed
        (MERGE: no stop in between; profiles_sp.seam)."""
        last = len(self.deltas) - 1
        return [SegmentDef("line", tuple(float(d) for d in delta), True, 0.0,
                           0.0 if j == 0 else None,
                           seam(self.speeds, self.sp, j) if j < last else self.speeds[j],
                           self.accels[j], None, self.speeds[j])
                for j, delta in enumerate(self.deltas)]

    def resolve(self, origin: tuple[float, ...]) -> None:
        """Segments of every move loaded so far, from the group's start position."""
        defs = self.definitions()
        if 0 < len(self.segments) < len(defs):  # the last one's seam: the move after it
            self.segments[-1].v_end = defs[len(self.segments) - 1].v_end
        while len(self.segments) < len(defs):
            j = len(self.segments)
            defn = defs[j]
            start = self.segments[-1].end if self.segments else origin
            if j in self.arcs and len(self.arcs[j]) > 3:  # MSPHERICAL (geometry.py)
                defn = sphere_definition(self.arcs[j], start,
                                         tuple(float(d) for d in self.deltas[j][3:]), defn)
            elif j in self.arcs:  # MOVECIRC: the centre on the path's own frame
                dx, dy, angle = self.arcs[j]  # (MHELICAL: the third axis rises along it)
                rise = tuple(float(d) for d in self.deltas[j][2:])
                defn = SegmentDef("arc", (start[0] + dx, start[1] + dy, *rise), True, angle,
                                  defn.v_start, defn.v_end, defn.accel, None, defn.v_top)
            if self.segments:
                last = self.segments[-1]
                self.segments.append(Segment(defn, last.end, last.s0 + last.length, last.v_end))
            else:
                self.segments.append(Segment(defn, origin, 0.0, None))

    def segment_index(self, s: float) -> int:
        i = 0
        while (i + 1 < len(self.segments)
               and self.segments[i].s0 + self.segments[i].length <= s + 1e-9):
            i += 1
        return i

    def moves_left(self, tick: int, period: float) -> int:
        """Moves not yet finished (they hold the axes' move buffer)."""
        if not self.started or self.plan is None:
            return len(self.deltas)
        s, _v = self.plan.state((tick - self.plan_tick) * period)
        return len(self.deltas) - self.segment_index(s)

    def next_boundary(self, now: int, period: float) -> int | None:
        """The next tick the path finishes one of its moves (a move buffer slot frees),
        while more moves follow; None for a single-axis profile or the last move."""
        if self.plan is None or self.profile is not None:
            return None
        s, _v = self.plan.state((now - self.plan_tick) * period)
        i = self.segment_index(s)
        while i < len(self.segments) - 1:
            segment = self.segments[i]
            t = self.plan.time_at(segment.s0 + segment.length)
            if t is None:
                return None
            tick = self.plan_tick + math.ceil(t / period - 1e-9)
            if tick > now:
                return tick
            i += 1
        return None

    # ---- where the run is -------------------------------------------------------------
    def distance_speed(self, ticks: Ticks, period: float) -> tuple[np.ndarray, np.ndarray]:
        """Path distance from the run's start (counts) and path speed (counts/s)."""
        if self.profile is not None:
            offset, speed = profile_offset_speed(self.profile,
                                                 (ticks - self.start_tick) * period)
            return np.abs(offset), speed
        assert self.arrays is not None
        return self.arrays.state((ticks - self.plan_tick) * period)

    def length(self) -> float:
        """The path length the run ends at (counts)."""
        if self.profile is not None:
            return abs(float(self.profile.final_offset))
        assert self.plan is not None
        return self.plan.s_end

    def plan_new(self, now: int, stop: bool = False, period: float = 0.001) -> PathPlan:
        """The path planned from where it is now (from rest when it starts now)."""
        if self.plan is None:
            return plan_path(self.segments, 0, 0.0, 0.0, self.scale)
        s, v = self.plan.state((now - self.plan_tick) * period)
        i = self.segment_index(s)
        if stop:
            return plan_stop(self.segments, i, s, v, 1.0)
        return plan_path(self.segments, i, s, v, self.scale)

    def motion_for(self, plan: PathPlan, k: int, origin: int) -> ContourMotion:
        return ContourMotion(plan, k, float(origin))


def single_profile(distance: int, speed: float, accel: float, decel: float,
                   sramp: float = 0.0, jerk: float = 0.0) -> Motion:
    """A single-axis move from rest: trapezoid (or triangle) at ACCEL/DECEL, linear ramps;
    with SRAMP (seconds) each ramp's acceleration rises linearly over `sramp`, holds at
    ACCEL/DECEL and falls over `sramp` (the shared S-curve whose jerk share p gives a
    rise of p/2 of the ramp: a ramp to SPEED lasts SPEED/ACCEL + sramp, so p = 2 sramp /
    (SPEED/ACCEL + sramp), at most 1: I). With a jerk limit (VP_MODE 5/6, counts/s^3)
    each ramp's acceleration rises at `jerk` (profiles_sp.jerk_ramp)."""
    if jerk > 0:
        up, share_up = jerk_ramp(speed, accel, jerk)
        down, share_down = jerk_ramp(speed, decel, jerk)
        return plan_move(distance, 0.0, speed, up, down, RampShape.SCURVE, share_up,
                         share_down)
    if sramp <= 0:
        return plan_move(distance, 0.0, speed, accel, decel, SHAPE)
    up = min(1.0, 2 * sramp / (speed / accel + sramp))
    down = min(1.0, 2 * sramp / (speed / decel + sramp))
    return plan_move(distance, 0.0, speed, accel, decel, RampShape.SCURVE, up, down)


# ---- linked axes ----------------------------------------------------------------------------
@dataclass
class Connpath:
    """CONNPATH(base[, ratio]) AXIS(n): n moves by ratio x the path distance of the group
    based on `base` (in the base axis's user units, converted with n's UNITS)."""

    base: int
    ratio: float
    origin: float  # n's demand position (counts) when linked
    distance0: float  # the base group's path distance (user units) when linked


@dataclass
class Follow:
    """Which of the link's movement a link follows (link option bits 5 and 14): only
    its forward movement ("forward": each stretch of forward travel adds, backward
    travel is ignored), or only forward movement past the highest position it reached
    ("threshold"). `effective` maps the link's position to the position the link acts
    on; `rebase` takes in the link's travel up to a point (the machine calls it at every
    event and change, between which the link's motion is one monotonic closed form, D)."""

    mode: str  # "forward" or "threshold"
    acc: float = 0.0  # the effective position at `anchor` (threshold: the high water)
    anchor: float | None = None  # the link position `acc` was taken at

    def effective(self, link: np.ndarray) -> np.ndarray:
        if self.anchor is None:
            return link
        if self.mode == "threshold":
            return np.maximum(link, self.acc)
        return self.acc + np.maximum(link - self.anchor, 0.0)

    def rebase(self, link: float) -> None:
        if self.anchor is None:
            self.acc = self.anchor = link
            return
        self.acc = float(self.effective(np.array([link]))[0])
        self.anchor = link

    def raw(self, effective: float) -> float:
        """The link position at which, moving forward from here, the effective position
        reaches `effective`."""
        if self.anchor is None:
            return effective
        if self.mode == "threshold":
            return effective
        return self.anchor + (effective - self.acc)


@dataclass
class Cambox:
    """CAMBOX(start, end, multiplier, link distance, link axis[, options[, link pos[,
    offset start]]]) AXIS(n): while the link axis travels `distance` user units from
    `link_origin`, n follows the TABLE values start..end, offset by the first value
    (counts, times the multiplier), interpolated linearly.

    Options (the CAMBOX help page): `repeat` (bit 2) runs the profile again and again,
    both ways, each cycle going on from where the last ended; `wait` names the start
    event a MARK (bit 0), MARKB (bit 8) or R_MARK (bit 9) start waits for, and until it
    comes `link_origin` is None and the axis holds; `held` (bit 1 or a registration
    start) keeps the axis at its start while the link is short of the start point;
    `pattern` (bit 3) is the TABLE index of the control block whose pattern values
    scale each cycle in turn (runs `pattern_cycle` and the machine's events)."""

    values: np.ndarray  # TABLE(start..end)
    multiplier: float
    distance: float  # link axis user units
    link: int
    link_origin: float | None  # the link axis's DPOS where the profile's 0 is
    origin: float  # n's demand position (counts) at the profile's 0
    repeat: bool = False
    wait: str | None = None  # "MARK", "MARKB", "R_MARK": the start event not yet come
    held: bool = False  # holds at its start until the link reaches it
    offset: float = 0.0  # bit 7: where in the link distance the profile starts
    pattern: int | None = None  # bit 3: the control block's TABLE index
    channel: int = 0  # bit 9: the R_MARK channel
    start_pos: float | None = None  # bit 1: the link DPOS it starts at
    follow: Follow | None = None  # bits 5/14: only the link's forward movement counts
    table_start: int = 0  # the TABLE index of values[0] (TABLE_POINTER)

    def __post_init__(self) -> None:
        self.values = np.asarray(self.values, dtype=float) - float(self.values[0])

    def pointer(self, link_dpos: float) -> float:
        """TABLE_POINTER: the TABLE index of the interval the link is in, plus the share
        of it done (help TABLE_POINTER); at its first value until the start comes (D)."""
        if self.link_origin is None:
            return float(self.table_start)
        link = np.array([link_dpos])
        if self.follow is not None:
            link = self.follow.effective(link)
        u = float(link[0]) - self.link_origin
        if self.repeat:
            u -= np.floor(u / self.distance) * self.distance
        x = min(max(u / self.distance, 0.0), 1.0) * (len(self.values) - 1)
        return self.table_start + x

    @property
    def span(self) -> float:
        """Counts moved over one whole profile."""
        return self.multiplier * float(self.values[-1])

    def shape(self, u: np.ndarray) -> np.ndarray:
        """Counts after u (0..distance) of link travel, from the profile's start."""
        n = len(self.values)
        x = np.clip(u / self.distance, 0.0, 1.0) * (n - 1)
        return self.multiplier * np.interp(x, np.arange(n), self.values)

    def counts(self, link_dpos: np.ndarray) -> np.ndarray:
        if self.link_origin is None:
            return np.full(np.shape(link_dpos), self.origin)
        if self.follow is not None:
            link_dpos = self.follow.effective(link_dpos)
        u = link_dpos - self.link_origin
        if self.repeat:
            cycles = np.floor(u / self.distance)
            out = self.origin + cycles * self.span + self.shape(u - cycles * self.distance)
            if self.held:
                out = np.where(u < 0, self.origin, out)
            return out
        return self.origin + self.shape(u)

    def slope(self, link_dpos: np.ndarray) -> np.ndarray:
        """d(counts)/d(link travel) of the profile."""
        if self.link_origin is None:
            return np.zeros(np.shape(link_dpos))
        if self.follow is not None:
            link_dpos = self.follow.effective(link_dpos)
        u = link_dpos - self.link_origin
        if self.repeat:
            u = u - np.floor(u / self.distance) * self.distance
        n = len(self.values)
        x = np.clip(u / self.distance, 0.0, 1.0) * (n - 1)
        j = np.minimum(x.astype(int), n - 2)
        step = self.values[j + 1] - self.values[j]
        inside = (u >= 0) & (u < self.distance)
        return np.where(inside, self.multiplier * step * (n - 1) / self.distance, 0.0)

    def start_at(self, link_dpos: float, here: float) -> None:
        """The profile starts now with the link at `link_dpos` and the axis at `here`;
        with an offset start (bit 7) the axis is taken as being `offset` into it."""
        self.link_origin = link_dpos - self.offset
        self.origin = here - float(self.shape(np.array([self.offset]))[0])

    def end_position(self) -> float | None:
        """The link axis DPOS the profile ends at (None: repeating or not started)."""
        if self.link_origin is None or self.repeat:
            return None
        return self.link_origin + self.distance

    def stop_repeating(self, link_dpos: float) -> None:
        """REP_OPTION bit 1: the cycle running now is the last."""
        if not self.repeat or self.link_origin is None:
            return
        cycles = math.floor((link_dpos - self.link_origin) / self.distance)
        if self.held:
            cycles = max(cycles, 0)
        self.origin += cycles * self.span
        self.link_origin += cycles * self.distance
        self.repeat = False


@dataclass
class Connect:
    """CONNECT(ratio, link axis): ratio counts of this axis per count of the link axis."""

    ratio: float
    link: int
    origin: float = 0.0  # this axis's own demand (counts) when it took effect
    link_origin: float = 0.0  # the link axis's demand (counts) then
    ramp_from: float | None = None  # CLUTCH_RATE: the ratio of the cycle ending at `since`
    since: int = 0  # the tick `origin` is at while the ratio ramps (clutch.py)

    def counts(self, link_counts: np.ndarray) -> np.ndarray:
        return self.origin + self.ratio * (link_counts - self.link_origin)


@dataclass
class Movelink:
    """MOVELINK: `distance` counts over `span` counts of the link axis's travel, ramping
    over `accel` and `decel` of it (all counts; see the module docstring)."""

    distance: float
    span: float
    accel: float
    decel: float
    link: int
    repeat: bool = False  # option 4: runs again and again (both ways) until CANCEL
    start_at: float | None = None  # option 2: the link position (counts) it starts at
    wait: str | None = None  # options 1/256: the registration event not yet come
    curve: int | None = None  # option 16: the ramps' curve (bits 10..12), None linear
    follow: Follow | None = None  # bits 5/14: only the link's forward movement counts
    origin: float = 0.0
    link_origin: float = 0.0
    shaped: float | None = None  # MOVELINK_MODIFY: the distance its ramps were shaped for
    adjust: list[tuple[float, float, float]] = field(default_factory=list)
    # MOVELINK_MODIFY's offsets, each added over a stretch of link travel (links_modify.py)

    def ramp(self, z: np.ndarray) -> np.ndarray:
        """The distance share of a ramp after the fraction z of it (the integral of its
        speed curve, 1/2 at the end for every curve: so the peak ratio is the trapezoid's).
        Curves (MOVELINK page, bits 10..12): 0 sine, 1 power 9, 2 power 7, 3 power 5
        polynomial speed (the smoothstep polynomials: peak accelerations 1.57, 2.46,
        2.19, 1.88 times the linear ramp's, the page's 1.55, 2.42, 2.16, 1.86: I)."""
        c = self.curve
        if c is None:
            return z * z / 2.0
        if c == 0:
            return z / 2.0 - np.sin(np.pi * z) / (2.0 * np.pi)
        if c == 3:
            return z ** 4 * (2.5 - 3.0 * z + z * z)
        if c == 2:
            return z ** 5 * (7.0 - 14.0 * z + 10.0 * z * z - 2.5 * z ** 3)
        return z ** 6 * (21.0 - 60.0 * z + 67.5 * z * z - 35.0 * z ** 3 + 7.0 * z ** 4)

    def ramped(self, x: np.ndarray, a: float, d: float) -> np.ndarray:
        """The share (0..1) of a ramped move after the fraction x of its link travel,
        ramping up over the first fraction a and down over the last d (at most twice
        the mean ratio: no overflow for any span)."""
        peak = 1.0 / (1.0 - (a + d) / 2.0)  # the share of the link's speed between ramps
        shape = peak * (x - a / 2.0)
        with np.errstate(over="ignore", invalid="ignore"):  # (branches not taken)
            if a > 0:
                shape = np.where(x < a, peak * a * self.ramp(np.clip(x / a, 0.0, 1.0)),
                                 shape)
            if d > 0:
                rest = np.clip((1.0 - x) / d, 0.0, 1.0)
                shape = np.where(x > 1.0 - d, 1.0 - peak * d * self.ramp(rest), shape)
        return shape

    def profile(self, u: np.ndarray) -> np.ndarray:
        """Counts moved after `u` counts of link travel, 0 <= u <= span (with what
        MOVELINK_MODIFY added: links_modify.py)."""
        distance = self.distance if self.shaped is None else self.shaped
        moved = distance * self.ramped(u / self.span, self.accel / self.span,
                                       self.decel / self.span)
        for offset, start, end in self.adjust:
            z = np.clip((u - start) / (end - start), 0.0, 1.0)
            moved = moved + offset * np.where(z < 0.5, 2.0 * z * z,
                                              1.0 - 2.0 * (1.0 - z) ** 2)
        return moved

    def counts(self, link_counts: np.ndarray) -> np.ndarray:
        if self.wait is not None:
            return np.full(np.shape(link_counts), self.origin)
        if self.follow is not None:
            link_counts = self.follow.effective(link_counts)
        u = link_counts - self.link_origin
        if self.repeat:
            cycles = np.floor(u / self.span)
            return self.origin + cycles * self.distance + self.profile(u - cycles * self.span)
        return self.origin + self.profile(np.clip(u, 0.0, self.span))

    @property
    def link_end(self) -> float:
        return self.link_origin + self.span


@dataclass
class Flexlink(Movelink):
    """FLEXLINK: `base` counts at a constant ratio over the whole link span, plus
    `distance - base` counts of an excitation move over the window from `window[0]` to
    `window[1]` (counts of link travel), ramping over its first `accel` and last `decel`
    counts on the option's curve (sine unless bits 10..12 say otherwise)."""

    base: float = 0.0
    window: tuple[float, float] = (0.0, 0.0)

    def profile(self, u: np.ndarray) -> np.ndarray:
        w0, w1 = self.window
        width = w1 - w0
        excite = self.distance - self.base
        moved = self.base * u / self.span
        if width <= 0:
            return moved + np.where(u >= w0, excite, 0.0)
        x = np.clip((u - w0) / width, 0.0, 1.0)
        return moved + excite * self.ramped(x, self.accel / width, self.decel / width)


Link = Connpath | Cambox | Connect | Movelink


@dataclass(frozen=True)
class ServoGains:
    """What the shared servo loop reads of a servo axis (following.py sets it)."""

    gains: Gains = Gains()
    servo_polarity: int = 1


@dataclass
class TrioAxis(MotionAxis):
    """One axis: the shared kinematics plus what the MC405 keeps per axis."""

    params: dict[str, float] = field(default_factory=dict)
    fraction: float = 0.0  # demand beyond `steps` at rest (a linked axis stops anywhere)
    datum: float = 0.0  # DEFPOS: DPOS = (demand counts + datum) / UNITS
    link: Link | None = None
    pending_link: Link | None = None  # CONNPATH/CAMBOX loaded behind buffered moves
    link_end: int | None = None  # CAMBOX: the tick it completes (cached per revision)
    config: ServoGains = field(default_factory=ServoGains)  # a servo axis's loop gains

    @property
    def units(self) -> float:
        return self.params["UNITS"]
