"""What every command's handler works with: the command context, the refusal, and
operands in the axis's units (user units, encoder counts, motor steps)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from maxk.commands.max.lexer import ParsedCommand
from maxk.personalities.maxk.axis import Axis
from maxk.personalities.maxk.board import Board
from maxk.personalities.maxk.queue import Action


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


# ---- what queued commands build ------------------------------------------------------
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
