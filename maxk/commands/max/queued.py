"""The queued commands' actions beyond motion (I/O, aux output, axis type, servo gains
and loop, encoder ratio, position maintenance), and QUEUED: each queued mnemonic's
action factory, the binding its table entry's timing names."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from maxk.commands.max.context import (
    CommandError,
    Context,
    QueuedFactory,
    _set,
    in_counts,
    scaled_out_of_range,
)
from maxk.commands.max.queued_motion import (
    _acceleration,
    _base_velocity,
    _deceleration,
    _done,
    _fractional_jog,
    _go,
    _go_to,
    _home,
    _home_encoder_mode,
    _in_position,
    _jog,
    _limit_level_for,
    _limit_mode,
    _limits_on,
    _load,
    _loop_end,
    _loop_start,
    _move_absolute,
    _move_relative,
    _one_step,
    _ramp,
    _timed_move,
    _velocity,
    _wait,
    _wait_cycle,
    _while_start,
)
from maxk.commands.max.table import Timing, bind
from maxk.firmware_model.profiles import RampShape
from maxk.firmware_model.servo import ServoLoop
from maxk.personalities.maxk.axis import Axis
from maxk.personalities.maxk.board import Board
from maxk.personalities.maxk.queue import Action
from maxk.personalities.maxk.waits import WAIT_REST_RETRY, InputWait, Wait


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
    """BD: bits for lines the model lacks are ignored (hosts send 16-bit words, D)."""

    def action(axis: Axis, board: Board) -> None:
        board.io.direction = value & board.io.mask  # type: ignore[operator]
        board.cross_axis_event = True  # an SW may be waiting on this line

    return action


def _configure_bit(value: object, ctx: Context) -> Action:
    bit, output = (int(v) for v in value)  # type: ignore[attr-defined]

    def action(axis: Axis, board: Board) -> None:
        if output:
            board.io.direction |= 1 << bit
        else:
            board.io.direction &= ~(1 << bit)
        board.cross_axis_event = True  # an SW may be waiting on this line

    return action


def _wait_input(value: object, ctx: Context) -> Action:
    def action(axis: Axis, board: Board) -> Wait | None:
        if board.io.level(value, board):  # type: ignore[arg-type]
            return None
        return InputWait(int(value))  # type: ignore[call-overload]

    return action


def _set_aux_state(on: bool) -> QueuedFactory:
    """AN/AF (and PH/PL): bare, or a 1 in the axis's slot; a 0 leaves the axis alone."""

    def factory(value: object, ctx: Context) -> Action:
        def action(axis: Axis, board: Board) -> None:
            if value is not None and not value:
                return
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

    def action(axis: Axis, board: Board) -> Wait | None:
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
            # An open-loop stepper has no loop: hosts send these to every axis (D).

        return action

    return factory


def _absolute_encoder(kind: str) -> QueuedFactory:
    """ECA/ECB bits,clock (checked on arrival); ECI back to incremental."""

    def factory(value: object, ctx: Context) -> Action:
        setting = None if value is None else tuple(int(v) for v in value)  # type: ignore

        def action(axis: Axis, board: Board) -> None:
            axis.config.encoder_interface = kind
            axis.config.absolute_encoder = setting  # type: ignore[assignment]

        return action

    return factory


ABSOLUTE_ENCODER_CLOCKS = (31_250, 62_500, 125_000, 250_000, 500_000, 1_000_000, 2_000_000,
                           4_000_000)
"""Manual 4.9: the SSI clock frequencies the board can put out."""


def _motor_from_encoder(value: object, ctx: Context) -> Action:
    """SME (D): the motor counter takes the encoder reading, in motor steps."""

    def action(axis: Axis, board: Board) -> None:
        if axis.config.axis_type != "E":
            return
        steps = round(axis.to_steps(axis.encoder_position(board)))
        if steps != axis.motor_position(board):
            axis.load_position(steps, True, False, board)

    return action


