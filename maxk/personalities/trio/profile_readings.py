"""Readings of the running profile that the TrioBASIC help added after the MC405's token
table: REMAIN_TIME, STOPPING_DISTANCE, MOVE_FORCE_* and VP_DEMAND_* (helpwords.NEWER_WORDS).

- REMAIN_TIME: the seconds until the moves the axis holds are done (C: its page, "all the
  MOVES loaded in the buffer"): the running run's end tick less now, plus, for each
  single-axis move buffered behind it, the time of its own profile from rest with the rates
  it loaded with (D: moves start from rest when MERGE is off; its FORCE_DWELL counted),
  in whole servo cycles as the moves end on them (D). A buffered multi-axis run is not
  counted until it starts: its path is resolved from where the axes are then (D). Links
  and moves without an end (FORWARD, jogs) add nothing: they have no time left (D).
- MOVE_FORCE_SPEED, MOVE_FORCE_ACCEL, MOVE_FORCE_DECEL: the FORCE_SPEED, FORCE_ACCEL and
  FORCE_DECEL the running move loaded with (C: their pages), on every axis of its group;
  -1 with no move running or a move that is not an SP move (D).
- STOPPING_DISTANCE: how far the axis would run if its move were cancelled now (C: its page,
  "using the current deceleration parameters"; D: the rates a CANCEL would use here, the
  move's DECEL with its SRAMP/JERK and FASTJERK, machine._stop): from the profile speed v
  with the acceleration starting from 0, a symmetric ramp down of time T = v / (D (1 -
  p/2)) (p the S-curve's jerk share, 0 linear) covering v T / 2; for a path, along it (in
  the base's user units, on every axis of the group: D); while a stop runs, what is left
  of it; 0 at rest and on links (D).
- VP_DEMAND_SPEED, VP_DEMAND_ACCEL, VP_DEMAND_DECEL, VP_DEMAND_JERK: the demands the
  velocity profiler is running the move in force on (C: their pages, "demand", user units
  per s, s^2, s^3). The pages do not say loaded rates or the rate now (VP_SPEED and VP_ACCEL
  read that), so D: the rates the move now running loaded with, as the profiler was given
  them (SPEED or FORCE_SPEED after SPEED_FACTOR, V_LIMIT and INTERP_FACTOR; its ACCEL or
  FORCE_ACCEL; the run's DECEL; its jerk limit, 0 in VP_MODE 0), in the base axis's user
  units, on every axis of its group; the demand speed 0 while a CANCEL/RAPIDSTOP ramps it
  to rest; all 0 with no move running, on links and CAMs (their own profile).
"""

from __future__ import annotations

import math

from .moves import Host
from .moves import current as current_move
from .profiles_sp import stop_jerk
from .runs import Run, ramp_shares, single_profile

READS = frozenset({"REMAIN_TIME", "STOPPING_DISTANCE", "MOVE_FORCE_SPEED", "MOVE_FORCE_ACCEL",
                   "MOVE_FORCE_DECEL", "VP_DEMAND_SPEED", "VP_DEMAND_ACCEL",
                   "VP_DEMAND_DECEL", "VP_DEMAND_JERK"})
_FORCED = ("MOVE_FORCE_SPEED", "MOVE_FORCE_ACCEL", "MOVE_FORCE_DECEL")


def read(m: Host, name: str, axis: int) -> float:
    queue = m.queues[axis]
    run = queue[0] if queue else None
    if name in _FORCED:
        if run is None or not run.started:
            return -1.0
        values = run.forced.get(current_move(m, run))
        return values[_FORCED.index(name)] if values is not None else -1.0
    if name.startswith("VP_DEMAND_"):
        return _demand(m, run, name) if run is not None and run.started \
            and run.preset is None else 0.0
    if name == "REMAIN_TIME":
        if run is None or not run.started:
            return 0.0
        ticks = max(0, run.end_tick - m.tick)
        for later in list(queue)[1:]:
            ticks += _ticks_from_rest(m, later)
        return ticks * m.period
    if run is None or not run.started:
        return 0.0
    if run.stopping:
        return float(m.axis_parameter("REMAIN", axis)) if run.single else \
            _path_left(m, run) / run.units
    v = abs(m.axis_parameter("VP_SPEED", run.base)) * run.units  # counts/s
    if v <= 0 or run.decel <= 0:
        return 0.0
    jerk = stop_jerk(m.axes[run.base].params, run.units, run.jerk)
    _shape, _up, down, _share_up, share = ramp_shares(v, run.decel, run.decel, run.sramp,
                                                      jerk)
    p = share or 0.0
    time = v / (down * (1 - p / 2))
    return v * time / 2 / run.units


def _demand(m: Host, run: Run, name: str) -> float:
    """The demand the running move loaded with, in the base axis's user units."""
    if name == "VP_DEMAND_SPEED":
        value = 0.0 if run.stopping else run.speeds[current_move(m, run)]
    elif name == "VP_DEMAND_ACCEL":
        value = run.accels[current_move(m, run)]
    elif name == "VP_DEMAND_DECEL":
        value = run.decel
    else:
        value = run.jerk
    return value / run.units


def _ticks_from_rest(m: Host, run: Run) -> int:
    """The servo cycles a buffered run takes from rest (0 when it has no end)."""
    if run.single and run.preset is None:
        profile = single_profile(run.deltas[0][0], run.speeds[0], run.accels[0], run.decel,
                                 run.sramp, run.jerk)
        end = profile.end_time
    elif run.preset is not None:
        end = run.preset.end_time
    else:
        return 0
    if end is None:
        return 0
    dwell = math.ceil(run.dwell / m.period - 1e-9) if run.dwell > 0 else 0
    return math.ceil(end / m.period - 1e-9) + dwell


def _path_left(m: Host, run: Run) -> float:
    s_done, _v = run.distance_speed(m._now(), m.period)
    return max(0.0, run.length() - float(s_done[0]))
