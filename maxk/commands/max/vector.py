"""The vector-task commands (contouring): VA VV VP VC VE VG VH VID VIO VO VOA VRV VRC.

They address a task (`VP[2]A,...`; without `[n]`, task 1) rather than an axis queue:
the definition commands (VA VV VIO VP VC VE) build the task's contour in the order they
are sent, VO VOA VG VH act on the task at once, VRV VRC report it. Everything is checked
before anything changes (docs/contouring.md, firmware_model/contouring.py).
"""

from __future__ import annotations

from collections.abc import Callable

from maxk.commands.max.context import CommandError
from maxk.commands.max.lexer import ParsedCommand
from maxk.commands.max.table import Timing, bind
from maxk.firmware_model.path import SegmentDef
from maxk.personalities.maxk.board import Board
from maxk.personalities.maxk.contouring import (
    DEFAULT_TASK,
    DEFAULT_VOA_SPAN,
    TASKS,
    Contour,
    ContourTask,
)
from maxk.personalities.maxk.queue import QueueEntry

MAX_ARC_DEGREES = 3600.0

Handler = Callable[[Board, ContourTask, ParsedCommand], str | None]


def dispatch_vector(board: Board, cmd: ParsedCommand) -> str | None:
    index = DEFAULT_TASK if cmd.task is None else cmd.task
    if index not in TASKS:
        raise CommandError(f"{cmd.mnemonic}[{index}]: vector tasks are 1-{TASKS[-1]}")
    reply = cmd.spec.handler(board, board.contour_task(index), cmd)  # type: ignore[misc]
    if board.cross_axis_event:
        board.run_queues()
    return reply


# ---- operands ---------------------------------------------------------------------------
def _numbers(cmd: ParsedCommand, least: int) -> list[float | None]:
    """The operand slots as numbers (None for empty ones), range-checked, at least
    `least` and at most the command's arity of them."""
    spec = cmd.spec
    slots = cmd.slots
    if len(slots) > spec.arity:
        raise CommandError(f"{spec.mnemonic}: at most {spec.arity} operand"
                           f"{'s' if spec.arity > 1 else ''}")
    values: list[float | None] = []
    for slot in slots:
        if slot is None:
            values.append(None)
            continue
        value = float(int(slot, 16)) if spec.hex_operands else float(slot)
        if spec.value_range is not None:
            lo, hi = spec.value_range
            if not lo <= value <= hi:
                raise CommandError(f"{spec.mnemonic}{slot}: operand out of range "
                                   f"({lo:g} to {hi:g})")
        values.append(value)
    values += [None] * (least - len(values))
    return values


def _required(cmd: ParsedCommand, value: float | None, what: str) -> float:
    if value is None:
        raise CommandError(f"{cmd.mnemonic} needs {what}")
    return value


