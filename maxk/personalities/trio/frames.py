"""The MC405's robot (kinematic) frames: world positions kept apart from motor positions.

What the TrioBASIC help gives (pages FRAME, FRAME_GROUP, FRAME_TRANS, AXIS_DPOS,
AXIS_UNITS, WORLD_DPOS), as built here:

- A frame group is a set of axes and the TABLE offset of the frame's parameters
  (FRAME_GROUP(group, table_offset, axes...)). FRAME on an axis of no group, or with no
  group defined, makes group 0 the lowest axes at table offset 0.
- With FRAME <> 0 on a group, DPOS (by UNITS) is the world position: moves and links plan
  it exactly as on any axis. Each axis's motor demand, AXIS_DPOS (by AXIS_UNITS), is the
  frame's inverse transform of the group's world positions, at every servo tick
  (`motor_counts`, on arrays of ticks as `kinematics.py` evaluates demand), and the
  motor follows it: the world, limit inputs and a servo loop see the motor. MPOS reads
  the motor by AXIS_UNITS, so FE (between MPOS and AXIS_DPOS) is 0 (D: the shared servo
  loop runs on a planned profile, not on a transformed demand; a servo axis in a frame
  follows AXIS_DPOS exactly, as a linked servo axis does).
- Enabling a frame: DPOS becomes the forward transform of the present AXIS_DPOS (no
  motion); FRAME = 0: DPOS becomes MPOS again (page, FRAME 5 homing). Either only while
  the group's axes are idle (D: the page warns the change moves the machine otherwise).
- The frames whose transform the FRAME page gives exactly: 2 (XY single belt), 5 (two
  axes rotated by a 2x2 matrix and its inverse from TABLE), 6 (polar programming of an
  XY machine) and 10 (XY programming of a polar machine). Transforms work on raw
  positions: world DPOS * UNITS, axis AXIS_DPOS * AXIS_UNITS (FRAME_TRANS page). Any
  other frame is refused (its equations are not on the page).
- FRAME_REP_DIST (its page, REP_OPTION's bit 3): an orientation axis's DPOS reads folded
  at +-FRAME_REP_DIST while its frame is on, AXIS_DPOS never (`folded`).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from maxk.firmware_model.world import STUCK_ACTIVE, STUCK_INACTIVE, World

from .drive import INPUTS
from .memory import TABLE_SIZE
from .runs import Run, TrioAxis

SIZES = {2: 2, 5: 2, 6: 2, 10: 2}
"""Axes each built frame transforms (FRAME page)."""
PARAMETERS = {2: 0, 5: 8, 6: 1, 10: 3}
"""TABLE values each frame reads from its group's offset (FRAME page)."""
GROUPS = 8  # FRAME_GROUP 0..7 (page)
READS = frozenset({"FRAME", "AXIS_DPOS", "TRANS_DPOS", "WORLD_DPOS"})
TWO_PI = 2.0 * math.pi
STRETCH_CHUNK = 65536  # servo ticks frame 10 follows at once (bounds the arrays)
LOOK_AHEAD = 1024  # servo ticks searched at once for a joint limit (then looked at again)
AXIS_FS_BIT, AXIS_RS_BIT = 1 << 16, 1 << 17  # AXISSTATUS (AXIS_FS_LIMIT, AXIS_RS_LIMIT pages)


class FrameHost(Protocol):
    """What the frames need of the machine (`MC405Machine`)."""

    axes: list[TrioAxis]
    queues: list[deque[Run]]
    tick: int
    revision: int
    world: World
    inverted_inputs: set[int]

    def _stop(self, run: Run, decel: float | None = None) -> None: ...
    def fast_decel(self, run: Run) -> float | None: ...

    def demand_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...

    def axis_idle(self, axis: int) -> bool: ...

    def table_read(self, index: int) -> float: ...

    def changed(self) -> None: ...


Arrays = list[np.ndarray]


def _branch(angle: np.ndarray, near: float) -> np.ndarray:
    """The angle (radians) plus the whole turns that bring it nearest `near`."""
    return angle + TWO_PI * np.round((near - angle) / TWO_PI)


