"""From parsed commands to the board: mode, operand checks, queueing, replies.

Every refusal is decided before anything changes, so a bad command has no effect at all:
it sets the command-error flag (doorbell bit 24), records why, and the stream goes on.
"""

from __future__ import annotations

from collections.abc import Callable

from maxk.commands.line_session import log_fault
from maxk.commands.max.context import CommandError, Context
from maxk.commands.max.immediate import IMMEDIATE  # noqa: F401  (binds the behaviours)
from maxk.commands.max.lexer import (
    CLEAR_ERROR,
    ControlCharacter,
    Lexer,
    LexError,
    ParsedCommand,
)
from maxk.commands.max.queued import SETTING_QUERIES, validate_queued
from maxk.commands.max.queued_motion import go_together, linear_target
from maxk.commands.max.table import AA, Operand, Start, Timing, check_bound
from maxk.commands.max.vector import dispatch_vector
from maxk.personalities.maxk.axis import Axis, LinearMove, StartGroup
from maxk.personalities.maxk.board import Board
from maxk.personalities.maxk.queue import QueueEntry

_MODE_NAMES = {"single": "single-axis", "AA": "AA", "AM": "AM"}


class Interpreter:
    """One command stream into a board. Several streams (doors) may share a board: the
    command mode lives on the board, as on the real controller; each stream has its own
    lexer so a half-sent command from one client never mixes with another's."""

    def __init__(self, board: Board) -> None:
        self.board = board
        self.lexer = Lexer()
        # WQ holds this stream: the commands parsed since, and the axes it waits on.
        self._held: list[ParsedCommand | LexError | ControlCharacter] = []
        self._hold_axes: list[Axis] | None = None
        self.late_replies: list[str] = []  # replies of held queries, for the next write
        # A session takes every reply the moment it is made, so a reply and a flag
        # notification raised after it reach the host in that order.
        self.on_reply: Callable[[str], None] | None = None
        self.echo = False  # EN/EF: this stream's bytes are echoed (the session does it)

    def write(self, data: str | bytes, *, whole: bool = False) -> list[str]:
        """Feed host bytes; return the replies of the queries completed by them.

        `whole`: the write is whole commands (a PC68-style host writes `AX LP4000` with
        no terminator), so its end completes a command still open, as a `;` would."""
        replies: list[str] = []
        if self.late_replies:
            replies, self.late_replies = self.late_replies, []
        if whole:
            data = (data.decode("latin-1") if isinstance(data, bytes | bytearray)
                    else data) + ";"
        items = self.lexer.feed(data)
        if self._hold_axes is not None:
            # A control character acts on arrival, also while WQ holds the stream (D).
            for item in items:
                if type(item) is ControlCharacter:
                    self._control(item)
            self._held.extend(i for i in items if type(i) is not ControlCharacter)
        else:
            self._run(items, self.on_reply or replies.append)
        if self.board.parser_waits:  # a flush without a later event may release one
            for resume in list(self.board.parser_waits):
                resume()
        if self.late_replies:
            replies += self.late_replies
            self.late_replies = []
        return replies

    def _control(self, item: ControlCharacter) -> None:
        """^X clears the command error (the VME8 driver's CMD_CLEAR, 'clears command errors
        only'); the other control characters only end the command before them."""
        if item.char == CLEAR_ERROR:
            self.board.command_error = False

    def _run(self, items: list[ParsedCommand | LexError | ControlCharacter],
             emit: Callable[[str], None]) -> None:
        board = self.board
        for k, item in enumerate(items):
            if type(item) is LexError:
                board.report_error(item.reason, item.text)
                continue
            if type(item) is ControlCharacter:
                self._control(item)
                continue
            try:
                reply = _dispatch(board, item)  # type: ignore[arg-type]
            except CommandError as error:
                board.report_error(str(error), item.text)
                continue
            except Exception:  # a fault of ours: logged, refused as a bad command (D)
                log_fault("MAX interpreter", item.text)
                board.report_error(FAULT_REASON, item.text)
                continue
            mnemonic = item.spec.mnemonic  # type: ignore[union-attr]
            if mnemonic == "EN" or mnemonic == "EF":
                self.echo = mnemonic == "EN"
            if reply is not None:
                emit(reply)
            if board.parser_hold is not None:  # WQ with work in the queue: hold the rest
                self._hold_axes, board.parser_hold = board.parser_hold, None
                self._held = items[k + 1:]
                board.parser_waits.append(self._resume)
                return

    def _resume(self) -> None:
        """After an event: once the queues a WQ waits on are empty, run what was held."""
        axes = self._hold_axes
        if axes is None or any(a.wait is not None or a.queue.pending() for a in axes):
            return
        self.board.parser_waits.remove(self._resume)
        self._hold_axes = None
        items, self._held = self._held, []
        self._run(items, self.on_reply or self.late_replies.append)

    def execute(self, item: ParsedCommand | LexError | ControlCharacter) -> str | None:
        board = self.board
        if isinstance(item, LexError):
            board.report_error(item.reason, item.text)
            return None
        if isinstance(item, ControlCharacter):
            self._control(item)
            return None
        try:
            return _dispatch(board, item)
        except CommandError as error:
            board.report_error(str(error), item.text)
            return None
        except Exception:  # a fault of ours (as in _run)
            log_fault("MAX interpreter", item.text)
            board.report_error(FAULT_REASON, item.text)
            return None


