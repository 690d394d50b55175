"""The MAXk board: axes, flags and doorbell, switches, power-up, on the shared engine.

Time is an integer tick counter at the update period (1/8192 s = 122.07 us by default).
The engine is event driven: stepper motions are closed-form, so advancing jumps from
one event (a motion ending, a wait expiring) to the next and runs the queues there.

Long module: the board's flags, switches, homing, slip and power-up all act on the one
state its axes share (flags latched per axis, the doorbell image, the archive); capture
lives in capture.py, vector tasks in contouring.py, the queues in axis.py.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from maxk.firmware_model.engine import Engine
from maxk.firmware_model.profiles import plan_move
from maxk.firmware_model.servo import advance_servo_axes
from maxk.firmware_model.world import AxisWorld, World
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.axis import Axis
from maxk.personalities.maxk.capture import (
    CaptureConfig,
    CaptureRing,
    capture_inputs,
    capture_triggers,
    fire_captures,
    read_inputs,
)
from maxk.personalities.maxk.config import AxisConfig
from maxk.personalities.maxk.contouring import TASKS, ContourTask
from maxk.personalities.maxk.homing import Homing, home_condition, next_home_position
from maxk.personalities.maxk.io import GeneralIO
from maxk.personalities.maxk.models import (
    DEFAULT_MODEL,
    DEFAULT_UPDATE_RATE_HZ,
    BoardModel,
    model_by_name,
)
from maxk.personalities.maxk.parameters import ArchiveError, ParameterArchive, restore, snapshot
from maxk.personalities.maxk.waits import WAIT_MOTION, InputWait, TickWait


@dataclass(frozen=True)
class CommandErrorRecord:
    """Why the command-error flag was set: shown by the REPL and kept for tests."""

    tick: int
    command: str
    reason: str

    def __str__(self) -> str:
        return f"{self.command!r}: {self.reason}" if self.command else self.reason


FlagListener = Callable[[int], None]
"""Called with the MAXnet-style word of the flags an event set (done, overtravel, slip of
one axis, or a command error): what a `%000 SSSSSSSS` notification carries."""


class Board(Engine):
    """A MAXk board model in virtual time."""

    def __init__(self, model: str | BoardModel = DEFAULT_MODEL,
                 update_rate_hz: int = DEFAULT_UPDATE_RATE_HZ,
                 archive: ParameterArchive | None = None) -> None:
        super().__init__(update_rate_hz)
        self.model = model if isinstance(model, BoardModel) else model_by_name(model)
        self.axes = [Axis(i, letter) for i, letter in enumerate(self.model.axis_letters)]
        self.world = World.default(len(self.axes))
        self.archive = archive if archive is not None else ParameterArchive()
        self.firmware_state = 0
        self._init_done_tick = 1  # the firmware flags read 0xFFFFFFFF until then
        self._cycle_origin = 0  # CC counts update cycles since the last power-up/reset
        self.io = GeneralIO.for_lines(self.model.io_lines)
        self.capture_ring = CaptureRing()
        self.capture_config = [CaptureConfig() for _ in self.axes]
        self._input_levels = 0  # input levels as last seen, for input-edge capture
        self._capturing_inputs = False  # cached: refreshed by world_changed()
        # Command mode: ("single", axis index) after AX..AK, or "AA" / "AM".
        self.mode: str = "single"
        self.current_axis = 0
        self.command_error = False
        self.cross_axis_event = False  # set when one axis's queue can unblock another's
        self.errors: deque[CommandErrorRecord] = deque(maxlen=200)
        self._listeners: list[FlagListener] = []
        self._servo_axes: list[Axis] = []  # PSM axes: their loops run every tick
        self.tasks: dict[int, ContourTask] = {}  # vector tasks (contouring), by index
        self._due: list[Axis] = []  # axes whose queues the present tick's events woke
        # WQ: the axes a command stream waits on (read and cleared by its interpreter),
        # and the streams waiting, called after every event until their queues are empty.
        self.parser_hold: list[Axis] | None = None
        self.parser_waits: list[Callable[[], None]] = []
        self.command_buffer: tuple[str, int | None] = ("normal", None)  # #BB / #BN
        self.add_source(_AxesSource(self))
        self._tasks_source: _TasksSource | None = None  # added with the first vector task
        self.load_power_up_parameters()

    # ---- lookup ----------------------------------------------------------------------
    def axis(self, letter: str) -> Axis:
        index = self.model.axis_letters.find(letter.upper())
        if index < 0 or len(letter) != 1:
            raise KeyError(f"{self.model.name} has no axis {letter!r}")
        return self.axes[index]

    # ---- time ------------------------------------------------------------------------
    def run_queues(self, axes: Iterable[Axis] | None = None) -> None:
        """Run queues at the current tick until none can progress. Queues are independent
        except at AA-mode GO barriers: only then is every axis given another pass."""
        for axis in self.axes if axes is None else axes:
            axis.run_queue(self)
        while self.cross_axis_event:
            self.cross_axis_event = False
            for axis in self.axes:
                axis.run_queue(self)

    def settle(self) -> None:
        self.run_queues()

    def after_events(self, now: int) -> None:
        """The tick's axes and tasks have acted: run the queues they woke, check slips
        and position maintenance, record input edges."""
        due = self._due
        self._due = []
        self.run_queues(due)
        for axis in due:
            if axis.config.slip_detect:
                self.check_slip(axis)
            if axis.holding and axis.motion is None:
                self.maintain(axis)
        if self._capturing_inputs:
            capture_inputs(self)
        if self.parser_waits:
            for resume in list(self.parser_waits):  # a WQ may release a host's stream
                resume()

    def integrate(self, limit: int) -> bool:
        """Servo loops run every tick: simulate them up to the next event (their inputs
        change only at events). A following-error trip is an event of their own."""
        return bool(self._servo_axes) and self._advance_servos(limit)

    @property
    def servo_axes(self) -> list[Axis]:
        return self._servo_axes

    def refresh_servo_axes(self) -> None:
        self._servo_axes = [a for a in self.axes if a.servo is not None]

    def _advance_servos(self, limit: int) -> bool:
        """Run every servo loop up to `limit`; act on the earliest following-error trip
        (time then stands at its tick). True if one was handled."""
        advance_servo_axes(self._servo_axes, self, limit)
        trips = [a for a in self._servo_axes if a.servo.trip_tick is not None]  # type: ignore
        if not trips:
            return False
        first = min(t for a in trips if a.servo is not None
                    and (t := a.servo.trip_tick) is not None)
        self.tick = max(self.tick, first)
        for axis in trips:
            if axis.servo.trip_tick == first:  # type: ignore[union-attr]
                self.following_error_trip(axis)
        self.run_queues()
        return True

    def following_error_trip(self, axis: Axis) -> None:
        """Following error above 32768 counts (manual 2.13): the PID is disabled so the
        motor cannot run away. The DAC goes to 0 V, the trajectory stops, the queue is
        flushed and the axis's slip flag (doorbell bit 16+i, EA 'S') is set. CL1 or HN
        closes the loop again (docs/servo.md)."""
        servo = axis.servo
        assert servo is not None
        servo.trip_tick = None
        servo.tripped = True
        self.stop_with_linked(axis, hard=True)
        self.set_axis_flag(axis, F.AXIS_SLIP)

    def is_idle(self) -> bool:
        """No axis moving and no queue holding work."""
        return all(a.motion is None and a.wait is None and len(a.queue) == 0 for a in self.axes)

    def run_until_idle(self, timeout_ticks: int) -> bool:
        return self.run_until(Board.is_idle, timeout_ticks)

    # ---- flags -----------------------------------------------------------------------
    def add_flag_listener(self, listener: FlagListener) -> None:
        self._listeners.append(listener)

    def remove_flag_listener(self, listener: FlagListener) -> None:
        if listener in self._listeners:
            self._listeners.remove(listener)

    def _notify(self, word: int) -> None:
        for listener in list(self._listeners):
            listener(word)

    def set_axis_flag(self, axis: Axis, bit: int) -> None:
        """Latch a flag. Listeners hear the bits this event set (a MAXnet notification
        names its cause), so a command error latched earlier does not colour a later
        done notification."""
        if not axis.flags & bit:
            axis.flags |= bit
            if self._listeners:
                self._notify(F.maxnet_event_bits(axis.index, bit))

    def clear_axis_flags(self, axis: Axis, bits: int) -> None:
        axis.flags &= ~bits

    def report_error(self, reason: str, command: str = "") -> None:
        """Set the command-error flag (doorbell bit 24) and remember why."""
        self.errors.append(CommandErrorRecord(self.tick, command, reason))
        self.command_error = True
        if self._listeners:
            self._notify(F.COMMAND_ERROR)  # every bad command is reported

    @property
    def last_error(self) -> CommandErrorRecord | None:
        return self.errors[-1] if self.errors else None

    @property
    def doorbell(self) -> int:
        """The outbound doorbell register (ODBR) image."""
        return F.doorbell_word([a.flags for a in self.axes], self.command_error)

    def write_doorbell(self, mask: int) -> None:
        """Host writes ones to clear doorbell bits (write-one-to-clear)."""
        for axis in self.axes[:8]:
            i = axis.index
            if mask & (1 << (F.DONE_SHIFT + i)):
                axis.flags &= ~F.AXIS_DONE
            if mask & (1 << (F.OVERTRAVEL_SHIFT + i)):
                axis.flags &= ~F.AXIS_OVERTRAVEL
            if mask & (1 << (F.SLIP_SHIFT + i)):
                axis.flags &= ~F.AXIS_SLIP
        for axis, bit in zip(self.axes[8:], (F.W_NOTIFY, F.K_NOTIFY), strict=False):
            if mask & bit:
                axis.flags = 0
        if mask & F.COMMAND_ERROR:
            self.command_error = False

    def clear_interrupts(self) -> None:
        """IC: clear the command-error flag and every latched done/overtravel/slip flag."""
        self.command_error = False
        for axis in self.axes:
            axis.flags = 0

    # ---- the world: switches, limits and home ----------------------------------------
    def limit_pressed(self, axis: Axis, direction: int) -> bool:
        """Is the limit switch on this side pressed at the axis's present position?"""
        world = self.world.axes[axis.index]
        switch = world.plus_limit if direction > 0 else world.minus_limit
        return switch.active(axis.steps_now(self))

    def home_active(self, axis: Axis) -> bool:
        return self.world.axes[axis.index].home.active(axis.steps_now(self))

    def limit_blocks(self, axis: Axis, direction: int) -> bool:
        """A move toward a pressed limit is refused while limits are enabled."""
        return axis.config.limits_enabled and self.limit_pressed(axis, direction)

    def refuse_into_limit(self, axis: Axis) -> None:
        """A motion into an active limit: the overtravel flag, and nothing moves. The
        queue goes on (a following ID sets done: hosts read done + L as 'at a limit'),
        unlike a limit tripped mid-move, which flushes it."""
        axis.homing = None
        self.set_axis_flag(axis, F.AXIS_OVERTRAVEL)

    def schedule_switches(self, axis: Axis) -> None:
        """Find the next tick at which the running motion trips a limit or meets home."""
        axis.switch_tick = None
        if axis.capture_pending:
            axis.capture_pending = []
        m = axis.motion
        if m is None:
            return
        world = self.world.axes[axis.index]
        if (m.end_time is not None and m.monotonic and axis.homing is None
                and not self.capture_config[axis.index].on_position):
            # Fast path for a plain move or stop: only the limit ahead can matter, and
            # only if the motion ends at or beyond it.
            switch = world.plus_limit if m.direction > 0 else world.minus_limit
            edge = switch.low if m.direction > 0 else switch.high
            if (not axis.config.limits_enabled or switch.fault is not None or edge is None
                    or m.direction * (axis.steps + m.final_offset - edge) < 0):
                return
        reach = getattr(m, "reach", None)
        if (reach is not None and axis.homing is None
                and not self.capture_config[axis.index].on_position
                and not (axis.config.limits_enabled and _limit_within(axis.steps, reach, world))):
            return  # (a contour far from every limit: its phases need not be made)
        candidates: list[int] = []
        if axis.config.limits_enabled:
            for direction, switch in ((1, world.plus_limit), (-1, world.minus_limit)):
                if switch.fault is not None or switch.active(axis.steps_now(self)):
                    continue  # stuck, or already pressed (a stop decelerating into it)
                edge = switch.low if direction > 0 else switch.high
                if edge is not None:
                    tick = axis.tick_reaching(edge, direction, self)
                    if tick is not None:
                        candidates.append(tick)
        homing = axis.homing
        if homing is not None:
            target = next_home_position(axis.config, self.world.axes[axis.index],
                                        axis.steps_now(self), homing.direction)
            if target is not None:
                tick = axis.tick_reaching(target, homing.direction, self)
                if tick is not None:
                    candidates.append(tick)
        axis.capture_pending = capture_triggers(self, axis)
        candidates.extend(t for t, _trigger in axis.capture_pending)
        if candidates:
            axis.switch_tick = min(candidates)

    def capturing_inputs(self) -> bool:
        """Does any axis capture input edges? Cached; world_changed() refreshes it."""
        return self._capturing_inputs

    def _switch_event(self, axis: Axis) -> None:
        """A limit, home condition or capture edge is reached on this tick: act on it."""
        axis.switch_tick = None
        if axis.motion is None:
            return
        if axis.capture_pending:
            fire_captures(self, axis)
        self.check_motion(axis)

    def check_motion(self, axis: Axis) -> None:
        """Act on what is true for a moving axis now: a pressed limit ahead trips, home
        met ends a search; otherwise look for the next switch event."""
        if axis.motion is None:
            return
        direction = axis.travel_direction(self)
        if axis.config.limits_enabled and self.limit_pressed(axis, direction):
            self.limit_tripped(axis)
            return
        homing = axis.homing
        if homing is not None:
            at = self._home_reached(axis, homing)
            if at is not None:
                self.home_found(axis, homing, at)
                return
        self.schedule_switches(axis)

    def world_changed(self) -> None:
        """The stage changed under the board (a switch moved, a fault was injected, an
        input changed): act on what is now true, find the next switch events again, and
        let waiting queues look. Called from outside the engine (the API, scripts), and
        after any change to `capture_config`."""
        was_capturing = self._capturing_inputs
        self._capturing_inputs = any(c.on_inputs for c in self.capture_config)
        if self._capturing_inputs:
            if not was_capturing:
                self._input_levels = read_inputs(self)  # no edge for what was already so
            capture_inputs(self)
        for axis in self.axes:
            self.check_motion(axis)
            self.check_slip(axis)
            self.maintain(axis)
        for task in self.tasks.values():
            task.override_changed(self)  # an analog override input may have moved
        self.run_queues()

    # ---- encoder steppers: slip (stall) detection and position maintenance ------------
    def check_slip(self, axis: Axis) -> None:
        """TN with ES: an encoder stepper whose encoder disagrees with its motor by more
        than the slip tolerance has stalled: the slip flag (doorbell bit 16+i, EA 'S'),
        and the axis stops at once with its queue flushed, like a hard limit."""
        c = axis.config
        if c.axis_type != "E" or not c.slip_detect or axis.correcting is not None:
            return
        if abs(axis.position_error(self)) <= c.slip_tolerance:
            return
        self.set_axis_flag(axis, F.AXIS_SLIP)
        self.stop_with_linked(axis, hard=True)

    def maintain(self, axis: Axis, in_position_wait: bool = False) -> None:
        """HN on an encoder stepper at rest: if the encoder is outside the deadband (HD)
        of where the motor counter says it should be, step the stage back at the hold
        velocity (HV). The correction does not change the motor counter (RP).
        `in_position_wait`: an IP entry waits for this correction, so its own place in
        the queue does not count as work."""
        if not axis.holding or axis.motion is not None or axis.config.axis_type != "E":
            return
        if not in_position_wait and (axis.wait is not None or len(axis.queue)):
            return  # the queue is busy: maintenance waits for the axis to be idle
        error = axis.position_error(self)
        if abs(error) <= axis.config.hold_deadband:
            return
        c = axis.config
        steps = round(axis.to_steps(error))
        if steps == 0:
            return
        velocity = max(1, round(axis.to_steps(c.hold_velocity))) if c.hold_velocity \
            else c.velocity
        origin = axis.steps
        motion = plan_move(steps, 0, velocity, c.acceleration, c.deceleration, c.ramp,
                           *c.ramp_params)
        if axis.start_motion(motion, self):
            axis.correcting = origin

    def _home_reached(self, axis: Axis, homing: Homing) -> int | None:
        """The exact position where home was met during the last update cycle, if it was:
        the hardware latches the count, even when the axis passed it within the cycle."""
        steps = axis.steps_now(self)
        previous = axis.steps_at_tick(self.tick - 1, self.period)
        step = 1 if steps >= previous else -1
        if abs(steps - previous) > 100_000:
            previous = steps - step * 100_000
        for p in range(previous, steps + step, step):
            if home_condition(axis.config, self.world.axes[axis.index], p):
                return p
        return None

    def limit_tripped(self, axis: Axis) -> None:
        """Overtravel: flag, then stop at once and flush the queue (LMH/SF, the factory
        style), or decelerate and let the rest of the queue run after the stop (LMS/SL:
        TALON's PC39 homing string seeks a limit and queues the home search behind it;
        D for the MAXk, facts table 2). The other axes of a coordinated MT/ML move stop
        with it; a contour's axes stop with their path and flush."""
        self.set_axis_flag(axis, F.AXIS_OVERTRAVEL)
        if axis.config.limit_hard_stop or getattr(axis.motion, "contour", False):
            self.stop_with_linked(axis, hard=axis.config.limit_hard_stop)
            return
        for stopping in [axis, *axis.linked]:
            stopping.linked = []
            stopping.stop(self)

    def stop_with_linked(self, axis: Axis, hard: bool) -> None:
        """A fault on one axis (limit, stall, following-error trip): it and the other
        axes of its MT/ML move flush their queues and stop at once (hard) or ramp down."""
        for stopping in [axis, *axis.linked]:
            stopping.linked = []
            stopping.flush(self)
            if hard:
                stopping.kill(self)  # also ends a home search, moving or not
            else:
                stopping.stop(self)

    def start_homing(self, axis: Axis, direction: int, load_value: int | None) -> bool:
        """HM/HR/KM/KR: see homing.py for the search. False when home is already here."""
        if axis.velocities_refused(self, "HM" if direction > 0 else "HR"):
            return False
        homing = Homing(direction, load_value)
        here = axis.steps_now(self)
        if home_condition(axis.config, self.world.axes[axis.index], here):
            self.home_found(axis, homing, here)
            return False
        axis.homing = homing
        velocity = direction * axis.config.velocity
        if not axis.start_jog(velocity, self):
            axis.homing = None
            return False
        return True

    def home_found(self, axis: Axis, homing: Homing, at: int) -> None:
        """Home met at physical position `at`: load the counters there, ramp to a stop."""
        axis.homing = None
        old_motor, old_encoder = axis.counter_offset, axis.encoder_offset
        if homing.load_value is not None:
            axis.counter_offset = homing.load_value - at
            if axis.servo is not None:  # as LP does: encoder hosts read RE
                axis.encoder_offset = homing.load_value - axis.servo.encoder_counts()
            else:  # an open-loop stepper's ideal encoder too: RE stays equal to RP
                axis.encoder_offset = homing.load_value - axis.encoder_counts(at, self)
        axis.resync(self)
        if axis.servo is not None:
            axis.servo.counters_moved(axis.counter_offset - old_motor,
                                      axis.encoder_offset - old_encoder)
        axis.stop(self)

    @staticmethod
    def limit_bits(index: int) -> tuple[int, int]:
        """(minus, plus) bit numbers of an axis in QL and the limit word (Table 3-2)."""
        return (index, index + 8) if index < 8 else (index + 8, index + 16)

    def limit_inputs_raw(self) -> int:
        """QL: raw limit input levels (evidence 3.4 layout). Switches are wired to match
        the configured level: a pressed active-low switch reads 0, a released one 1."""
        word = 0
        for axis in self.axes:
            i = axis.index
            high = axis.config.limit_active_high
            minus = self.limit_pressed(axis, -1) == high
            plus = self.limit_pressed(axis, 1) == high
            minus_bit, plus_bit = self.limit_bits(i)
            word |= (minus << minus_bit) | (plus << plus_bit)
        return word

    def limit_status_word(self) -> int:
        """Shared memory 0x40 (Table 3-2): bit set while that limit is active."""
        word = 0
        for axis in self.axes:
            minus_bit, plus_bit = self.limit_bits(axis.index)
            word |= (self.limit_pressed(axis, -1) << minus_bit)
            word |= (self.limit_pressed(axis, 1) << plus_bit)
        return word

    def home_status_word(self) -> int:
        """Shared memory 0x44 (Table 3-3): bit i while axis i's home switch is active."""
        return sum(1 << a.index for a in self.axes if self.home_active(a))

    # ---- parameters, power-up and reset -----------------------------------------------
    @property
    def firmware_flags(self) -> int:
        """Shared memory 0x048 (Table 3-4): 0xFFFFFFFF until power-up initialization is
        over (the first update cycle), then the running bit and what was loaded."""
        if self.tick < self._init_done_tick:
            return F.FIRMWARE_INITIALIZING
        return self.firmware_state

    @property
    def cycle_count(self) -> int:
        """Update cycles since power-up or the last reset (CC)."""
        return self.tick - self._cycle_origin

    def _apply_parameters(self, sets: list[dict] | None) -> None:
        """The archived fields from `sets` (None: the factory set); what the archive does
        not hold (axis type, homing logic, TN, ...) stays. All axes are checked before any
        changes (ValueError); encoder counters read on where they were (ER may change)."""
        factory = snapshot(AxisConfig())
        if sets is not None and (not isinstance(sets, list) or len(sets) < len(self.axes)):
            raise ValueError("the archive does not hold a set for every axis")
        configs = [restore(axis.config, factory if sets is None else sets[axis.index])
                   for axis in self.axes]
        for axis, config in zip(self.axes, configs, strict=True):
            encoder = axis.encoder_position(self)
            axis.config = config
            axis.keep_encoder_reading(encoder, self)

    def load_power_up_parameters(self) -> None:
        """Power-up: the saved parameter set if the archive is good, else the factory set
        with the checksum-error bit (12) and the factory bit (18)."""
        state = F.FIRMWARE_RUNNING
        try:
            sets = self.archive.load(self.model.name)
        except (ArchiveError, ValueError, TypeError, KeyError) as exc:
            sets = None
            state |= F.ARCHIVE_CHECKSUM_ERROR
            self.errors.append(CommandErrorRecord(self.tick, "", f"power-up: {exc}"))
        try:
            self._apply_parameters(sets)
        except Exception as exc:  # a valid checksum over values this
            self._apply_parameters(None)  # firmware cannot take: the factory set
            sets = None
            state |= F.ARCHIVE_CHECKSUM_ERROR
            self.errors.append(CommandErrorRecord(self.tick, "", f"power-up: {exc}"))
        state |= F.USER_DEFAULTS_LOADED if sets is not None else F.FACTORY_DEFAULTS_LOADED
        self.firmware_state = state

    def save_parameters(self) -> None:
        """APP: the working parameters become the power-up defaults. A failed write
        sets the programming-error bit (13) and raises ArchiveError."""
        try:
            self.archive.save(self.model.name, [a.config for a in self.axes])
        except ArchiveError:
            self.firmware_state |= F.ARCHIVE_PROGRAMMING_ERROR
            raise
        self.firmware_state &= ~F.ARCHIVE_PROGRAMMING_ERROR

    def restore_parameters(self, factory: bool) -> None:
        """RDF (factory) / RDP (the saved set) into working memory. RDP with no saved
        set, or a bad one, raises ArchiveError and changes nothing."""
        sets = None
        if not factory:
            sets = self.archive.load(self.model.name)
            if sets is None:
                raise ArchiveError("no parameters were saved (APP)")
        try:
            self._apply_parameters(sets)  # checks every axis before it changes one
        except Exception as exc:  # any bad value: nothing changes
            raise ArchiveError(f"archive values not accepted: {exc}") from None
        loaded = F.FACTORY_DEFAULTS_LOADED if factory else F.USER_DEFAULTS_LOADED
        self.firmware_state = (self.firmware_state & ~(F.FACTORY_DEFAULTS_LOADED
                                                       | F.USER_DEFAULTS_LOADED)) | loaded

    def reset(self) -> None:
        """A controller reset: everything stops at once, queues, flags and modes clear,
        servo loops open, position counters read 0 where the stages stand, and the
        power-up sequence runs again (flags 0xFFFFFFFF for one update cycle, then the
        parameters from the archive or the factory). Virtual time goes on."""
        for axis in self.axes:
            axis.flush(self)
            axis.kill(self)
        # where the stages stand: a servo's motor is where its encoder says
        physical = [a.steps if a.servo is None else round(a.servo.p) for a in self.axes]
        stages = [a.backlash_now(self) for a in self.axes]  # the play and BC's extra steps
        self.tasks = {}
        kept = [a.config for a in self.axes]
        self.axes = [Axis(i, letter) for i, letter in enumerate(self.model.axis_letters)]
        for axis, steps, config, stage in zip(self.axes, physical, kept, stages, strict=True):
            axis.steps = steps
            axis.backlash = stage
            axis.counter_offset = -steps
            axis.config = AxisConfig(home_encoder=config.home_encoder,
                                     home_pattern=config.home_pattern)
            axis.encoder_offset = -axis.encoder_counts(steps, self)
            axis.rest_since = self.tick
        self._servo_axes = []
        self.io = GeneralIO.for_lines(self.model.io_lines)
        self.capture_ring = CaptureRing()
        self.capture_config = [CaptureConfig() for _ in self.axes]
        self.mode = "single"
        self.current_axis = 0
        self.command_error = False
        self.cross_axis_event = False
        if self.update_rate_hz != DEFAULT_UPDATE_RATE_HZ:
            self.set_update_rate(DEFAULT_UPDATE_RATE_HZ)
        self._init_done_tick = self.tick + 1
        self._cycle_origin = self.tick
        self.load_power_up_parameters()
        self.world_changed()

    # ---- vector tasks ----------------------------------------------------------------
    def contour_task(self, index: int) -> ContourTask:
        """Vector task 1-8 (contouring), made on first use."""
        if index not in TASKS:
            raise KeyError(f"no vector task {index} (1-{TASKS[-1]})")
        task = self.tasks.get(index)
        if task is None:
            task = self.tasks[index] = ContourTask(index)
            if self._tasks_source is None:  # (a board that never contours asks no tasks)
                self._tasks_source = _TasksSource(self)
                self.add_source(self._tasks_source)
        return task

    # ---- whole-board actions ---------------------------------------------------------
    def set_update_rate(self, rate_hz: int) -> None:
        """#UR: a new update rate resets the position counters (evidence 2.5, TRAJ)."""
        self.change_update_rate(rate_hz)
        for axis in self.axes:
            old_motor, old_encoder = axis.counter_offset, axis.encoder_offset
            axis.counter_offset = -axis.steps
            if axis.servo is not None:
                axis.encoder_offset = -axis.servo.encoder_counts()
                axis.servo.counters_moved(axis.counter_offset - old_motor,
                                          axis.encoder_offset - old_encoder)
            else:
                axis.encoder_offset = -axis.encoder_counts(axis.steps, self)
            axis.resync(self)

    def stop_all(self) -> None:
        """SA: every axis stops as ST stops one."""
        for axis in self.axes:
            axis.stop_and_flush(self)

    def kill_all(self) -> None:
        for axis in self.axes:
            axis.flush(self)
            axis.kill(self)


