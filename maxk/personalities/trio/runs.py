"""Moves of the MC405 on the shared machine: runs of buffered moves, and linked axes.

A *run* is what one BASE group does from rest to rest: one interpolated path on the
shared path planner (`firmware_model/path.py`) whose segments are the group's moves,
joined without stopping while MERGE is ON, or one single-axis move as a closed-form
profile (`profiles.plan_move`). Each axis of a path run follows its coordinate of the
path as a `ContourMotion`, a single-axis run its profile, through `MotionAxis.begin`,
so positions, limit and trigger searches work on them unchanged.

A *linked* axis has no motion of its own (link_kinds.py): CONNPATH moves it by the path
distance of a group, CAMBOX by a TABLE profile over another axis's travel. Its demand position is a
closed-form function of the tick through the motions it follows.

A merged run that never comes to rest (a program looping MOVEs with MERGE ON) keeps only
the moves not yet complete: when it is re-planned, the moves the path has passed (and
MOVE_COUNT has counted) are dropped once `DROP_AFTER` of them have gathered, and every
index of the run (its moves, their kinds, SP speeds, arcs, MOVE_PA copies) counts from
the first move kept (`dropped` says how many went). Path distances stay measured from the
run's start, so DPOS, REMAIN, VECTOR_BUFFERED and the plans' arithmetic are unchanged;
MOVES_BUFFERED, MTYPE/NTYPE and MOVE_PA look only at the move running and those after it.
An S-ramped run (SRAMP, JERK) keeps the move running now and those after it (its re-plan
carries the ramp running, which may end in a later move).

Everything here evaluates on arrays of ticks (numpy, the shared machine's
`firmware_model/sampling.py`), so a trace of every servo cycle of a stretch costs a few
array operations; a single reading is an array of one.
"""

from __future__ import annotations

import bisect
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
from maxk.firmware_model.path_scurve import (
    SRamp,
    level_point,
    plan_continued,
    plan_profiled,
    plan_shaped,
    plan_shaped_stop,
)
from maxk.firmware_model.profiles import Motion, RampShape, move_phases, plan_move
from maxk.firmware_model.profiles import plan_stop as profile_stop
from maxk.firmware_model.sampling import PlanArrays, profile_offset_speed
from maxk.firmware_model.servo import Gains

from .geometry import sphere_definition
from .link_kinds import Link
from .profiles_sp import jerk_ramp, jerk_top, seam

Ticks = np.ndarray  # integer servo ticks
DROP_AFTER = 64  # complete moves a merged run gathers before it drops them (D: amortised)
CORNER_HELD, CORNER_LOADED = 1, 3  # a run behind a corner: held, or let in at 0 speed
SHAPE = RampShape.LINEAR  # the MC405's ramps: linear (trapezoid) unless SRAMP/JERK shape them


