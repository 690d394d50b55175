"""CHANNEL_READ and CHANNEL_WRITE: bytes between a channel and a buffer (VRs, a STRING
variable, an INTEGER array), from their TrioBASIC help pages.

Their buffers go by reference (a STRING variable is written, an array's elements are
read), so the interpreter hands over the argument expressions, not their values. Files
opened FOR INPUT are read, files opened FOR OUTPUT written; the terminal channels have
nothing to read while a program runs and what is written to them reaches the
command-line hosts (D, as PRINT #n and GET #n do here).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...personalities.trio.memory import VR_COUNT
from .datawords import crc_direct
from .lexer import TrioError
from .parser import Assign, Expr, Str, Var

if TYPE_CHECKING:
    from .interpreter import Interpreter, ProcessContext

CHANNEL_BYTES = 4096  # bytes one CHANNEL_READ or CHANNEL_WRITE moves at most (D)


def _vr_index(value: float, count: int = 1) -> int:
    if value != int(value) or not 0 <= value <= VR_COUNT - count:
        raise TrioError("Parameter out of range")
    return int(value)


def _string_capacity(interp: Interpreter, expr: Expr, ctx: ProcessContext) -> int | None:
    """A DIM'd STRING(n) variable's n, else None (the VR form)."""
    if isinstance(expr, Var) and ctx.types.get(expr.name, "").startswith("STRING"):
        return int(ctx.types[expr.name][6:])
    return None


def _vr_delimiters(interp: Interpreter, base: Expr, count: Expr,
                   ctx: ProcessContext) -> list[int]:
    first, number = interp.integer(base, ctx), interp.integer(count, ctx)
    if not 0 <= number <= 256:
        raise TrioError("Parameter out of range")
    _vr_index(first, number)
    return [int(interp.machine.vr_read(first + k)) for k in range(number)]


def channel_write(interp: Interpreter, args: tuple[Expr, ...], ctx: ProcessContext) -> float:
    """CHANNEL_WRITE(channel, buffer[, count]): a string's characters (its first count),
    or count values from VR(buffer) on or from an INTEGER array, each its low 8 bits
    (D), written to the channel; returns how many were written (help page)."""
    if len(args) not in (2, 3):
        raise TrioError("Syntax error")
    channel = interp.integer(args[0], ctx)
    if not 0 <= channel <= 255:
        raise TrioError("Parameter out of range")
    count = interp.integer(args[2], ctx) if len(args) == 3 else None
    if count is not None and not 0 <= count <= CHANNEL_BYTES:
        raise TrioError("Parameter out of range")
    source = args[1]
    if isinstance(source, Var) and source.name in ctx.arrays:
        values = ctx.arrays[source.name]
        if count is None or count > len(values):
            raise TrioError("Parameter out of range")
        codes = [int(interp.number_value(v)) & 0xFF for v in values[:count]]
    else:
        value = interp.evaluate(source, ctx)
        if isinstance(value, str):
            codes = [ord(c) & 0xFF for c in value[:count]]
        else:
            if count is None:
                raise TrioError("Syntax error")
            first = _vr_index(value, count)
            codes = [int(interp.machine.vr_read(first + k)) & 0xFF for k in range(count)]
    text = "".join(chr(c) for c in codes)
    hook = interp.hook
    if channel in hook.files and channel not in hook.sources:  # a file open for output
        hook.write_file(channel, text)
    elif channel in hook.sources:
        raise TrioError("Parameter out of range")  # a file open for reading (D)
    elif channel >= 20:
        raise TrioError("Channel not open")
    else:
        interp.output(text)
    return float(len(codes))


def channel_read(interp: Interpreter, args: tuple[Expr, ...], ctx: ProcessContext) -> float:
    """CHANNEL_READ(channel, buffer...): characters from the channel until the buffer is
    full, the channel is empty, or a delimiter is read (it is taken, not stored, I); the
    character after the escape character is stored whatever it is (the escape itself is
    not, D). VR form (channel, base, size[, dbase, dcount[, escape[, crc]]]): VR(base) the
    reason it stopped (0 empty or full, k the k-th delimiter), the characters from
    VR(base + 1) then a 0, size - 2 at most (D), returns the count. STRING form (channel,
    s[, delimiters[, escape[, crc]]]): s takes the characters, returns -k for the k-th
    delimiter, else 0. crc: VR(crc) the CRC16 mode 2 of the characters with CRC16(0, ...)'s
    set-up, 0 without one (D)."""
    if len(args) < 2:
        raise TrioError("Syntax error")
    channel = interp.integer(args[0], ctx)
    if not 0 <= channel <= 255:
        raise TrioError("Parameter out of range")
    capacity = _string_capacity(interp, args[1], ctx)
    rest: tuple[Expr, ...]
    if capacity is not None:
        given = interp.evaluate(args[2], ctx) if len(args) > 2 else ""
        if isinstance(given, str):
            delimiters, rest = [ord(c) for c in given], args[3:]
        else:  # the delimiters in VRs: base and count (the page's example 3)
            if len(args) < 4:
                raise TrioError("Syntax error")
            delimiters, rest = _vr_delimiters(interp, args[2], args[3], ctx), args[4:]
        if len(rest) > 2:
            raise TrioError("Syntax error")
        size = capacity
    else:
        if len(args) not in (3, 5, 6, 7):
            raise TrioError("Syntax error")
        base, size = interp.integer(args[1], ctx), interp.integer(args[2], ctx)
        if not 2 <= size <= CHANNEL_BYTES:
            raise TrioError("Parameter out of range")
        _vr_index(base, size)
        delimiters = _vr_delimiters(interp, args[3], args[4], ctx) if len(args) > 3 else []
        rest = args[5:]
        size -= 2
    escape = interp.integer(rest[0], ctx) if rest else None
    crc_at = _vr_index(interp.integer(rest[1], ctx)) if len(rest) > 1 else None
    hook = interp.hook
    if channel >= 20 and channel not in hook.files:
        raise TrioError("Channel not open")
    waiting = hook.files.get(channel, [])  # (the next character last)
    taken: list[int] = []
    stopped = 0
    while waiting and len(taken) < size:
        code = waiting.pop()
        if escape is not None and code == escape:
            if waiting:
                taken.append(waiting.pop())
            continue
        if code in delimiters:
            stopped = delimiters.index(code) + 1
            break
        taken.append(code)
    if crc_at is not None:
        crc = crc_direct(hook.crc, taken, 0) if hook.crc is not None else 0
        interp.machine.vr_write(crc_at, float(crc))
    if capacity is not None:
        target = args[1]
        assert isinstance(target, Var)  # (a STRING variable: _string_capacity)
        interp.assign(Assign(target, Str("".join(chr(c) for c in taken))), ctx)
        return float(-stopped)
    base = interp.integer(args[1], ctx)
    interp.machine.vr_write(base, float(stopped))
    for k, code in enumerate(taken):
        interp.machine.vr_write(base + 1 + k, float(code))
    interp.machine.vr_write(base + 1 + len(taken), 0.0)
    return float(len(taken))
