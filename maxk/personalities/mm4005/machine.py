"""The MM4005 on the shared machine: an `Engine` at the servo update rate whose axes are
`MotionAxis` runs of closed-form profiles, whose trajectory runs on the path planner and
whose pulses are path triggers. It is what the language's `MM4005Machine` protocol asks
for (maxk/commands/mm4005/machine.py), with no wire format.

Time: integer ticks of the servo update cycle, 0.5 ms (manual 7.1.1: "the servo update
cycle (0.0005s)", C). The MPN's Tbase is that cycle too (I: the pulse output is set once
per cycle, which is what VV x Tbase bounds: at most one pulse per cycle).

Long module: one machine whose point-to-point moves, home searches, both trajectories,
servo loops and events act on the same axes and must see each other's state (a stop, a
limit or a following error ends whatever the axis is doing).

Decisions (D) beyond the manual are listed in docs/mm4005.md: the home search's edge and
stages, a stop at a hardware limit, a PA/PR while moving (stop, then go), MF stopping at
once, the power-up state.
"""

from __future__ import annotations

import math
from typing import Final

from maxk.firmware_model.axis import MotionAxis, MotionEnds
from maxk.firmware_model.engine import Engine
from maxk.firmware_model.profiles import RampShape, plan_jog, plan_move, plan_stop
from maxk.firmware_model.servo import DAC_LIMIT, Gains, ServoLoop, advance_servo_axes
from maxk.firmware_model.world import STUCK_ACTIVE, Switch, World

from .errors import TRAJECTORY_VELOCITY, TRAVEL_LIMITS, UNAUTHORIZED, MM4005Error
from .execution import PulseRecord, TrajectoryExecution
from .io import GpioPort
from .programs import ProgramStore, Tasks, Variables
from .settings import FULL_SCALE, AxisSettings
from .stage import HomeSearch, HomeStage, MM4005Axis, ServoConfig
from .status import AxisStatus
from .timed import PulseTrace, TimedExecution, TimedTrajectory, TracePoint
from .trace_mode import AxisTrace, GlobalTrace
from .trajectory import Trajectory, TrajectoryRun

UPDATE_RATE_HZ: Final = 2000  # manual 7.1.1: servo update cycle 0.0005 s (C)
VERSION: Final = "MM4005 Version 2.42"  # as the EPICS test device answered (I)
MAX_AXES: Final = 4  # the MM4005 drives up to 4 axes (manual title, C)
_RAMP: Final = RampShape.LINEAR  # trapezoidal profile (MM4006 manual 4.4.1, I)


