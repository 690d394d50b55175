"""Speed profiles of the MC405's moves: jerk-limited ramps (VP_MODE, JERK, SRAMP) and the
advanced speed control of the SP moves (FORCE_SPEED, STARTMOVE_SPEED, ENDMOVE_SPEED).

- VP_MODE 0 (the default): trapezoids, SRAMP blending each ramp over SRAMP ms (runs.py).
  VP_MODE 5 and 6: jerk limited: a single-axis move's acceleration rises at JERK (user
  units/s^3) to ACCEL, holds and falls at JERK, so a ramp to SPEED lasts SPEED/ACCEL +
  ACCEL/JERK, or 2 sqrt(SPEED/JERK) when ACCEL is never reached (C: JERK and VP_MODE
  pages); in mode 6 an SRAMP above 0 sets JERK = ACCEL/SRAMP for both ramps (C: SRAMP
  page: with another DECEL the deceleration differs). JERK 0 in mode 5/6: no jerk limit,
  linear ramps (D).
- An SP move carries FORCE_SPEED as its own top speed and, when not -1, STARTMOVE_SPEED
  and ENDMOVE_SPEED as the speeds it starts and ends at (C: their pages); the shared
  path planner (`path.SegmentDef.v_top`) cruises each move at its top and joins merged
  moves at the seam speeds `seam` gives, ramping within the moves on either side; the
  last move known always ends at rest (C: ENDMOVE_SPEED page, "overwritten to zero").
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

VP_MODES = frozenset({0.0, 5.0, 6.0})  # the modes the VP_MODE page lists
DIRECTIONS = ("START_DIR_LAST", "END_DIR_LAST", "CHANGE_DIR_LAST")  # set as SP moves load
UNSET = -1.0  # STARTMOVE_SPEED / ENDMOVE_SPEED: not used (their power-up value, C)


def jerk_counts(params: Mapping[str, float], units: float) -> float:
    """The jerk limit a move loaded now runs with, counts/s^3 (0: none)."""
    mode = params.get("VP_MODE", 0.0)
    if mode not in (5.0, 6.0):
        return 0.0
    sramp = params.get("SRAMP", 0.0)
    if mode == 6.0 and sramp > 0:
        return params["ACCEL"] * units / (sramp / 1000.0)
    return max(0.0, params.get("JERK", 0.0)) * units * params.get("JERK_FACTOR", 1.0)


def sramp_seconds(params: Mapping[str, float]) -> float:
    """SRAMP's blend (s) of a move loaded now: VP_MODE 0 only (5/6 take a jerk)."""
    if params.get("VP_MODE", 0.0) in (5.0, 6.0):
        return 0.0
    return max(0.0, params.get("SRAMP", 0.0)) / 1000.0


def jerk_ramp(speed: float, accel: float, jerk: float) -> tuple[float, float]:
    """(peak acceleration, the S-curve's jerk share) of a jerk-limited ramp from rest to
    `speed`: ACCEL when the ramp reaches it (the acceleration rises over ACCEL/JERK),
    else sqrt(SPEED x JERK), a triangle of acceleration (share 1)."""
    peak = min(accel, math.sqrt(speed * jerk))
    rise = peak / jerk
    return peak, min(1.0, 2.0 * rise / (speed / peak + rise))


def jerk_top(distance: float, speed: float, accel: float, decel: float,
             jerk: float) -> float:
    """The highest speed up to `speed` whose jerk-limited ramps from rest and back to rest
    (`jerk_ramp` up at ACCEL, down at DECEL) fit within `distance`: a move too short to
    reach SPEED peaks there, its jerk still JERK (the limit VP_MODE 5/6 is about; was:
    the ramps to SPEED squeezed into the move, the jerk many times JERK)."""
    def need(v: float) -> float:
        total = 0.0
        for rate in (accel, decel):
            peak = min(rate, math.sqrt(v * jerk))
            total += v / 2.0 * (v / peak + peak / jerk) if peak > 0 else 0.0
        return total

    if distance <= 0 or need(speed) <= distance:
        return speed
    lo, hi = 0.0, speed
    for _ in range(200):  # bisection (each step halves the bracket: ends at the last bit)
        mid = (lo + hi) / 2.0
        if mid <= lo or mid >= hi:
            break
        if need(mid) <= distance:
            lo = mid
        else:
            hi = mid
    return lo


