"""The MC405's axes against the world and their drives: limits that stop motion, motion
errors, the drive enable and the Z-mark datum searches.

What a Trio controller does, as docs/trio.md records it (source and confidence there):

- **Limits**: the forward limit is on while FWD_IN's input reads 0 (active low, INVERT_IN
  applied: the machine's `digital_input`) or DPOS is beyond FS_LIMIT (user units); the
  reverse ones REV_IN and RS_LIMIT. A motion reaching one is found
  exactly to the servo tick by the shared machine (`MotionEnds`: a bisection over the
  motion's phases) and cancelled there: the axis ramps down at FASTDEC, or DECEL when
  FASTDEC is 0 (a path along itself at its ACCEL), so it stops a ramp's distance past the
  limit. A move that would start into an active limit is cancelled as it starts (it
  makes no step); moves away from the limit run. AXISSTATUS shows bit 4/5 while the
  switch is active and bit 9/10 while DPOS is beyond the software limit.
  AXIS_MODE bit 14 turns the software limits off (`axismode.py`). An axis whose demand
  a link or ADDAX makes is watched by `linked_limits.py` instead.
- **Motion errors** (`errors.py`): each time the machine looks (every event), an axis
  whose AXISSTATUS gains a bit that its ERRORMASK holds (default 268: following error
  exceeded, remote drive errors) goes into motion error: every axis stops at once (WDOG
  OFF), or only the axes of its DISABLE_GROUP (their AXIS_ENABLE and SERVO OFF). DATUM(0)
  clears every axis's error, DATUM(7) one axis's. While an axis is in error it refuses
  moves.
- **The drive enable**: AXIS_ENABLE OFF disables an axis's drive; a servo axis (ATYPE 36
  or 77, the seed's servo types) also needs WDOG ON and SERVO ON. A move on a disabled
  axis is refused, and a servo axis whose drive goes off while it moves stops at once. A
  pulse/direction axis (ATYPE 43, 35 ...) runs its demand whatever WDOG says (the seed's
  example 1 loads its moves before WDOG=ON).
- **Following error** (`following.py`): a servo axis with gains runs the shared servo
  loop on the world's motor; FE = DPOS - MPOS is compared with FE_LIMIT (bit 8) and
  FE_RANGE (bit 1). Any other axis follows its demand exactly: MPOS = DPOS, FE = 0.
- **DATUM(1)/(2)**: a search forward / reverse at CREEP for the encoder's Z mark (the
  world's index mark of the axis); on the tick the mark is reached DPOS becomes 0 there
  and the axis ramps down at DECEL. DATUM(0) clears the motion errors.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from typing import Any, Protocol

from maxk.firmware_model.axis import MotionAxis, MotionEnds
from maxk.firmware_model.world import STUCK_ACTIVE, STUCK_INACTIVE, Switch, World

from .axismode import compared_position, mpos_compared, soft_limits
from .errors import MotionErrors
from .following import SERVO_ATYPES, Following, MotorHost
from .linked_limits import LinkedLimits
from .runs import Run, TrioAxis
from .stepratio import demand_for


class _Encoders(Protocol):
    def sync_all(self) -> None: ...


class DriveHost(MotorHost, Protocol):
    """What the drive needs of the machine (`MC405Machine`)."""

    axes: list[TrioAxis]
    queues: list[deque[Run]]
    distance_done: list[float]
    system: dict[str, float]
    world: World
    tick: int
    period: float
    revision: int  # counts every change (a parameter, the world, a motion event)
    inverted_inputs: set[int]  # INVERT_IN
    links: Any  # links.LinkedMoves: what a motion error or a limit ends (errors.py)

    @property
    def axis_count(self) -> int: ...
    @property
    def outputs(self) -> _Encoders: ...
    def dpos(self, axis: int) -> float: ...
    def demand(self, axis: int) -> float: ...
    def digital_input(self, number: int) -> bool: ...
    def axis_idle(self, axis: int) -> bool: ...
    def changed(self) -> None: ...
    def move(self, axes: Sequence[int], distances: Sequence[float]) -> None: ...
    def _stop(self, run: Run, decel: float | None = None) -> None: ...
    def _unlink(self, axis: int) -> None: ...
    def own_demand(self, axis: int) -> float: ...
    def fast_decel(self, run: Run) -> float | None: ...

INPUTS = 1024  # inputs a limit or datum may be wired to (as IN: IOSIZE)

# AXISSTATUS bits (manual's axis status table; docs/trio.md)
FE_WARNING = 1 << 1  # |FE| beyond FE_RANGE
REMOTE_COMMS = 1 << 2  # remote drive comms error (never set: no remote drives)
REMOTE_ERROR = 1 << 3  # remote drive error (never set)
FWD_LIMIT = 1 << 4  # in the forward limit (FWD_IN's input on)
REV_LIMIT = 1 << 5  # in the reverse limit
DATUMING = 1 << 6  # a DATUM(1)/(2) search runs
FE_EXCEEDED = 1 << 8  # |FE| beyond FE_LIMIT
FWD_SOFT = 1 << 9  # DPOS beyond FS_LIMIT
REV_SOFT = 1 << 10  # DPOS below RS_LIMIT
ERRORMASK_DEFAULT = FE_EXCEEDED | REMOTE_ERROR | REMOTE_COMMS  # 268

# DRIVE_STATUS: the CiA 402 status word bits an EtherCAT drive reports (I), as far as the
# emulator knows them
READY, SWITCHED_ON, ENABLED, FAULT, VOLTAGE, QUICK_STOP, DISABLED = (1, 2, 4, 8, 16, 32, 64)
TARGET_REACHED, LIMIT_ACTIVE, FOLLOWING = 1 << 10, 1 << 11, 1 << 13

_CAN_SET = FWD_LIMIT | REV_LIMIT | FWD_SOFT | REV_SOFT | DATUMING
"""The AXISSTATUS bits the emulator can set (FE is 0, there are no remote drives)."""
AXIS_READS = frozenset({"AXISSTATUS", "MPOS", "FE", "DRIVE_STATUS"})
SYSTEM_READS = frozenset({"MOTION_ERROR", "ERROR_AXIS"})
_FOREVER = 2.0 ** 50  # counts a Z-mark search may travel (as FORWARD)


class Drive:
    """Limits, motion errors, drive enables and Z-mark searches of one MC405."""

    def __init__(self, machine: DriveHost) -> None:
        self.m = machine
        self.limits = _Limits(self)
        self.errors = MotionErrors(self)  # (errors.py)
        self.linked = LinkedLimits(self)  # limits on linked axes (linked_limits.py)
        self.following = Following(machine, self.enabled,
                                   lambda axis: bool(self.motion_error >> axis & 1))
        self.reset()

    def reset(self) -> None:
        """Power-up: no errors, no searches (the axes are new)."""
        self.linked.reset()
        self.errors.reset()  # MOTION_ERROR, ERROR_AXIS, the bits held, DISABLE_GROUP
        self.look_again: int | None = None  # the cycle after a limit's cancel (below)
        self.searches: dict[int, tuple[int, Run]] = {}  # axis -> a Z-mark search's
        # direction and its run (the FORWARD/REVERSE at CREEP)
        self.following.reset()
        self.limits.reset(self.m.axes)

    # ---- what the language reads -----------------------------------------------------
    def axis_parameter(self, name: str, axis: int) -> float:
        if name == "AXISSTATUS":
            return float(self.axis_status(axis))
        if name in ("MPOS", "FE"):
            a = self.m.axes[axis]
            fe = self.following.error_counts(axis) / a.units  # 0: profile-only
            return self.m.dpos(axis) - fe if name == "MPOS" else self.following.shown(axis, fe)
        return float(self.drive_status(axis))

    @property
    def motion_error(self) -> int:
        return self.errors.motion_error

    def system_parameter(self, name: str) -> float:
        errors = self.errors
        return float(errors.motion_error if name == "MOTION_ERROR" else errors.error_axis)

    def axis_status(self, axis: int) -> int:
        m = self.m
        params = m.axes[axis].params
        bits = self.errors.latched[axis]
        for name, bit in (("FWD_IN", FWD_LIMIT), ("REV_IN", REV_LIMIT)):
            wired = params[name]
            if 0 <= wired < INPUTS and not m.digital_input(int(wired)):
                bits |= bit
        dpos, (fs, rs) = compared_position(self, axis), soft_limits(params)  # (bits 8, 14)
        if dpos > fs:
            bits |= FWD_SOFT
        if dpos < rs:
            bits |= REV_SOFT
        if self.searching(axis) is not None:
            bits |= DATUMING
        fe = self.following.checked_error(axis) / m.axes[axis].units
        if self.following.beyond_limit(axis, fe) or self.following.tripped(axis):
            bits |= FE_EXCEEDED
        if params["FE_RANGE"] > 0 and abs(fe) > params["FE_RANGE"]:
            bits |= FE_WARNING
        return bits

    def settable(self, axis: int) -> int:
        """The AXISSTATUS bits that can be set on the axis (FE only with a servo loop)."""
        servo = self.m.axes[axis].servo is not None
        return _CAN_SET | FE_EXCEEDED | FE_WARNING if servo else _CAN_SET

    def drive_status(self, axis: int) -> int:
        """DRIVE_STATUS: the CiA 402 status word of the axis's drive as the emulator knows
        it (enabled or disabled, fault while in motion error, target reached when idle,
        internal limit while a limit bit is set)."""
        word = VOLTAGE
        word |= (READY | SWITCHED_ON | ENABLED | QUICK_STOP) if self.enabled(axis) else DISABLED
        if self.motion_error >> axis & 1:
            word |= FAULT
        if self.m.axis_idle(axis):
            word |= TARGET_REACHED
        status = self.axis_status(axis)
        if status & (FWD_LIMIT | REV_LIMIT | FWD_SOFT | REV_SOFT):
            word |= LIMIT_ACTIVE
        if status & FE_EXCEEDED:
            word |= FOLLOWING
        return word

    def enabled(self, axis: int) -> bool:
        """Is the axis's drive enabled (see the module docstring)?"""
        params = self.m.axes[axis].params
        override = params.get("AXIS_ENABLE_OVERRIDE", 0.0) != 0  # for WDOG, AXIS_ENABLE (C)
        servo_on = (self.m.system["WDOG"] != 0 or override) and params["SERVO"] != 0
        return (params["AXIS_ENABLE"] != 0 or override) and (
            servo_on or int(params["ATYPE"]) not in SERVO_ATYPES)

    # ---- moves -----------------------------------------------------------------------
    def check_move(self, axes: tuple[int, ...]) -> None:
        """Refuse a move on an axis in motion error or with its drive disabled (before
        anything is loaded)."""
        for a in axes:
            if self.motion_error >> a & 1:
                raise ValueError("Axis in error")
            if not self.enabled(a):
                raise ValueError("Axis not enabled")

    def started(self, run: Run) -> None:
        """A run has just started: cancel it where it starts if it moves an axis into a
        limit that is active (it makes no step)."""
        m = self.m
        for k, a in enumerate(run.axes):
            delta = run.deltas[0][k]
            if delta and self._into_limit(a, 1 if delta > 0 else -1):
                m._stop(run)
                return

    def _into_limit(self, axis: int, direction: int) -> bool:
        """Is a limit ahead of a run starting now on (the axis stands on its `steps`)?"""
        m = self.m
        a = m.axes[axis]
        params = a.params
        wired = params["FWD_IN" if direction > 0 else "REV_IN"]
        if 0 <= wired < INPUTS and not m.digital_input(int(wired)):
            return True
        dpos, (fs, rs) = compared_position(self, axis), soft_limits(params)  # (AXIS_MODE)
        return dpos > fs if direction > 0 else dpos < rs

    def datum(self, axis: int, mode: int) -> None:
        """DATUM(0) clears every motion error, DATUM(7) the axis's (errors.py); DATUM(1)/(2)
        start a Z-mark search forward / reverse at CREEP."""
        m = self.m
        if mode in (0, 7):
            self.errors.clear(None if mode == 0 else axis)
            m.changed()
            return
        if mode not in (1, 2):
            raise ValueError("Parameter out of range")
        params = m.axes[axis].params
        if not params["CREEP"] > 0:
            raise ValueError("Parameter out of range")
        direction = 1 if mode == 1 else -1
        speed = params["SPEED"]
        params["SPEED"] = params["CREEP"]
        try:
            m.move([axis], [_FOREVER / params["UNITS"] * direction])
        finally:
            params["SPEED"] = speed
        self.searches[axis] = (direction, m.queues[axis][-1])
        m.changed()

    def searching(self, axis: int) -> int | None:
        """The direction of the Z-mark search the axis runs now (None: none running; a
        search whose run has ended or is stopping is forgotten)."""
        found = self.searches.get(axis)
        if found is None:
            return None
        direction, run = found
        queue = self.m.queues[axis]
        if run not in queue or run.stopping:
            del self.searches[axis]
            return None
        running = queue[0] is run and run.started and self.m.axes[axis].motion is not None
        return direction if running else None

    # ---- the limits, for the shared machine ----------------------------------------------
    def limit_at(self, axis: MotionAxis, side: int) -> float | None:
        """The physical position of the first limit of that side the axis meets: its limit
        switch (through FWD_IN/REV_IN) or its software limit; None while its run is already
        stopping (a stop is never lengthened) or for none."""
        m = self.m
        queue = m.queues[axis.index]
        if not queue or queue[0].stopping or self.linked.covers(axis.index):
            return None  # (an axis whose demand a link adds to: linked_limits.py)
        found = self.edges(axis.index, side, dpos=False)
        reach = queue[0].length() + 1.0  # no axis of a run travels further than its path
        found = [edge for edge in found if side * (edge - axis.steps) <= reach]
        if not found:
            return None
        return min(found) if side > 0 else max(found)

    def edges(self, axis: int, side: int, dpos: bool) -> list[float]:
        """The demand counts (DEFPOS not applied) from which that side's limits act: the
        limit switch through FWD_IN/REV_IN (one the world drives as an edge) and the
        software limit (unless it compares MPOS and `dpos` is False)."""
        m = self.m
        a = m.axes[axis]
        params = a.params
        found: list[float] = []
        wired = -1 if m.framed(axis) else params["FWD_IN" if side > 0 else "REV_IN"]
        if 0 <= wired < INPUTS and int(wired) not in (*m.world.digital, *m.inverted_inputs):
            stage = m.world.axes[axis]  # (a joint in a FRAME: frames.py finds it)
            switch = stage.plus_limit if side > 0 else stage.minus_limit
            edge = _edge(switch, side)
            found += [] if edge is None else [demand_for(params, edge + stage.lost_steps, side)]
        soft = soft_limits(params)[0 if side > 0 else 1] * a.units - a.datum
        if abs(soft) < 2.0 ** 62 and (dpos or not mpos_compared(params, a.servo is not None)):
            found.append(math.ceil(soft) if side > 0 else math.floor(soft))
        return found

    def limit_key(self, axis: MotionAxis) -> tuple[object, ...]:
        """What the limits an axis meets depend on besides its motion."""
        m = self.m
        i = axis.index
        a = m.axes[i]
        p = a.params
        stage = m.world.axes[i]
        queue = m.queues[i]
        return (p["FWD_IN"], p["REV_IN"], soft_limits(p), a.units, a.datum,
                stage.plus_limit, stage.plus_limit.fault, stage.minus_limit,
                stage.minus_limit.fault, stage.lost_steps, bool(queue and queue[0].stopping),
                frozenset(m.world.digital), frozenset(m.inverted_inputs),
                self.linked.covers(i))

    def on_limit(self, axis: MotionAxis, side: int, tick: int) -> None:
        """A motion reached a limit: cancel the run there (a single axis ramps down at
        FASTDEC, or DECEL when FASTDEC is 0; a path at its ACCEL)."""
        m = self.m
        queue = m.queues[axis.index]
        if not queue or not queue[0].started:
            return
        m.outputs.sync_all()
        self._cancel_for_limit(queue[0])
        self.searches.pop(axis.index, None)
        m.changed()

    def _cancel_for_limit(self, run: Run) -> None:
        m = self.m
        self.look_again = m.tick + 1  # (DPOS passes FS_LIMIT/RS_LIMIT, AXISSTATUS bits
        # 9/10, on the ramp's first cycle: a motion error on them acts on that cycle)
        m._stop(run, decel=m.fast_decel(run))

    # ---- what the machine looks at on every change ------------------------------------------
    def look(self, now: int) -> None:
        """At a limit or Z-mark event, and when a command or the world changed something
        (the machine calls it then): Z marks reached, limits driven as inputs, drives
        switched off under a servo axis, motion errors."""
        m = self.m
        changed = False
        self.following.configure()
        for axis in list(self.searches):
            direction = self.searching(axis)
            if direction is None:
                continue
            a = m.axes[axis]
            queue = m.queues[axis]
            mark = self.mark_position(axis, direction)
            if mark is not None and direction * (a.steps_now(m) - mark) >= 0:
                m.outputs.sync_all()
                a.datum = -mark  # DPOS is 0 on the mark
                m._stop(queue[0])
                del self.searches[axis]
                changed = True
        for i, a in enumerate(m.axes):
            queue = m.queues[i]
            if a.link is not None and not self.enabled(i):
                self.errors.halt([i])  # a linked axis's drive went off: its link ends
                changed = True
                continue
            if a.motion is None or not queue or not queue[0].started or queue[0].stopping:
                continue
            if not self.enabled(i):
                self.errors.halt([i])
                changed = True
                continue
            direction = a.travel_direction(m)
            if self._level_limit(i, direction):
                m.outputs.sync_all()
                self._cancel_for_limit(queue[0])
                changed = True
        if self.linked.look(now):
            changed = True
        if self.errors.check():
            changed = True
        if changed:
            m.changed()

    def following_error(self) -> None:
        """The servo loops stopped on a following error (`Following.integrate`): its bit
        holds, and a motion error follows if ERRORMASK has it."""
        for axis in self.following.over:
            self.errors.latched[axis] |= FE_EXCEEDED
            loop = self.m.axes[axis].servo
            if loop is not None and loop.trip_tick is not None:
                loop.trip_tick = None  # (the loop stays tripped until DATUM(0))
                loop.tripped = True
        self.following.over = []
        self.look(self.m.tick)

    def _level_limit(self, axis: int, direction: int) -> bool:
        """A limit input the world drives as a level (or a stuck switch) that is on
        ahead of the axis: it acts when next looked at."""
        m = self.m
        params = m.axes[axis].params
        wired = params["FWD_IN" if direction > 0 else "REV_IN"]
        if not 0 <= wired < INPUTS:
            return False
        stage = m.world.axes[axis]
        switch = stage.plus_limit if direction > 0 else stage.minus_limit
        if int(wired) in (*m.world.digital, *m.inverted_inputs) or switch.fault == STUCK_ACTIVE:
            return not m.digital_input(int(wired))
        return False

    # ---- Z marks ----------------------------------------------------------------------
    def mark_tick(self, axis: int, direction: int) -> int | None:
        """The tick the running search reaches its Z mark: now if it has (None: never)."""
        mark = self.mark_position(axis, direction)
        if mark is None:
            return None
        a = self.m.axes[axis]
        if direction * (a.steps_now(self.m) - mark) >= 0:  # type: ignore[arg-type]
            return self.m.tick
        return a.tick_reaching(mark, direction, self.m)  # type: ignore[arg-type]

    def mark_position(self, axis: int, direction: int) -> int | None:
        """Where (physical counts) the running search meets the first Z mark count ahead
        of where it started: the mark's first count forward, its last in reverse."""
        m = self.m
        a = m.axes[axis]
        stage = m.world.axes[axis]
        period, width, offset = stage.index_period, stage.index_width, stage.index_offset
        if period <= 0 or width <= 0 or a.motion is None:
            return None
        here = a.steps_at_tick(a.motion_start, m.period) - stage.lost_steps
        if direction > 0:  # the mark's first count, ahead
            mark = offset + math.floor((here - offset) / period + 1) * period
        else:  # its last count, behind
            top = offset + width - 1
            mark = top - math.floor((top - here) / period + 1) * period
        return mark + stage.lost_steps


