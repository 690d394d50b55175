"""One axis of the board: its parameters, its queue and its motion in closed form; the
AA-mode start groups and MT/ML linear moves that start axes together.

MT/ML linear interpolation (manual Appendix C): "The controller would calculate the
relative velocities required to perform a straight line move from the current position
to the desired absolute position so that all axes arrive at their destinations at the
same time." One reference profile is planned for the longest distance; each axis follows
it scaled by its own distance (`profiles.scaled`), so every point lies on the line. The
reference's speed, acceleration and deceleration are the largest that keep every axis
within its own VL, AC and DC (and VB); the ramp shape is the first axis's. Limits (D):
an axis that would start into a pressed limit refuses the whole move; a limit tripped on
one axis stops every axis of the move the same way and flushes their queues.

Long module: the axis and the AA start groups and MT/ML moves it waits on belong
together: a flush withdraws the axis from its group, a group's firing starts the axes;
apart, each would need the other's protocol.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol, cast

from maxk.firmware_model.axis import MotionAxis
from maxk.firmware_model.motion import Clock, MotionPlan
from maxk.firmware_model.profiles import plan_jog, plan_move, plan_stop, scaled
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.backlash import PLAIN_DOWN, PLAIN_UP, Backlash, walk
from maxk.personalities.maxk.config import AxisConfig, wrap32
from maxk.personalities.maxk.homing import Homing
from maxk.personalities.maxk.queue import QUEUE_COMMANDS_PER_UPDATE, CommandQueue
from maxk.personalities.maxk.waits import (
    WAIT_MOTION,
    WAIT_REST_RETRY,
    InputWait,
    SyncWait,
    TickWait,
    Wait,
)

if TYPE_CHECKING:
    from maxk.firmware_model.outputs import PositionTrigger
    from maxk.firmware_model.world import World
    from maxk.personalities.maxk.io import GeneralIO


class AxisHost(Protocol):
    """What an axis, a start group and a linear move ask of the board they are on (the
    MAXk `Board`, which sits above this module)."""

    tick: int
    period: float
    cross_axis_event: bool

    @property
    def axes(self) -> Sequence[Axis]: ...
    @property
    def world(self) -> World: ...
    @property
    def io(self) -> GeneralIO: ...

    def limit_blocks(self, axis: Axis, direction: int) -> bool: ...
    def refuse_into_limit(self, axis: Axis) -> None: ...
    def schedule_switches(self, axis: Axis) -> None: ...
    def report_error(self, reason: str, command: str = "") -> None: ...


@dataclass
class Axis(MotionAxis):
    """A MAXk axis: the shared kinematics plus its parameters, queue and flags. The
    motor counter is 32-bit wrapped; the encoder is ideal but for the world's missed
    steps."""

    config: AxisConfig = field(default_factory=AxisConfig)
    queue: CommandQueue = field(default_factory=CommandQueue)
    # position-capture edges ahead: (tick reached, trigger with the entry's home bits)
    capture_pending: list[tuple[int, PositionTrigger[int]]] = field(default_factory=list)
    pending_target: int | None = None  # set by MA/MR, consumed by GO
    pending_linear: LinearMove | None = None  # set by MT/ML, consumed by GO
    # queue entries executed at `queue_work_tick` (bounded by QUEUE_COMMANDS_PER_UPDATE)
    queue_work_tick: int = -1
    queue_work: int = 0
    homing: Homing | None = None  # a running HM/HR/KM/KR search
    linked: list = field(default_factory=list)  # the other axes of a running MT/ML move
    aux_on: bool = False  # AN / AF
    dac: int = 0  # AO: general purpose analog output count (non-servo axes)
    holding: bool = False  # HN on an encoder stepper: position maintenance
    # The lost steps the counters account for: set where motor and encoder were last
    # made to agree (LP, LO, LPE, ER, PS, homing, #UR) and moved on by every position-
    # maintenance correction. Missed steps beyond it are the position error.
    lost_accounted: int = 0
    correcting: int | None = None  # steps at the start of a position-maintenance move
    units_seen: bool = False  # a UU was sent: operand ranges are checked on the counts
    flags: int = 0  # latched AXIS_DONE / AXIS_OVERTRAVEL / AXIS_SLIP
    wait: Wait | None = None  # what the queue is blocked on
    backlash: Backlash = field(default_factory=Backlash)  # at the running motion's origin
    # an ended motion still to walk: (origin, plan, seconds run or None: all, end step)
    backlash_pending: tuple[int, MotionPlan, float | None, int] | None = None
    _play: int = 0  # the world's play when the running motion began (finish has no board)

    def motor_position(self, board: AxisHost) -> int:
        value = self.steps_at_tick(board.tick, board.period) + self.counter_offset
        return value if -0x8000_0000 <= value <= 0x7FFF_FFFF else wrap32(value)

    def encoder_position(self, board: AxisHost) -> int:
        if self.servo is not None:
            return wrap32(self.servo.encoder_counts() + self.encoder_offset)
        return wrap32(self.encoder_counts(self.steps_now(board), board) + self.encoder_offset)

    def encoder_counts(self, steps: int, board: AxisHost) -> int:
        """What a stepper's encoder counts at a motor position: the stage lags the motor
        by the steps it missed (a world fault) and by its backlash (less BC's extra
        steps), scaled by the ER ratio."""
        stage = steps - board.world.axes[self.index].lost_steps + self.stage_offset(board)
        counts, motor_steps = self.config.encoder_ratio
        if counts == motor_steps:
            return stage
        return stage * counts // motor_steps

    def keep_encoder_reading(self, reading: int, board: AxisHost) -> None:
        """After a change of type or ratio the encoder counter reads on from `reading`,
        and motor and encoder agree from here."""
        self.encoder_offset = 0
        self.encoder_offset = reading - self.encoder_position(board)
        self.resync(board)

    def to_steps(self, counts: float) -> float:
        """Encoder mode (ER): distances, velocities and accelerations arrive in encoder
        counts; the motor runs in steps."""
        counts_per, steps_per = self.config.encoder_ratio
        return counts if counts_per == steps_per else counts * steps_per / counts_per

    def position_error(self, board: AxisHost) -> int:
        """Encoder stepper: how far the encoder reads from where it would, had no steps
        been missed since the counters last agreed (encoder counts; exact at any ER
        ratio: the same rounding on both sides)."""
        lost = board.world.axes[self.index].lost_steps
        if lost == self.lost_accounted:
            return 0
        steps = self.steps_now(board)
        counts, motor_steps = self.config.encoder_ratio
        if counts == motor_steps:
            return lost - self.lost_accounted
        return ((steps - self.lost_accounted) * counts // motor_steps
                - (steps - lost) * counts // motor_steps)

    # ---- backlash (backlash.py) ----------------------------------------------------------
    def backlash_now(self, board: AxisHost) -> Backlash:
        """The stage's backlash state at this tick (a servo has none)."""
        self._settle_backlash(board)
        m = self.motion
        if m is None or self.servo is not None:
            return self.backlash
        t = (board.tick - self.motion_start) * board.period
        return walk(self.backlash, self.steps, m, t, self.steps_now(board),
                    board.world.axes[self.index].backlash, self.config.backlash)

    def stage_offset(self, board: AxisHost) -> int:
        """Steps the stage stands ahead of the motor counter's steps (backlash, BC)."""
        if self.servo is not None:
            return 0
        self._settle_backlash(board)
        s = self.backlash
        if self.motion is None or not (s.extra or s.play or self.config.backlash
                                       or board.world.axes[self.index].backlash):
            return s.offset
        return self.backlash_now(board).offset

    def _settle_backlash(self, board: AxisHost) -> None:  # finish_motion has no board
        pending = self.backlash_pending
        if pending is not None:
            self.backlash_pending = None
            origin, motion, until, end = pending
            play, bc, state = board.world.axes[self.index].backlash, self.config.backlash, \
                self.backlash
            if not (play or bc or state.play) and getattr(motion, "monotonic", False):
                moved = end - origin  # no play, no BC, one way: only the direction (hot)
                if moved and (moved > 0) != (state.direction > 0):
                    self.backlash = state.turned()
                return
            self.backlash = walk(state, origin, motion, until, end, play, bc)

    def begin(self, motion: MotionPlan, engine: Clock) -> None:
        board: AxisHost = engine  # type: ignore[assignment]  # (a board is the clock)
        if self.backlash_pending is not None:
            self._settle_backlash(board)
        self._play = board.world.axes[self.index].backlash
        super().begin(motion, engine)

    def freeze(self, engine: Clock) -> tuple[float, float]:
        m, origin, t = self.motion, self.steps, (engine.tick - self.motion_start) * engine.period
        out = super().freeze(engine)
        if m is not None and self.servo is None:
            self.backlash_pending = (origin, m, t, self.steps)
            self._settle_backlash(cast("AxisHost", engine))
        return out

    def resync(self, board: AxisHost) -> None:
        """Motor and encoder agree here (after LP, LO, LPE, ER, PS, homing, #UR)."""
        self.lost_accounted = board.world.axes[self.index].lost_steps

    @property
    def has_encoder(self) -> bool:
        return self.config.axis_type in ("E", "M")

    @property
    def loop_closed(self) -> bool:
        """CL?: a servo's PID running, or an encoder stepper's position maintenance."""
        if self.servo is not None:
            return self.servo.closed and not self.servo.tripped
        return self.holding

    # ---- motion control --------------------------------------------------------------
    def start_motion(self, motion: MotionPlan, board: AxisHost, *, stopping: bool = False) -> bool:
        """Start a planned motion now. A motion into an active limit switch is refused
        (the overtravel flag is set instead); a stop is never refused."""
        if not stopping and self.correcting is not None:
            self._end_correction()
        if not stopping and motion.phases and board.limit_blocks(self, motion.direction):
            board.refuse_into_limit(self)
            return False
        if not stopping and self.linked:
            self.linked = []
        self.begin(motion, board)
        board.schedule_switches(self)
        return True

    def _rebase(self, board: AxisHost) -> tuple[float, float]:
        """Freeze the running motion at this tick; return (fractional residual, velocity)."""
        self.capture_pending = []
        return self.freeze(board)

    def velocities_refused(self, board: AxisHost, command: str) -> bool:
        """VL and VB are a pair only when a move uses them: set alone, either may pass the
        other (the EPICS motor record sends VL before VB); a move that would use VB not
        below VL is a command error and does not start (D, issue 40; 'OMS errors if VB =
        VL', evidence 2.2)."""
        c = self.config
        if c.base_velocity < c.velocity:
            return False
        board.report_error(f"VB{c.base_velocity} is not below VL{c.velocity}",
                           f"A{self.letter} {command}")
        return True

    def start_move(self, target: int, board: AxisHost) -> bool:
        """GO: a point-to-point move from rest to target. False if nothing to do."""
        distance = target - self.motor_position(board)
        if distance == 0 or self.velocities_refused(board, "GO"):
            return False
        return self.start_motion(self.config.plan_move(distance), board)

    def start_jog(self, velocity: float, board: AxisHost) -> bool:
        """JG: ramp from the present velocity to a signed jog velocity and slew (JF's
        keeps a fraction of a step/s: a float, which a compiled build must be told)."""
        residual, current = self._rebase(board)
        c = self.config
        motion = plan_jog(residual, current, velocity, c.base_velocity, c.acceleration,
                          c.deceleration, c.ramp, *c.ramp_params)
        return self.start_motion(motion, board, stopping=velocity == 0)

    def stop_and_flush(self, board: AxisHost) -> None:
        """ST/SA: flush the queue and decelerate; later entries wait until the axis rests.

        An AC or DC the host queued just before the stop (`AX AC200000; ST ID;`, evidence
        E4) is applied first, so the stop uses the deceleration the host asked for.
        """
        for entry in self.queue.pending():
            if entry.applied_at_stop:
                entry.action(self, board)
        self.flush(board)
        self.stop(board)
        if self.motion is not None:
            self.wait = WAIT_REST_RETRY

    def stop(self, board: AxisHost) -> None:
        """Decelerate to VB at the deceleration rate, then stop (ending any home search)."""
        self.homing = None
        if self.motion is None or getattr(self.motion, "contour", False):
            return  # a contour axis ramps down with its path (the flush told the contour)
        residual, current = self._rebase(board)
        c = self.config
        motion = plan_stop(residual, current, c.base_velocity, c.deceleration, c.ramp,
                           c.ramp_params[1])
        self.start_motion(motion, board, stopping=True)

    def kill(self, board: AxisHost) -> None:
        """KL/KS: stop at once, no deceleration; the position keeps the whole steps made."""
        self.homing = None
        if self.motion is None:
            return
        self._rebase(board)

    def finish_motion(self) -> None:
        m = self.motion
        if m is not None and self.servo is None:
            state = self.backlash
            if not (self._play or self.config.backlash or state.play) and m.monotonic:
                moved = m.final_offset  # the hot path: only the direction changes
                if moved and (moved > 0) != (state.direction > 0):
                    # state.turned(), its plain case inlined (a compiled build calls
                    # no Python method per back-and-forth move)
                    self.backlash = ((PLAIN_DOWN if moved < 0 else PLAIN_UP)
                                     if not state.extra else state.turned())
            else:
                self.backlash_pending = (self.steps, m, None, self.steps + m.final_offset)
        super().finish_motion()
        if self.capture_pending:
            self.capture_pending = []

    def motion_ended(self) -> None:
        if self.correcting is not None:
            self._end_correction()

    def _end_correction(self) -> None:
        """A position-maintenance move leaves the motor counter where it was: it moved
        the stage back under the encoder, not the commanded position."""
        if self.correcting is not None:
            moved = self.steps - self.correcting
            self.counter_offset -= moved
            self.lost_accounted += moved
            self.correcting = None

    def step(self, direction: int, board: AxisHost) -> bool:
        """MO: one step in the MP/MM direction (refused into an active limit)."""
        if board.limit_blocks(self, direction):
            board.refuse_into_limit(self)
            return False
        self._settle_backlash(board)
        self.backlash = self.backlash.leg(direction, board.world.axes[self.index].backlash,
                                          self.config.backlash)
        self.steps += direction
        self.direction = direction
        return True

    def load_position(self, value: int, motor: bool, encoder: bool, board: AxisHost) -> None:
        """LP (both), LO (motor only), LPE (encoder only): counters move, the stage not."""
        steps = self.steps_now(board)
        old_motor, old_encoder = self.counter_offset, self.encoder_offset
        if motor:
            self.counter_offset = value - steps
            if self.correcting is not None:  # the counter is re-based: count from here
                self.correcting = steps
        if encoder:
            if self.servo is not None:
                self.encoder_offset = value - self.servo.encoder_counts()
            else:
                self.encoder_offset = value - self.encoder_counts(steps, board)
        self.resync(board)
        if self.servo is not None:  # LP0 zeroes the position error (manual 2.13)
            self.servo.counters_moved(self.counter_offset - old_motor,
                                      self.encoder_offset - old_encoder)

    # ---- queue -----------------------------------------------------------------------
    def next_event(self, board: AxisHost) -> int | None:
        """The next tick at which something changes for this axis, if any."""
        best = self.motion_end
        switch = self.switch_tick
        if switch is not None and (best is None or switch < best):
            best = switch
        wait = self.wait
        kind = type(wait)  # exact types: this runs for every axis at every event
        if kind is TickWait or kind is InputWait:
            if kind is TickWait:
                t = cast(TickWait, wait).tick
            elif board.world.inputs_time_dependent():
                t = board.tick + 1  # an input that is a function: look every update cycle
            else:
                return best  # constant inputs change only through the world (world_changed)
            if best is None or t < best:
                best = t
        return best

    def run_queue(self, board: AxisHost) -> bool:
        """Execute queue entries at the current tick until one blocks. True if progress."""
        progressed = False
        queue = self.queue
        while True:
            wait = self.wait
            if wait is not None:
                if wait is WAIT_MOTION:
                    if self.motion is not None:
                        return progressed
                    self.wait = None
                    queue.advance()
                elif wait is WAIT_REST_RETRY:
                    if self.motion is not None:
                        return progressed
                    self.wait = None
                elif type(wait) is TickWait:
                    if board.tick < wait.tick:
                        return progressed
                    self.wait = None
                    if not wait.retry:
                        queue.advance()
                elif type(wait) is InputWait:
                    if board.io.level(wait.bit, board) == wait.low:
                        return progressed
                    self.wait = None
                    queue.advance()
                else:  # a synchronisation group (AA-mode GO) or a contour's anchor
                    if not cast(SyncWait, wait).ready(board):
                        return progressed
                    self.wait = WAIT_MOTION
                    continue
                progressed = True
            entry = queue.peek()
            if entry is None:
                return progressed
            tick = board.tick
            if self.queue_work_tick != tick:
                self.queue_work_tick = tick
                self.queue_work = 0
            elif self.queue_work >= QUEUE_COMMANDS_PER_UPDATE:
                self.wait = TickWait(tick + 1, retry=True)  # this update's share is spent
                return progressed
            self.queue_work += 1
            result = entry.action(self, board)
            progressed = True
            if result is None:
                queue.advance()
            else:
                self.wait = result

    def flush(self, board: AxisHost) -> None:
        """Drop every pending entry. An AA start group this axis had not yet joined no
        longer waits for it: the remaining members may start on this very tick."""
        queue = self.queue
        if self.pending_linear is not None:
            self.pending_linear.withdraw(self, board)
            self.pending_linear = None
        groups = [e.sync for e in queue.pending() if e.sync is not None]
        if isinstance(self.wait, GroupWait):
            groups.append(self.wait.group)
        for group in groups:
            group.withdraw(self, board)
            board.cross_axis_event = True
        queue.flush()
        self.wait = None
        self.pending_target = None

    def aux_level(self, board: AxisHost) -> bool:
        """The aux output: AN/AF, or in PA1 mode on while moving and SE ms after."""
        if self.aux_on:
            return True
        if not self.config.aux_auto:
            return False
        if self.motion is not None:
            return True
        settle = math.ceil(self.config.settle_ms / 1000.0 / board.period - 1e-9)
        return board.tick < self.rest_since + settle

    # ---- flags -----------------------------------------------------------------------
    def status_string(self, board: AxisHost) -> str:
        """QA/RA: direction P|M, done D|N, on a limit L|N, home H|N (evidence 3.4).

        L and H are the live switch states; the latched overtravel flag is the doorbell's
        (bits 8-15), cleared by RA, IC or the host writing ones."""
        steps = self.steps_now(board)
        world = board.world.axes[self.index]
        on_limit = world.plus_limit.active(steps) or world.minus_limit.active(steps)
        return (
            ("P" if self.travel_direction(board) >= 0 else "M")
            + ("D" if self.flags & F.AXIS_DONE else "N")
            + ("L" if on_limit else "N")  # live: asyn sets limit status from it
            + ("H" if world.home.active(steps) else "N")
        )