def interp_share(factors: Sequence[float], deltas: Sequence[float]) -> float:
    """INTERP_FACTOR: the share of a straight move's length that its interpolated axes
    (INTERP_FACTOR not 0) make; the vector speed and acceleration hold along that share,
    so the whole path runs 1/share faster and every axis still ends together (C: the
    INTERP_FACTOR page's X-only speed graph). 0: no interpolated axis moves."""
    whole = math.sqrt(sum(d * d for d in deltas))
    if whole == 0:
        return 1.0
    return math.sqrt(sum(d * d for f, d in zip(factors, deltas, strict=True) if f != 0)) / whole


MIN_FACTOR = 1e-3
"""The least LOOKAHEAD_FACTOR applied (D: 0, an operator's knob at its end stop, would
stop the SP moves for ever; they crawl at a thousandth of their speeds instead)."""


def lookahead(params: Mapping[str, float]) -> float:
    """LOOKAHEAD_FACTOR as applied to the SP moves' speeds."""
    return max(MIN_FACTOR, params.get("LOOKAHEAD_FACTOR", 1.0))


def sp_adjusted(params: Mapping[str, float], units: float, speed: float, accel: float,
                sp: tuple[float, float], share: float
                ) -> tuple[float, float, tuple[float, float]]:
    """An SP move's (FORCE_SPEED, ACCEL, (STARTMOVE_SPEED, ENDMOVE_SPEED)) as loaded, in
    counts: its speeds over the interpolated share (INTERP_FACTOR) and by LOOKAHEAD_FACTOR
    (C: the three speeds); with FORCE_RAMP the move's rate is |FORCE_RAMP| and its top
    the higher of FORCE_SPEED and ENDMOVE_SPEED, so it ramps over its whole length from
    the one to the other (C: the FORCE_RAMP page's rate is (end^2 - start^2) / 2 dist, a
    constant acceleration over the move)."""
    factor = lookahead(params)
    start, end = (v / share * factor if v >= 0 else v for v in sp)
    speed *= factor
    ramp = params.get("FORCE_RAMP", 0.0)
    if ramp != 0:
        accel = abs(ramp) * units / share
        if end >= 0:
            speed = max(speed, end)
    return speed, accel, (start, end)


def sp_speeds(params: Mapping[str, float], units: float) -> tuple[float, float]:
    """(STARTMOVE_SPEED, ENDMOVE_SPEED) an SP move loaded now carries, counts/s; a
    negative value (the -1 of power-up) is not used."""
    start = params.get("STARTMOVE_SPEED", UNSET)
    end = params.get("ENDMOVE_SPEED", UNSET)
    return (start * units if start >= 0 else UNSET, end * units if end >= 0 else UNSET)


def seam(speeds: list[float], sp: Mapping[int, tuple[float, float]], j: int) -> float:
    """The speed at which move j hands over to move j + 1 of a merged run (counts/s).

    An SP move runs at FORCE_SPEED from its start: the move before it ramps to it at its
    end (C: FORCE_SPEED page, example 1); after an SP move a plain move starts at the SP
    move's speed and ramps to its own (same example); two plain moves join at the first
    one's speed (D: as before the SP moves). ENDMOVE_SPEED of move j and STARTMOVE_SPEED
    of move j + 1, where used, cap the seam (C: their pages; both: the lower, D)."""
    after = sp.get(j + 1)
    before = sp.get(j)
    speed = speeds[j + 1] if after is not None else speeds[j]
    if before is not None and before[1] >= 0:
        speed = min(speed, before[1])
    if after is not None and after[0] >= 0:
        speed = min(speed, after[0])
    return speed