# ---- definition state -----------------------------------------------------------------
def _va(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    (value,) = _numbers(cmd, 1)
    task.accel = _required(cmd, value, "an acceleration")


def _vv(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    values = _numbers(cmd, 1)
    if len(cmd.slots) == 2:
        start, end = values
    else:
        start, end = None, values[0]
    task.v_end = _required(cmd, end, "an end velocity")
    task.v_start = start  # None: go on from the previous segment's end velocity


def _vio(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    on, off, mask = (_numbers(cmd, 3) + [None, None])[:3]
    on_bits = int(_required(cmd, on, "the on bits"))
    off_bits = None if off is None else int(off)
    mask_bits = int(mask) if mask is not None else on_bits | (off_bits or 0)
    task.io = (on_bits, off_bits, mask_bits) if mask_bits else None


def _vid(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    (value,) = _numbers(cmd, 1)
    task.done_on_finish = bool(_required(cmd, value, "0 or 1"))


# ---- segments ---------------------------------------------------------------------------
def _open_or_extend(board: Board, task: ContourTask, cmd: ParsedCommand,
                    named: dict[int, float]) -> tuple[Contour, bool]:
    """The contour this segment goes into (a new one for a first VP), checked for room."""
    contour = task.defining
    letters = board.model.axis_letters
    if contour is None:
        axes = tuple(sorted(named))
        new = True
    else:
        outside = sorted(set(named) - set(contour.axes))
        if outside:
            raise CommandError(f"{cmd.mnemonic}: axis {','.join(letters[i] for i in outside)} "
                               f"is not in the contour "
                               f"({','.join(letters[i] for i in contour.axes)})")
        axes = contour.axes
        new = False
    short = [letters[i] for i in axes if board.axes[i].queue.free_units < 1]
    if short:
        raise CommandError(f"{cmd.mnemonic}: command queue full on axis {','.join(short)}")
    if new:
        contour = Contour(task, axes)
    return contour, new  # type: ignore[return-value]


def _segment(board: Board, task: ContourTask, contour: Contour, kind: str,
             values: tuple[float | None, ...], relative: bool = False,
             angle: float = 0.0) -> SegmentDef:
    first = board.axes[contour.axes[0]].config
    return SegmentDef(kind, values, relative, angle, task.v_start,
                      task.v_end if task.v_end is not None else float(first.velocity),
                      task.accel if task.accel is not None else float(first.acceleration),
                      task.io)


def _add(board: Board, task: ContourTask, contour: Contour, new: bool, defn: SegmentDef,
         text: str) -> None:
    if not new:
        contour.add(defn, board)
        return
    task.contours.append(contour)
    contour.add(defn, board)
    axes = [board.axes[i] for i in contour.axes]
    for axis in axes:
        axis.queue.push(QueueEntry("VP", 1, contour.arrive, text, contour))
    for axis in axes:
        axis.run_queue(board)


def _vp(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    spec = cmd.spec
    slots = cmd.slots
    if board.mode == "single":
        if len(slots) != 1 or slots[0] is None:
            raise CommandError("VP: one position in single-axis mode")
        indexed = [(board.current_axis, slots[0])]
    else:
        if any(s is not None for s in slots[len(board.axes):]):
            raise CommandError(f"VP: {len(slots)} operands for {len(board.axes)} axes")
        indexed = [(i, s) for i, s in enumerate(slots) if s is not None]
    if not indexed:
        raise CommandError("VP: no position given")
    lo, hi = spec.value_range  # type: ignore[misc]
    named: dict[int, float] = {}
    for i, slot in indexed:
        value = float(slot)
        if not lo <= value <= hi:
            raise CommandError(f"VP{slot}: operand out of range ({lo:g} to {hi:g})")
        named[i] = float(int(value))  # whole counts; decimals truncate, as MA's do
    contour, new = _open_or_extend(board, task, cmd, named)
    defn = _segment(board, task, contour, "line",
                    tuple(named.get(i) for i in contour.axes), relative=cmd.form == "R")
    _add(board, task, contour, new, defn, cmd.text)


def _vc(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    values = _numbers(cmd, 3)
    if len(cmd.slots) != 3 or any(v is None for v in values):
        raise CommandError("VC needs the centre (two coordinates) and the angle: VC#,#,#")
    cx, cy, angle = values
    assert cx is not None and cy is not None and angle is not None
    if angle == 0 or abs(angle) > MAX_ARC_DEGREES:
        raise CommandError(f"VC: the angle must be nonzero and within +/-{MAX_ARC_DEGREES:g}")
    contour = task.defining
    if contour is None or len(contour.axes) < 2:
        raise CommandError("VC: open the contour with a VP naming at least two axes first")
    contour, new = _open_or_extend(board, task, cmd, {})
    defn = _segment(board, task, contour, "arc", (float(int(cx)), float(int(cy))),
                    angle=angle)
    _add(board, task, contour, new, defn, cmd.text)


def _ve(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    contour = task.defining
    if contour is not None:
        contour.close(board)


# ---- the running task -------------------------------------------------------------------
def _vg(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    task.go(board)


def _vh(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    (value,) = _numbers(cmd, 1)
    if _required(cmd, value, "0 or 1"):
        task.hold_now(board)
    else:
        task.hold = True


def _vo(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    (value,) = _numbers(cmd, 1)
    task.override = _required(cmd, value, "a percentage")
    task.override_input = None
    task.override_changed(board)


def _voa(board: Board, task: ContourTask, cmd: ParsedCommand) -> None:
    channel, span = _numbers(cmd, 2)
    channel = _required(cmd, channel, "an analog input (0-3)")
    last = board.model.analog_inputs - 1
    if not channel.is_integer() or not 0 <= channel <= last:
        raise CommandError(f"VOA: {board.model.name} has no analog input {channel:g} "
                           f"(0-{last})")
    span = DEFAULT_VOA_SPAN if span is None else span
    if span <= 0:
        raise CommandError("VOA: the span must be above 0 V")
    task.override_input = (int(channel), span)
    task.override_changed(board)


def _vrv(board: Board, task: ContourTask, cmd: ParsedCommand) -> str:
    head = task.running
    speed = head.where(board)[1] if head is not None else 0.0
    return str(round(speed))


def _vrc(board: Board, task: ContourTask, cmd: ParsedCommand) -> str:
    head = task.running
    if head is not None and head.segments:
        return str(round(head.segments[min(head.current, len(head.segments) - 1)].accel))
    if task.accel is not None:
        return str(round(task.accel))
    return str(board.axes[board.current_axis].config.acceleration)


_HANDLERS: dict[str, Handler] = {
    "VA": _va, "VV": _vv, "VIO": _vio, "VID": _vid, "VP": _vp, "VC": _vc, "VE": _ve,
    "VG": _vg, "VH": _vh, "VO": _vo, "VOA": _voa, "VRV": _vrv, "VRC": _vrc,
}


bind(Timing.VECTOR, _HANDLERS)
