"""The shapes shared by the MM4005 lexer, command table and handlers."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum
from typing import Protocol

from maxk.personalities.mm4005 import ErrorRegister
from maxk.personalities.mm4005.programs import Wait

from .machine import MM4005Machine


class AxisRule(Enum):
    """What the optional number before the mnemonic (``xx`` in ``xxAAnn``) means."""

    NONE = "none"  # controller command: a number is an axis error (B)
    ALL_OR_ONE = "all or one"  # missing or 0: every axis (manual 3.75 MS: 'Missing: 0')
    REQUIRED = "required"  # 1..axis count, else B
    PHYSICAL = "physical axis"  # AX/AY: the axis to assign; missing reports the assignment
    ELEMENT = "element"  # LT: an element number, missing lists them all


class Operand(Enum):
    """What may follow the mnemonic (``nn``)."""

    NONE = "none"
    NUMBER = "number"
    INTEGER = "integer"
    CHAR = "char"  # TB's error code
    MODE = "mode"  # OR's optional search mode 0..2
    OPTIONAL_NUMBER = "optional number"  # BA: a missing value means 0 (manual 3.25)
    SIGN = "sign"  # MV: '+', '-' or a signed number (sibling ESP300 'xxMV+')
    ANY = "any"  # a listed command not modelled: whatever follows is taken (it answers Q)


class LineOwner(Protocol):
    """Who sent the line a handler runs in: a host's session (EP enters its next lines
    into a program; a program it starts replies to it) or a running program."""

    def begin_entry(self, number: int) -> None:
        """EP: this owner's next lines go into program `number`, up to QP."""
        ...

    def emit(self, text: str) -> None:
        """A reply that comes later than its line (a program's TP)."""
        ...

    @property
    def in_program(self) -> bool:
        """The line is one of a stored program's."""
        ...


class Line(Protocol):
    """A command line under way (session.LineRun)."""

    wait: Wait | None
    done: bool
    failed: bool

    def stop(self) -> None: ...


class LineRunner(Protocol):
    """What runs lines (session.Interpreter): a program runs its lines through it."""

    def start(self, line: str, owner: LineOwner | None) -> Line | None: ...

    def proceed(self, run: Line) -> None: ...


@dataclass(slots=True)
class Context:
    """What a handler works on: the machine and the error register; while a handler
    runs, who sent its line (`owner`); a wait command leaves its wait in `wait` and the
    line holds there."""

    machine: MM4005Machine
    errors: ErrorRegister = field(default_factory=ErrorRegister)
    owner: LineOwner | None = None
    wait: Wait | None = None
    runner: LineRunner | None = None


@dataclass(frozen=True, slots=True)
class VariableRef:
    """``$Ypp`` in place of a value (manual 3.3.1): read when the command runs."""

    number: int


@dataclass(frozen=True, slots=True)
class Command:
    """One parsed command: ``axis`` is None for 'all axes' or no number; ``value`` is the
    operand (None when absent); ``query`` is a trailing '?'."""

    spec: CommandSpec
    axis: int | None
    value: float | int | str | VariableRef | None
    query: bool

    # The lexer has already checked the operand against the entry's Operand, so a handler
    # takes it with its type (one place for what every handler module asserted itself).
    def number(self) -> float:
        assert isinstance(self.value, float)
        return self.value

    def integer(self) -> int:
        assert isinstance(self.value, int)
        return self.value

    def axis_number(self) -> int:
        assert self.axis is not None
        return self.axis


Handler = Callable[[Context, Command], list[str]]


@dataclass(frozen=True, slots=True)
class CommandSpec:
    """A command table entry: behaviour bound to the mnemonic, with its evidence."""

    mnemonic: str
    handler: Handler
    axis: AxisRule
    operand: Operand
    query: bool  # accepts '?' and then replies
    replies: bool  # replies without '?' (a 'tell' command)
    summary: str
    source: str
    confidence: str  # C certain / I inferred / D our decision
    note: str = ""