FAULT_REASON = "internal fault (logged)"  # the error record of a fault of ours (D)

_CONVERTED: dict[tuple[str, str], object] = {}
"""Operands already converted and range-checked, by mnemonic and text (hosts send the
same ones over and over); not for user units, which the action checks."""


def _convert(cmd: ParsedCommand, slot: str, axis: Axis | None = None) -> object:
    spec = cmd.spec
    if axis is None or not axis.units_seen or not spec.user_units:
        key = (spec.mnemonic, slot)
        known = _CONVERTED.get(key)
        if known is None:
            known = _convert_fresh(cmd, slot, axis)
            if len(_CONVERTED) >= 4096:
                _CONVERTED.clear()
            _CONVERTED[key] = known
        return known
    return _convert_fresh(cmd, slot, axis)


def _convert_fresh(cmd: ParsedCommand, slot: str, axis: Axis | None) -> object:
    spec = cmd.spec
    if spec.operand in (Operand.LETTER, Operand.PATTERN):
        return slot
    value = float(int(slot, 16)) if spec.operand is Operand.HEX else float(slot)
    if axis is not None and axis.units_seen and spec.user_units:
        return value  # maybe user units (UU may be queued): the action checks the counts
    if spec.value_range is not None:
        lo, hi = spec.value_range
        if not lo <= value <= hi:
            raise CommandError(f"{spec.mnemonic}{slot}: operand out of range "
                               f"({_fmt(lo)} to {_fmt(hi)})")
    return int(value) if spec.integer else value


def _fmt(x: float) -> str:
    return str(int(x)) if float(x).is_integer() else str(x)


def _set_mode(board: Board, cmd: ParsedCommand) -> None:
    m = cmd.mnemonic
    if m in ("AA", "AM"):
        board.mode = m
        return
    letter = m[1]
    index = board.model.axis_letters.find(letter)
    if index < 0:
        raise CommandError(f"{m}: {board.model.name} has no {letter} axis")
    board.mode = "single"
    board.current_axis = index


_MODE, _VECTOR, _IMMEDIATE = Timing.MODE, Timing.VECTOR, Timing.IMMEDIATE
"""Module globals: read for every command, faster than enum members by class."""


def _dispatch(board: Board, cmd: ParsedCommand) -> str | None:
    spec = cmd.spec
    timing = spec.timing
    if timing is _MODE:
        _set_mode(board, cmd)
        return None
    mode = board.mode
    if mode not in spec.modes:
        raise CommandError(f"{spec.mnemonic} is not allowed in {_MODE_NAMES[mode]} mode")
    if timing is _VECTOR:
        return dispatch_vector(board, cmd)
    axes_all = board.axes
    slots = cmd.slots
    if not spec.per_axis:
        return _dispatch_positional(board, cmd, axes_all[board.current_axis])
    if mode == "single":
        axes = [axes_all[board.current_axis]]
        if len(slots) > 1:
            raise CommandError(f"{spec.mnemonic}: one operand in single-axis mode, "
                               f"got {len(slots)}")
        values = [_convert(cmd, slots[0], axes[0]) if slots and slots[0] is not None
                  else None]
    elif not slots:
        axes = list(axes_all)
        values = [None] * len(axes)
    else:
        if any(slot is not None for slot in slots[len(axes_all):]):
            raise CommandError(f"{spec.mnemonic}: {len(slots)} operands for "
                               f"{len(axes_all)} axes")
        axes = []
        values = []
        for axis, slot in zip(axes_all, slots, strict=False):
            if slot is not None:
                axes.append(axis)
                values.append(_convert(cmd, slot, axis))
        if not axes:
            raise CommandError(f"{spec.mnemonic}: no operand given")
    ctx = Context(board, cmd, axes, values)
    if timing is _IMMEDIATE:
        reply = spec.handler(ctx)  # type: ignore[misc]
        if board.cross_axis_event:  # a flush released an AA start group
            board.run_queues()
        return reply
    if cmd.query:
        return ctx.per_axis(SETTING_QUERIES[spec.mnemonic])
    _enqueue(ctx)
    return None