# ---- CORNER_MODE: corner and radius speed control of SP moves -----------------------------
def direction(delta: tuple[float, ...], arc: tuple[float, ...] | None,
               end: bool) -> tuple[float, float]:
    """The direction (first two axes) a move starts (end False) or ends in: a line's
    vector; an arc's tangent, from its centre (relative to its start) and its turn (an
    MSPHERICAL's (centre, e2, end, turn): it leaves along e2, geometry.py)."""
    if arc is None:
        return (float(delta[0]), float(delta[1]) if len(delta) > 1 else 0.0)
    if len(arc) > 3:
        centre, e2, turn = arc[0:3], arc[3:6], math.radians(arc[9])
        radius = math.sqrt(sum(c * c for c in centre)) or 1.0
        e1 = [-c / radius for c in centre]  # the start, from the centre
        if not end:
            return (e2[0], e2[1])
        return (-e1[0] * math.sin(turn) + e2[0] * math.cos(turn),
                -e1[1] * math.sin(turn) + e2[1] * math.cos(turn))
    cx, cy, turn = arc
    rx, ry = -cx, -cy  # the start, from the centre
    if end:
        angle = math.radians(turn)
        rx, ry = (rx * math.cos(angle) - ry * math.sin(angle),
                  rx * math.sin(angle) + ry * math.cos(angle))
    return (-ry, rx) if turn > 0 else (ry, -rx)


def heading(direction: tuple[float, float]) -> float:
    """A direction as START_DIR_LAST and END_DIR_LAST give it: radians from the Y axis
    toward X (0 up Y, PI/2 up X, -PI..PI; C: their pages)."""
    return math.atan2(direction[0], direction[1])


def change_of_direction(before: float, after: float) -> float:
    """The unsigned change (0..PI) from one heading to another (CHANGE_DIR_LAST, C)."""
    return abs(math.remainder(after - before, 2.0 * math.pi))


def corner_speed(params: Mapping[str, float], force: float, angle: float) -> float | None:
    """CORNER_MODE bit 1: the STARTMOVE_SPEED (counts/s) a corner of `angle` gives a move
    at FORCE_SPEED `force` (None: no slowing). Beyond STOP_ANGLE (when above 0) it stops;
    beyond DECEL_ANGLE (when below STOP_ANGLE) the speed falls linearly from FORCE_SPEED
    at DECEL_ANGLE to 0 at STOP_ANGLE (the DECEL_ANGLE page's proportional reduction: D,
    its formula as printed gives 0 at DECEL_ANGLE, the reverse of its own text)."""
    if not int(params.get("CORNER_MODE", 0.0)) & 2:
        return None
    stop = params.get("STOP_ANGLE", 0.0)
    decel = params.get("DECEL_ANGLE", 0.0)
    if stop > 0 and angle > stop:
        return 0.0
    if decel < stop and angle > decel:
        return force * (stop - angle) / (stop - decel)
    return None


def radius_speed(params: Mapping[str, float], units: float, force: float, radius: float,
                 accel: float) -> float:
    """CORNER_MODE bit 3: an arc's FORCE_SPEED (counts/s) for its radius (counts): by the
    ratio radius / FULL_SP_RADIUS (bit 4 clear), or so that v^2 / r stays within the
    centripetal acceleration at FULL_SP_RADIUS (bit 4) or within ACCEL (bits 4 and 5);
    (C: CORNER_MODE and FULL_SP_RADIUS pages)."""
    mode = int(params.get("CORNER_MODE", 0.0))
    if not mode & 8 or radius <= 0:
        return force
    full = params.get("FULL_SP_RADIUS", 0.0) * units
    if mode & 16:
        limit = accel if mode & 32 else (force * force / full if full > 0 else math.inf)
        return min(force, math.sqrt(limit * radius))
    if full > 0 and radius < full:
        return force * radius / full
    return force


Arc = tuple[float, ...]  # an arc's centre from its start (counts) and turn (deg); or
# an MSPHERICAL's (centre, e2, end, turn) (geometry.py)


def cornered(params: Mapping[str, float], units: float, force: float, accel: float,
             sp: tuple[float, float], delta: tuple[float, ...], arc: Arc | None
             ) -> tuple[float, tuple[float, float], tuple[float, float, float]]:
    """An SP move's FORCE_SPEED and (STARTMOVE_SPEED, ENDMOVE_SPEED) after CORNER_MODE
    (an arc's radius speed control; the change of direction from END_DIR_LAST, the end
    of the SP move loaded before, lowering its STARTMOVE_SPEED: C, the corner control
    "operates by setting the next move's STARTMOVE_SPEED", at load), and its
    (START_DIR_LAST, END_DIR_LAST, CHANGE_DIR_LAST)."""
    start = heading(direction(delta, arc, False))
    end = heading(direction(delta, arc, True))
    change = change_of_direction(params.get("END_DIR_LAST", 0.0), start)
    if arc is not None:
        force = radius_speed(params, units, force, math.sqrt(sum(c * c for c in arc[0:3]))
                             if len(arc) > 3 else math.hypot(arc[0], arc[1]), accel)
    corner = corner_speed(params, force, change)
    if corner is not None:
        sp = (corner if sp[0] < 0 else min(sp[0], corner), sp[1])
    return force, sp, (start, end, change)