def _wait_input_low(value: object, ctx: Context) -> Action:
    """BW (D): the queue waits until input bit # reads low."""

    def action(axis: Axis, board: Board) -> Wait | None:
        if not board.io.level(value, board):  # type: ignore[arg-type]
            return None
        return InputWait(int(value), low=True)  # type: ignore[call-overload]

    return action


def _accepted(value: object, ctx: Context) -> Action:
    """Commands whose effect no source gives (RTL, IOK, DBI) or that have nothing to do
    here (EF): accepted, so a host's set-up runs without a command error; each table
    entry says so."""

    def action(axis: Axis, board: Board) -> None:
        return None

    return action


def _encoder_ratio(value: object, ctx: Context) -> Action:
    """ER counts,steps: the encoder ratio; an encoder stepper other than 1:1 is then in
    encoder mode (evidence 2.4). Motor and encoder are taken to agree from here."""
    counts, steps = (int(v) for v in value)  # type: ignore[attr-defined]

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
    "JF": _fractional_jog,
    "GP": _go_to,
    "TM": _timed_move,
    "WTC": _wait_cycle,
    "PH": _set_aux_state(True),
    "PL": _set_aux_state(False),
    "ECI": _absolute_encoder("incremental"),
    "ECA": _absolute_encoder("SSI"),
    "ECB": _absolute_encoder("BiSS"),
    "EDI": _set("encoder_inverted", True),
    "EDN": _set("encoder_inverted", False),
    "KOD": lambda value, ctx: _set("kod", float(value))(value, ctx),  # type: ignore[arg-type]
    "RTL": _accepted,
    "SME": _motor_from_encoder,
    "BC": _set("backlash"),
    "BW": _wait_input_low,
    "IOK": _accepted,
    "IP": _in_position,
    "WH": _while_start,
    "WG": _loop_end,
    "EF": _accepted,
    "EN": _accepted,  # the echo is the stream's: the interpreter sets it
    "DBI": _accepted,
}

NOT_MODELLED_YET: dict[str, str] = {
    "ET": "ET: encoder tracking (electronic gearing) is not modelled",
}
"""Commands in the table whose effect is not modelled yet: refused visibly, never ignored."""


def _not_modelled(mnemonic: str) -> QueuedFactory:
    def refuse(value: object, ctx: Context) -> Action:
        raise CommandError(NOT_MODELLED_YET[mnemonic])

    return refuse


bind(Timing.QUEUED, QUEUED)
bind(Timing.QUEUED, {m: _not_modelled(m) for m in NOT_MODELLED_YET})


_BIT_COMMANDS = frozenset({"BH", "BL", "IO", "SW", "BW"})
"""Commands naming one I/O line: a line the model does not have is refused."""


def validate_queued(ctx: Context) -> None:
    """Refusals that can be decided when the command arrives, before anything is queued."""
    m = ctx.command.mnemonic
    if m in NOT_MODELLED_YET:
        raise CommandError(NOT_MODELLED_YET[m])
    if m == "UU":  # from now on this axis's operands are range-checked when they run
        for axis in ctx.axes:
            axis.units_seen = True
    if m in _BIT_COMMANDS:
        lines = ctx.board.model.io_lines
        bits = [v[0] if isinstance(v, tuple) else v for v in ctx.values if v is not None]
        if any(bit >= lines for bit in bits):
            raise CommandError(f"{m}: {ctx.board.model.name} has general purpose I/O lines "
                               f"0-{lines - 1} (Table 6-2)")
    if m == "IO" and ctx.values[0][1] not in (0, 1):
        raise CommandError("IO#,#: the second operand is 0 (input) or 1 (output)")
    if m in ("ECA", "ECB"):
        data_bits, clock = ctx.values[0]  # (not `bits`: a list above, for a compiled build)
        if not 1 <= data_bits <= 32:
            raise CommandError(f"{m}{data_bits},{clock}: 1 to 32 data bits")
        if clock not in ABSOLUTE_ENCODER_CLOCKS:
            raise CommandError(f"{m}{data_bits},{clock}: the clock is one of "
                               + ", ".join(map(str, ABSOLUTE_ENCODER_CLOCKS)) + " Hz")


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