def _dispatch_positional(board: Board, cmd: ParsedCommand, axis) -> str | None:
    """Board-level commands with positional operands (BH3, IO5,0, BDff00, AI2).

    Queued ones go into the addressed axis's queue in single-axis mode, so they happen in
    step with its moves; in AA/AM mode there is no one queue to choose, so they act at
    once."""
    spec = cmd.spec
    slots = cmd.slots
    if not slots and spec.operand_optional:
        values: list = []
    else:
        if len(slots) != spec.arity or any(s is None for s in slots):
            raise CommandError(f"{spec.mnemonic} takes {spec.arity} operand"
                               f"{'s' if spec.arity > 1 else ''}")
        values = [_convert(cmd, s) for s in slots]  # type: ignore[arg-type]
    value = values[0] if len(values) == 1 else tuple(values)
    ctx = Context(board, cmd, [axis], [value])
    if spec.timing is Timing.IMMEDIATE:
        return spec.handler(ctx)  # type: ignore[misc]
    if board.mode == "single":
        _enqueue(ctx)
        return None
    validate_queued(ctx)
    action = spec.handler(value, ctx)  # type: ignore[misc]
    if action(axis, board) is not None:
        raise CommandError(f"{spec.mnemonic} cannot wait outside a queue")
    if board.cross_axis_event:  # an output changed: an SW may be waiting on it
        board.run_queues()
    return None


_GO, _LINEAR_ABSOLUTE, _LINEAR_RELATIVE = Start.GO, Start.LINEAR_ABSOLUTE, Start.LINEAR_RELATIVE
"""Module globals: read for every queued command, faster than enum members by class."""


def _enqueue(ctx: Context) -> None:
    board = ctx.board
    spec = ctx.command.spec
    validate_queued(ctx)
    units = spec.units
    mnemonic = spec.mnemonic
    for a in ctx.axes:
        queue = a.queue
        if queue.capacity - queue.used_units < units:  # (free_units, inlined)
            short = [a.letter for a in ctx.axes if a.queue.free_units < units]
            raise CommandError(f"{mnemonic}: command queue full on axis {','.join(short)}")
    text = ctx.command.text
    start = spec.start
    if start is _GO and board.mode == AA:
        group = StartGroup(ctx.axes)
        for axis in ctx.axes:
            axis.queue.push(QueueEntry(mnemonic, units, go_together(group), text, group))
        board.run_queues(ctx.axes)
        return None
    sync = None
    if start is _LINEAR_ABSOLUTE or start is _LINEAR_RELATIVE:
        sync = LinearMove(StartGroup(ctx.axes))  # a flush of one axis withdraws it
        relative = start is _LINEAR_RELATIVE
        actions = [linear_target(sync, v, relative) for v in ctx.values]
    else:
        factory = spec.handler
        actions = [factory(value, ctx) for value in ctx.values]  # type: ignore[misc]
    direct = mnemonic != "LS" and mnemonic != "WH"  # LE/WG jump back to them
    for axis, action in zip(ctx.axes, actions, strict=True):
        queue = axis.queue
        if direct and axis.wait is None and not queue.entries:
            # An idle axis with an empty queue reaches this entry at once: run it now,
            # exactly as push-then-pop would, and queue it only if it has to wait.
            result = action(axis, board)
            if result is None:
                continue
            queue.push(QueueEntry(mnemonic, units, action, text, sync, spec.applied_at_stop))
            axis.wait = result
        else:
            queue.push(QueueEntry(mnemonic, units, action, text, sync, spec.applied_at_stop))
        axis.run_queue(board)
    if board.cross_axis_event:
        board.run_queues()
    return None


check_bound()  # every entry has its behaviour, now that every module bound its own
