"""MHELICAL, MOVEMODIFY and what the MC405 reports of the moves it holds.

- MHELICAL(end1, end2, centre1, centre2, direction, distance3[, mode]): MOVECIRC's arc on
  the first two BASE axes while the third moves `distance3` in proportion to the arc,
  one segment of the shared path planner (`path.Segment`: an arc whose further axes
  rise linearly). Mode 0 (the default) runs the true helix at the base axis's SPEED,
  ACCEL and DECEL: the planner's path is the arc, so its rates are scaled by the arc's
  share of the helix's length (the help page: the third axis counts in the path speed);
  mode 1 runs the circle at them, the third axis following (the page: only the first two
  axes count). Lengths are in counts, as the page asks the three UNITS to be equal (I).
- MOVEMODIFY(position): the running single-axis move now ends at `position` (absolute,
  DPOS): re-planned from where the axis is, at the speed it has, on the path planner;
  when it cannot stop in time it stops and comes back (I). On an idle axis it is an
  absolute move (I).
- The reports: MTYPE (the move running), NTYPE (the next one held), MOVES_BUFFERED,
  REMAIN, ENDMOVE, MSPEED, LINK_AXIS, ADDAX_AXIS (see docs/trio.md, "Moves and links").
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol

import numpy as np

from maxk.firmware_model.path import PathPlan, plan_path

from .compensate import Compensation
from .link_kinds import Cambox, Connect, Link, Movelink
from .links import Host as LinkHost
from .links import LinkedMoves
from .runs import Run, move_length


class Host(LinkHost, Protocol):
    """What these moves need of the machine (Host) beyond what links do."""

    links: LinkedMoves
    distance_done: list[float]

    def _counts(self, axis: int, value: float) -> float: ...
    def _end_counts(self, axis: int) -> float: ...
    def _load(self, axes: tuple[int, ...], deltas: list[int],
              arc: tuple[float, ...] | None = None, kind: int = 1, *,
              helix: float = 1.0) -> None: ...
    def _apply_plan(self, run: Run, plan: PathPlan) -> None: ...
    def can_load(self, axes: Sequence[int]) -> bool: ...
    def axis_idle(self, axis: int) -> bool: ...
    def vp_speed_at(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...
    def axis_parameter(self, name: str, axis: int) -> float: ...

# MTYPE/NTYPE codes (I: the manual's MTYPE table as recalled; see keywords.py)
IDLE, MOVE, MOVEABS, MHELICAL, MOVECIRC, MOVEMODIFY = 0, 1, 2, 3, 4, 5
FORWARD, REVERSE = 10, 11
CAM, FWD_JOG, REV_JOG = 13, 14, 15
CAMBOX, CONNECT, MOVELINK, CONNPATH = 20, 21, 22, 23
COMPENSATE_XY = 26
FOREVER = 2 ** 50  # counts: the interpreter's FORWARD/REVERSE move (reported as such)
_UNCOUNTED = (FWD_JOG, REV_JOG)  # MOVE_COUNT leaves jogs out (C)
REPORTS = frozenset({"MTYPE", "NTYPE", "MOVES_BUFFERED", "REMAIN", "ENDMOVE", "MSPEED",
                     "DEMAND_SPEED", "LINK_AXIS", "ADDAX_AXIS", "ENDMOVE_BUFFER", "VP_ACCEL",
                     "VP_JERK", "IN_POS", "VECTOR_BUFFERED", "MSPEEDF"})


def link_kind(link: Link) -> int:
    if isinstance(link, Connect):
        return CONNECT
    if isinstance(link, Movelink):
        return MOVELINK
    if isinstance(link, Cambox):
        return CAMBOX
    if isinstance(link, Compensation):
        return COMPENSATE_XY
    return CONNPATH


def move_kind(axes: tuple[int, ...], deltas: list[int], absolute: bool) -> int:
    """MOVE or MOVEABS, or FORWARD/REVERSE (the interpreter's endless move)."""
    if len(axes) == 1 and abs(deltas[0]) == FOREVER:
        return FORWARD if deltas[0] > 0 else REVERSE
    return MOVEABS if absolute else MOVE


def arc_of(m: Host, axes: tuple[int, ...], args: list[float]
           ) -> tuple[int, int, tuple[float, float, float]]:
    """The end (whole counts) and (centre, turn) of MOVECIRC's and MHELICAL's arc from
    the first five arguments; direction 1 turns clockwise, 0 anticlockwise (I); an end
    on the start is a whole circle."""
    if args[4] not in (0, 1):
        raise ValueError("Parameter out of range")
    ex, ey = (round(m._counts(a, v)) for a, v in zip(axes[:2], args[:2], strict=True))
    cx, cy = (m._counts(a, v) for a, v in zip(axes[:2], args[2:4], strict=True))
    if cx == 0 and cy == 0:
        raise ValueError("Parameter out of range")
    start = math.atan2(-cy, -cx)
    end = math.atan2(ey - cy, ex - cx)
    turn = math.degrees(end - start) % 360.0
    if args[4] == 1:
        turn = turn - 360.0 if turn > 0 else -360.0
    elif turn == 0:
        turn = 360.0
    return ex, ey, (cx, cy, turn)


def mhelical(m: Host, axes: tuple[int, ...], args: list[float]) -> None:
    """MHELICAL: mode 0 a true helix, 1 the circle's path speed (module docstring); a mode
    beyond the page's 0 and 1, or an 8th or 9th argument not 0, is refused (D)."""
    if len(args) < 6 or (len(args) > 6 and args[6] not in (0, 1)) \
            or any(a != 0 for a in args[7:]):
        raise ValueError("Parameter out of range")
    ex, ey, arc = arc_of(m, axes, args)
    rise = round(m._counts(axes[2], args[5]))
    helix = 1.0
    if len(args) < 7 or args[6] == 0:
        cx, cy, turn = arc
        arc_length = math.hypot(cx, cy) * math.radians(abs(turn))
        helix = math.hypot(arc_length, rise) / arc_length if arc_length > 0 else 1.0
    m._load(axes[:3], [ex, ey, rise], arc=arc, kind=MHELICAL, helix=helix)


def own_target(m: Host, axis: int, position: float) -> int:
    """The axis's own demand (physical counts) at which DPOS reads `position` (what
    DEFPOS and ended ADDAXes shifted taken off)."""
    return round(m._counts(axis, position) - m.axes[axis].datum - m.links.shift[axis])


def movemodify(m: Host, axis: int, position: float, min_rate: float) -> None:
    target = own_target(m, axis, position)
    queue = m.queues[axis]
    run = queue[0] if queue else None
    a = m.axes[axis]
    if a.link is not None or a.pending_link is not None:
        raise ValueError("Parameter out of range")  # a linked move: no end to move (D)
    if run is None or not run.started:
        if not m.can_load([axis]):
            raise ValueError("Parameter out of range")  # (D: the buffer is full)
        delta = target - m._end_counts(axis)
        if not abs(delta) < 2.0 ** 53:
            raise ValueError("Parameter out of range")
        m._load((axis,), [round(delta)], kind=MOVEMODIFY)  # idle: an absolute move (I)
        return
    if run.axes != (axis,) or run.stopping or moves_left(m, run) > 1:
        raise ValueError("Parameter out of range")  # (D: only a single axis's last move)
    params = a.params
    speed, accel = params["SPEED"] * a.units, params["ACCEL"] * a.units
    if not min(speed, accel) >= min_rate:
        raise ValueError("Parameter out of range")
    now = m._now()
    here = float(m.own_counts(axis, now)[0])
    velocity = a.velocity(m) if a.motion is not None else 0.0
    distance = target - here
    direction = 1.0 if velocity > 0 else -1.0
    stopping = velocity * velocity / (2.0 * accel)
    if velocity == 0 or (distance * direction > 0 and abs(distance) >= stopping):
        deltas: list[float] = [distance]
        speeds = [speed]
    else:  # it cannot stop short of the new end: stop, then come back (at rest between)
        deltas = [direction * stopping, distance - direction * stopping]
        speeds = [0.0, speed]
    s_done, _v = run.distance_speed(now, m.period)
    m.distance_done[axis] += float(s_done[0]) / run.units
    new = Run((axis,), [(d,) for d in deltas], speeds,  # type: ignore[misc]
              [accel] * len(deltas), params["DECEL"] * a.units, a.units, single=False)
    new.kinds = {j: MOVEMODIFY for j in range(len(deltas))}
    new.counted = len(deltas) - 1  # (the move it modifies was counted)
    new.started = True
    new.start_tick = m.tick
    new.resolve((here,))
    queue[0] = new
    m._apply_plan(new, plan_path(new.segments, 0, 0.0, abs(velocity), 1.0))
    m.changed()


def count_moves(m: Host) -> None:
    """MOVE_COUNT: each move of a run that has become the running one (MTYPE) since the
    last look counts once on every axis of its group; zero-length moves and jogs do not
    (C: MOVE_COUNT page). Looked at when a run starts and at every motion event, which
    every move boundary of a path is."""
    for queue in m.queues:
        run = queue[0] if queue else None
        if run is None or not run.started:
            continue  # (a group's run heads each of its axes' queues: counted once)
        now = _current(m, run)
        if now <= run.counted:
            continue
        moves = sum(1 for j in range(run.counted + 1, now + 1)
                    if any(run.deltas[j]) and run.kinds.get(j, MOVE) not in _UNCOUNTED)
        run.counted = now
        for a in run.axes:
            params = m.axes[a].params  # each move by MOVE_COUNT_INC (its page)
            params["MOVE_COUNT"] += moves * params.get("MOVE_COUNT_INC", 1.0)


def moves_left(m: Host, run: Run) -> int:
    return run.moves_left(m.tick, m.period)


def current(m: Host, run: Run) -> int:
    """The index of the move a started run is on (MOVE_FORCE_*, profile_readings.py)."""
    return _current(m, run)


def _current(m: Host, run: Run) -> int:
    """The index of the move a started run is on."""
    if run.plan is None or run.profile is not None:
        return 0
    s, _v = run.plan.state((m.tick - run.plan_tick) * m.period)
    return run.segment_index(s)


def held(m: Host, axis: int) -> tuple[bool, list[int]]:
    """(a move is executing, the MTYPEs of every move the axis holds, in order)."""
    a = m.axes[axis]
    kinds: list[int] = []
    queue = m.queues[axis]
    for run in queue:
        first = _current(m, run) if run.started else 0
        kinds += [run.kinds.get(j, MOVE) for j in range(first, len(run.deltas))]
    for link in (a.link, a.pending_link, *m.links.chains[axis]):
        if link is not None:
            kinds.append(link_kind(link))
    executing = bool(queue and queue[0].started) or a.link is not None
    return executing, kinds


def report(m: Host, name: str, axis: int) -> float:
    """The value of one of REPORTS."""
    a = m.axes[axis]
    if name in ("MTYPE", "NTYPE", "MOVES_BUFFERED"):
        executing, kinds = held(m, axis)
        if name == "MOVES_BUFFERED":
            return float(len(kinds) - executing)
        index = (0 if name == "MTYPE" else 1) if executing else (None if name == "MTYPE"
                                                                  else 0)
        return float(kinds[index]) if index is not None and index < len(kinds) else 0.0
    if name == "VECTOR_BUFFERED":
        return _vector_buffered(m, axis)
    if name == "IN_POS":  # (C: the IN_POS page's four conditions, strictly less)
        executing, kinds = held(m, axis)
        params = a.params
        inside = (not executing and not kinds
                  and abs(m.axis_parameter("FE", axis)) < params["IN_POS_DIST"]
                  and abs(report(m, "MSPEED", axis)) < params["IN_POS_SPEED"])
        return -1.0 if inside else 0.0
    if name == "LINK_AXIS":
        link = a.link
        leader = getattr(link, "link", getattr(link, "base", None))
        return float(leader) if isinstance(leader, int) else -1.0
    if name == "ADDAX_AXIS":
        added = m.links.addax.get(axis)
        return float(added.link) if added is not None else -1.0
    now = m._now()
    if name == "ENDMOVE_BUFFER":  # the end of every move buffered, as DPOS reads (C)
        return (m._end_counts(axis) + a.datum + m.links.shift[axis]) / a.units
    if name in ("VP_ACCEL", "VP_JERK"):
        # VP_SPEED's change over the servo cycle before now (and its change: D)
        ticks = np.maximum(np.arange(m.tick - 2, m.tick + 1), 0)
        v = m.vp_speed_at(axis, ticks)
        accel = np.diff(v) / m.period
        if name == "VP_ACCEL":
            return float(accel[-1])
        return float(accel[1] - accel[0]) / m.period if m.tick >= 2 else 0.0
    if name in ("MSPEED", "DEMAND_SPEED", "MSPEEDF"):  # (the demand is what the axis
        # measures, D; MSPEEDF is MSPEED with MSPEED_FILTER at 1, C, and unfiltered, D)
        if m.tick == 0:
            return 0.0
        ticks = np.array([m.tick - 1, m.tick])
        d = m.demand_counts(axis, ticks)
        return float(d[1] - d[0]) / m.period / a.units
    here = float(m.own_counts(axis, now)[0])
    end = _move_end(m, axis, here)
    if name == "REMAIN":
        return abs(end - here) / a.units
    extra = float(m.demand_counts(axis, now)[0]) - here  # ADDAX's part, as DPOS has it
    return (end + extra + a.datum) / a.units  # ENDMOVE


def _vector_buffered(m: Host, axis: int) -> float:
    """The path length still to run of the moves of the group based on the axis, the
    running one's remainder included (D: "available for deceleration"), in the base's
    user units as each run loaded them."""
    total = 0.0
    for run in m.queues[axis]:
        if run.base != axis or run.preset is not None:
            continue
        left = run.dropped_length  # (added in order: the same sum once moves are dropped)
        for j, delta in enumerate(run.deltas):
            left += move_length(delta, run.arcs.get(j))
        if run.started:
            s_done, _v = run.distance_speed(m._now(), m.period)
            left = max(0.0, (run.length() if run.stopping else left) - float(s_done[0]))
        total += left / run.units
    return total


def _move_end(m: Host, axis: int, here: float) -> float:
    """Where the axis's own demand ends the move it runs (here when none has an end)."""
    a = m.axes[axis]
    if isinstance(a.link, Movelink) and not a.link.repeat:
        return a.link.origin + a.link.distance
    queue = m.queues[axis]
    run = queue[0] if queue else None
    if run is None or not run.started or a.motion is None:
        return here
    if run.profile is not None:
        return float(a.steps + run.profile.final_offset)
    segment = run.segments[_current(m, run)]
    return float(segment.end[run.axes.index(axis)])


def set_endmove(m: Host, axis: int, value: float, min_rate: float) -> None:
    """ENDMOVE = v: on an idle axis the demand steps to v (C: manual, DPOS); on a running
    single-axis move it is MOVEMODIFY(v) (D); otherwise refused."""
    if m.axis_idle(axis):
        target = m._counts(axis, value) - m.axes[axis].datum - m.links.shift[axis]
        added = m.links.addax.get(axis)
        if added is not None:
            target -= m.demand(added.link) - added.origin
        a = m.axes[axis]
        a.steps = math.floor(target)
        a.fraction = target - a.steps
        m.changed()
        return
    movemodify(m, axis, value, min_rate)


__all__ = ["REPORTS", "arc_of", "held", "mhelical", "move_kind", "movemodify", "report",
           "set_endmove"]