def _limit_within(steps: int, reach: tuple[float, float], world: AxisWorld) -> bool:
    """Could a motion whose offsets stay within `reach` from `steps` meet a limit's edge?
    (Whole steps: the offset truncated, or the final one rounded; one step spare.)"""
    low = steps + math.floor(reach[0]) - 1
    high = steps + math.ceil(reach[1]) + 1
    plus, minus = world.plus_limit.low, world.minus_limit.high
    return (plus is not None and high >= plus) or (minus is not None and low <= minus)


class _AxesSource:
    """The axes as one event source: motions ending, switches and capture edges reached,
    queue waits expiring, inputs polled while captured. Every axis whose queue may now
    move is marked for the board's `after_events`, in axis order (an axis waiting on an
    input looks at every event).

    One scan an event: `next_event` notes which axes share the earliest tick (and which
    wait on an input), and `on_event` at that very tick looks only at those. The engine
    asks `next_event` just before it acts, and nothing acts before the axes at a tick (they
    are the board's first source), so the note holds; any other call scans them all."""

    __slots__ = ("board", "_best", "_hits", "_inputs", "_noted")
    every_event = True  # an axis waiting on an input (SW) looks at every event

    def __init__(self, board: Board) -> None:
        self.board = board
        self._best: int | None = None
        self._hits: list[Axis] = []  # the axes whose next tick is _best, in axis order
        self._inputs: list[Axis] = []  # the axes waiting on an input
        self._noted = False

    def next_event(self) -> int | None:
        board = self.board
        best: int | None = None
        hits: list[Axis] = []
        inputs: list[Axis] | None = None
        for axis in board.axes:
            # Axis.next_event inlined for the common cases (asked for every axis at every
            # event): a motion's end, a switch, a tick wait; inputs by the method
            t = axis.motion_end
            switch = axis.switch_tick
            if switch is not None and (t is None or switch < t):
                t = switch
            wait = axis.wait
            if wait is not None and wait is not WAIT_MOTION:
                kind = type(wait)
                if kind is TickWait:
                    tick = wait.tick  # type: ignore[union-attr]
                    if t is None or tick < t:
                        t = tick
                elif kind is InputWait:
                    t = axis.next_event(board)
                    if inputs is None:
                        inputs = [axis]
                    else:
                        inputs.append(axis)
            if t is not None:
                if best is None or t < best:
                    best = t
                    hits = [axis]
                elif t == best:
                    hits.append(axis)
        if board._capturing_inputs and board.world.inputs_time_dependent():
            # inputs given as functions of time are looked at every update cycle while an
            # axis captures input edges (the edges are recorded in `after_events`)
            poll = board.tick + 1
            if best is None or poll < best:
                best, hits = poll, []
        self._best, self._hits, self._inputs = best, hits, inputs or []
        self._noted = True
        return best

    def on_event(self, now: int) -> None:
        board = self.board
        due = board._due
        if self._noted:
            self._noted = False
            best = self._best
            if best is not None and now > best:
                candidates = board.axes  # (time stood past the noted tick: look at all)
            elif best == now:
                candidates = self._hits
                if self._inputs:
                    marks = {a.index for a in candidates} | {a.index for a in self._inputs}
                    candidates = [board.axes[i] for i in sorted(marks)]
            else:
                candidates = self._inputs
        else:
            candidates = board.axes
        for axis in candidates:
            marked = False
            switch = axis.switch_tick
            if switch is not None and switch <= now:
                board._switch_event(axis)
                marked = True
            end = axis.motion_end
            if end is not None and end <= now:
                axis.finish_motion()
                marked = True
            elif not marked:
                wait = axis.wait
                if wait is not None:
                    kind = type(wait)
                    marked = kind is InputWait or (kind is TickWait and wait.tick <= now)  # type: ignore[union-attr]
            if marked:
                due.append(axis)


class _TasksSource:
    """The vector tasks: segment starts (VIO), contour ends, holds."""

    __slots__ = ("board", "_asked")

    def __init__(self, board: Board) -> None:
        self.board = board
        self._asked: list[tuple[ContourTask, int | None]] = []

    def next_event(self) -> int | None:
        board = self.board
        tasks = board.tasks
        if not tasks:  # (most boards run no vector task: asked at every event)
            if self._asked:
                self._asked = []
            return None
        best: int | None = None
        asked = self._asked = []
        for task in tasks.values():
            t = task.next_event(board)
            asked.append((task, t))
            if t is not None and (best is None or t < best):
                best = t
        return best

    def on_event(self, now: int) -> None:
        # the engine asked next_event() just before this call: the tasks' answers hold
        # (asked again for the tasks after one that acted, as it may have changed them)
        board = self.board
        due = board._due
        acted = False
        for task, asked in self._asked:
            t = task.next_event(board) if acted else asked
            if t is not None and t <= now:
                for axis in task.on_event(board):
                    # by identity: Axis is a dataclass, its == compares every field
                    if not any(d is axis for d in due):
                        due.append(axis)
                acted = True
