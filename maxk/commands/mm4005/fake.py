"""An in-memory MM4005 machine for language tests and for doors until the shared engine
carries the MM4005: axes move at constant speed VA (acceleration ignored), a trajectory
runs at constant VV, time advances only through ``advance``. It keeps the firmware
state the language reads (limits, presets, power, status bits) faithfully; the motion
itself is deliberately simple.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from maxk.personalities.mm4005 import AxisStatus, Trajectory, TrajectoryRun
from maxk.personalities.mm4005.errors import UNAUTHORIZED, MM4005Error
from maxk.personalities.mm4005.programs import ProgramStore, Tasks, Variables
from maxk.personalities.mm4005.settings import AxisSettings
from maxk.personalities.mm4005.timed import PulseTrace, TimedTrajectory


@dataclass
class FakeAxis:
    """One axis's settings and its current straight-line move, if any."""

    position: float = 0.0
    velocity: float = 1.0
    acceleration: float = 4.0
    resolution: float = 0.001
    loop_type: int = 0
    limits: tuple[float, float] = (-100.0, 100.0)
    home_preset: float = 0.0
    powered: bool = True
    direction_positive: bool = True
    move: tuple[int, float, float, float] | None = None  # start tick, start, end, speed
    moving_in_trajectory: bool = False


@dataclass
class _Running:
    run: TrajectoryRun
    start_tick: int