class StartGroup:
    """An AA-mode GO: every member's queue must reach it, then all start on one tick.

    Inside an LS/LE loop the same GO is reached again on every pass, so the group fires
    in rounds: round r fires when every member has arrived r + 1 times. An axis whose
    queue is flushed withdraws, so the others are not held forever.
    """

    __slots__ = ("members", "arrivals", "fired")

    def __init__(self, members: list[Axis]) -> None:
        self.members = {a.index for a in members}
        self.arrivals: dict[int, int] = {}
        self.fired = 0  # rounds fired so far

    def arrive(self, axis: Axis, board: AxisHost) -> GroupWait:
        round_ = self.arrivals.get(axis.index, 0)
        self.arrivals[axis.index] = round_ + 1
        board.cross_axis_event = True  # other members' queues may now move
        self._maybe_fire(board)
        return GroupWait(self, round_)

    def withdraw(self, axis: Axis, board: AxisHost) -> None:
        self.members.discard(axis.index)
        self.arrivals.pop(axis.index, None)
        board.cross_axis_event = True

    def _maybe_fire(self, board: AxisHost) -> None:
        while self.members and all(self.arrivals.get(m, 0) > self.fired for m in self.members):
            self.fired += 1
            for index in sorted(self.members):
                member = board.axes[index]
                if member.pending_linear is not None:
                    member.pending_linear.start(board)  # starts all its axes at once
                target = member.pending_target
                member.pending_target = None
                if target is not None:
                    member.start_move(target, board)


