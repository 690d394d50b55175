"""The actions that queued motion commands leave in an axis queue: velocities and
ramps, moves and GO, jogs, steps, position loads, waits and loops, limits and homing.

An action returns None when finished or a wait that holds the queue (Axis.run_queue)."""

from __future__ import annotations

from maxk.commands.max.context import (
    Context,
    QueuedFactory,
    encoder_mode,
    in_counts,
    in_steps,
    scaled_out_of_range,
)
from maxk.firmware_model.profiles import RampShape
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.axis import Axis, LinearMove, StartGroup
from maxk.personalities.maxk.board import Board
from maxk.personalities.maxk.models import (
    POSITION_MAX,
    POSITION_MIN,
)
from maxk.personalities.maxk.queue import Action
from maxk.personalities.maxk.waits import WAIT_MOTION, WAIT_REST_RETRY, TickWait, Wait


def _velocity(raw: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        value = in_steps(axis, raw, 1)
        if axis.units_seen and scaled_out_of_range(axis, board, "VL", raw, value):
            return
        axis.config.velocity = value  # type: ignore[assignment]

    return action


def _base_velocity(raw: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        value = in_steps(axis, raw)
        if axis.units_seen and scaled_out_of_range(axis, board, "VB", raw, value):
            return
        axis.config.base_velocity = value  # type: ignore[assignment]

    return action


def _acceleration(raw: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        value = in_steps(axis, raw, 1)
        if axis.units_seen and scaled_out_of_range(axis, board, "AC", raw, value):
            return
        axis.config.acceleration = value  # type: ignore[assignment]
        axis.config.deceleration = value  # type: ignore[assignment]

    return action


def _ramp(shape: RampShape) -> QueuedFactory:
    def factory(value: object, ctx: Context) -> Action:
        def action(axis: Axis, board: Board) -> None:
            axis.config.ramp = shape
            if value is not None:
                axis.config.ramp_factor = value  # type: ignore[assignment]

        return action

    return factory


def _deceleration(raw: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        value = in_steps(axis, raw, 1)
        if not scaled_out_of_range(axis, board, "DC", raw, value):
            axis.config.deceleration = value

    return action


def _move_absolute(raw: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        value = target = in_counts(axis, raw)
        if encoder_mode(axis):  # an encoder position: go by the encoder's distance to it
            distance = value - axis.encoder_position(board)
            target = axis.motor_position(board) + round(axis.to_steps(distance))
        if not POSITION_MIN <= target <= POSITION_MAX:
                board.report_error(f"target {target} is outside the 32-bit position range",
                                   f"A{axis.letter} MA{value}")
                return
        axis.pending_target = target  # type: ignore[assignment]
        axis.pending_linear = None

    return action


def linear_target(move: LinearMove, raw: float, relative: bool) -> Action:
    """MT/ML on one axis: record its target in the shared linear move."""

    def action(axis: Axis, board: Board) -> None:
        value = in_counts(axis, raw)
        if encoder_mode(axis):  # encoder counts, as MA and MR take them
            distance = value if relative else value - axis.encoder_position(board)
            value = round(axis.to_steps(distance)) + (0 if relative
                                                      else axis.motor_position(board))
        target = axis.motor_position(board) + value if relative else value
        if not POSITION_MIN <= target <= POSITION_MAX:
            board.report_error(f"target {target} is outside the 32-bit position range",
                               f"A{axis.letter} {'ML' if relative else 'MT'}{value}")
            return
        move.set_target(axis, target)

    return action


def _move_relative(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        target = axis.motor_position(board) + in_steps(axis, value)
        if not POSITION_MIN <= target <= POSITION_MAX:
            board.report_error(f"target {target} is outside the 32-bit position range",
                               f"A{axis.letter} MR{value}")
            return
        axis.pending_target = target
        axis.pending_linear = None

    return action


def _go(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> Wait | None:
        if axis.motion is not None:
            return WAIT_REST_RETRY
        if axis.pending_linear is not None:
            # An MT/ML move starts when every axis in it has reached its GO (AM mode).
            return axis.pending_linear.group.arrive(axis, board)
        target = axis.pending_target
        if target is None:
            return None
        axis.pending_target = None
        # `moving`, not `axis.motion is not None`: the check above narrowed the
        # attribute to None, and a compiled build (mypyc) enforces what mypy narrowed
        if axis.start_move(target, board) and axis.moving:
            return WAIT_MOTION
        return None

    return action


def go_together(group: StartGroup) -> Action:
    def action(axis: Axis, board: Board) -> Wait | None:
        if axis.motion is not None:
            return WAIT_REST_RETRY
        return group.arrive(axis, board)

    return action


def _jog(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> Wait | None:
        velocity = in_steps(axis, value)
        if scaled_out_of_range(axis, board, "JG", value, velocity):
            return None
        axis.start_jog(velocity, board)
        if axis.motion is not None and axis.ramp_end > board.tick:
            return TickWait(axis.ramp_end)
        return None

    return action


def _one_step(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> Wait | None:
        if axis.motion is not None:
            return WAIT_REST_RETRY
        axis.step(axis.config.move_direction, board)
        return TickWait(board.tick + 1)

    return action


def _load(motor: bool, encoder: bool) -> QueuedFactory:
    def factory(value: object, ctx: Context) -> Action:
        def action(axis: Axis, board: Board) -> None:
            counts = in_counts(axis, value)
            if not POSITION_MIN <= counts <= POSITION_MAX:
                board.report_error(f"position {counts} is outside the 32-bit range",
                                   f"A{axis.letter} {ctx.command.text}")
                return
            axis.load_position(counts, motor, encoder, board)

        return action

    return factory


def _wait(value: object, ctx: Context) -> Action:
    """WT#: # update cycles (SySal converts its milliseconds with the ?UR rate)."""

    def action(axis: Axis, board: Board) -> Wait | None:
        ticks = int(value)  # type: ignore[call-overload]
        return TickWait(board.tick + ticks) if ticks > 0 else None

    return action


def _done(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        board.set_axis_flag(axis, F.AXIS_DONE)

    return action


def _loop_start(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        axis.queue.loop_start(value)  # type: ignore[arg-type]

    return action


def _loop_end(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> Wait | None:
        # Jumping back takes one update cycle, so no loop can spin within a tick.
        return TickWait(board.tick + 1) if axis.queue.loop_end() else None

    return action


def _limit_mode(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        c = axis.config
        if value == "F":
            c.limits_enabled = False
        else:
            c.limits_enabled = True
            if value in ("H", "S"):
                c.limit_hard_stop = value == "H"
        board.check_motion(axis)  # limits turned on while running into one: trip now

    return action


def _limits_on(enabled: bool) -> QueuedFactory:
    def factory(value: object, ctx: Context) -> Action:
        def action(axis: Axis, board: Board) -> None:
            axis.config.limits_enabled = enabled
            board.check_motion(axis)

        return action

    return factory


def _limit_level_for(attr: str) -> QueuedFactory:
    """LT/HT: an active level given as H or L."""

    def factory(value: object, ctx: Context) -> Action:
        def action(axis: Axis, board: Board) -> None:
            setattr(axis.config, attr, value == "H")

        return action

    return factory


def _home(direction: int, load: bool) -> QueuedFactory:
    def factory(value: object, ctx: Context) -> Action:
        def action(axis: Axis, board: Board) -> Wait | None:
            if axis.motion is not None:
                return WAIT_REST_RETRY
            load_value = (value if value is not None else 0) if load else None
            if board.start_homing(axis, direction, load_value):  # type: ignore[arg-type]
                return WAIT_MOTION
            return WAIT_REST_RETRY if axis.moving else None  # `moving`: see _go

        return action

    return factory


def _home_encoder_mode(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        axis.config.home_encoder = value != 0

    return action


# ---- what host programs send beyond the manual (issue 17) -----------------------------
def _fractional_jog(value: object, ctx: Context) -> Action:
    """JF: JG with the fraction of a step/s kept (tracking hosts resend it to steer)."""

    def action(axis: Axis, board: Board) -> Wait | None:
        axis.start_jog(float(value), board)  # type: ignore[arg-type]
        if axis.motion is not None and axis.ramp_end > board.tick:
            return TickWait(axis.ramp_end)
        return None

    return action


def _go_to(raw: object, ctx: Context) -> Action:
    """GP: MA# and GO in one (SySal's position segment); holds until the move ends."""

    def action(axis: Axis, board: Board) -> Wait | None:
        if axis.motion is not None:
            return WAIT_REST_RETRY
        target = in_counts(axis, raw)
        if not POSITION_MIN <= target <= POSITION_MAX:
            board.report_error(f"target {target} is outside the 32-bit position range",
                               f"A{axis.letter} GP{raw}")
            return None
        axis.pending_target = None
        axis.pending_linear = None
        # `moving`, not `axis.motion is not None`: the check above narrowed the
        # attribute to None, and a compiled build (mypyc) enforces what mypy narrowed
        if axis.start_move(target, board) and axis.moving:
            return WAIT_MOTION
        return None

    return action


def _timed_move(value: object, ctx: Context) -> Action:
    """TM±n: the distance VL covers in n update cycles, in the sign's direction."""

    def action(axis: Axis, board: Board) -> Wait | None:
        if axis.motion is not None:
            return WAIT_REST_RETRY
        cycles = int(value)  # type: ignore[call-overload]
        distance = round(axis.config.velocity * abs(cycles) * board.period)
        target = axis.motor_position(board) + (distance if cycles >= 0 else -distance)
        if not POSITION_MIN <= target <= POSITION_MAX:
            board.report_error(f"target {target} is outside the 32-bit position range",
                               f"A{axis.letter} TM{value}")
            return None
        # `moving`, not `axis.motion is not None`: the check above narrowed the
        # attribute to None, and a compiled build (mypyc) enforces what mypy narrowed
        if axis.start_move(target, board) and axis.moving:
            return WAIT_MOTION
        return None

    return action


CYCLE_COUNTER_MASK = 0x3FFF_FFFF  # CC: 30 bits (SySal checks 0..0x3FFFFFFF)


def _wait_cycle(value: object, ctx: Context) -> Action:
    """WTC#: hold the queue until the cycle counter CC reaches #; a time up to half the
    counter's range in the past is taken as passed (no wait)."""

    def action(axis: Axis, board: Board) -> Wait | None:
        ahead = (int(value) - board.cycle_count) & CYCLE_COUNTER_MASK  # type: ignore
        if ahead == 0 or ahead > CYCLE_COUNTER_MASK // 2:
            return None
        return TickWait(board.tick + ahead)

    return action


def _in_position(value: object, ctx: Context) -> Action:
    """IP: done once at rest and, under position maintenance, inside the deadband."""

    def action(axis: Axis, board: Board) -> Wait | None:
        if axis.motion is not None:
            return WAIT_REST_RETRY
        if axis.holding and abs(axis.position_error(board)) > axis.config.hold_deadband:
            board.maintain(axis, True)  # starts the correction that brings it in
            if axis.moving:  # `moving`, not `motion is not None`: see _go
                return WAIT_REST_RETRY
        board.set_axis_flag(axis, F.AXIS_DONE)
        return None

    return action


WHILE_FOREVER = 2**62
"""WH's loop count: no host runs a WH loop long enough to use it up."""


def _while_start(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        axis.queue.loop_start(WHILE_FOREVER)

    return action
