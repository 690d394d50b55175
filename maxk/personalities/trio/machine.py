"""The MC405 on the shared engine: axes, buffered moves, linked axes and PWM outputs.

`MC405Machine` is an `Engine` whose tick is one servo cycle (SERVO_PERIOD, 1000 us by
default) and implements what TrioBASIC needs of a controller (the language's
`TrioMachine` protocol, structurally). Moves are runs of the shared machine
(`runs.py`); the engine jumps from event to event (a run ends, a CAMBOX ends, a gate
position is passed), and everything between is closed form:

- PWM modes 2 and 8: the mark is a `ComputedOutput` of the link axis's VP_SPEED and the
  amplitude axis's DPOS, evaluated at whatever servo tick it is read, traced or plotted.
- The gating FIFO: the head entry is a `PositionTrigger` on its axis; `trigger_ticks`
  finds the exact tick the axis passes it (bisection), and the gate toggles there.
- PWM_ENCODER follows the axis's whole counts and ignores DEFPOS.

`revision` counts every change a waiting program could notice; the process scheduler
of the language uses it to wake WAIT IDLE and full-buffer waits.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from maxk.firmware_model.axis import MotionAxis
from maxk.firmware_model.engine import Engine
from maxk.firmware_model.outputs import ComputedOutput, PositionTrigger, trigger_ticks
from maxk.firmware_model.profiles import plan_stop as profile_stop

from .memory import TableMemory, VrMemory
from .pwm import PWM_ATYPES, GateEntry, PwmBank, PwmError, PwmMode, PwmOutput
from .runs import (
    SHAPE,
    Cambox,
    Connpath,
    Link,
    PlanArrays,
    Run,
    profile_offset_speed,
    single_profile,
)
from .trace import PwmTrace

MOVE_BUFFER = 16  # moves an axis holds, running and buffered (D)
SERVO_PERIODS = (250, 500, 1000, 2000)
AXIS_COUNT = 16  # axes 0-4 on the board, 5-15 virtual (D)
_PWM_PARAMETERS = frozenset({"PWM_CYCLE", "PWM_MARK", "PWM_ENCODER"})
_COMPUTED = frozenset({"DPOS", "MPOS", "VP_SPEED"})


@dataclass
class TrioAxis(MotionAxis):
    """One axis: the shared kinematics plus what the MC405 keeps per axis."""

    params: dict[str, float] = field(default_factory=dict)
    fraction: float = 0.0  # demand beyond `steps` at rest (a linked axis stops anywhere)
    datum: float = 0.0  # DEFPOS: DPOS = (demand counts + datum) / UNITS
    link: Link | None = None
    pending_link: Link | None = None  # CONNPATH/CAMBOX loaded behind buffered moves
    link_end: int | None = None  # CAMBOX: the tick it completes (cached per revision)

    @property
    def units(self) -> float:
        return self.params["UNITS"]


@dataclass(frozen=True)
class GateEdge:
    """The gate of a PWM output toggled: at this servo tick, to this level."""

    tick: int
    axis: int
    level: bool
    position: int  # the FIFO entry (PWM_ENCODER counts)


class MC405Machine(Engine):
    """The MC405's firmware on the shared engine (one tick = one servo cycle)."""

    def __init__(self, axis_defaults: Mapping[str, float], system_defaults: Mapping[str, float],
                 axis_count: int = AXIS_COUNT) -> None:
        self._axis_defaults = dict(axis_defaults)
        self._system_defaults = dict(system_defaults)
        self._axis_count = axis_count
        period = int(self._system_defaults.get("SERVO_PERIOD", 1000))
        super().__init__(1e6 / period)
        self.revision = 0
        self.gate_edges: list[GateEdge] = []
        self.tracer: PwmTrace | None = None
        self._power_up()
        self.add_source(_MotionEvents(self))
        self.add_source(_GateEvents(self))

    def _power_up(self) -> None:
        """Parameters, motion, PWM, TABLE and VR as at power-up (time goes on)."""
        self.system = dict(self._system_defaults)
        self.axes = [TrioAxis(i, str(i), params=dict(self._axis_defaults))
                     for i in range(self._axis_count)]
        self.queues: list[deque[Run]] = [deque() for _ in range(self._axis_count)]
        self.distance_done = [0.0] * self._axis_count  # path distance per base, user units
        self.pwm = PwmBank(self._axis_count)
        self.table = TableMemory()
        self.vr = VrMemory()
        self.computed: dict[int, ComputedOutput] = {}
        self._encoder_counts: dict[int, int] = {a: 0 for a in self.pwm.outputs}
        for output in self.pwm.outputs.values():
            output.on_gate = self._gate_fired
        self._changed()

    def restart(self) -> None:
        """EX: the controller restarts; a new SERVO_PERIOD takes effect now."""
        period = int(self.system.get("SERVO_PERIOD", 1000))
        self._system_defaults["SERVO_PERIOD"] = period
        if abs(self.period - period / 1e6) > 1e-12:
            self.change_update_rate(1e6 / period)
        self._power_up()

    def _changed(self) -> None:
        self.revision += 1

    # ---- the engine's hooks: traces see every servo cycle ---------------------------------
    def integrate(self, limit: int) -> bool:
        if self.tracer is not None and limit > self.tick:
            self.tracer.stretch(self.tick + 1, limit)
        return False

    def after_events(self, now: int) -> None:
        if self.tracer is not None:
            self.tracer.at_event(now)

    def trace(self, pwm_axes: tuple[int, ...] = (4,), xy: tuple[int, int] = (0, 1)) -> PwmTrace:
        """Record every servo cycle from now on (the XY path and the PWM outputs)."""
        self.tracer = PwmTrace(self, pwm_axes, xy)
        self.tracer.at_event(self.tick)
        return self.tracer

    # ---- the TrioMachine protocol -----------------------------------------------------------
    @property
    def axis_count(self) -> int:
        return self._axis_count

    def servo_tick(self) -> int:
        return self.tick

    def servo_period_us(self) -> int:
        return round(self.period * 1e6)

    def axis_parameter(self, name: str, axis: int) -> float:
        if name in _PWM_PARAMETERS:
            output = self.pwm[axis]
            if name == "PWM_CYCLE":
                return output.cycle
            if name == "PWM_MARK":
                return self.mark(axis)
            self._sync_encoder(axis)
            return output.encoder
        if name in ("DPOS", "MPOS"):  # MPOS = DPOS: no following error is modelled (D)
            return self.dpos(axis)
        if name == "VP_SPEED":
            return self.vp_speed(axis)
        return self.axes[axis].params[name]

    def set_axis_parameter(self, name: str, axis: int, value: float) -> None:
        if name == "PWM_CYCLE":
            self.pwm[axis].set_cycle(value)
        elif name == "PWM_MARK":
            self.pwm[axis].set_mark(value)
        elif name in _COMPUTED or name not in self.axes[axis].params:
            raise ValueError("Parameter is read only")
        else:
            self.axes[axis].params[name] = value
        self._changed()

    def system_parameter(self, name: str) -> float:
        return self.system[name]

    def set_system_parameter(self, name: str, value: float) -> None:
        if name == "SERVO_PERIOD" and value not in SERVO_PERIODS:
            raise ValueError("Parameter out of range")
        self.system[name] = value  # SERVO_PERIOD: from the next restart (EX)
        self._changed()

    def can_load(self, axes: Sequence[int]) -> bool:
        return all(self._buffered(a) < MOVE_BUFFER and self.axes[a].link is None
                   and self.axes[a].pending_link is None for a in axes)

    def _buffered(self, axis: int) -> int:
        return sum(run.moves_left(self.tick, self.period) for run in self.queues[axis])

    def move(self, axes: Sequence[int], distances: Sequence[float]) -> None:
        deltas = [round(d * self.axes[a].units) for a, d in zip(axes, distances, strict=True)]
        self._load(tuple(axes), deltas)

    def move_abs(self, axes: Sequence[int], positions: Sequence[float]) -> None:
        deltas = []
        for a, p in zip(axes, positions, strict=True):
            axis = self.axes[a]
            target = round(p * axis.units) - axis.datum  # physical counts
            deltas.append(round(target - self._end_counts(a)))
        self._load(tuple(axes), deltas)

    def axis_idle(self, axis: int) -> bool:
        a = self.axes[axis]
        return not self.queues[axis] and a.link is None and a.pending_link is None

    def defpos(self, axes: Sequence[int], positions: Sequence[float]) -> None:
        for a, p in zip(axes, positions, strict=True):
            axis = self.axes[a]
            axis.datum = p * axis.units - self.demand(a)  # DPOS reads p from now
        self._changed()

    def set_acc(self, axis: int, rate: float) -> None:
        params = self.axes[axis].params
        params["ACCEL"] = params["DECEL"] = rate
        self._changed()

    def cancel(self, axis: int) -> None:
        a = self.axes[axis]
        if a.link is not None or a.pending_link is not None:
            self._unlink(axis)
        elif self.queues[axis] and self.queues[axis][0].started:
            self._stop(self.queues[axis][0])
        self._changed()

    def rapidstop(self) -> None:
        for axis in range(self._axis_count):
            queue = self.queues[axis]
            while queue and not queue[-1].started:
                queue.pop()
            if self.axes[axis].link is not None or self.axes[axis].pending_link is not None:
                self._unlink(axis)
        for queue in self.queues:
            if queue and queue[0].started and not queue[0].stopping:
                self._stop(queue[0])
        self._changed()

    def connpath(self, axis: int, args: Sequence[float]) -> None:
        base = args[0]
        if base != int(base) or not 0 <= base < self._axis_count or int(base) == axis:
            raise ValueError("Invalid axis number")
        ratio = args[1] if len(args) > 1 else 1.0
        link = Connpath(int(base), ratio, 0.0, 0.0)
        self._link(axis, link)

    def cambox(self, axis: int, args: Sequence[float]) -> None:
        start, end, multiplier, distance, link_axis = args[:5]
        if len(args) > 5 and args[5] != 0:
            raise ValueError("CAMBOX options are not supported")
        if link_axis != int(link_axis) or not 0 <= link_axis < self._axis_count \
                or int(link_axis) == axis:
            raise ValueError("Invalid axis number")
        if distance <= 0 or start != int(start) or end != int(end) or end <= start:
            raise ValueError("Parameter out of range")
        values = np.array(self.table.read_run(int(start), int(end)))
        self._link(axis, Cambox(values, multiplier, distance, int(link_axis), 0.0, 0.0))

    def pwm_control(self, axis: int, args: Sequence[float]) -> None:
        output = self.pwm[axis]
        self._sync_encoder(axis)
        if output.computed:
            output.load_mark(self.mark(axis))  # the last loaded mark stays when the mode goes
        output.control(args, self.table, self.axes[axis].units, self._axis_count)
        self._link_mark(axis, output)
        self._changed()

    def table_read(self, index: int) -> float:
        return self.table.read(index)

    def table_write(self, start: int, values: Sequence[float]) -> None:
        self.table.write(start, values)
        self._changed()

    def vr_read(self, index: int) -> float:
        return self.vr.read(index)

    def vr_write(self, index: int, value: float) -> None:
        self.vr.write(index, value)
        self._changed()

    # ---- loading moves -------------------------------------------------------------------------
    def _end_counts(self, axis: int) -> float:
        """Where the axis stands once its buffered moves are done (physical counts)."""
        position = self.demand(axis)
        for run in self.queues[axis]:
            k = run.axes.index(axis)
            if run.started and run.profile is None and run.plan is not None:
                position = float(round(run.segments[-1].end[k])) if run.segments else position
            elif run.started and run.profile is not None:
                position = float(self.axes[axis].steps + run.profile.final_offset) \
                    if self.axes[axis].motion is not None else position
            else:
                position += sum(delta[k] for delta in run.deltas)
        return position

    def _load(self, axes: tuple[int, ...], deltas: list[int]) -> None:
        base = self.axes[axes[0]]
        speed = base.params["SPEED"] * base.units
        accel = base.params["ACCEL"] * base.units
        decel = base.params["DECEL"] * base.units
        if speed <= 0 or accel <= 0 or decel <= 0:
            raise ValueError("Parameter out of range")
        merge = base.params["MERGE"] != 0
        last = self.queues[axes[0]][-1] if self.queues[axes[0]] else None
        if (merge and last is not None and last.axes == axes and last.mergeable
                and all(self.queues[a] and self.queues[a][-1] is last for a in axes)):
            last.deltas.append(tuple(deltas))
            last.speeds.append(speed)
            last.accels.append(accel)
            if last.started:
                last.resolve(())
                self._apply_plan(last, last.plan_new(self.tick, period=self.period))
            self._changed()
            return
        run = Run(axes, [tuple(deltas)], [speed], [accel], decel, base.units,
                  single=len(axes) == 1 and not merge)
        for a in axes:
            self.queues[a].append(run)
        self._start_ready()
        self._changed()

    def _start_ready(self) -> None:
        """Start every run at the head of all its axes' queues whose axes are free."""
        for queue in self.queues:
            run = queue[0] if queue else None
            if run is None or run.started:
                continue
            if all(self.queues[a][0] is run and self.axes[a].link is None
                   and self.axes[a].pending_link is None for a in run.axes):
                self._start(run)

    def _start(self, run: Run) -> None:
        now = self.tick
        run.started = True
        run.start_tick = now
        for a in run.axes:  # a linked axis that stopped between counts starts from a count
            axis = self.axes[a]
            axis.steps, axis.fraction = round(axis.steps + axis.fraction), 0.0
        if run.single:
            axis = self.axes[run.base]
            run.profile = single_profile(run.deltas[0][0], run.speeds[0], run.accels[0],
                                         run.decel)
            axis.begin(run.profile, self)
            run.end_tick = axis.motion_end if axis.motion_end is not None else now
            return
        run.resolve(tuple(float(self.axes[a].steps) for a in run.axes))
        self._apply_plan(run, run.plan_new(now, period=self.period))

    def _apply_plan(self, run: Run, plan: object) -> None:
        from maxk.firmware_model.path import PathPlan

        assert isinstance(plan, PathPlan)
        now = self.tick
        run.plan = plan
        run.arrays = PlanArrays(plan)
        run.plan_tick = now
        end = plan.end_time if plan.end_time is not None else 0.0
        run.end_tick = now + math.ceil(end / self.period - 1e-9)
        for k, a in enumerate(run.axes):
            axis = self.axes[a]
            axis.steps = axis.steps_at_tick(now, self.period)
            axis.begin(run.motion_for(plan, k, axis.steps), self)

    def _stop(self, run: Run) -> None:
        """CANCEL: ramp down now (a path along itself at its ACCEL, a single axis at
        DECEL); the moves buffered behind it then run."""
        run.stopping = True
        if run.profile is not None:
            axis = self.axes[run.base]
            residual, velocity = axis.freeze(self)
            run.profile = profile_stop(residual, velocity, 0.0, run.decel, SHAPE)
            run.start_tick = self.tick
            axis.begin(run.profile, self)
            run.end_tick = axis.motion_end if axis.motion_end is not None else self.tick
            run.deltas = run.deltas[:1]
            return
        self._apply_plan(run, run.plan_new(self.tick, stop=True, period=self.period))
        run.deltas = run.deltas[:len(run.segments)]

    def _finish_runs(self, now: int) -> None:
        for queue in self.queues:
            run = queue[0] if queue else None
            if run is None or not run.started or run.end_tick > now:
                continue
            for a in run.axes:
                axis = self.axes[a]
                if axis.motion is not None:
                    axis.finish_motion()
                self.queues[a].popleft()
            self.distance_done[run.base] += run.length() / run.units
        for a, axis in enumerate(self.axes):
            if axis.pending_link is not None and not self.queues[a]:
                link, axis.pending_link = axis.pending_link, None
                self._attach(a, link)
        self._start_ready()

    # ---- linked axes --------------------------------------------------------------------------
    def _link(self, axis: int, link: Link) -> None:
        a = self.axes[axis]
        if self.queues[axis]:
            a.pending_link = link  # it starts when the buffered moves are done
        else:
            self._attach(axis, link)
        self._changed()

    def _attach(self, axis: int, link: Link) -> None:
        link.origin = self.demand(axis)
        if isinstance(link, Connpath):
            link.distance0 = float(self.path_distance(link.base, self._now())[0])
        else:
            link.link_origin = self.dpos(link.link)
        self.axes[axis].link = link

    def _unlink(self, axis: int) -> None:
        a = self.axes[axis]
        if a.link is not None:
            position = self.demand(axis)
            a.link = None
            a.steps = math.floor(position)
            a.fraction = position - a.steps
        a.pending_link = None
        a.link_end = None

    # ---- positions and speeds, on arrays of ticks -----------------------------------------------
    def _now(self) -> np.ndarray:
        return np.array([self.tick])

    def demand_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """The exact demand position (physical counts, DEFPOS not applied) at ticks
        between now and the next event."""
        a = self.axes[axis]
        link = a.link
        if isinstance(link, Connpath):
            travelled = self.path_distance(link.base, ticks) - link.distance0
            return link.origin + link.ratio * travelled * a.units
        if isinstance(link, Cambox):
            return link.counts(self.dpos_at(link.link, ticks) - link.link_origin)
        m = a.motion
        if m is None:
            return np.full(ticks.shape, a.steps + a.fraction)
        run = self.queues[axis][0]
        if run.profile is not None:
            offset, _speed = profile_offset_speed(run.profile,
                                                  (ticks - a.motion_start) * self.period)
            position = a.steps + offset
        else:
            assert run.arrays is not None
            s, _v = run.arrays.state((ticks - run.plan_tick) * self.period)
            position = run.arrays.point(s, run.axes.index(axis))
        if a.motion_end is not None:
            position = np.where(ticks >= a.motion_end, float(a.steps + m.final_offset),
                                position)
        return position

    def dpos_at(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        a = self.axes[axis]
        return (self.demand_counts(axis, ticks) + a.datum) / a.units

    def path_distance(self, base: int, ticks: np.ndarray) -> np.ndarray:
        """The path distance (base user units) every run based on `base` has made."""
        done = self.distance_done[base]
        queue = self.queues[base]
        run = queue[0] if queue else None
        if run is None or not run.started or run.base != base:
            return np.full(ticks.shape, done)
        s, _v = run.distance_speed(ticks, self.period)
        return done + s / run.units

    def vp_speed_at(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """VP_SPEED: the path speed of the run the axis takes part in (every axis of an
        interpolated group reads the group's path speed, I), in the base's user units."""
        a = self.axes[axis]
        link = a.link
        if isinstance(link, Connpath):
            return abs(link.ratio) * self.path_speed(link.base, ticks)
        if isinstance(link, Cambox):
            travelled = self.dpos_at(link.link, ticks) - link.link_origin
            return np.abs(link.slope(travelled)) * self.vp_speed_at(link.link, ticks) / a.units
        queue = self.queues[axis]
        run = queue[0] if queue else None
        if run is None or not run.started:
            return np.zeros(ticks.shape)
        _s, v = run.distance_speed(ticks, self.period)
        return v / run.units

    def path_speed(self, base: int, ticks: np.ndarray) -> np.ndarray:
        queue = self.queues[base]
        run = queue[0] if queue else None
        if run is None or not run.started or run.base != base:
            return np.zeros(ticks.shape)
        return run.distance_speed(ticks, self.period)[1] / run.units

    def demand(self, axis: int) -> float:
        return float(self.demand_counts(axis, self._now())[0])

    def dpos(self, axis: int) -> float:
        return float(self.dpos_at(axis, self._now())[0])

    def vp_speed(self, axis: int) -> float:
        return float(self.vp_speed_at(axis, self._now())[0])

    def counts_at(self, axis: int, tick: int) -> int:
        """Whole counts the axis has made (what PWM_ENCODER counts)."""
        a = self.axes[axis]
        if a.link is not None:
            return math.floor(float(self.demand_counts(axis, np.array([tick]))[0]))
        return a.steps_at_tick(tick, self.period)

    # ---- PWM ---------------------------------------------------------------------------------
    def _link_mark(self, axis: int, output: PwmOutput) -> None:
        """Modes 2 and 8: the mark is a computed output of VP_SPEED (x DPOS)."""
        if not output.computed:
            self.computed.pop(axis, None)
            return
        speed_axis, amplitude_axis = output.links
        assert speed_axis is not None

        def speed(tick: int) -> float:
            return float(self.vp_speed_at(speed_axis, np.array([tick]))[0])

        def amplitude(tick: int) -> float:
            if amplitude_axis is None:
                return 1.0
            return float(self.dpos_at(amplitude_axis, np.array([tick]))[0])

        self.computed[axis] = ComputedOutput(output.computed_mark, speed, amplitude)

    def mark(self, axis: int) -> int:
        """PWM_MARK now: the register, or in modes 2/8 the mark this servo cycle loaded."""
        output = self.pwm[axis]
        computed = self.computed.get(axis)
        if computed is not None:
            output.load_mark(int(computed.value_at(self.tick)))
        return output.mark

    def marks_at(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """The mark of every servo cycle in `ticks` (between now and the next event)."""
        output = self.pwm[axis]
        if axis not in self.computed:
            return np.full(ticks.shape, output.mark, dtype=np.int64)
        speed_axis, amplitude_axis = output.links
        assert speed_axis is not None
        speed = self.vp_speed_at(speed_axis, ticks)
        if output.mode is PwmMode.SPEED_PROFILE and amplitude_axis is not None:
            value = speed * self.dpos_at(amplitude_axis, ticks) * output.multiplier \
                + output.offset
        else:
            value = speed * output.multiplier + output.offset
        value = np.minimum(value, output.limit)
        value = np.where(np.isfinite(value), np.clip(value, 0.0, 65535.0), 0.0)
        return value.astype(np.int64)

    def pwm_enabled(self, axis: int) -> bool:
        """WDOG ON and an ATYPE whose Z channel is the PWM output (35, 36)."""
        atype = int(self.axes[axis].params["ATYPE"])
        return self.system.get("WDOG", 0) != 0 and atype in PWM_ATYPES

    def duty(self, axis: int) -> float:
        output = self.pwm[axis]
        self.mark(axis)
        return output.duty(self.system.get("WDOG", 0) != 0, int(self.axes[axis].params["ATYPE"]))

    def _sync_encoder(self, axis: int) -> None:
        """PWM_ENCODER follows the whole counts the axis made since the last look."""
        output = self.pwm.outputs.get(axis)
        if output is None:
            return
        counts = self.counts_at(axis, self.tick)
        moved = counts - self._encoder_counts[axis]
        self._encoder_counts[axis] = counts
        output.move_encoder(moved)  # (0 too: an entry made passed by PWM_CONTROL(6) fires)

    def _gate_fired(self, axis: int, entry: GateEntry) -> None:
        self.gate_edges.append(GateEdge(self.tick, axis, entry.level, entry.position))
        self._changed()

    def next_gate_tick(self, axis: int) -> int | None:
        """The tick the axis passes the FIFO head (None: not with the present motion)."""
        output = self.pwm[axis]
        head = output.next_gate()
        a = self.axes[axis]
        if head is None or a.motion is None or a.link is not None:
            return None  # (a linked axis's gates are compared when it is read: D)
        self._sync_encoder(axis)
        need = head.counts_to_pass(output.encoder)
        if need == 0:
            return self.tick
        here = a.steps_at_tick(self.tick, self.period)
        trigger = PositionTrigger(here + need, 1 if need > 0 else -1, head)
        found = trigger_ticks(a, self, [trigger])
        return found[0][0] if found else None

    # ---- CAMBOX ends ----------------------------------------------------------------------
    def cambox_end_tick(self, axis: int) -> int | None:
        """The tick the link axis has travelled the CAMBOX's link distance."""
        link = self.axes[axis].link
        assert isinstance(link, Cambox)
        if self.dpos(link.link) - link.link_origin >= link.distance - 1e-9:
            return self.tick
        target = link.link_origin + link.distance  # link axis DPOS, user units
        la = self.axes[link.link]
        position = target * la.units - la.datum  # link axis demand, counts
        inner = la.link
        if isinstance(inner, Connpath):
            queue = self.queues[inner.base]
            run = queue[0] if queue else None
            if run is None or not run.started or run.plan is None or inner.ratio <= 0:
                return None
            needed = ((position - inner.origin) / (inner.ratio * la.units)
                      + inner.distance0 - self.distance_done[inner.base]) * run.units
            plan = run.plan
            if needed > plan.s_end and needed <= plan.s_end + 1e-9 * max(1.0, plan.s_end):
                needed = plan.s_end  # the path's end, within rounding
            t = plan.time_at(needed)
            if t is None:
                return None
            return max(self.tick, run.plan_tick + math.ceil(t / self.period - 1e-9))
        if inner is not None or la.motion is None:
            return None  # (a CAMBOX linked to a CAMBOX axis ends when next looked at: D)
        return la.tick_reaching(math.ceil(position - 1e-9), 1, self)

    def _finish_camboxes(self, now: int) -> None:
        for a, axis in enumerate(self.axes):
            if isinstance(axis.link, Cambox) and axis.link_end is not None \
                    and axis.link_end <= now:
                self._unlink(a)
                self._changed()


class _MotionEvents:
    """Runs and CAMBOXes ending: the ticks the motion changes by itself."""

    def __init__(self, machine: MC405Machine) -> None:
        self.machine = machine
        self._cache: tuple[int, int, int | None] = (-1, -1, None)

    def next_event(self) -> int | None:
        m = self.machine
        if self._cache[0] == m.revision and self._cache[1] == m.tick:
            return self._cache[2]
        best: int | None = None
        for queue in m.queues:
            if queue and queue[0].started and (best is None or queue[0].end_tick < best):
                best = queue[0].end_tick
        for a, axis in enumerate(m.axes):
            if isinstance(axis.link, Cambox):
                axis.link_end = m.cambox_end_tick(a)
                if axis.link_end is not None and (best is None or axis.link_end < best):
                    best = axis.link_end
        if best is not None:
            best = max(best, m.tick)
        self._cache = (m.revision, m.tick, best)
        return best

    def on_event(self, now: int) -> None:
        m = self.machine
        for a in m.pwm.outputs:  # the encoders see the motion before it changes
            m._sync_encoder(a)
        m._finish_camboxes(now)
        m._finish_runs(now)
        m._changed()


class _GateEvents:
    """The gating FIFOs: the tick each head position is passed."""

    def __init__(self, machine: MC405Machine) -> None:
        self.machine = machine
        self._cache: tuple[int, int | None] = (-1, None)

    def next_event(self) -> int | None:
        m = self.machine
        if self._cache[0] == m.revision:
            return self._cache[1]
        best: int | None = None
        for a, output in m.pwm.outputs.items():
            if output.fifo:
                tick = m.next_gate_tick(a)
                if tick is not None and (best is None or tick < best):
                    best = tick
        self._cache = (m.revision, best)
        return best

    def on_event(self, now: int) -> None:
        m = self.machine
        for a, output in m.pwm.outputs.items():
            if output.fifo:
                m._sync_encoder(a)
        m._changed()


Clock = Callable[[], int]
__all__ = ["MOVE_BUFFER", "SERVO_PERIODS", "GateEdge", "MC405Machine", "PwmError", "TrioAxis"]
