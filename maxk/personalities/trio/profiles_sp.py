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
from collections.abc import Mapping

VP_MODES = frozenset({0.0, 5.0, 6.0})  # the modes the VP_MODE page lists
UNSET = -1.0  # STARTMOVE_SPEED / ENDMOVE_SPEED: not used (their power-up value, C)


def jerk_counts(params: Mapping[str, float], units: float) -> float:
    """The jerk limit a move loaded now runs with, counts/s^3 (0: none)."""
    mode = params.get("VP_MODE", 0.0)
    if mode not in (5.0, 6.0):
        return 0.0
    sramp = params.get("SRAMP", 0.0)
    if mode == 6.0 and sramp > 0:
        return params["ACCEL"] * units / (sramp / 1000.0)
    return max(0.0, params.get("JERK", 0.0)) * units


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