def to_axes(frame: int, table: Sequence[float], world: Arrays,
            near: Sequence[float] | None = None) -> Arrays:
    """Inverse kinematics: raw world positions (DPOS * UNITS) to raw axis positions
    (AXIS_DPOS * AXIS_UNITS). `near`: raw axis positions at the tick before the first
    one asked for, from which a turning axis's angle is followed turn by turn along the
    ticks (frame 10's whole revolutions, TABLE offset 1 and 2 on the controller)."""
    x, y = world
    if frame == 2:  # X = (A0 + A1) / 2, Y = (A0 - A1) / 2 (page)
        return [x + y, x - y]
    if frame == 5:  # (x', y') = (x, y) * [[T0, T1], [T2, T3]] (page)
        return [x * table[0] + y * table[2], x * table[1] + y * table[3]]
    if frame == 6:  # world (radius, angle * scale) to X, Y (page)
        angle = y / _scale(table[0])
        return [x * np.cos(angle), x * np.sin(angle)]
    if frame == 10:  # world X, Y to (radius, angle * edges per radian) (page)
        scale = _scale(table[0])
        angle = np.arctan2(y, x)
        if near is not None:  # (ticks in order from the reference: followed turn by turn)
            followed = np.unwrap(np.concatenate(([near[1] / scale], np.ravel(angle))))
            angle = followed[1:].reshape(np.shape(angle))
        return [np.hypot(x, y), angle * scale]
    raise ValueError("Parameter out of range")


def to_world(frame: int, table: Sequence[float], axes: Arrays,
             near: Sequence[float] | None = None) -> Arrays:
    """Forward kinematics: raw axis positions to raw world positions; `near`: raw world
    positions frame 6's angle is kept nearest (else atan2's -pi..pi)."""
    a, b = axes
    if frame == 2:
        return [(a + b) * 0.5, (a - b) * 0.5]
    if frame == 5:  # (x, y) = (x', y') * [[T4, T5], [T6, T7]] (page)
        return [a * table[4] + b * table[6], a * table[5] + b * table[7]]
    if frame == 6:
        scale = _scale(table[0])
        angle = np.arctan2(b, a)
        if near is not None:
            angle = _branch(angle, near[1] / scale)
        return [np.hypot(a, b), angle * scale]
    if frame == 10:
        angle = b / _scale(table[0])
        return [a * np.cos(angle), a * np.sin(angle)]
    raise ValueError("Parameter out of range")


def _scale(value: float) -> float:
    """A frame's counts per radian: 0 (an unset table) cannot scale an angle."""
    if value == 0 or not math.isfinite(value):
        raise ValueError("Parameter out of range")
    return value


def transform(frame: int, table: Sequence[float], values: Sequence[float],
              forward: bool) -> list[float]:
    """FRAME_TRANS on plain numbers: forward (AXIS_DPOS to DPOS) or inverse."""
    if frame not in SIZES:
        raise ValueError("Parameter out of range")
    arrays = [np.array([v], dtype=float) for v in values]
    out = (to_world if forward else to_axes)(frame, table, arrays)
    result = [float(v[0]) for v in out]
    if not all(math.isfinite(v) for v in result):
        raise ValueError("Parameter out of range")
    return result


def fold(position: float, rep: float, from_zero: bool) -> float:
    """A position folded by a repeat distance rep > 0 (REP_DIST, FRAME_REP_DIST) into
    -rep..rep, or 0..rep (`from_zero`, REP_OPTION bit 0). The remainder is exact and
    never overflows (a fold far smaller than the position, down to the least float, reads
    a value instead of failing; a position within the fold reads unchanged)."""
    span = rep if from_zero else 2.0 * rep
    r = math.fmod(position, span)  # (exact, the sign of position)
    if from_zero:
        return r + span if r < 0 else r
    if r >= rep:
        return r - span
    return r + span if r < -rep else r


