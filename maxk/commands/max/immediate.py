"""What immediate commands do the moment they are parsed: stops and kills, reports and
queries, flags, parameters in flash. IMMEDIATE binds each immediate mnemonic to its
handler (a Context in, the reply text or None out)."""

from __future__ import annotations

from collections.abc import Callable

from maxk.commands.max.context import (
    CommandError,
    Context,
)
from maxk.commands.max.queued import (
    SETTING_QUERIES,
)
from maxk.commands.max.table import Timing, bind
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.axis import Axis
from maxk.personalities.maxk.board import Board
from maxk.personalities.maxk.io import volts_to_counts
from maxk.personalities.maxk.models import (
    FIRMWARE_VERSION,
    FPGA_VERSION,
    SERIAL_NUMBER,
    UPDATE_RATES_HZ,
)
from maxk.personalities.maxk.parameters import ArchiveError


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
    if ctx.values[0] >= board.model.analog_inputs:
        raise CommandError(f"AI{ctx.values[0]}: {board.model.name} has analog inputs "
                           f"0-{board.model.analog_inputs - 1} (Table 6-2)")
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


def _wait_for_queue(ctx: Context) -> None:
    """WQ: if the addressed queue(s) still hold work, the interpreter that sent it holds
    the rest of its stream until they do not (board.parser_hold tells it which)."""
    busy = [a for a in ctx.addressed if a.wait is not None or a.queue.pending()]
    if busy:
        ctx.board.parser_hold = busy


def _reset(ctx: Context) -> None:
    ctx.board.reset()


def _command_buffer(mode: str) -> Callable[[Context], None]:
    def handler(ctx: Context) -> None:
        size = ctx.values[0] if ctx.values and isinstance(ctx.values[0], int) else None
        ctx.board.command_buffer = (mode, size if size is not None
                                    else ctx.board.command_buffer[1])

    return handler


def _servo_probe(ctx: Context) -> None:
    """KK (the VME58's PID probe): a command error unless the axis has a servo loop."""
    axis = ctx.axes[0]
    if axis.servo is None:
        raise CommandError(f"KK: axis {axis.letter} has no servo loop")


def _aux_query(ctx: Context) -> str:
    return ctx.per_axis(lambda a: "=h" if a.aux_level(ctx.board) else "=l")


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
    "AB?": _aux_query,
    "?AB": _aux_query,
    "SD": _stop,
    "WQ": _wait_for_queue,
    "RS": _reset,
    "#BB": _command_buffer("big"),
    "#BN": _command_buffer("normal"),
    "#BF": lambda ctx: None,
    "#WC": lambda ctx: None,
    "RL": _limits_raw,
    "KK": _servo_probe,
    "AI": _analog_in,
    "?KA": _gain_query("ka"),
    "?KP": _gain_query("kp"),
}


bind(Timing.IMMEDIATE, IMMEDIATE)
