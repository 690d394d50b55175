"""One axis of the board: its parameters, its queue and its motion in closed form."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from maxk.firmware_model.axis import MotionAxis, MotionPlan
from maxk.firmware_model.profiles import RampShape, plan_jog, plan_move, plan_stop
from maxk.firmware_model.servo import Gains
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.queue import CommandQueue

if TYPE_CHECKING:
    from maxk.personalities.maxk.board import Board
    from maxk.personalities.maxk.coordinated import LinearMove
    from maxk.personalities.maxk.homing import Homing


def wrap32(value: int) -> int:
    """Position counters are signed 32-bit registers: they wrap, as the hardware's do."""
    return ((value + 0x8000_0000) & 0xFFFF_FFFF) - 0x8000_0000


# Waits a queue entry can leave the axis in. A tuple ("tick", t) waits for a tick.
WAIT_MOTION = "motion"  # until the running motion has ended, then go on
WAIT_REST_RETRY = "rest-retry"  # until the axis is at rest, then run the same entry again


@dataclass
class AxisConfig:
    """The axis parameters that commands set; factory defaults from manual 2.14."""

    velocity: int = 200_000  # VL, steps/s
    base_velocity: int = 0  # VB
    acceleration: int = 2_000_000  # AC (also sets the deceleration)
    deceleration: int = 2_000_000  # DC
    ramp: RampShape = RampShape.LINEAR
    ramp_factor: int = 0  # PN# operand, stored only (its meaning is not in the evidence)
    scurve_factor: int = 0  # SS#, stored only
    ramp_parameter: int = 0  # PR#, stored only
    axis_type: str = "O"  # PSO open-loop stepper, PSE stepper with encoder, PSM servo
    limit_active_high: bool = False  # LTL factory: active low
    limits_enabled: bool = True  # LN/LF, LMN/LMF
    limit_hard_stop: bool = True  # LMH stop at once (factory "hard"), LMS decelerate
    home_active_high: bool = False  # manual 2.14: "Home Active 'Low'" (HT/HH/HL)
    home_encoder: bool = False  # HE: encoder home logic; HS (factory): home switch alone
    home_pattern: str = "1111"  # EH: +A, -B, Index, Home switch (1 true, 0 false, X ignore)
    move_direction: int = 1  # MP / MM
    aux_auto: bool = False  # PA1: aux output on while moving
    settle_ms: int = 0  # SE: aux stays on this long after the axis comes to rest
    gains: Gains = field(default_factory=Gains)  # KP KI KD KU KV KA KF KO (servo)
    servo_bipolar: bool = True  # SVB1 +/-10 V (factory), SVB0 unipolar 0..10 V + sign
    servo_polarity: int = 1  # SVN normal (factory); SVI inverts the DAC output
    encoder_ratio: tuple[int, int] = (1, 1)  # ER: encoder counts, motor steps
    slip_tolerance: int = 0  # ES: encoder counts of disagreement before a slip
    slip_detect: bool = False  # TN/TF: stall (slip) detection on/off
    hold_velocity: int = 0  # HV: position maintenance correction velocity
    hold_deadband: int = 0  # HD: position maintenance deadband, encoder counts
    hold_gain: int = 0  # HG: position maintenance gain (stored)
    user_units: float | None = None  # UU: counts per user unit; None after UF (factory)