class MM4005(Engine):
    """An MM4005 controller's axes, trajectory and pulses in virtual time."""

    def __init__(self, axis_count: int = MAX_AXES, update_rate_hz: float = UPDATE_RATE_HZ,
                 version: str = VERSION) -> None:
        if not 1 <= axis_count <= MAX_AXES:
            raise ValueError(f"an MM4005 has 1 to {MAX_AXES} axes, not {axis_count}")
        super().__init__(update_rate_hz)
        self.version = version
        self.world = World.default(axis_count)
        self.axes = [MM4005Axis(i, str(i + 1), host=self) for i in range(axis_count)]
        for axis in self.axes:
            self.add_source(axis)  # (its home search's edge)
        self.ends = MotionEnds(self.axes, self, self._on_end, limit_at=self._limit_at,
                               on_limit=self._on_limit)
        self.add_source(self.ends)
        self.trajectory = Trajectory()
        self.execution: TrajectoryExecution | None = None  # the running or last run
        self.timed = TimedTrajectory(axis_count)  # NC/DT/DX/...: the time-based one
        self.timed_run: TimedExecution | None = None
        self.pulse_trace = PulseTrace()  # the last run's pulses, a bounded ring
        self.settings = [AxisSettings() for _ in range(axis_count)]
        self._servo_axes: list[MM4005Axis] = []
        self.following_errors: list[int] = []
        self.programs = ProgramStore()  # the controller gives it its archive
        self.variables = Variables()  # $Y1..$Y120 (3.3.1, 3.145 TY)
        self.tasks = Tasks(lambda: self.tick)  # waiting command lines, the program
        self.add_source(self.tasks)
        self.gpio = GpioPort(self.world, self)  # SB/RA on the world's I/O (io.py)
        self.global_trace = GlobalTrace(self, self.pulse_trace, self._positions,
                                        self.trajectory_element)  # GQ/SQ (trace_mode.py)
        self.add_source(self.global_trace)
        self.axis_trace = AxisTrace(self, self._positions)  # TM/SP (trace_mode.py)
        self.add_source(self.axis_trace)

    def settle(self) -> None:
        """Before time moves: a wait already over (a stop from another host) ends now."""
        self.tasks.poll()

    def after_events(self, now: int) -> None:
        """Once the tick's sources acted: a WS ends on the tick its motion ended."""
        self.tasks.poll()

    # ---- what the language reads ----------------------------------------------------------
    @property
    def axis_count(self) -> int:
        return len(self.axes)

    @property
    def tick_period(self) -> float:
        return self.period

    @property
    def trajectory_base_period(self) -> float:
        """Tbase of the MPN formula: the servo update cycle (I)."""
        return self.period

    def axis(self, number: int) -> MM4005Axis:
        return self.axes[number - 1]

    def position(self, axis: int) -> float:
        a = self.axis(axis)
        return a.encoder(self) * a.resolution

    # ---- the servo ----------------------------------------------------------------------
    def apply_gains(self, axis: int) -> None:
        """UF: the gains set take effect. KP > 0 runs the axis through the shared servo
        (PID on the world's motor plant); KP 0, the factory value, leaves the exact,
        profile-only axis (D)."""
        a = self.axis(axis)
        settings = self.settings[axis - 1]
        settings.update_filter()
        kp, ki, kd, ks = settings.active_gains
        if not settings.servo_on:
            a.servo = None
        else:
            full_p, full_i, full_d = FULL_SCALE  # the manual's 0..1 on the shared filter
            a.config = ServoConfig(Gains(kp=kp * full_p, ki=ki * full_i, kd=kd * full_d,
                                         ku=ks * DAC_LIMIT / 4.0))
            if a.servo is None:
                a.servo = ServoLoop(float(a.steps_now(self)), self.tick)
                a.servo.closed = a.powered
        self._servo_axes = [x for x in self.axes if x.servo is not None]

    def integrate(self, limit: int) -> bool:
        """The servo loops run every tick up to the next event; a following error above
        FE (checked at each event and each slice a door advances) or the loop's own trip
        turns the motor off (the error is reported as F)."""
        servos = self._servo_axes
        if not servos:
            return False
        advance_servo_axes(servos, self, limit)
        tripped = [a for a in servos if a.servo is not None and a.servo.trip_tick is not None]
        if tripped:  # the loop's own trip: act at its tick (the others wait ahead)
            first = min(a.servo.trip_tick for a in tripped  # type: ignore[union-attr]
                        if a.servo is not None and a.servo.trip_tick is not None)
            self.tick = max(self.tick, first)
            for a in tripped:
                assert a.servo is not None
                if a.servo.trip_tick == first:
                    a.servo.trip_tick = None
                    self._following_error(a)
            return True
        over = [a for a in servos if a.powered and abs(a.exact_counts_at(self, limit)
                - a.servo_counts()) * a.resolution > self.settings[a.index].following_limit]
        if not over:
            return False
        self.tick = max(self.tick, limit)  # the loops stand at `limit`: act there
        for a in over:
            self._following_error(a)
        return True

    def _following_error(self, a: MM4005Axis) -> None:
        """The motor is turned off (as MF); the next command line records error F."""
        self.following_errors.append(a.index + 1)
        self.set_power(a.index + 1, False)

    def take_errors(self) -> list[int]:
        """Axes whose following error turned their motor off since the last look."""
        out, self.following_errors = self.following_errors, []
        return out

    def theoretical_position(self, axis: int) -> float:
        a = self.axis(axis)
        return a.exact_counts(self) * a.resolution

    def target(self, axis: int) -> float:
        a = self.axis(axis)
        return a.target_counts * a.resolution

    def velocity(self, axis: int) -> float:
        return self.axis(axis).speed

    def set_velocity(self, axis: int, value: float) -> None:
        self.axis(axis).speed = value

    def desired_velocity(self, axis: int) -> float:
        """DV: the profile's velocity now, units/s."""
        a = self.axis(axis)
        return a.velocity(self) * a.resolution

    def acceleration(self, axis: int) -> float:
        return self.axis(axis).acceleration

    def set_acceleration(self, axis: int, value: float) -> None:
        self.axis(axis).acceleration = value

    def resolution(self, axis: int) -> float:
        return self.axis(axis).resolution

    def loop_type(self, axis: int) -> int:
        return self.axis(axis).loop_type

    def travel_limits(self, axis: int) -> tuple[float, float]:
        return self.axis(axis).limits

    def set_travel_limits(self, axis: int, left: float, right: float) -> None:
        self.axis(axis).limits = (left, right)

    def home_preset(self, axis: int) -> float:
        return self.axis(axis).home_preset

    def set_home_preset(self, axis: int, value: float) -> None:
        self.axis(axis).home_preset = value

    def define_home(self, axis: int, limits: tuple[float, float]) -> None:
        a = self.axis(axis)
        a.load_position(a.to_counts(a.home_preset), self)
        a.limits = limits

    def status(self, axis: int) -> AxisStatus:
        a = self.axis(axis)
        world = self.world.axes[a.index]
        steps = a.steps_now(self)
        moving = a.motion is not None or a.homing is not None
        direction = a.travel_direction(self) if a.motion is not None else a.direction
        return AxisStatus(moving=moving, power_off=not a.powered,
                          direction_positive=direction > 0,
                          plus_limit=world.plus_limit.active(steps),
                          minus_limit=world.minus_limit.active(steps),
                          home_signal=world.home.active(steps))

    def trajectory_element(self) -> int:
        timed = self.timed_run
        if timed is not None and not timed.finished:
            return timed.element_at(self.tick)
        run = self.execution
        return 0 if run is None else run.element()

    @property
    def pulse_log(self) -> list[PulseRecord]:
        """The XY trajectory's pulses the ring still holds, in firing order."""
        return [r for r in self.pulse_trace.records if isinstance(r, PulseRecord)]

    @property
    def trace_points(self) -> list[TracePoint]:
        """The time-based trajectory's pulses the ring still holds, in firing order."""
        return [r for r in self.pulse_trace.records if isinstance(r, TracePoint)]

    def is_idle(self) -> bool:
        run = self.execution
        timed = self.timed_run
        return (all(a.motion is None and a.homing is None for a in self.axes)
                and (run is None or run.finished) and (timed is None or timed.finished)
                and not self.tasks.busy)

    # ---- the time-based trajectory ----------------------------------------------------------
    def verify_timed(self) -> None:
        """VC: check the time-based definition against each axis's VU and GC."""
        self.timed.verify(lambda axis: self.settings[axis - 1].get("VU"))

    def execute_timed(self, scale: float) -> None:
        """EC: run the verified time-based trajectory, element times x ``scale``. Every
        taking-part axis must be powered and still (D)."""
        from .errors import TRAJECTORY_NOT_VERIFIED
        timed = self.timed
        if not timed.verified:
            raise MM4005Error(TRAJECTORY_NOT_VERIFIED, "VC first")
        for number in timed.axes:
            a = self.axis(number)
            if not a.powered or a.motion is not None or a.homing is not None:
                raise MM4005Error(UNAUTHORIZED, f"axis {number} off or moving")
        for number, figures in timed.figures.items():  # a time scale below 1 speeds it up
            if figures.velocity / scale > self.settings[number - 1].get("VU"):
                raise MM4005Error(TRAJECTORY_VELOCITY, f"axis {number} at this time scale")
        for number in timed.axes:  # one way along each element: extremes at its boundaries
            here = self.theoretical_position(number)
            left, right = self.axis(number).limits
            position = low = high = here
            for element in timed.elements:
                position += element.moves.get(number, 0.0)
                low, high = min(low, position), max(high, position)
            if low < left - 1e-9 or high > right + 1e-9:
                raise MM4005Error(TRAVEL_LIMITS, f"axis {number} would leave TL..TR")
        previous = self.timed_run
        if previous is not None:
            self.remove_source(previous)
        run = TimedExecution(timed, [self.axis(n) for n in sorted(timed.axes)], self,
                             self._positions, scale, self.pulse_trace)
        self.timed_run = run
        self.add_source(run)
        for a in run.axes:
            self.schedule_switches(a)

    def input_level(self, bit: int) -> bool:
        """RB: a GPIO input bit's level in the world (manual 3.103)."""
        return self.world.digital_level(bit, self)

    def _positions(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """Every installed axis's TH and TP now, in user units (a time-based pulse)."""
        th: list[float] = []
        tp: list[float] = []
        for a in self.axes:
            exact, encoder = a.th_tp_counts(self)
            th.append(exact * a.resolution)
            tp.append(encoder * a.resolution)
        return tuple(th), tuple(tp)

    def elements_done(self) -> int:
        """XC: elements of the time-based trajectory completed (0 before any run)."""
        run = self.timed_run
        return 0 if run is None else run.elements_done()

    def abort(self) -> None:
        """AB: every axis and any trajectory stop where they are, at once; power stays
        on (D); a running program ends (D)."""
        self.tasks.stop_programs()
        timed = self.timed_run
        if timed is not None:
            timed.abort()
        run = self.execution
        if run is not None and not run.finished:
            run.abort()
        for a in self.axes:
            a.homing = None
            a.pending_target = None
            if a.motion is not None:
                a.freeze(self)
            a.target_counts = a.counts(self)

    def _timed_stop(self, a: MM4005Axis) -> bool:
        """ST or a limit on an axis of the time-based run: the run ends, its later pulses
        never fire, each of its axes brakes at its AC (D)."""
        timed = self.timed_run
        if timed is None or timed.finished or a not in timed.axes:
            return False
        timed.abort_braking()
        for member in timed.axes:
            if member.motion is not None:
                self._plan_stop(member)
        return True

    def known_end(self) -> int | None:
        """The last tick at which a motion or trajectory now running is planned to end
        (None: one runs without a planned end, a home search seeking its switch)."""
        ends: list[int] = []
        timed = self.timed_run
        if timed is not None and not timed.finished:
            ends.append(timed.end_tick)
        for a in self.axes:
            if a.motion is not None:
                if a.motion_end is None:
                    return None
                ends.append(a.motion_end)
        run = self.execution
        if run is not None and not run.finished and run.end_tick is not None:
            ends.append(run.end_tick)
        return max(ends) if ends else None

    # ---- commands that move ---------------------------------------------------------------
    def move_to(self, axis: int, position: float) -> None:
        """PA/PR: a trapezoidal move at VA and AC. Given while the axis moves, the axis
        first stops at AC and then goes to the new destination (D)."""
        a = self.axis(axis)
        if a.in_trajectory:
            raise MM4005Error(UNAUTHORIZED, "the axis runs a trajectory")
        target = a.to_counts(position)
        if a.motion is not None:
            a.homing = None
            a.pending_target = target
            self._plan_stop(a)
            a.target_counts = target
            return
        self._start_move(a, target)

    def _start_move(self, a: MM4005Axis, target: int) -> None:
        """Check and plan first, then change the axis: a refused move leaves DP as it was."""
        distance = target - a.counts(self)
        if distance == 0:
            a.target_counts = target
            return
        if self._limit_pressed(a, 1 if distance > 0 else -1):
            raise MM4005Error(UNAUTHORIZED, "travel limit switch pressed that way")
        c = a.counts_per_second
        motion = plan_move(distance, 0.0, c(a.speed), c(a.acceleration), c(a.acceleration),
                           _RAMP)
        a.target_counts = target
        a.begin(motion, self)
        self.schedule_switches(a)

    def _plan_stop(self, a: MM4005Axis) -> None:
        residual, velocity = a.freeze(self)
        decel = a.counts_per_second(a.acceleration)
        motion = plan_stop(residual, velocity, 0.0, decel, _RAMP)
        a.target_counts = a.steps + motion.final_offset + a.counter_offset
        a.begin(motion, self)
        if a.motion is None:  # it was at rest already: what follows a stop follows now
            self._motion_done(a)
        else:
            self.schedule_switches(a)

    def stop(self, axis: int) -> None:
        """ST: decelerate at AC (a trajectory's axes ramp down along the path at VS)."""
        a = self.axis(axis)
        if self._timed_stop(a):
            return
        run = self.execution
        if a.in_trajectory and run is not None:
            run.stop()
            for member in run.axes:
                self.schedule_switches(member)
            return
        a.pending_target = None
        a.homing = None
        if a.motion is not None:
            self._plan_stop(a)

    def set_power(self, axis: int, on: bool) -> None:
        """MO/MF. Power off stops the axis where it is, at once (and a trajectory it is in)."""
        a = self.axis(axis)
        if not on:
            timed = self.timed_run
            if timed is not None and a in timed.axes:
                timed.abort()
            run = self.execution
            if a.in_trajectory and run is not None:
                run.abort()
            a.homing = None
            a.pending_target = None
            if a.motion is not None:
                a.freeze(self)
            a.target_counts = a.counts(self)
        servo = a.servo
        if servo is not None and on != a.powered:
            if on:  # the command starts where the motor stands: no jump
                a.steps = servo.encoder_counts()
                a.target_counts = a.counts(self)
                servo.reset_filter(0.0)
                servo.tripped = False
            servo.closed = on
        a.powered = on

    def search_home(self, axis: int, mode: int) -> None:
        """OR: travel at VA toward the home switch's edge (the first active count met
        moving up), latch it, brake at AC, come back onto it; it then reads XH (D: every
        mode searches the switch; the encoder index is not modelled)."""
        a = self.axis(axis)
        edge, direction = self._home_edge(a)
        a.pending_target = None
        a.homing = HomeSearch(HomeStage.SEEK, direction, edge)
        c = a.counts_per_second
        motion = plan_jog(0.0, 0.0, direction * c(a.speed), 0.0, c(a.acceleration),
                          c(a.acceleration), _RAMP)
        a.begin(motion, self)
        self.schedule_switches(a)

    def _home_edge(self, a: MM4005Axis) -> tuple[int | None, int]:
        """The home position (steps) and which way the search starts from here; without
        a usable switch (none, or stuck by a fault) the search goes up until a limit
        stops it (D)."""
        switch = self.world.axes[a.index].home
        here = a.steps_now(self)
        if switch.fault is None and switch.low is not None:
            edge = math.ceil(switch.low)
            return edge, (1 if here < edge else -1)
        if switch.fault is None and switch.high is not None:
            edge = math.floor(switch.high)
            return edge, (-1 if here > edge else 1)
        return None, 1

    def start_trajectory(self, run: TrajectoryRun) -> None:
        """ET accepted: X and Y follow the planned path; NS's pulses fire on the way."""
        previous = self.execution
        if previous is not None and not previous.finished:
            raise MM4005Error(UNAUTHORIZED, "a trajectory is running")
        if previous is not None:
            self.remove_source(previous)
        x, y = self.axis(run.x_axis), self.axis(run.y_axis)
        for a in (x, y):
            a.pending_target = None
            a.homing = None
            a.in_trajectory = True
        execution = TrajectoryExecution(run, x, y, self, self.pulse_trace)
        self.execution = execution
        self.add_source(execution)
        for a in (x, y):
            self.schedule_switches(a)

    # ---- events ----------------------------------------------------------------------------
    def axis_event(self, axis: MM4005Axis, now: int) -> None:
        """A home search's tick has come: it meets the home edge."""
        if axis.switch_tick is not None and now >= axis.switch_tick:
            axis.switch_tick = None
            homing = axis.homing
            if (axis.motion is not None and homing is not None
                    and homing.stage is HomeStage.SEEK and self._home_met(axis, homing)):
                homing.stage = HomeStage.BRAKE
                self._plan_stop(axis)
            elif axis.motion is not None:
                self.schedule_switches(axis)

    def _home_met(self, a: MM4005Axis, homing: HomeSearch) -> bool:
        if homing.edge is None:
            return False
        here = a.steps_now(self)
        if homing.direction > 0:
            return here >= homing.edge
        return here <= homing.edge - 1

    def _limit_pressed(self, a: MM4005Axis, direction: int) -> bool:
        world = self.world.axes[a.index]
        switch = world.plus_limit if direction > 0 else world.minus_limit
        return switch.active(a.steps_now(self))

    def _limit_at(self, axis: MotionAxis, side: int) -> float | None:
        """Where that side's hardware limit is active from, for the shared `MotionEnds`:
        a switch stuck active is active everywhere (-inf/+inf), one stuck inactive
        never."""
        world = self.world.axes[axis.index]
        switch = world.plus_limit if side > 0 else world.minus_limit
        if switch.fault == STUCK_ACTIVE:
            return -math.inf if side > 0 else math.inf
        return _edge(switch, side)

    def _on_limit(self, axis: MotionAxis, side: int, tick: int) -> None:
        assert isinstance(axis, MM4005Axis)
        self._limit_tripped(axis)

    def _on_end(self, axis: MotionAxis, tick: int) -> None:
        assert isinstance(axis, MM4005Axis)
        self._motion_done(axis)

    def _limit_tripped(self, a: MM4005Axis) -> None:
        """A hardware travel limit: the axis brakes at AC (a trajectory along its path at
        VS; a time-based run ends, each of its axes braking at its AC); a home search or
        a waiting destination is abandoned (D). MS shows the limit's bit while the
        switch is active."""
        a.homing = None
        a.pending_target = None
        if self._timed_stop(a):
            return
        run = self.execution
        if a.in_trajectory and run is not None:
            run.stop()
        else:
            self._plan_stop(a)

    def _motion_done(self, a: MM4005Axis) -> None:
        homing = a.homing
        if homing is not None:
            if homing.stage is HomeStage.BRAKE:
                homing.stage = HomeStage.RETURN
                assert homing.edge is not None  # only a met edge brakes a search
                distance = homing.edge - a.steps_now(self)
                if distance:
                    c = a.counts_per_second
                    a.begin(plan_move(distance, 0.0, c(a.speed), c(a.acceleration),
                                      c(a.acceleration), _RAMP), self)
                    return
            a.homing = None
            a.load_position(a.to_counts(a.home_preset), self)
            return
        if a.pending_target is not None:
            target, a.pending_target = a.pending_target, None
            try:
                self._start_move(a, target)
            except MM4005Error:
                a.target_counts = a.counts(self)  # into a pressed limit: it stays (D)

    def schedule_switches(self, a: MM4005Axis) -> None:
        """A home search: the tick at which it meets the home edge (bisection over its
        monotonic phases, exact to the tick). Limits are the shared `MotionEnds`'."""
        a.switch_tick = None
        homing = a.homing
        if (a.motion is not None and homing is not None and homing.stage is HomeStage.SEEK
                and homing.edge is not None):
            goal = homing.edge if homing.direction > 0 else homing.edge - 1
            a.switch_tick = a.tick_reaching(goal, homing.direction, self)

    # ---- power-up --------------------------------------------------------------------------
    def reset(self) -> None:
        """Power-up again (D): motion stops at once, settings and the trajectory go back to
        their defaults, each counter reads 0 where its stage stands (the stage keeps its
        place in the world); virtual time goes on. Waiting lines and a running program
        are gone; the stored programs stay (non-volatile, I)."""
        self.tasks.clear()
        self.variables = Variables()  # 0 again at power-up (D)
        if self.execution is not None:
            self.remove_source(self.execution)
            self.execution = None
        if self.timed_run is not None:
            self.remove_source(self.timed_run)
            self.timed_run = None
        self.timed = TimedTrajectory(len(self.axes))
        self.pulse_trace.begin()
        self.global_trace.reset()
        self.axis_trace.reset()
        self.gpio.clear()  # every output low at power-up (D)
        self.settings = [AxisSettings() for _ in self.axes]
        self._servo_axes = []
        self.following_errors = []
        for i, old in enumerate(self.axes):
            old.freeze(self)
            self.remove_source(old)
            axis = MM4005Axis(i, str(i + 1), host=self, steps=old.steps)
            axis.counter_offset = -old.steps
            self.axes[i] = axis  # (the same list: MotionEnds ends the new axes' motions)
            self.add_source(axis)
        self.ends.changed()
        self.trajectory = Trajectory()

    def world_changed(self) -> None:
        """A switch moved or a fault was set: every running motion looks again, and a
        limit now pressed under an axis travelling into it acts on this tick."""
        self.ends.changed()
        for a in self.axes:
            self.schedule_switches(a)
        self.ends.act_now()


def _edge(switch: Switch, direction: int) -> float | None:
    """Where a limit switch becomes active travelling `direction` (None: never)."""
    if switch.fault is not None:
        return None
    return switch.low if direction > 0 else switch.high