@dataclass
class FrameGroup:
    """FRAME_GROUP: axes in ascending order, the TABLE offset of the frame's data, the
    frame on them and, while one is on, each axis's DEFPOS offset when it was enabled
    (motor counts = AXIS_DPOS * AXIS_UNITS - that offset)."""

    table_offset: int
    axes: tuple[int, ...]
    frame: int = 0
    motor_datum: list[float] = field(default_factory=list)
    near: list[float] = field(default_factory=list)  # raw axis positions at the last event
    scale: float = 0.0  # frame 6 / 10's last usable TABLE scale (`Frames.table`)


class Frames:
    """The MC405's frame groups (see the module docstring)."""

    def __init__(self, machine: FrameHost) -> None:
        self.m = machine
        self.groups: dict[int, FrameGroup] = {}
        self._looked: tuple[int, int, int | None] = (-1, -1, None)  # revision, tick, event
        self._acted = -1  # the tick on_event last looked at (searched from the next one)

    def reset(self) -> None:
        """Power-up: no groups, no frame."""
        self.groups.clear()
        self._looked = (-1, -1, None)
        self._acted = -1

    # ---- which axes are in a frame ------------------------------------------------------
    def group_of(self, axis: int) -> FrameGroup | None:
        for group in self.groups.values():
            if axis in group.axes:
                return group
        return None

    def active(self, axis: int) -> FrameGroup | None:
        """The group whose frame is on and holds the axis, or None."""
        group = self.group_of(axis)
        return group if group is not None and group.frame else None

    def framed(self, axis: int) -> bool:
        return self.active(axis) is not None

    def folded(self, axis: int, position: float, params: dict[str, float]) -> float:
        """DPOS of an axis with REP_OPTION bit 3 (FRAME_REP_DIST and REP_OPTION pages):
        REP_DIST does not fold it; while its frame is on, FRAME_REP_DIST above 0 folds it
        into -FRAME_REP_DIST..FRAME_REP_DIST, or 0..FRAME_REP_DIST with bit 0 too (C);
        with the frame off it is not folded (C). AXIS_DPOS and MPOS are never folded (C);
        the machine keeps the unfolded position, as REP_DIST's fold (D)."""
        rep = params.get("FRAME_REP_DIST", 0.0)
        if not rep > 0 or not self.framed(axis):
            return position
        return fold(position, rep, bool(int(params.get("REP_OPTION", 0.0)) & 1))

    # ---- the motor's demand ---------------------------------------------------------------
    def table(self, group: FrameGroup, frame: int) -> list[float]:
        """The frame's TABLE parameters, read live (the page: changing them with the frame
        on moves the machine unpredictably). A scale that cannot scale an angle (0, not
        finite) written while frame 6 or 10 is on is not taken: the frame keeps the last
        one it ran on (D), so the servo cycle and FRAME = 0 go on working."""
        values = [self.m.table_read(group.table_offset + k) for k in range(PARAMETERS[frame])]
        if frame in (6, 10) and group.frame == frame:
            if values[0] != 0 and math.isfinite(values[0]):
                group.scale = values[0]
            elif group.scale:
                values[0] = group.scale
        return values

    def world_raw(self, group: FrameGroup, ticks: np.ndarray) -> Arrays:
        m = self.m
        return [m.demand_counts(a, ticks) + m.axes[a].datum for a in group.axes]

    def axis_raw(self, group: FrameGroup, ticks: np.ndarray) -> Arrays:
        """AXIS_DPOS * AXIS_UNITS of every axis of an active group at the ticks."""
        return to_axes(group.frame, self.table(group, group.frame),
                       self.world_raw(group, ticks), group.near or None)

    def motor_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """The motor demand (physical counts, as `demand_counts` of an axis in no frame)."""
        group = self.active(axis)
        if group is None:
            return self.m.demand_counts(axis, ticks)
        k = group.axes.index(axis)
        return self.axis_raw(group, ticks)[k] - group.motor_datum[k]

    def stretch(self, limit: int) -> None:
        """Before the engine jumps to `limit`: follow frame 10's angle tick by tick over
        the stretch, so the whole turns it has made are known at the next event (D: the
        controller counts them each servo cycle, TABLE offset 1 and 2)."""
        for group in self.groups.values():
            if group.frame != 10 or limit <= self.m.tick:
                continue
            scale = _scale(self.table(group, 10)[0])
            if all(self.m.axis_idle(a) for a in group.axes):  # the world stands still
                x, y = self.world_raw(group, np.array([limit]))
                angle = float(_branch(np.arctan2(y, x), group.near[1] / scale)[0])
                group.near = [float(np.hypot(x[0], y[0])), angle * scale]
                continue
            for first in range(self.m.tick + 1, limit + 1, STRETCH_CHUNK):
                ticks = np.arange(first, min(first + STRETCH_CHUNK, limit + 1))
                x, y = self.world_raw(group, ticks)
                start = group.near[1] / scale
                angles = np.unwrap(np.concatenate(([start], np.arctan2(y, x))))
                group.near = [float(np.hypot(x[-1], y[-1])), float(angles[-1]) * scale]

    # ---- FRAME, AXIS_DPOS, MPOS, WORLD_DPOS ---------------------------------------------
    def read(self, name: str, axis: int, dpos: float) -> float:
        """FRAME, AXIS_DPOS (TRANS_DPOS), WORLD_DPOS of an axis; `dpos`: its DPOS."""
        group = self.active(axis)
        if name == "FRAME":
            return float(group.frame) if group is not None else 0.0
        if name == "WORLD_DPOS" or group is None:
            return dpos  # (no USER_FRAME or TOOL_OFFSET: the world is DPOS; FRAME 0: 1:1)
        return self.axis_dpos(axis)

    def axis_dpos(self, axis: int) -> float:
        """AXIS_DPOS of an axis in an active frame, in AXIS_UNITS."""
        group = self.active(axis)
        assert group is not None
        k = group.axes.index(axis)
        raw = self.axis_raw(group, np.array([self.m.tick]))[k]
        return float(raw[0]) / self.m.axes[axis].params["AXIS_UNITS"]

    # ---- FRAME = n ----------------------------------------------------------------------
    def set_frame(self, axis: int, value: float) -> None:
        """FRAME = n on an axis: on the axis's group (or the default group)."""
        frame = int(value)
        if frame != value or frame != 0 and frame not in SIZES:
            raise ValueError("Parameter out of range")
        group = self.group_of(axis)
        if group is not None:
            if frame and len(group.axes) != SIZES[frame]:
                raise ValueError("Parameter out of range")  # (page: sizes must match)
            self.set_group_frame(group, frame)
            return
        if frame == 0:
            return  # (no group, no frame: nothing to turn off)
        # the default group: the lowest axes, table offset 0, in place of group 0 (page)
        old = self.groups.get(0)
        axes = tuple(range(SIZES[frame]))
        self.check_axes(axes)
        if any(self.group_of(a) not in (None, old) for a in axes):
            raise ValueError("Parameter out of range")  # (D: an axis in one group only)
        moving = axes + (old.axes if old is not None else ())
        if not all(self.m.axis_idle(a) for a in moving) or frame in (6, 10) \
                and self.m.table_read(0) == 0:
            raise ValueError("Parameter out of range")  # (before anything changes)
        if old is not None and old.frame:
            self.set_group_frame(old, 0)
        group = FrameGroup(0, axes)
        self.groups[0] = group
        try:
            self.set_group_frame(group, frame)
        except ValueError:
            if old is None:
                del self.groups[0]
            else:
                self.groups[0] = old
            raise

    def check_axes(self, axes: Sequence[int]) -> None:
        if not all(0 <= a < len(self.m.axes) for a in axes):
            raise ValueError("Invalid axis number")

    def set_group_frame(self, group: FrameGroup, frame: int) -> None:
        """Turn a group's frame on, off or to another one, on idle axes, no motion."""
        if frame == group.frame:
            return
        m = self.m
        if not all(m.axis_idle(a) for a in group.axes):
            raise ValueError("Parameter out of range")  # (D: the axes must be idle)
        now = np.array([m.tick])
        if group.frame:  # off first: DPOS becomes the motor's position
            motor = [float(v[0]) for v in self.axis_raw(group, now)]
            if frame:  # (the new frame checked on them before anything changes)
                transform(frame, self.table(group, frame), motor, forward=True)
            for k, a in enumerate(group.axes):
                physical = motor[k] - group.motor_datum[k]
                axis = m.axes[a]
                axis.steps = math.floor(physical)
                axis.fraction = physical - axis.steps
                axis.datum = group.motor_datum[k]
            group.frame, group.motor_datum, group.near = 0, [], []
        if frame:
            table = self.table(group, frame)
            here = [float(m.demand_counts(a, now)[0]) for a in group.axes]
            raw = [here[k] + m.axes[a].datum for k, a in enumerate(group.axes)]
            world = transform(frame, table, raw, forward=True)  # (checked before any change)
            group.motor_datum = [m.axes[a].datum for a in group.axes]
            for k, a in enumerate(group.axes):
                m.axes[a].datum = world[k] - here[k]  # DPOS: the world position
            group.frame = frame
            group.near = raw
            group.scale = table[0] if frame in (6, 10) else 0.0
        m.changed()

    # ---- the joints' software limits (AXIS_FS_LIMIT, AXIS_RS_LIMIT) ---------------------------
    def joint_limits(self, axis: int) -> tuple[float, float]:
        """(AXIS_FS_LIMIT, AXIS_RS_LIMIT) as they act, in AXIS_UNITS: only in a frame, and
        one beyond REP_DIST is off (pages; the reverse one below -REP_DIST, I)."""
        p = self.m.axes[axis].params
        fs, rs, rep = p["AXIS_FS_LIMIT"], p["AXIS_RS_LIMIT"], p["REP_DIST"]
        return (fs if fs <= rep else math.inf, rs if rs >= -rep else -math.inf)

    def status_bits(self, axis: int) -> int:
        """AXISSTATUS bits 16 / 17 while AXIS_DPOS is beyond AXIS_FS_LIMIT / AXIS_RS_LIMIT."""
        if not self.framed(axis):
            return 0
        fs, rs = self.joint_limits(axis)
        here = self.axis_dpos(axis)
        return (AXIS_FS_BIT if here > fs else 0) | (AXIS_RS_BIT if here < rs else 0)

    def _switches(self, axis: int) -> list[tuple[int, float]]:
        """The joint's limit switches wired through FWD_IN / REV_IN, as (side, the motor
        position, counts, where each begins): FRAME page, they act on the motor (one the
        world drives as a level, or stuck, acts when looked at, drive.py)."""
        m = self.m
        params, stage = m.axes[axis].params, m.world.axes[axis]
        found = []
        for side, name, switch in ((1, "FWD_IN", stage.plus_limit),
                                   (-1, "REV_IN", stage.minus_limit)):
            wired = params[name]
            edge = switch.low if side > 0 else switch.high
            if (0 <= wired < INPUTS and int(wired) not in (*m.world.digital, *m.inverted_inputs)
                    and switch.fault not in (STUCK_ACTIVE, STUCK_INACTIVE) and edge is not None):
                found.append((side, float(edge)))
        return found

    def _running(self, group: FrameGroup) -> list[Run]:
        runs: list[Run] = []
        for a in group.axes:
            queue = self.m.queues[a]
            if queue and queue[0].started and not queue[0].stopping and queue[0] not in runs:
                runs.append(queue[0])
        return runs

    def _outward(self, group: FrameGroup, first: int, last: int) -> int | None:
        """The first tick in first..last on which a joint is beyond its limit and going
        further out (D: moves back from beyond it run), or None."""
        limits = [self.joint_limits(a) for a in group.axes]
        if all(lim == (math.inf, -math.inf) and not self._switches(a)
               for a, lim in zip(group.axes, limits, strict=True)):
            return None
        ticks = np.arange(first - 1, last + 1)
        raw = self.axis_raw(group, ticks)
        found: int | None = None
        for k, a in enumerate(group.axes):
            fs, rs = limits[k]
            pos = raw[k] / self.m.axes[a].params["AXIS_UNITS"]
            step = np.diff(pos)
            out = ((pos[1:] > fs) & (step > 0)) | ((pos[1:] < rs) & (step < 0))
            motor = raw[k][1:] - group.motor_datum[k] - self.m.world.axes[a].lost_steps
            for side, edge in self._switches(a):
                out |= (side * (motor - edge) >= 0) & (side * step > 0)
            if out.any():
                tick = first + int(np.argmax(out))
                found = tick if found is None else min(found, tick)
        return found

    def next_event(self) -> int | None:
        """The tick a joint passes its software limit while its group moves, exact to the
        tick (searched LOOK_AHEAD ticks at a time: none found, looked at again then)."""
        m = self.m
        revision, tick, event = self._looked
        if revision == m.revision and tick == m.tick:
            return event
        event = None
        first = m.tick + 1 if self._acted == m.tick else m.tick
        for group in self.groups.values():
            if not group.frame or not self._running(group):
                continue
            found = self._outward(group, first, m.tick + LOOK_AHEAD)
            if found is None and any(self.joint_limits(a) != (math.inf, -math.inf)
                                     or self._switches(a) for a in group.axes):
                found = m.tick + LOOK_AHEAD  # (look again)
            if found is not None and (event is None or found < event):
                event = found
        self._looked = (m.revision, m.tick, event)
        return event

    def on_event(self, now: int) -> None:
        """A joint passed its limit: every move of its group is cancelled, the running
        ones ramping down at the base's FASTDEC, or DECEL when FASTDEC is 0 (a path
        along itself at its ACCEL), the buffered ones dropped (pages: CANCEL all moves
        on the FRAME_GROUP, I)."""
        m = self.m
        for group in self.groups.values():
            runs = self._running(group) if group.frame else []
            if not runs or self._outward(group, now, now) is None:
                continue
            for run in runs:
                m._stop(run, decel=m.fast_decel(run))
            for a in group.axes:
                queue = m.queues[a]
                while queue and not queue[-1].started:
                    queue.pop()
            m.changed()
        self._looked = (-1, -1, None)
        self._acted = now  # (never the same tick again: no event that acts on nothing)

    # ---- FRAME_GROUP ----------------------------------------------------------------------
    def frame_group(self, group: int, offset: float, axes: Sequence[int]) -> None:
        """FRAME_GROUP(group, table_offset, axes...): define a group, or delete it with
        table_offset -1 (its frame goes off first)."""
        if not 0 <= group < GROUPS or offset != int(offset) or not -1 <= offset < TABLE_SIZE:
            raise ValueError("Parameter out of range")  # (D: an offset inside the TABLE)
        old = self.groups.get(group)
        if offset == -1:
            if axes:
                raise ValueError("Parameter out of range")
            if old is not None:
                self.set_group_frame(old, 0)
                del self.groups[group]
            return
        self.check_axes(axes)
        if not axes or any(b <= a for a, b in zip(axes, axes[1:], strict=False)):
            raise ValueError("Parameter out of range")  # (page: ascending order)
        others = [g for n, g in self.groups.items() if n != group]
        if any(a in g.axes for g in others for a in axes):
            raise ValueError("Parameter out of range")  # (D: an axis in one group only)
        if old is not None:
            self.set_group_frame(old, 0)
        self.groups[group] = FrameGroup(int(offset), tuple(axes))
        self.m.changed()

    def describe(self, group: int) -> str:
        """FRAME_GROUP(group)'s printed line: no USER_FRAME, TOOL_OFFSET or VOLUME_LIMIT
        is modelled, so theirs are the identity ones (page example 3's form)."""
        if not 0 <= group < GROUPS:
            raise ValueError("Parameter out of range")
        g = self.groups.get(group)
        if g is None:
            return f"{group} [-1] :"
        axes = ", ".join(str(a) for a in g.axes)
        zeros = ", ".join(["0.00000"] * 6)
        return (f"{group} [{g.table_offset}] : {axes} {{0:{zeros}}} "
                "TO={0:0.00000, 0.00000, 0.00000} VL={0, 0}")


__all__ = ["GROUPS", "READS", "SIZES", "FrameGroup", "Frames", "to_axes", "to_world",
           "transform"]
