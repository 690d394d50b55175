"""What each command does: immediate handlers and the actions queued commands leave.

Immediate handlers take a Context and return the reply text (or None). Queued commands
become one QueueEntry per addressed axis whose action runs when the queue reaches it;
an action returns None when finished or a wait that holds the queue (see Axis.run_queue).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

from maxk.commands.max.lexer import ParsedCommand
from maxk.firmware_model.profiles import RampShape
from maxk.firmware_model.servo import ServoLoop
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.axis import Axis, LinearMove, StartGroup
from maxk.personalities.maxk.board import Board
from maxk.personalities.maxk.io import volts_to_counts
from maxk.personalities.maxk.models import (
    FIRMWARE_VERSION,
    FPGA_VERSION,
    POSITION_MAX,
    POSITION_MIN,
    SERIAL_NUMBER,
    UPDATE_RATES_HZ,
)
from maxk.personalities.maxk.parameters import ArchiveError
from maxk.personalities.maxk.queue import Action
from maxk.personalities.maxk.waits import WAIT_MOTION, WAIT_REST_RETRY, InputWait, TickWait


class CommandError(Exception):
    """The command is refused: the command-error flag is set and nothing changes."""


@dataclass(slots=True)
class Context:
    board: Board
    command: ParsedCommand
    axes: list[Axis]  # addressed axes (current axis, or every axis / the filled slots)
    values: list  # one operand value per addressed axis (None when there is none)

    @property
    def addressed(self) -> list[Axis]:
        """Axes an operand-less command acts on: the current axis, or all in AA/AM."""
        return self.board.axes if self.listing else self.axes

    @property
    def listing(self) -> bool:
        """True in AA/AM mode, where reports answer one comma-separated field per axis."""
        return self.board.mode != "single"

    def per_axis(self, fn: Callable[[Axis], str]) -> str:
        if self.listing:
            return ",".join(fn(a) for a in self.board.axes)
        return fn(self.axes[0])


# ---- queued actions -------------------------------------------------------------------
QueuedFactory = Callable[[object, Context], Action]


_OPERAND = object()


def _set(attr: str, constant: object = _OPERAND) -> QueuedFactory:
    """A queued setting: the axis parameter `attr` takes the operand (or a constant)."""

    def factory(value: object, ctx: Context) -> Action:
        new = value if constant is _OPERAND else constant

        def action(axis: Axis, board: Board) -> None:
            setattr(axis.config, attr, new)

        return action

    return factory


def encoder_mode(axis: Axis) -> bool:
    """ER put this encoder stepper in encoder mode: operands are encoder counts."""
    counts, steps = axis.config.encoder_ratio
    return axis.config.axis_type == "E" and counts != steps


def scaled_out_of_range(axis: Axis, board: Board, mnemonic: str, raw: object,
                        value: int) -> bool:
    """With user units on, ranges apply to the scaled value: report one outside."""
    if not axis.units_seen:
        return False  # the operand was range-checked when it arrived
    from maxk.commands.max.table import COMMANDS

    spec = COMMANDS[mnemonic]
    if spec.value_range is None:
        return False
    low, high = spec.value_range
    if low <= value <= high:
        return False
    board.report_error(f"{mnemonic}{raw} is {value} counts in user units: out of range "
                       f"({low:g} to {high:g})", f"A{axis.letter} {mnemonic}{raw}")
    return True


def in_counts(axis: Axis, value: object) -> int:
    """A position operand in counts: user units (UU) scale it and round to the nearest
    count; without them decimals truncate toward zero (MR-200.9 moves -200)."""
    factor = axis.config.user_units
    if factor is None:
        return int(value)  # type: ignore[call-overload]
    scaled = value * factor  # type: ignore[operator]
    return int(math.copysign(math.floor(abs(scaled) + 0.5), scaled))  # nearest, .5 away


def in_steps(axis: Axis, value: object, least: int = 0) -> int:
    """A distance, velocity or acceleration operand in motor steps: user units first,
    then encoder mode converts encoder counts to the nearest step."""
    c = axis.config
    if c.user_units is None:
        counts = int(value)  # type: ignore[call-overload]
        if c.axis_type != "E" or c.encoder_ratio[0] == c.encoder_ratio[1]:
            return counts if counts >= least or value < 0 else least  # type: ignore
    else:
        counts = in_counts(axis, value)
    if not encoder_mode(axis):
        return max(least, counts) if value >= 0 else counts  # type: ignore[operator]
    steps = round(axis.to_steps(counts))
    return max(least, steps) if value >= 0 else steps  # type: ignore[operator]


def _velocity(raw: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        value = in_steps(axis, raw, 1)
        if axis.units_seen and scaled_out_of_range(axis, board, "VL", raw, value):
            return
        if value <= axis.config.base_velocity:  # type: ignore[operator]
            board.report_error(f"VL{value} is not above VB{axis.config.base_velocity}",
                               f"A{axis.letter} VL{value}")
            return
        axis.config.velocity = value  # type: ignore[assignment]

    return action


def _base_velocity(raw: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        value = in_steps(axis, raw)
        if axis.units_seen and scaled_out_of_range(axis, board, "VB", raw, value):
            return
        if value >= axis.config.velocity:  # type: ignore[operator]
            board.report_error(f"VB{value} is not below VL{axis.config.velocity}",
                               f"A{axis.letter} VB{value}")
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
    def action(axis: Axis, board: Board) -> object:
        if axis.motion is not None:
            return WAIT_REST_RETRY
        if axis.pending_linear is not None:
            # An MT/ML move starts when every axis in it has reached its GO (AM mode).
            return axis.pending_linear.group.arrive(axis, board)
        target = axis.pending_target
        if target is None:
            return None
        axis.pending_target = None
        if axis.start_move(target, board) and axis.motion is not None:
            return WAIT_MOTION
        return None

    return action


def go_together(group: StartGroup) -> Action:
    def action(axis: Axis, board: Board) -> object:
        if axis.motion is not None:
            return WAIT_REST_RETRY
        return group.arrive(axis, board)

    return action


def _jog(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> object:
        velocity = in_steps(axis, value)
        if scaled_out_of_range(axis, board, "JG", value, velocity):
            return None
        axis.start_jog(velocity, board)
        if axis.motion is not None and axis.ramp_end > board.tick:
            return TickWait(axis.ramp_end)
        return None

    return action


def _one_step(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> object:
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
    def action(axis: Axis, board: Board) -> object:
        ticks = math.ceil(value / 1000.0 / board.period - 1e-9)  # type: ignore[operator]
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
    def action(axis: Axis, board: Board) -> object:
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
        def action(axis: Axis, board: Board) -> object:
            if axis.motion is not None:
                return WAIT_REST_RETRY
            load_value = (value if value is not None else 0) if load else None
            if board.start_homing(axis, direction, load_value):  # type: ignore[arg-type]
                return WAIT_MOTION
            return WAIT_REST_RETRY if axis.motion is not None else None

        return action

    return factory


def _home_encoder_mode(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        axis.config.home_encoder = value != 0

    return action


def _bit_level(high: bool) -> QueuedFactory:
    def factory(value: object, ctx: Context) -> Action:
        def action(axis: Axis, board: Board) -> None:
            bit = value  # type: ignore[assignment]
            if not board.io.direction >> bit & 1:  # type: ignore[operator]
                board.report_error(f"bit {bit} is an input (BD/IO make it an output)",
                                   f"{'BH' if high else 'BL'}{bit}")
                return
            board.io.set_output(bit, high, board.tick)  # type: ignore[arg-type]
            board.cross_axis_event = True  # an SW may be waiting on this line

        return action

    return factory


def _set_outputs(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        io = board.io
        io.latch((io.outputs & ~io.direction) | (value & io.direction),  # type: ignore[operator]
                 board.tick)
        board.cross_axis_event = True  # an SW may be waiting on this line

    return action


def _direction_mask(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        board.io.direction = value  # type: ignore[assignment]
        board.cross_axis_event = True  # an SW may be waiting on this line

    return action


def _configure_bit(value: object, ctx: Context) -> Action:
    bit, output = value  # type: ignore[misc]

    def action(axis: Axis, board: Board) -> None:
        if output:
            board.io.direction |= 1 << bit
        else:
            board.io.direction &= ~(1 << bit)
        board.cross_axis_event = True  # an SW may be waiting on this line

    return action


def _wait_input(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> object:
        if board.io.level(value, board):  # type: ignore[arg-type]
            return None
        return InputWait(value)

    return action


def _set_aux_state(on: bool) -> QueuedFactory:
    def factory(value: object, ctx: Context) -> Action:
        def action(axis: Axis, board: Board) -> None:
            axis.aux_on = on

        return action

    return factory


def _analog_out(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> None:
        if axis.config.axis_type == "M":
            board.report_error(f"AO: axis {axis.letter} is a servo; its DAC drives the motor",
                               f"A{axis.letter} AO{value}")
            return
        axis.dac = value  # type: ignore[assignment]

    return action


def _axis_type(value: object, ctx: Context) -> Action:
    """PSO/PSE/PSM. The type changes at rest (a running move finishes first); the
    counters carry on where they were, so RP and RE do not jump."""

    def action(axis: Axis, board: Board) -> object:
        if axis.motion is not None:
            return WAIT_REST_RETRY
        old = axis.config.axis_type
        if value == old:
            return None
        encoder = axis.encoder_position(board)
        if axis.servo is not None:  # leaving servo: the commanded position is where we are
            axis.servo = None
        axis.config.axis_type = value  # type: ignore[assignment]
        axis.holding = False
        if value == "M":  # the motor starts where the stepper stands
            axis.servo = ServoLoop(axis.steps, board.tick)
        axis.keep_encoder_reading(encoder, board)
        board.refresh_servo_axes()
        return None

    return action


def _gain(name: str) -> QueuedFactory:
    """KP KI KD KU KV KA KF KO: a filter coefficient (stored on any axis, used on PSM)."""

    def factory(value: object, ctx: Context) -> Action:
        def action(axis: Axis, board: Board) -> None:
            axis.config.gains = replace(axis.config.gains, **{name: float(value)})  # type: ignore

        return action

    return factory


def _loop(on: bool, mnemonic: str) -> QueuedFactory:
    """CL1/CL0 and HN/HF: a servo's loop closed or open; on an encoder stepper, position
    maintenance on or off. CL1 after a following-error trip re-enables the PID."""

    def factory(value: object, ctx: Context) -> Action:
        closing = on if value is None else value == "1"

        def action(axis: Axis, board: Board) -> None:
            servo = axis.servo
            if servo is not None:
                if closing and (not servo.closed or servo.tripped):
                    servo.tripped = False
                    error = axis.motor_position(board) - (servo.p + axis.encoder_offset)
                    servo.reset_filter(error)
                servo.closed = closing
                return
            if axis.config.axis_type == "E":
                axis.holding = closing
                if closing:
                    board.maintain(axis)
                return
            board.report_error(f"{mnemonic}: axis {axis.letter} is an open-loop stepper "
                               "(PSO): no encoder to close the loop on",
                               f"A{axis.letter} {ctx.command.text}")

        return action

    return factory


def _encoder_ratio(value: object, ctx: Context) -> Action:
    """ER counts,steps: the encoder ratio; an encoder stepper other than 1:1 is then in
    encoder mode (evidence 2.4). Motor and encoder are taken to agree from here."""
    counts, steps = value  # type: ignore[misc]

    def action(axis: Axis, board: Board) -> None:
        if counts <= 0 or steps <= 0:
            board.report_error("ER: both operands must be positive (encoder counts, motor "
                               "steps)", f"A{axis.letter} ER{counts},{steps}")
            return
        here = axis.encoder_position(board)
        axis.config.encoder_ratio = (counts, steps)
        axis.keep_encoder_reading(here, board)

    return action


def _hold_velocity(raw: object) -> Action:
    def action(axis: Axis, board: Board) -> None:
        value = in_counts(axis, raw)
        if not scaled_out_of_range(axis, board, "HV", raw, value):
            axis.config.hold_velocity = value

    return action


def _then_check_slip(attr: str, new: object) -> Action:
    """ES/TN: a disagreement that is already there counts from the moment detection
    (or the new tolerance) is in force."""

    def action(axis: Axis, board: Board) -> None:
        setattr(axis.config, attr, new)
        board.check_slip(axis)

    return action


QUEUED: dict[str, QueuedFactory] = {
    "VL": _velocity,
    "VB": _base_velocity,
    "AC": _acceleration,
    "DC": _deceleration,
    "LA": _ramp(RampShape.LINEAR),
    "PF": _ramp(RampShape.LINEAR),
    "PN": _ramp(RampShape.PARABOLIC),
    "SC": _ramp(RampShape.SCURVE),
    "CN": _ramp(RampShape.COSINE),
    "SS": _set("scurve_factor"),
    "PR": _set("ramp_parameter"),
    "MA": _move_absolute,
    "MR": _move_relative,
    "GO": _go,
    "GD": _go,
    "GN": _go,
    "JG": _jog,
    "MP": _set("move_direction", 1),
    "MM": _set("move_direction", -1),
    "MO": _one_step,
    "LP": _load(True, True),
    "LO": _load(True, False),
    "LPE": _load(False, True),
    "WT": _wait,
    "ID": _done,
    "LS": _loop_start,
    "LE": _loop_end,
    "PS": _axis_type,
    "CL": _loop(True, "CL"),
    "ER": _encoder_ratio,
    "ES": lambda value, ctx: _then_check_slip("slip_tolerance", value),
    "TN": lambda value, ctx: _then_check_slip("slip_detect", True),
    "TF": _set("slip_detect", False),
    "IS": lambda value, ctx: _then_check_slip("slip_detect", True),
    "HV": lambda value, ctx: _hold_velocity(value),
    "UU": _set("user_units"),
    "UF": _set("user_units", None),
    "HD": _set("hold_deadband"),
    "HG": _set("hold_gain"),
    "HN": _loop(True, "HN"),
    "HF": _loop(False, "HF"),
    "KP": _gain("kp"),
    "KI": _gain("ki"),
    "KD": _gain("kd"),
    "KU": _gain("ku"),
    "KV": _gain("kv"),
    "KA": _gain("ka"),
    "KF": _gain("kf"),
    "KO": _gain("ko"),
    "SVB": lambda value, ctx: _set("servo_bipolar", bool(value))(value, ctx),
    "SVN": _set("servo_polarity", 1),
    "SVP": lambda value, ctx: _set("servo_polarity", -1 if value == "-" else 1)(value, ctx),
    "LT": _limit_level_for("limit_active_high"),
    "LH": _set("limit_active_high", True),
    "LL": _set("limit_active_high", False),
    "LM": _limit_mode,
    "HM": _home(1, True),
    "HR": _home(-1, True),
    "KM": _home(1, False),
    "KR": _home(-1, False),
    "HS": _set("home_encoder", False),
    "HE": _set("home_encoder", True),
    "HI": _home_encoder_mode,
    "HT": _limit_level_for("home_active_high"),
    "HH": _set("home_active_high", True),
    "HL": _set("home_active_high", False),
    "EH": _set("home_pattern"),
    "BD": _direction_mask,
    "BH": _bit_level(True),
    "BL": _bit_level(False),
    "BS": _set_outputs,
    "IO": _configure_bit,
    "SW": _wait_input,
    "AN": _set_aux_state(True),
    "AF": _set_aux_state(False),
    "PA": lambda value, ctx: _set("aux_auto", value == "1")(value, ctx),
    "SE": _set("settle_ms"),
    "AO": _analog_out,
    "SL": _set("limit_hard_stop", False),
    "SF": _set("limit_hard_stop", True),
    "LN": _limits_on(True),
    "LF": _limits_on(False),
}

NOT_MODELLED_YET: dict[str, str] = {}
"""Commands in the table whose effect is not modelled yet: refused visibly, never ignored."""


def validate_queued(ctx: Context) -> None:
    """Refusals that can be decided when the command arrives, before anything is queued."""
    m = ctx.command.mnemonic
    if m in NOT_MODELLED_YET:
        raise CommandError(NOT_MODELLED_YET[m])
    if m == "UU":  # from now on this axis's operands are range-checked when they run
        for axis in ctx.axes:
            axis.units_seen = True
    if m == "IO" and ctx.values[0][1] not in (0, 1):
        raise CommandError("IO#,#: the second operand is 0 (input) or 1 (output)")


# ---- queries of queued settings (PS? LT? LM? CL?) --------------------------------------
def _limit_mode_letter(axis: Axis) -> str:
    c = axis.config
    if not c.limits_enabled:
        return "=f"
    return "=h" if c.limit_hard_stop else "=s"


SETTING_QUERIES: dict[str, Callable[[Axis], str]] = {
    "PS": lambda a: "=" + a.config.axis_type,
    "LT": lambda a: "=h" if a.config.limit_active_high else "=l",
    "HT": lambda a: "=h" if a.config.home_active_high else "=l",
    "LM": _limit_mode_letter,
    "CL": lambda a: "on" if a.loop_closed else "off",
}


# ---- immediate handlers ---------------------------------------------------------------
def _stop(ctx: Context) -> None:
    for axis in ctx.addressed:
        axis.stop_and_flush(ctx.board)


def _stop_all(ctx: Context) -> None:
    ctx.board.stop_all()


def _kill_all(ctx: Context) -> None:
    ctx.board.kill_all()


def _flagged_axes(ctx: Context) -> list[Axis]:
    """KS/SI: the axes with a 1 in their slot (AA/AM), or the addressed axis (KS, KS1)."""
    if ctx.listing and not ctx.command.slots:
        raise CommandError(f"{ctx.command.mnemonic} in AA/AM mode names the axes: "
                           f"{ctx.command.mnemonic}1,,1")
    if ctx.listing or ctx.values[0] is not None:
        return [a for a, v in zip(ctx.axes, ctx.values, strict=True) if v]
    return ctx.axes  # bare KS/SI in single-axis mode: the addressed axis


def _kill_selected(ctx: Context) -> None:
    for axis in _flagged_axes(ctx):
        axis.flush(ctx.board)
        axis.kill(ctx.board)


def _clear_queues(ctx: Context) -> None:
    """SI: flush the flagged axes' queues (the trajectory scan's 'clear motor queue')."""
    for axis in _flagged_axes(ctx):
        axis.flush(ctx.board)


def _clear_done(ctx: Context) -> None:
    for axis in ctx.addressed:
        ctx.board.clear_axis_flags(axis, F.AXIS_DONE)


def _interrupt_clear(ctx: Context) -> None:
    ctx.board.clear_interrupts()


def _flush(ctx: Context) -> None:
    for axis in ctx.addressed:
        axis.flush(ctx.board)


def _report_position(ctx: Context) -> str:
    board = ctx.board
    return ctx.per_axis(lambda a: str(a.motor_position(board)))


def _report_encoder(ctx: Context) -> str:
    board = ctx.board
    return ctx.per_axis(lambda a: str(a.encoder_position(board)))


def _every_axis(fn: Callable[[Axis, Board], object]) -> Callable[[Context], str]:
    """PP, PE, QI: a report that always lists every axis, whatever the mode."""

    def handler(ctx: Context) -> str:
        board = ctx.board
        return ",".join(str(fn(a, board)) for a in board.axes)

    return handler


def _report_velocity(ctx: Context) -> str:
    board = ctx.board
    return ctx.per_axis(lambda a: str(round(a.velocity(board))))


def _report_acceleration(ctx: Context) -> str:
    return ctx.per_axis(lambda a: str(a.config.acceleration))


def _query_axis(ctx: Context) -> str:
    board = ctx.board
    return ctx.per_axis(lambda a: a.status_string(board))


def _report_axis(ctx: Context) -> str:
    board = ctx.board
    reply = ctx.per_axis(lambda a: a.status_string(board))
    for axis in ctx.addressed:
        board.clear_axis_flags(axis, F.AXIS_DONE | F.AXIS_OVERTRAVEL | F.AXIS_SLIP)
    return reply


_status_all = _every_axis(Axis.status_string)


def _report_interrupts(ctx: Context) -> str:
    board = ctx.board
    reply = _status_all(ctx)
    for axis in board.axes:
        board.clear_axis_flags(axis, F.AXIS_DONE)
    return reply


def _queue_free(ctx: Context) -> str:
    return ctx.per_axis(lambda a: str(a.queue.free_units))


def _encoder_status(axis: Axis, board: Board) -> str:
    """Slip detection enabled E|D, position maintenance (or a servo's loop) enabled E|D,
    slipped S|N (the latched slip flag: a stall, or a servo's following-error trip),
    within the deadband D|N (while maintaining position), and the index mark under the
    encoder H|N (evidence 3.4)."""
    c = axis.config
    at_index = board.world.axes[axis.index].index_active(axis.steps_now(board))
    in_band = axis.holding and abs(axis.position_error(board)) <= c.hold_deadband
    return (("E" if c.slip_detect and axis.servo is None else "D")
            + ("E" if axis.loop_closed else "D")
            + ("S" if axis.flags & F.AXIS_SLIP else "N")
            + ("D" if in_band else "N")
            + ("H" if at_index else "N"))


def _encoder_report(ctx: Context) -> str:
    board = ctx.board
    if ctx.listing:
        return ",".join(_encoder_status(a, board) if a.has_encoder else "" for a in board.axes)
    axis = ctx.axes[0]
    if not axis.has_encoder:
        raise CommandError(f"EA: axis {axis.letter} has no encoder (PSO)")
    return _encoder_status(axis, board)


def _limits_raw(ctx: Context) -> str:
    return format(ctx.board.limit_inputs_raw(), "x")


def _identify(ctx: Context) -> str:
    return (f"{ctx.board.model.name}, ver:{FIRMWARE_VERSION}, S/N: {SERIAL_NUMBER}, "
            f"FPGA:{FPGA_VERSION}")


def _update_rate(ctx: Context) -> str | None:
    board = ctx.board
    if ctx.command.query:
        return str(board.update_rate_hz)
    rate = ctx.values[0]
    if rate not in UPDATE_RATES_HZ:
        raise CommandError(f"#UR{rate}: the update rate must be one of "
                           + ", ".join(map(str, UPDATE_RATES_HZ)))
    if not board.is_idle():
        raise CommandError("#UR: the update rate can only change while every axis is idle "
                           "(no motion, nothing queued)")
    board.set_update_rate(rate)
    return None


def _gain_query(name: str) -> Callable[[Context], str]:
    """?KA / ?KP: the gain of a servo axis; a command error on any other axis is how
    drivers detect that an axis has no PID (evidence 2.4)."""

    def handler(ctx: Context) -> str:
        def one(axis: Axis) -> str:
            if axis.servo is None:
                raise CommandError(f"{ctx.command.mnemonic}: axis {axis.letter} has no servo "
                                   "loop")
            return format_gain(getattr(axis.config.gains, name))

        if ctx.listing:
            return ",".join(one(a) if a.servo is not None else "" for a in ctx.board.axes)
        return one(ctx.axes[0])

    return handler


def format_gain(value: float) -> str:
    """Gains as the host sends them: `KP2.5` -> 2.5, `KP10` -> 10."""
    return f"{value:.6f}".rstrip("0").rstrip(".") or "0"


def _analog_in(ctx: Context) -> str:
    board = ctx.board
    return str(volts_to_counts(board.world.analog_volts(ctx.values[0], board)))


def _save_parameters(ctx: Context) -> None:
    try:
        ctx.board.save_parameters()
    except ArchiveError as exc:
        raise CommandError(f"APP: {exc} (firmware flag bit 13)") from None


def _restore_parameters(factory: bool) -> Callable[[Context], None]:
    def handler(ctx: Context) -> None:
        try:
            ctx.board.restore_parameters(factory)
        except ArchiveError as exc:
            raise CommandError(f"{ctx.command.mnemonic}: {exc}") from None

    return handler


IMMEDIATE: dict[str, Callable[[Context], str | None]] = {
    "ST": _stop,
    "SA": _stop_all,
    "KL": _kill_all,
    "KS": _kill_selected,
    "SI": _clear_queues,
    "CA": _clear_done,
    "IC": _interrupt_clear,
    "FL": _flush,
    "RP": _report_position,
    "RE": _report_encoder,
    "PP": _every_axis(Axis.motor_position),
    "PE": _every_axis(Axis.encoder_position),
    "RV": _report_velocity,
    "RC": _report_acceleration,
    "QA": _query_axis,
    "RA": _report_axis,
    "RI": _report_interrupts,
    "QI": _status_all,
    "RQC": _queue_free,
    "EA": _encoder_report,
    "QL": _limits_raw,
    "WY": _identify,
    "#WS": lambda ctx: "=0",
    "CC": lambda ctx: str(ctx.board.cycle_count & 0x3FFF_FFFF),
    "APP": _save_parameters,
    "RDP": _restore_parameters(False),
    "RDF": _restore_parameters(True),
    "#UR": _update_rate,
    "?UR": lambda ctx: str(ctx.board.update_rate_hz),
    "?PS": lambda ctx: ctx.per_axis(SETTING_QUERIES["PS"]),
    "?LS": lambda ctx: ctx.per_axis(SETTING_QUERIES["LT"]),
    "?PM": lambda ctx: ctx.per_axis(lambda a: "=on" if a.loop_closed else "=off"),
    "BX": lambda ctx: format(ctx.board.io.word(ctx.board), "04x"),
    "RB": lambda ctx: format(ctx.board.io.direction, "04x"),
    "AB?": lambda ctx: ctx.per_axis(lambda a: "=h" if a.aux_level(ctx.board) else "=l"),
    "AI": _analog_in,
    "?KA": _gain_query("ka"),
    "?KP": _gain_query("kp"),
}