class GroupWait:
    """The queue wait of an axis standing at an AA-mode GO, for one round."""

    __slots__ = ("group", "round")

    def __init__(self, group: StartGroup, round_: int) -> None:
        self.group = group
        self.round = round_

    def ready(self, board: AxisHost) -> bool:
        self.group._maybe_fire(board)
        return self.group.fired > self.round


class LinearMove:
    """The axes and targets of one MT/ML command; its start group waits for their GOs."""

    def __init__(self, group: StartGroup) -> None:
        self.group = group
        self.targets: dict[int, int] = {}

    def set_target(self, axis: Axis, target: int) -> None:
        self.targets[axis.index] = target
        axis.pending_target = None
        axis.pending_linear = self

    def withdraw(self, axis: Axis, board: AxisHost) -> None:
        self.targets.pop(axis.index, None)
        self.group.withdraw(axis, board)

    def start(self, board: AxisHost) -> None:
        axes = [board.axes[i] for i in sorted(self.targets)]
        for axis in axes:
            axis.pending_linear = None
        distances = {a.index: self.targets[a.index] - a.motor_position(board) for a in axes}
        moving = [a for a in axes if distances[a.index] != 0]
        self.targets.clear()
        if not moving:
            return
        reference = max(abs(distances[a.index]) for a in moving)
        # Scale each axis's limits up to the reference distance; the tightest one wins.
        scale = {a.index: reference / abs(distances[a.index]) for a in moving}
        peak = min(a.config.velocity * scale[a.index] for a in moving)
        base = min(a.config.base_velocity * scale[a.index] for a in moving)
        accel = min(a.config.acceleration * scale[a.index] for a in moving)
        decel = min(a.config.deceleration * scale[a.index] for a in moving)
        first = moving[0].config
        motion = plan_move(reference, min(base, peak), peak, accel, decel, first.ramp,
                           *first.ramp_params)
        # One axis blocked by a pressed limit refuses the whole move: moving the others
        # alone would leave the line (D).
        blocked = [a for a in moving
                   if board.limit_blocks(a, 1 if distances[a.index] > 0 else -1)]
        if blocked:
            for axis in blocked:
                board.refuse_into_limit(axis)
            return
        for axis in moving:
            axis.start_motion(scaled(motion, distances[axis.index], reference), board)
            axis.linked = [a for a in moving if a is not axis]
