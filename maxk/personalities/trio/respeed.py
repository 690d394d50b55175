"""SPEED, ACCEL and DECEL changed while moves run (TrioBASIC help, VP_MODE: "all velocity
profiling modes allow the SPEED/ACCEL/DECEL motion parameters to be changed while
profiling non-SP move types"; the SP moves keep what they were loaded with).

A write to the base axis's SPEED, ACCEL or DECEL takes effect at once on the moves of
its BASE group that are not SP moves (so do SPEED_FACTOR and ACCEL_FACTOR in VP_MODE
5/6, their pages; V_LIMIT still caps each move, profiles_sp.v_limited): the one running
is re-planned from where it is, at the speed it has, toward the new speed at the new
rate, and the moves buffered behind it run at the new values (D: the page names the
profiling, not the buffered moves; a move reads them when it is profiled). A single-axis
move (a closed-form profile) becomes a path of its remaining distance first, with linear
ramps, or with SRAMP/JERK the S-ramps of path_scurve.py, the ramp running ending first
(D). Jogs (JOGSPEED), CAMs and MOVEMODIFY's re-plans keep theirs (D).
"""

from __future__ import annotations

import math
from typing import Any

from .feedhold import _as_path, _current
from .moves import CAM, FWD_JOG, MOVEMODIFY, REV_JOG
from .profiles_sp import lookahead, v_limited, vp_factors

_KEEP = frozenset({CAM, FWD_JOG, REV_JOG, MOVEMODIFY})


def respeed(m: Any, axis: int) -> None:
    """The base axis's SPEED/ACCEL/DECEL changed: its group's plain moves take them."""
    a = m.axes[axis]
    speed_factor, accel_factor = vp_factors(a.params)  # VP_MODE 5/6 (profiles_sp.py)
    speed = a.params["SPEED"] * a.units * speed_factor
    accel = a.params["ACCEL"] * a.units * accel_factor
    decel = a.params["DECEL"] * a.units * accel_factor
    if not min(speed, accel, decel) > 0:
        return  # (a zero SPEED: the moves keep theirs; a new one loads held at 0, D)
    for run in list(m.queues[axis]):
        if run.base != axis or run.stopping or run.preset is not None:
            continue
        first = _current(m, run) if run.started else 0
        changed = False
        for j in range(first, len(run.deltas)):
            if j in run.sp or run.kinds.get(j, 1) in _KEEP:
                continue
            capped = v_limited(speed, [m.axes[k].params.get("V_LIMIT", 0.0) * m.axes[k].units
                                       for k in run.axes], [float(d) for d in run.deltas[j]],
                               j in run.arcs, a.params.get("VP_MODE", 0.0))
            if run.speeds[j] != capped or run.accels[j] != accel:
                run.speeds[j], run.accels[j] = capped, accel
                changed = True
        if run.decel != decel and not run.sp and run.kinds.get(0, 1) not in _KEEP:
            run.decel = decel
            changed = True
        if changed and run.started:
            _replan(m, run, first)


def refactor(m: Any, axis: int) -> None:
    """LOOKAHEAD_FACTOR changed on a base axis: every SP move of its group not yet done
    carries the new factor on its FORCE_SPEED, STARTMOVE_SPEED and ENDMOVE_SPEED (C: its
    page, "all speeds in the motion buffer"); the one running is re-planned from where it
    is, at the speed it has, at its ACCEL (as SPEED above, D)."""
    factor = lookahead(m.axes[axis].params)
    for run in list(m.queues[axis]):
        if run.base != axis or run.stopping:
            continue
        first = _current(m, run) if run.started else 0
        changed = False
        for j in range(first, len(run.deltas)):
            old = run.factored.get(j)
            if j not in run.sp or old is None or old == factor:
                continue
            ratio = factor / old
            run.speeds[j] *= ratio
            start, end = run.sp[j]
            run.sp[j] = (start * ratio if start >= 0 else start,
                         end * ratio if end >= 0 else end)
            run.factored[j] = factor
            changed = True
        if changed and run.started:
            _replan(m, run, first)


def _replan(m: Any, run: Any, first: int) -> None:
    """The run's segments from move `first` on take their moves' new speeds, and the
    path is planned again from where it is."""
    if run.profile is not None:
        run = _as_path(m, run)
        first = 0
    defs = run.definitions(first)
    for j in range(first, len(run.segments)):
        seg, defn = run.segments[j], defs[j - first]
        seg.ceiling = defn.v_top if defn.v_top is not None else seg.ceiling
        seg.v_end = defn.v_end
        seg.accel = defn.accel
        if seg.radius > 0:
            seg.arc_cap = math.sqrt(seg.accel * seg.radius)
    m._apply_plan(run, run.plan_new(m.tick, period=m.period))
    m.changed()


__all__ = ["refactor", "respeed"]