def _segment_end(segment: Segment) -> float:
    return segment.s0 + segment.length


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
    corner: int = 0  # the CORNER_STATE handshake: CORNER_HELD, CORNER_LOADED (or 0)
    dwell: float = 0.0  # FORCE_DWELL of its last move, seconds: it ends at rest and waits
    interp: dict[int, float] = field(default_factory=dict)
    # move index -> its interpolated axes' share of its length (INTERP_FACTOR, < 1 only)
    factored: dict[int, float] = field(default_factory=dict)
    # an SP move's index -> the LOOKAHEAD_FACTOR its speeds carry
    carried: dict[int, dict[int, tuple[float, float]]] = field(default_factory=dict)
    # move index -> axis -> its (MOVE_PA, MOVE_PB) when the move loaded (move_pa.py)
    forced: dict[int, tuple[float, float, float]] = field(default_factory=dict)
    # an SP move's index -> FORCE_SPEED, FORCE_ACCEL, FORCE_DECEL as loaded (MOVE_FORCE_*)
    dropped: int = 0  # complete moves let go (the indices above count after them)
    dropped_length: float = 0.0  # their path lengths added in order (VECTOR_BUFFERED)

    @property
    def base(self) -> int:
        return self.axes[0]

    @property
    def path_scale(self) -> float:
        """The feed hold's speed scale, or 0 while let in at zero speed (corner_state)."""
        return 0.0 if self.corner == CORNER_LOADED else self.scale

    @property
    def mergeable(self) -> bool:
        return not self.single and not self.stopping and self.dwell == 0

    def definitions(self, first: int = 0) -> list[SegmentDef]:
        """Each move from `first` on (the list starts there) a relative straight segment
        at its own speed (its top); the first starts from rest (v_start 0), each hands
        over to the next at the seam speed (MERGE: no stop in between; profiles_sp.seam).
        Only the moves asked for: a merged chain of thousands stays linear to load."""
        last = len(self.deltas) - 1
        return [SegmentDef("line", tuple(float(d) for d in self.deltas[j]), True, 0.0,
                           0.0 if j + self.dropped == 0 else None,
                           self.seam(j) if j < last else self.speeds[j],
                           self.accels[j], None, self.speeds[j])
                for j in range(first, len(self.deltas))]

    def seam(self, j: int) -> float:
        """profiles_sp.seam; where INTERP_FACTOR gives the moves different path speeds,
        at most the lower (D: the interpolated axes never run over SPEED)."""
        speed = seam(self.speeds, self.sp, j)
        if j in self.interp or j + 1 in self.interp:
            speed = min(speed, self.speeds[j], self.speeds[j + 1])
        return speed

    def resolve(self, origin: tuple[float, ...]) -> None:
        """Segments of every move loaded so far, from the group's start position."""
        first = max(0, len(self.segments) - 1)
        defs = self.definitions(first)
        if 0 < len(self.segments) < len(self.deltas):  # the last one's seam: the next move
            self.segments[-1].v_end = defs[0].v_end
        while len(self.segments) < len(self.deltas):
            j = len(self.segments)
            defn = defs[j - first]
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
        """The segment that distance s is in: the first not ended by s (the last one
        past the end); a bisection on the segments' ends, which never decrease."""
        count = bisect.bisect_right(self.segments, s + 1e-9, key=_segment_end)
        return max(0, min(count, len(self.segments) - 1))

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

    @property
    def shaped(self) -> bool:
        """SRAMP (VP_MODE 0) or JERK (VP_MODE 5/6) shapes its speed changes: S-ramps."""
        return self.jerk > 0 or self.sramp > 0

    @property
    def ramp(self) -> SRamp:
        return SRamp(self.jerk, 0.0 if self.jerk > 0 else self.sramp)

    def plan_new(self, now: int, stop: bool = False, period: float = 0.001,
                 decel: float | None = None) -> PathPlan:
        """The path planned from where it is now (from rest when it starts now); a
        stop ramps down along it at `decel` (FASTDEC), else an S-curve path at its
        DECEL, a linear one at its ACCEL."""
        if self.shaped:
            return self._plan_shaped(now, stop, period, decel)
        if self.plan is None:
            return plan_path(self.segments, 0, 0.0, 0.0, self.path_scale)
        s, v = self.plan.state((now - self.plan_tick) * period)
        i = self.segment_index(s)
        if stop:
            return plan_stop(self.segments, i, s, v, 1.0, accel=decel)
        i = self.drop_complete(i)
        return plan_path(self.segments, i, s, v, self.path_scale)

    def drop_complete(self, current: int) -> int:
        """Before a re-plan from move `current`: let go of the moves before it that
        MOVE_COUNT has counted, once `DROP_AFTER` have gathered (the plan being replaced
        keeps its own list); the index of the current move afterwards. New lists are made,
        not the old ones cut, so the plan being replaced stays whole until it goes."""
        k = min(current, self.counted)
        while k > 0 and self.segments[k - 1].length == 0:
            k -= 1  # (a zero-length move just before stays: PathPlan.segment_at steps back)
        if k < DROP_AFTER:
            return current
        for j in range(k):  # (added one by one, as VECTOR_BUFFERED adds the rest after)
            self.dropped_length += move_length(self.deltas[j], self.arcs.get(j))
        self.segments = self.segments[k:]
        self.deltas = self.deltas[k:]
        self.speeds = self.speeds[k:]
        self.accels = self.accels[k:]
        for name in ("arcs", "kinds", "sp", "interp", "factored", "carried", "forced"):
            table = getattr(self, name)
            setattr(self, name, {j - k: value for j, value in table.items() if j >= k})
        self.counted -= k
        self.dropped += k
        return current - k

    def _plan_shaped(self, now: int, stop: bool, period: float,
                     decel: float | None) -> PathPlan:
        """plan_new with S-ramps (path_scurve.py): one move from rest runs the profile a
        single-axis move of its length would (ACCEL up, DECEL down); merged moves
        S-ramp between their speeds at ACCEL; a re-plan (a move merged in, a new
        speed) takes over once the ramp running has ended; a stop S-ramps down at once
        at `decel` (else DECEL)."""
        if self.plan is None:
            if (len(self.segments) == 1 and self.path_scale == 1.0
                    and self.segments[0].length > 0):
                seg = self.segments[0]
                top = min(seg.ceiling, seg.arc_cap)
                share = self.interp.get(0, 1.0)  # (INTERP_FACTOR: the path runs faster)
                if self.jerk > 0:  # (a short move peaks lower, at JERK: single_profile)
                    top = jerk_top(seg.length, top, self.accels[0], self.decel / share,
                                   self.jerk / share)
                shape, up, down, share_up, share_down = ramp_shares(
                    top, self.accels[0], self.decel / share, self.sramp, self.jerk / share)
                phases, end, _ramp_end, _peak = move_phases(
                    seg.length, 1, 0.0, top, up, down, shape, share_up, share_down)
                return plan_profiled(self.segments, phases, end)
            return plan_shaped(self.segments, 0, 0.0, 0.0, self.path_scale, self.ramp)
        t = (now - self.plan_tick) * period
        if stop:
            s, v = self.plan.state(t)
            i = self.segment_index(s)
            return plan_shaped_stop(self.segments, i, s, v,
                                    self.decel if decel is None else decel, self.ramp)
        head, s, v = level_point(self.plan, t)
        here, _v = self.plan.state(t)  # (the moves before the one running now may go)
        self.drop_complete(self.segment_index(here))
        return plan_shaped(self.segments, self.segment_index(s), s, v, self.path_scale,
                           self.ramp, head)

    def continued(self, old: Run, t: float, s: float) -> PathPlan | None:
        """The plan of this run, made of a running single-axis S-curve move `old` (its
        remaining distance, `t` s into its profile, `s` along): its S-ramp goes on as
        it was (None: not an S-curve, or a CAM's own profile)."""
        self.jerk, self.sramp = old.jerk, old.sramp
        motion = old.profile
        if not self.shaped or old.preset is not None or motion is None \
                or motion.end_time is None:
            return None
        return plan_continued(self.segments, motion.phases, motion.end_time, t, s)

    def stop_profile(self, residual: float, velocity: float, decel: float) -> Motion:
        """A single-axis run's ramp down now from `velocity` (CANCEL): an S-ramp with
        the run's SRAMP or JERK (its acceleration rising from 0 at once), else linear."""
        if not self.shaped or self.preset is not None:  # (a CAM stops linearly, D)
            return profile_stop(residual, velocity, 0.0, decel, SHAPE)
        shape, _up, down, _share_up, share = ramp_shares(abs(velocity), decel, decel,
                                                         self.sramp, self.jerk)
        return profile_stop(residual, velocity, 0.0, down, shape, share)

    def motion_for(self, plan: PathPlan, k: int, origin: int) -> ContourMotion:
        return ContourMotion(plan, k, float(origin))


