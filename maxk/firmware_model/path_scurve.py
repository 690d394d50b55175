"""S-curve speed along a path: the path planner's pieces with a jerk term.

`path.py` plans a path's speed as pieces of constant acceleration. A controller whose
speed changes are jerk limited (the MC405's VP_MODE 5/6 JERK, or VP_MODE 0 with SRAMP)
shapes them as S-ramps instead: the acceleration rises linearly (constant jerk), holds
and falls linearly back to zero, so each speed change is three pieces of constant jerk
(`path.Piece.j`) and the acceleration is continuous across every seam of the path
(every ramp starts and ends at zero acceleration). Positions stay closed-form (cubics
in time), so each axis's share of the path (`path.ContourMotion`), the trigger searches
and the servo work on it unchanged.

Three plans:

- `plan_profiled`: a path whose speed follows a given 1-D profile along its length (the
  phases a single-axis move of that length would run, `profiles.move_phases`): an
  interpolated move that nothing merges into runs its vector speed exactly as a
  single-axis move of its length would.
- `plan_shaped`: the speed planned across merged segments with S-ramps (`SRamp`): the
  forward and backward passes of `path.plan_path` with the S-ramp's distance in place of
  the constant acceleration's; a segment ramps from its start speed to its cruise and
  to its end speed within itself.
- `plan_shaped_stop`: ramp down along the path with an S-ramp (a CANCEL).

A plan re-made while a ramp is running keeps the running plan until that ramp has ended
(`level_point`): the acceleration never jumps (our decision for the MC405, recorded on
MERGE: a move loaded during a speed change takes effect once it has finished).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from maxk.firmware_model.path import PathPlan, Piece, Segment
from maxk.firmware_model.profiles import Phase, RampShape, shape_constants

_ITERATIONS = 200  # bisection steps (each halves the bracket: ends at the last bit)


@dataclass(frozen=True, slots=True)
class SRamp:
    """How a speed change is shaped: the acceleration rises at `jerk` (counts/s^3) to
    the accel given, or (jerk 0) over `rise` seconds (VP_MODE 0's SRAMP)."""

    jerk: float = 0.0
    rise: float = 0.0

    def shape(self, dv: float, accel: float) -> tuple[float, float]:
        """(peak acceleration, rise time) of a change of speed by |dv| at `accel`: with a
        jerk, accel when the change is long enough to reach it (dv >= accel^2/jerk), else
        sqrt(dv jerk), a triangle of acceleration; with a rise time, accel over at most
        half the ramp (a change shorter than 2 x rise: its acceleration rises over half
        of it, as a single-axis move's with SRAMP does)."""
        dv = abs(dv)
        if self.jerk > 0:
            peak = min(accel, math.sqrt(dv * self.jerk))
            return peak, peak / self.jerk if peak > 0 else 0.0
        return accel, min(self.rise, dv / accel)

    def duration(self, dv: float, accel: float) -> float:
        """Seconds a change of speed by |dv| lasts: |dv| / peak + rise."""
        if dv == 0:
            return 0.0
        peak, rise = self.shape(dv, accel)
        return abs(dv) / peak + rise

    def distance(self, v1: float, v2: float, accel: float) -> float:
        """Path length a ramp from v1 to v2 covers: the mean of its ends over its time
        (an S-ramp is symmetric about its middle)."""
        return (v1 + v2) / 2.0 * self.duration(v2 - v1, accel)

    def reach_up(self, v: float, length: float, accel: float) -> float:
        """The highest speed a ramp up from v reaches within `length`."""
        if length <= 0:
            return v
        lo, hi = v, math.sqrt(v * v + 2.0 * accel * length)  # (an S-ramp is longer)
        for _ in range(_ITERATIONS):
            mid = (lo + hi) / 2.0
            if mid <= lo or mid >= hi:
                break
            if self.distance(v, mid, accel) <= length:
                lo = mid
            else:
                hi = mid
        return lo

    def reach_down(self, v: float, length: float, accel: float) -> float:
        """The lowest speed a ramp down from v reaches within `length` (0: it stops).

        A ramp down to a low speed may take no shorter a distance than one to rest (its
        rise is not shorter: with a rise r, the distance v/2 (v/A + r) to rest equals
        the one to A r): where rest is out of reach, every speed below the answer is
        out of reach too (the distance rises from rest's to a peak, then falls to 0 at
        v), so a bisection finds it."""
        if self.distance(v, 0.0, accel) <= length * (1.0 + 1e-9) + 1e-12:
            return 0.0  # (within rounding: a speed the backward pass found, recomputed)
        lo, hi = 0.0, v
        for _ in range(_ITERATIONS):
            mid = (lo + hi) / 2.0
            if mid <= lo or mid >= hi:
                break
            if self.distance(v, mid, accel) <= length:
                hi = mid
            else:
                lo = mid
        return hi


def ramp_pieces(out: list[Piece], t: float, s: float, v1: float, v2: float, accel: float,
                ramp: SRamp) -> float:
    """Append an S-ramp from v1 to v2 (jerk up, hold, jerk down); the time it ends."""
    dv = v2 - v1
    if dv == 0:
        return t
    peak, rise = ramp.shape(dv, accel)
    sign = 1.0 if dv > 0 else -1.0
    a, j = sign * peak, sign * peak / rise if rise > 0 else 0.0
    hold = abs(dv) / peak - rise
    if rise > 0:
        first = Piece(t, rise, s, v1, 0.0, j)
        out.append(first)
        t, s = t + rise, first.s(rise)
        v1 = first.v(rise)
    if hold > 0:
        middle = Piece(t, hold, s, v1, a)
        out.append(middle)
        t, s = t + hold, middle.s(hold)
        v1 = middle.v(hold)
    if rise > 0:
        out.append(Piece(t, rise, s, v1, a, -j))
        t += rise
    return t


def _jerked(plan: PathPlan) -> PathPlan:
    """A plan whose pieces may carry a jerk: the servo kernel reads it so."""
    plan.jerked = True
    return plan


# ---- a path at a single-axis move's profile ----------------------------------------------
def profile_pieces(phases: Sequence[Phase]) -> list[Piece]:
    """A 1-D profile's phases (forward: linear or S-curve ramps, slews) as path pieces:
    an S-curve ramp is its rising corner (constant jerk), its straight middle and its
    falling corner, each started where the profile itself is (`Phase.distance`)."""
    out: list[Piece] = []
    for ph in phases:
        dv, T = ph.v2 - ph.v1, ph.duration
        s0 = ph.s0 * ph.direction  # (the distance along: a move runs one way)
        if dv == 0 or T == 0:
            out.append(Piece(ph.t0, T, s0, ph.v1, 0.0))
            continue
        if ph.shape is RampShape.LINEAR:
            out.append(Piece(ph.t0, T, s0, ph.v1, dv / T))
            continue
        if ph.shape is not RampShape.SCURVE:
            raise ValueError(f"a path follows linear or S-curve ramps, not {ph.shape}")
        p = ph.param if ph.param is not None else 1.0
        rise = p / 2.0 * T
        a = dv * shape_constants(RampShape.SCURVE, ph.param)[0] / T  # the peak
        out.append(Piece(ph.t0, rise, s0, ph.v1, 0.0, a / rise))
        if T - 2.0 * rise > 0:
            out.append(Piece(ph.t0 + rise, T - 2.0 * rise, s0 + ph.distance(rise),
                             ph.speed(rise), a))
        out.append(Piece(ph.t0 + T - rise, rise, s0 + ph.distance(T - rise),
                         ph.speed(T - rise), a, -a / rise))
    return out


def plan_continued(segments: list[Segment], phases: Sequence[Phase], end_time: float,
                   t: float, s: float) -> PathPlan:
    """A 1-D profile (one way) from `t` on, where it has gone `s`, as a plan along the
    path from its start (a single-axis move that becomes a path where it is: its S-ramp
    running goes on as it was, so a re-plan takes over when it has ended)."""
    last = segments[-1]
    pieces = [Piece(p.t0 - t, p.duration, p.s0 - s, p.v0, p.a, p.j)
              for p in profile_pieces(phases) if p.t0 + p.duration > t]
    return _jerked(PathPlan(segments, pieces, 0.0, end_time - t,
                            s_end=last.s0 + last.length))


def plan_profiled(segments: list[Segment], phases: Sequence[Phase],
                  end_time: float) -> PathPlan:
    """The whole known path (from its start, at rest) at the speed the phases give
    along its length; it stands exactly on the path's end from `end_time` on."""
    last = segments[-1]
    return _jerked(PathPlan(segments, profile_pieces(phases), 0.0, end_time,
                            s_end=last.s0 + last.length))


# ---- S-ramps across merged segments ---------------------------------------------------------
def _end_caps(segments: list[Segment], i0: int, scale: float) -> list[float]:
    """The cap on the speed at each segment's end (path.py's _end_cap): its end speed
    (x override), its own and the next one's ceilings; the known path ends at rest."""
    def seam_cap(seg: Segment) -> float:
        return seg.arc_cap if seg.topped else min(seg.ceiling * scale, seg.arc_cap)

    caps = [min(seg.v_end * scale, seam_cap(seg), seam_cap(segments[j + 1]))
            for j, seg in enumerate(segments[i0:-1], start=i0)]
    caps.append(0.0)
    return caps


def _bisect(need: Callable[[float], float], lo: float, hi: float, length: float,
            rising: bool) -> float:
    """The speed in [lo, hi] nearest `hi` (rising: need grows with the speed) or `lo`
    (falling) whose ramps fit within `length`."""
    for _ in range(_ITERATIONS):
        mid = (lo + hi) / 2.0
        if mid <= lo or mid >= hi:
            break
        if (need(mid) <= length) == rising:
            lo = mid
        else:
            hi = mid
    return lo if rising else hi



def _segment(out: list[Piece], t: float, s: float, length: float, v_in: float,
             v_out: float, top: float, accel: float, ramp: SRamp) -> float:
    """Append one segment's pieces: an S-ramp from v_in to its cruise speed, the cruise,
    an S-ramp to v_out. The cruise is `top` (its SPEED, FORCE_SPEED, x override) when
    both ramps fit; else, top above both ends, the highest speed whose ramps fit; top
    below an end, the lowest (down as near top as the length lets it, up again), or,
    too short to pass by top, the highest between the lower end and top that fits.
    Returns the time at its end."""
    def need(v: float) -> float:
        return ramp.distance(v_in, v, accel) + ramp.distance(v, v_out, accel)

    if need(top) <= length:
        cruise = top
    elif top >= max(v_in, v_out):
        cruise = _bisect(need, max(v_in, v_out), top, length, True)
    else:
        high = max(top, min(v_in, v_out))
        if need(high) <= length:
            cruise = _bisect(need, top, high, length, False)
        else:  # too short to pass by its top (two S-ramps cost more than one): the
            # highest speed between the lower end and top whose ramps fit (the lower end
            # itself does: one ramp from v_in to v_out)
            cruise = _bisect(need, min(v_in, v_out), top, length, True)
    t = ramp_pieces(out, t, s, v_in, cruise, accel, ramp)
    d1 = ramp.distance(v_in, cruise, accel)
    d3 = ramp.distance(cruise, v_out, accel)
    flat = length - d1 - d3
    if flat > 1e-9 and cruise > 0:
        out.append(Piece(t, flat / cruise, s + d1, cruise, 0.0))
        t += flat / cruise
    else:
        flat = 0.0
    return ramp_pieces(out, t, s + d1 + flat, cruise, v_out, accel, ramp)


def plan_shaped(segments: list[Segment], i0: int, s_now: float, v_now: float,
                scale: float, ramp: SRamp, head: Sequence[Piece] = ()) -> PathPlan:
    """Plan from s_now (inside segment i0) at speed v_now with no acceleration, every
    speed change an S-ramp, to rest at the end of the known path. `head`: pieces the
    plan runs first (the end of a ramp already running), ending at s_now, v_now."""
    if scale <= 0:  # held at speed 0 (a feed hold): ramp down now and wait there
        plan = plan_shaped_stop(segments, i0, s_now, v_now, segments[i0].accel, ramp, head)
        pieces = plan.pieces
        t = pieces[-1].t0 + pieces[-1].duration if pieces else 0.0
        pieces.append(Piece(t, math.inf, plan.s_end, 0.0, 0.0))
        return _jerked(PathPlan(segments, pieces, plan.s_start, None, s_end=plan.s_end))
    caps = _end_caps(segments, i0, scale)
    n = len(caps)
    allow = list(caps)
    for j in range(n - 1, 0, -1):  # backward: every later cap can still be met
        after = segments[i0 + j]
        allow[j - 1] = min(allow[j - 1],
                           ramp.reach_up(allow[j], after.length, after.accel))
    pieces = list(head)
    t = head[-1].t0 + head[-1].duration if head else 0.0
    s, v_in = s_now, v_now
    for j in range(n):
        seg = segments[i0 + j]
        length = seg.s0 + seg.length - s
        if length <= 0:
            s = seg.s0 + seg.length
            continue
        a = seg.accel
        top = min(seg.ceiling * scale, seg.arc_cap)
        v_out = max(min(allow[j], ramp.reach_up(v_in, length, a)),
                    ramp.reach_down(v_in, length, a))
        t = _segment(pieces, t, s, length, v_in, v_out, top, a, ramp)
        s, v_in = seg.s0 + seg.length, v_out
    return _jerked(PathPlan(segments, pieces, head[0].s0 if head else s_now, t, s_end=s))


def plan_shaped_stop(segments: list[Segment], i0: int, s_now: float, v_now: float,
                     accel: float, ramp: SRamp, head: Sequence[Piece] = ()) -> PathPlan:
    """Ramp down along the path now (after `head`), with an S-ramp at `accel` (a
    CANCEL); a path that ends sooner than that ramp stops at its end as planned."""
    end = segments[-1].s0 + segments[-1].length
    start = head[0].s0 if head else s_now
    if s_now + ramp.distance(v_now, 0.0, accel) >= end:
        return plan_shaped(segments, i0, s_now, v_now, 1.0, ramp, head)
    pieces = list(head)
    t = pieces[-1].t0 + pieces[-1].duration if pieces else 0.0
    if v_now <= 0:
        return _jerked(PathPlan(segments, pieces, start, t, s_end=s_now))
    t = ramp_pieces(pieces, t, s_now, v_now, 0.0, accel, ramp)
    return _jerked(PathPlan(segments, pieces, start, t,
                            s_end=s_now + ramp.distance(v_now, 0.0, accel)))


def level_point(plan: PathPlan, t: float) -> tuple[list[Piece], float, float]:
    """Where the plan's acceleration is next zero at or after t (the end of the ramp
    running at t; t itself on a cruise): (the pieces from t up to there, re-timed from
    0, the path distance and speed there)."""
    pieces = plan.pieces
    if plan.end_time is not None and t >= plan.end_time or not pieces:
        return [], plan.s_end, 0.0
    i = max(0, next((k for k, p in enumerate(pieces) if p.t0 > t), len(pieces)) - 1)
    p = pieces[i]
    tau = min(t - p.t0, p.duration)
    if p.a == 0 and p.j == 0:
        return [], p.s(tau), p.v(tau)
    head = [Piece(0.0, p.duration - tau, p.s(tau), p.v(tau), p.a + p.j * tau, p.j)]
    while i + 1 < len(pieces):  # on through the ramp while its acceleration goes on
        end_a = p.a + p.j * p.duration
        after = pieces[i + 1]
        if (abs(end_a) <= 1e-9 * max(1.0, abs(p.a))
                or abs(after.a - end_a) > 1e-9 * max(1.0, abs(end_a))):
            break  # (at zero, or a linear plan's step in acceleration)
        i += 1
        p = after
        last = head[-1]
        head.append(Piece(last.t0 + last.duration, p.duration, p.s0, p.v0, p.a, p.j))
    last = head[-1]
    return head, last.s(last.duration), last.v(last.duration)