@dataclass
class Axis(MotionAxis):
    """A MAXk axis: the shared kinematics plus its parameters, queue and flags. The
    motor counter is 32-bit wrapped; the encoder is ideal but for the world's missed
    steps."""

    config: AxisConfig = field(default_factory=AxisConfig)
    queue: CommandQueue = field(default_factory=CommandQueue)
    capture_pending: list = field(default_factory=list)  # [(tick, home bits, edge steps)]
    pending_target: int | None = None  # set by MA/MR, consumed by GO
    pending_linear: LinearMove | None = None  # set by MT/ML, consumed by GO
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
    wait: object = None  # what the queue is blocked on

    def motor_position(self, board: Board) -> int:
        return wrap32(self.steps_at_tick(board.tick, board.period) + self.counter_offset)

    def encoder_position(self, board: Board) -> int:
        if self.servo is not None:
            return wrap32(self.servo.encoder_counts() + self.encoder_offset)
        return wrap32(self.encoder_counts(self.steps_now(board), board) + self.encoder_offset)

    def encoder_counts(self, steps: int, board: Board) -> int:
        """What a stepper's encoder counts at a motor position: the stage lags the motor
        by the steps it missed (a world fault), scaled by the ER ratio."""
        stage = steps - board.world.axes[self.index].lost_steps
        counts, motor_steps = self.config.encoder_ratio
        if counts == motor_steps:
            return stage
        return stage * counts // motor_steps

    def keep_encoder_reading(self, reading: int, board: Board) -> None:
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

    def position_error(self, board: Board) -> int:
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

    def resync(self, board: Board) -> None:
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
    def start_motion(self, motion: MotionPlan, board: Board, *, stopping: bool = False) -> bool:
        """Start a planned motion now. A motion into an active limit switch is refused
        (the overtravel flag is set instead); a stop is never refused."""
        if not stopping:
            self._end_correction()
        if not stopping and motion.phases and board.limit_blocks(self, motion.direction):
            board.refuse_into_limit(self)
            return False
        if not stopping:
            self.linked = []
        self.begin(motion, board)
        board.schedule_switches(self)
        return True

    def _rebase(self, board: Board) -> tuple[float, float]:
        """Freeze the running motion at this tick; return (fractional residual, velocity)."""
        self.capture_pending = []
        return self.freeze(board)

    def start_move(self, target: int, board: Board) -> bool:
        """GO: a point-to-point move from rest to target. False if nothing to do."""
        distance = target - self.motor_position(board)
        if distance == 0:
            return False
        c = self.config
        motion = plan_move(distance, c.base_velocity, c.velocity, c.acceleration,
                           c.deceleration, c.ramp)
        return self.start_motion(motion, board)

    def start_jog(self, velocity: int, board: Board) -> bool:
        """JG: ramp from the present velocity to a signed jog velocity and slew."""
        residual, current = self._rebase(board)
        c = self.config
        motion = plan_jog(residual, current, velocity, c.base_velocity, c.acceleration,
                          c.deceleration, c.ramp)
        return self.start_motion(motion, board, stopping=velocity == 0)

    def stop_and_flush(self, board: Board) -> None:
        """ST/SA: flush the queue and decelerate; later entries wait until the axis rests.

        An AC or DC the host queued just before the stop (`AX AC200000; ST ID;`, evidence
        E4) is applied first, so the stop uses the deceleration the host asked for.
        """
        for entry in self.queue.pending():
            if entry.mnemonic in ("AC", "DC"):
                entry.action(self, board)
        self.flush(board)
        self.stop(board)
        if self.motion is not None:
            self.wait = WAIT_REST_RETRY

    def stop(self, board: Board) -> None:
        """Decelerate to VB at the deceleration rate, then stop (ending any home search)."""
        self.homing = None
        if self.motion is None or getattr(self.motion, "contour", False):
            return  # a contour axis ramps down with its path (the flush told the contour)
        residual, current = self._rebase(board)
        c = self.config
        motion = plan_stop(residual, current, c.base_velocity, c.deceleration, c.ramp)
        self.start_motion(motion, board, stopping=True)

    def kill(self, board: Board) -> None:
        """KL/KS: stop at once, no deceleration; the position keeps the whole steps made."""
        self.homing = None
        if self.motion is None:
            return
        self._rebase(board)

    def finish_motion(self) -> None:
        super().finish_motion()
        self.capture_pending = []

    def motion_ended(self) -> None:
        self._end_correction()

    def _end_correction(self) -> None:
        """A position-maintenance move leaves the motor counter where it was: it moved
        the stage back under the encoder, not the commanded position."""
        if self.correcting is not None:
            moved = self.steps - self.correcting
            self.counter_offset -= moved
            self.lost_accounted += moved
            self.correcting = None

    def step(self, direction: int, board: Board) -> bool:
        """MO: one step in the MP/MM direction (refused into an active limit)."""
        if board.limit_blocks(self, direction):
            board.refuse_into_limit(self)
            return False
        self.steps += direction
        self.direction = direction
        return True

    def load_position(self, value: int, motor: bool, encoder: bool, board: Board) -> None:
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
    def next_event(self, board: Board) -> int | None:
        """The next tick at which something changes for this axis, if any."""
        best = self.motion_end
        switch = self.switch_tick
        if switch is not None and (best is None or switch < best):
            best = switch
        wait = self.wait
        if type(wait) is tuple:
            if wait[0] == "tick":
                t = wait[1]
            elif board.world.inputs_time_dependent():
                t = board.tick + 1  # an input that is a function: look every update cycle
            else:
                return best  # constant inputs change only through the world (world_changed)
            if best is None or t < best:
                best = t
        return best

    def run_queue(self, board: Board) -> bool:
        """Execute queue entries at the current tick until one blocks. True if progress."""
        progressed = False
        queue = self.queue
        while True:
            wait = self.wait
            if wait is not None:
                if wait == WAIT_MOTION:
                    if self.motion is not None:
                        return progressed
                    self.wait = None
                    queue.advance()
                elif wait == WAIT_REST_RETRY:
                    if self.motion is not None:
                        return progressed
                    self.wait = None
                elif type(wait) is tuple:
                    if wait[0] == "input":  # SW: wait for an input bit to read high
                        if not board.io.level(wait[1], board):
                            return progressed
                    elif board.tick < wait[1]:
                        return progressed
                    self.wait = None
                    queue.advance()
                else:  # a synchronisation group (AA-mode GO)
                    if not wait.ready(board):  # type: ignore[attr-defined]
                        return progressed
                    self.wait = WAIT_MOTION
                    continue
                progressed = True
            entry = queue.peek()
            if entry is None:
                return progressed
            result = entry.action(self, board)
            progressed = True
            if result is None:
                queue.advance()
            else:
                self.wait = result

    def flush(self, board: Board) -> None:
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

    def aux_level(self, board: Board) -> bool:
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
    def status_string(self, board: Board) -> str:
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

    def arrive(self, axis: Axis, board: Board) -> GroupWait:
        round_ = self.arrivals.get(axis.index, 0)
        self.arrivals[axis.index] = round_ + 1
        board.cross_axis_event = True  # other members' queues may now move
        self._maybe_fire(board)
        return GroupWait(self, round_)

    def withdraw(self, axis: Axis, board: Board) -> None:
        self.members.discard(axis.index)
        self.arrivals.pop(axis.index, None)
        board.cross_axis_event = True

    def _maybe_fire(self, board: Board) -> None:
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

    def ready(self, board: Board) -> bool:
        self.group._maybe_fire(board)
        return self.group.fired > self.round