def stop_jerk(params: Mapping[str, float], units: float, jerk: float) -> float:
    """The jerk (counts/s^3) a jerk-limited move's stop ramps with (CANCEL, RAPIDSTOP, a
    limit): FASTJERK where it is above the move's JERK, in VP_MODE 5 and 6 (C: FASTJERK
    page); in VP_MODE 6 with SRAMP set, FASTDEC / SRAMP instead (C: the same page; SRAMP 0
    counts as not set, D). Read as the stop begins (D, as FASTDEC is)."""
    mode = params.get("VP_MODE", 0.0)
    if jerk <= 0 or mode not in (5.0, 6.0):
        return jerk
    sramp = params.get("SRAMP", 0.0)
    if mode == 6.0 and sramp > 0:
        fast = params.get("FASTDEC", 0.0) * units / (sramp / 1000.0)
    else:
        fast = params.get("FASTJERK", 0.0) * units
    return fast if fast > jerk else jerk


def v_limited(speed: float, limits: Sequence[float], deltas: Sequence[float],
              arc: bool, mode: float) -> float:
    """V_LIMIT: the vector speed (counts/s) of a move cut so that no axis with a limit
    (counts/s, <= 0 none) goes faster than it: a line's axis i runs at speed x |d_i| / L,
    so speed <= limit_i x L / |d_i|; an arc's path runs at the lowest limit of its axes
    (C: V_LIMIT page, its example's 45-degree move at 40 x sqrt(2)). Not in VP_MODE 5
    (C: the page)."""
    if mode == 5.0:
        return speed
    length = math.sqrt(sum(d * d for d in deltas))
    for limit, delta in zip(limits, deltas, strict=True):
        if limit <= 0:
            continue
        if arc:
            speed = min(speed, limit)
        elif delta != 0:
            speed = min(speed, limit * length / abs(delta))
    return speed


def forced_rates(params: Mapping[str, float], units: float, accel: float, decel: float,
                 jerk: float) -> tuple[float, float, float]:
    """An SP move's own (acceleration, deceleration, jerk), counts: FORCE_ACCEL,
    FORCE_DECEL and FORCE_JERK where set (above 0; -1, their power-up, not used: C, their
    pages; 0 not used, D), else the axis's ACCEL, DECEL and JERK. FORCE_JERK in VP_MODE 5
    and 6 only (C: AXIS_BLENDING page, "for VP_MODEs other than 0"), over SRAMP's jerk in
    VP_MODE 6 too (D)."""
    force_accel = params.get("FORCE_ACCEL", -1.0)
    force_decel = params.get("FORCE_DECEL", -1.0)
    force_jerk = params.get("FORCE_JERK", -1.0)
    if force_accel > 0:
        accel = force_accel * units
    if force_decel > 0:
        decel = force_decel * units
    if force_jerk > 0 and params.get("VP_MODE", 0.0) in (5.0, 6.0):
        jerk = force_jerk * units
    return accel, decel, jerk


def forced_values(params: Mapping[str, float]) -> tuple[float, float, float]:
    """(FORCE_SPEED, FORCE_ACCEL, FORCE_DECEL) as an SP move loads them, user units: what
    MOVE_FORCE_SPEED/ACCEL/DECEL read while it runs (C: their pages)."""
    return (params.get("FORCE_SPEED", 0.0), params.get("FORCE_ACCEL", -1.0),
            params.get("FORCE_DECEL", -1.0))


def vp_factors(params: Mapping[str, float]) -> tuple[float, float]:
    """(SPEED_FACTOR, ACCEL_FACTOR) on SPEED and on ACCEL and DECEL, in VP_MODE 5 and 6
    only (C: their pages); 1 in VP_MODE 0 (C). JERK_FACTOR is in jerk_counts."""
    if params.get("VP_MODE", 0.0) not in (5.0, 6.0):
        return 1.0, 1.0
    return params.get("SPEED_FACTOR", 1.0), params.get("ACCEL_FACTOR", 1.0)