@dataclass
class FakeMM4005:
    """Implements maxk.commands.mm4005.MM4005Machine in memory."""

    axis_count: int = 4
    version: str = "MM4005 Version 2.42"
    tick_period: float = 0.001
    trajectory_base_period: float = 0.001
    tick: int = 0
    trajectory: Trajectory = field(default_factory=Trajectory)
    axes: list[FakeAxis] = field(default_factory=list)
    runs: list[TrajectoryRun] = field(default_factory=list)
    _running: _Running | None = None
    timed: TimedTrajectory = field(default_factory=lambda: TimedTrajectory(4))
    pulse_trace: PulseTrace = field(default_factory=PulseTrace)
    settings: list[AxisSettings] = field(default_factory=list)
    inputs: dict[int, bool] = field(default_factory=dict)  # GPIO input bit -> level (RB)
    programs: ProgramStore = field(default_factory=ProgramStore)  # in memory only
    tasks: Tasks = field(init=False)
    variables: Variables = field(default_factory=Variables)

    def __post_init__(self) -> None:
        self.tasks = Tasks(lambda: self.tick)
        if not self.axes:
            self.axes = [FakeAxis() for _ in range(self.axis_count)]
        self.timed = TimedTrajectory(self.axis_count)
        self.settings = [AxisSettings() for _ in range(self.axis_count)]

    def input_level(self, bit: int) -> bool:
        return self.inputs.get(bit, False)

    # --- the time-based trajectory: defined and verified here; it runs on the engine ------
    def verify_timed(self) -> None:
        self.timed.verify(lambda axis: self.settings[axis - 1].get("VU"))

    def execute_timed(self, scale: float) -> None:
        raise MM4005Error(UNAUTHORIZED, "the in-memory machine does not run EC")

    def elements_done(self) -> int:
        return 0

    def apply_gains(self, axis: int) -> None:
        self.settings[axis - 1].update_filter()

    def take_errors(self) -> list[int]:
        return []

    def abort(self) -> None:
        for axis in range(1, self.axis_count + 1):
            self.stop(axis)

    def desired_velocity(self, axis: int) -> float:
        a = self._axis(axis)
        if a.move is None:
            return 0.0
        _tick, start, end, speed = a.move
        return speed if end >= start else -speed

    # --- time ---------------------------------------------------------------------------
    def advance(self, ticks: int) -> None:
        """What a door does before feeding bytes: move virtual time on (a held line
        goes on once its wait is over)."""
        self.tick += ticks
        self.tasks.poll()

    def _elapsed(self, since: int) -> float:
        return (self.tick - since) * self.tick_period

    def _axis(self, axis: int) -> FakeAxis:
        a = self.axes[axis - 1]
        self._settle_trajectory()
        if a.move is not None:
            start_tick, start, end, speed = a.move
            travelled = speed * self._elapsed(start_tick)
            if travelled >= abs(end - start):
                a.position, a.move = end, None
        return a

    def _settle_trajectory(self) -> None:
        running = self._running
        if running is None:
            return
        run = running.run
        if run.velocity * self._elapsed(running.start_tick) >= run.length:
            _, (x, y) = run.locate(run.length)
            for number, value in ((run.x_axis, x), (run.y_axis, y)):
                axis = self.axes[number - 1]
                axis.position, axis.moving_in_trajectory = value, False
            self._running = None

    def _live_position(self, axis: int) -> float:
        a = self._axis(axis)
        running = self._running
        if running is not None and axis in (running.run.x_axis, running.run.y_axis):
            run = running.run
            _, (x, y) = run.locate(run.velocity * self._elapsed(running.start_tick))
            return x if axis == run.x_axis else y
        if a.move is None:
            return a.position
        start_tick, start, end, speed = a.move
        step = speed * self._elapsed(start_tick)
        return start + step if end >= start else start - step

    # --- positions and settings ------------------------------------------------------------
    def position(self, axis: int) -> float:
        return self._live_position(axis)

    def theoretical_position(self, axis: int) -> float:
        return self._live_position(axis)

    def target(self, axis: int) -> float:
        a = self._axis(axis)
        return a.move[2] if a.move is not None else a.position

    def velocity(self, axis: int) -> float:
        return self.axes[axis - 1].velocity

    def set_velocity(self, axis: int, value: float) -> None:
        self.axes[axis - 1].velocity = value

    def acceleration(self, axis: int) -> float:
        return self.axes[axis - 1].acceleration

    def set_acceleration(self, axis: int, value: float) -> None:
        self.axes[axis - 1].acceleration = value

    def resolution(self, axis: int) -> float:
        return self.axes[axis - 1].resolution

    def loop_type(self, axis: int) -> int:
        return self.axes[axis - 1].loop_type

    def travel_limits(self, axis: int) -> tuple[float, float]:
        return self.axes[axis - 1].limits

    def set_travel_limits(self, axis: int, left: float, right: float) -> None:
        self.axes[axis - 1].limits = (left, right)

    def home_preset(self, axis: int) -> float:
        return self.axes[axis - 1].home_preset

    def set_home_preset(self, axis: int, value: float) -> None:
        self.axes[axis - 1].home_preset = value

    def define_home(self, axis: int, limits: tuple[float, float]) -> None:
        a = self._axis(axis)
        a.position, a.limits = a.home_preset, limits

    # --- power, status, motion -------------------------------------------------------------
    def set_power(self, axis: int, on: bool) -> None:
        a = self._axis(axis)
        if not on:
            self.stop(axis)
        a.powered = on

    def status(self, axis: int) -> AxisStatus:
        a = self._axis(axis)
        return AxisStatus(moving=a.move is not None or a.moving_in_trajectory,
                          power_off=not a.powered, direction_positive=a.direction_positive)

    def move_to(self, axis: int, position: float) -> None:
        start = self._live_position(axis)
        a = self.axes[axis - 1]
        if position != start:
            a.direction_positive = position > start
            a.move = (self.tick, start, position, a.velocity)
        else:
            a.position, a.move = start, None

    def stop(self, axis: int) -> None:
        """Stop at once (the fake has no deceleration); a running trajectory stops too."""
        running = self._running
        if running is not None and axis in (running.run.x_axis, running.run.y_axis):
            for number in (running.run.x_axis, running.run.y_axis):
                other = self.axes[number - 1]
                other.position = self._live_position(number)
                other.moving_in_trajectory = False
            self._running = None
        a = self._axis(axis)
        a.position, a.move = self._live_position(axis), None

    def search_home(self, axis: int, mode: int) -> None:
        """The fake's mechanical zero is where the axis reads its home preset."""
        self.move_to(axis, self.axes[axis - 1].home_preset)

    def start_trajectory(self, run: TrajectoryRun) -> None:
        self.runs.append(run)
        self._running = _Running(run, self.tick)
        for number in (run.x_axis, run.y_axis):
            self.axes[number - 1].moving_in_trajectory = True

    def trajectory_element(self) -> int:
        self._settle_trajectory()
        running = self._running
        if running is None:
            return 0
        number, _ = running.run.locate(running.run.velocity * self._elapsed(running.start_tick))
        return number