def move_length(delta: tuple[int, ...], arc: tuple[float, ...] | None) -> float:
    """A move's path length (counts): a line's, an arc's (MOVECIRC: centre, turn) or an
    MSPHERICAL's (centre in three axes, ..., turn last)."""
    if arc is None:
        return math.sqrt(sum(float(d) * float(d) for d in delta))
    radius = math.sqrt(sum(c * c for c in arc[0:3])) if len(arc) > 3 else \
        math.hypot(arc[0], arc[1])
    return radius * abs(math.radians(arc[-1]))


def single_profile(distance: int, speed: float, accel: float, decel: float,
                   sramp: float = 0.0, jerk: float = 0.0) -> Motion:
    """A single-axis move from rest: trapezoid (or triangle) at ACCEL/DECEL, linear ramps;
    with SRAMP (seconds) each ramp's acceleration rises linearly over `sramp`, holds at
    ACCEL/DECEL and falls over `sramp` (the shared S-curve whose jerk share p gives a
    rise of p/2 of the ramp: a ramp to SPEED lasts SPEED/ACCEL + sramp, so p = 2 sramp /
    (SPEED/ACCEL + sramp), at most 1: I). With a jerk limit (VP_MODE 5/6, counts/s^3)
    each ramp's acceleration rises at `jerk` (profiles_sp.jerk_ramp)."""
    if jerk <= 0 and sramp <= 0:
        return plan_move(distance, 0.0, speed, accel, decel, SHAPE)
    if jerk > 0:  # too short to reach SPEED: it peaks lower, at JERK (VP_MODE 5/6)
        speed = jerk_top(abs(distance), speed, accel, decel, jerk)
    shape, up, down, share_up, share_down = ramp_shares(speed, accel, decel, sramp, jerk)
    return plan_move(distance, 0.0, speed, up, down, shape, share_up, share_down)


def ramp_shares(speed: float, accel: float, decel: float, sramp: float, jerk: float
                ) -> tuple[RampShape, float, float, float | None, float | None]:
    """(shape, peak acceleration up, down, S-curve jerk share up, down) of a move's
    ramps to `speed` (single_profile's; an interpolated move's vector speed too)."""
    if jerk > 0:
        up, share_up = jerk_ramp(speed, accel, jerk)
        down, share_down = jerk_ramp(speed, decel, jerk)
        return RampShape.SCURVE, up, down, share_up, share_down
    if sramp <= 0:
        return SHAPE, accel, decel, None, None
    return (RampShape.SCURVE, accel, decel, min(1.0, 2 * sramp / (speed / accel + sramp)),
            min(1.0, 2 * sramp / (speed / decel + sramp)))




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