def _edge(switch: Switch, side: int) -> float | None:
    """Where a limit switch begins as the axis travels towards it (None: none, or a switch
    that a fault holds: a stuck-active one acts as a level, see `_level_limit`)."""
    if switch.fault in (STUCK_ACTIVE, STUCK_INACTIVE):
        return None
    return switch.low if side > 0 else switch.high


class _Limits(MotionEnds):
    """The shared machine's limit search for the MC405's axes, and the Z marks of the
    searches running (the drive looks on each of its events)."""

    def __init__(self, drive: Drive) -> None:
        super().__init__(drive.m.axes, drive.m, limit_at=drive.limit_at,
                         on_limit=drive.on_limit)
        self.drive = drive
        self._keys: dict[int, tuple[object, ...]] = {}
        self._revisions: dict[int, int] = {}  # per axis: the machine's revision at its key

    def reset(self, axes: list) -> None:  # type: ignore[type-arg]
        self.axes = axes
        self._limit.clear()
        self._keys.clear()
        self._revisions.clear()

    def _limit_tick(self, axis: MotionAxis) -> tuple[int | None, int]:
        revision = self.drive.m.revision  # (what the key holds changes only with it)
        if self._revisions.get(axis.index) != revision:
            self._revisions[axis.index] = revision
            key = self.drive.limit_key(axis)
            if self._keys.get(axis.index) != key:
                self._keys[axis.index] = key
                self._limit.pop(axis.index, None)
        return super()._limit_tick(axis)

    def next_event(self) -> int | None:
        soonest = super().next_event()
        again = self.drive.look_again
        if again is not None and (soonest is None or again < soonest):
            soonest = max(again, self.drive.m.tick)
        linked = self.drive.linked.next_event()
        if linked is not None and (soonest is None or linked < soonest):
            soonest = linked
        for axis in list(self.drive.searches):
            direction = self.drive.searching(axis)
            mark = None if direction is None else self.drive.mark_tick(axis, direction)
            if mark is not None and (soonest is None or mark < soonest):
                soonest = mark
        return soonest

    def on_event(self, now: int) -> None:
        super().on_event(now)
        if self.drive.look_again is not None and self.drive.look_again <= now:
            self.drive.look_again = None
        self.drive.look(now)
