"""Manual 3.3.1: a line holds commands ``xxAAnn`` separated by ',' or ';', blanks are
ignored anywhere (even inside a number), at most 110 characters a line; mnemonics are
case insensitive. ``nn`` is a value or '?'.

A line is parsed whole before anything runs: a malformed command (unknown mnemonic A,
bad axis B, bad operand C) rejects the entire line (our decision: nothing half-done).
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Mapping
from typing import Final

from maxk.personalities.mm4005.errors import (
    AXIS_NUMBER,
    PARAMETER,
    UNKNOWN_MESSAGE,
    VARIABLE_NUMBER,
    MM4005Error,
)
from maxk.personalities.mm4005.programs import Variables

from .spec import AxisRule, Command, CommandSpec, Operand, VariableRef

MAX_OPERAND: Final = 1e9
"""A number operand beyond this (in any unit: a 4-axis stage travels less than a metre)
is out of limits (C), so no setting ever holds an infinity or a value no stage has (D:
the manual gives per-command ranges we could not all find)."""

MAX_LINE: Final = 110  # manual 3.3.1.3
BLANKS: Final = " \t"
SEPARATORS: Final = re.compile(r"[,;]")
_COMMAND: Final = re.compile(r"(\d*)([A-Za-z]{2})(.*)\Z", re.S)
_NUMBER: Final = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\Z")
_INTEGER: Final = re.compile(r"[+-]?\d+\Z")
MODES: Final = range(0, 3)  # OR0..OR2 (D: modes seen in a public Tcl driver)


def split_line(line: str) -> list[str]:
    """The non-empty commands of one line, blanks removed."""
    if len(line) > MAX_LINE:
        raise MM4005Error(UNKNOWN_MESSAGE, f"line longer than {MAX_LINE} characters")
    compact = "".join(ch for ch in line if ch not in BLANKS)
    return [piece for piece in SEPARATORS.split(compact) if piece]


def _axis(rule: AxisRule, digits: str, axis_count: int) -> int | None:
    if len(digits) > 9:  # no axis or element number has this many digits
        raise MM4005Error(AXIS_NUMBER, f"number {digits[:20]}...")
    number = int(digits) if digits else None
    if rule is AxisRule.NONE:
        if number is not None:
            raise MM4005Error(AXIS_NUMBER, "this command takes no axis number")
        return None
    if rule is AxisRule.ELEMENT:
        return number or None
    if rule is AxisRule.ALL_OR_ONE and not number:
        return None
    if rule is AxisRule.PHYSICAL and number is None:
        return None
    if number is None or not 1 <= number <= axis_count:
        raise MM4005Error(AXIS_NUMBER, f"axis {digits or 'missing'}")
    return number


_NUMERIC: Final = (Operand.NUMBER, Operand.OPTIONAL_NUMBER, Operand.SIGN, Operand.INTEGER,
                   Operand.MODE)
_VARIABLE: Final = re.compile(r"\$([YySs])(\d*)\Z")


def _variable(spec: CommandSpec, text: str) -> VariableRef:
    """``$Ypp`` where a number is taken (3.3.1): pp 1..120 else O (as TY, 3.145); a
    string variable ``$Saa`` or a value variable where no number is taken answers C (D)."""
    match = _VARIABLE.match(text)
    if match is None or match.group(1) in "Ss" or spec.operand not in _NUMERIC:
        raise MM4005Error(PARAMETER, f"{spec.mnemonic} cannot take {text[:20]!r}")
    digits = match.group(2)
    if not digits or len(digits) > 4 or not Variables.valid(int(digits)):
        raise MM4005Error(VARIABLE_NUMBER, f"variable {digits or 'missing'}")
    return VariableRef(int(digits))


def resolve(command: Command, variables: Variables) -> Command:
    """The command with a ``$Ypp`` operand replaced by the variable's value now, checked
    as a written value would be."""
    ref = command.value
    if not isinstance(ref, VariableRef):
        return command
    value = variables.get(ref.number)
    text = repr(value) if isinstance(value, float) else str(value)
    if command.spec.operand in (Operand.INTEGER, Operand.MODE) and isinstance(value, float):
        if not value.is_integer():
            raise MM4005Error(PARAMETER, f"$Y{ref.number} = {text} is not whole")
        text = str(int(value))
    resolved, _query = _operand(command.spec, text)
    return dataclasses.replace(command, value=resolved)


def _operand(spec: CommandSpec, text: str
             ) -> tuple[float | int | str | VariableRef | None, bool]:
    if text[:1] == "$" and spec.operand is not Operand.ANY:
        return _variable(spec, text), False
    if text == "?":
        if spec.query or spec.replies:
            return None, True
        raise MM4005Error(PARAMETER, f"{spec.mnemonic} cannot be queried")
    kind = spec.operand
    if kind is Operand.ANY:
        return (text or None), False
    if kind is Operand.CHAR:
        if len(text) > 1:
            raise MM4005Error(PARAMETER, "one character expected")
        return (text.upper() or None), False
    if not text:
        if kind in (Operand.NUMBER, Operand.INTEGER, Operand.SIGN):
            raise MM4005Error(PARAMETER, f"{spec.mnemonic} needs a value")
        return (0 if kind is Operand.MODE else None), False
    if kind is Operand.NONE:
        raise MM4005Error(PARAMETER, f"{spec.mnemonic} takes no value")
    if kind is Operand.SIGN and text in ("+", "-"):
        return (1.0 if text == "+" else -1.0), False
    if kind in (Operand.NUMBER, Operand.OPTIONAL_NUMBER, Operand.SIGN):
        if not _NUMBER.match(text):
            raise MM4005Error(PARAMETER, f"not a number: {text!r}")
        value = float(text)
        if not abs(value) <= MAX_OPERAND:  # also infinities ('1e999') and NaN
            raise MM4005Error(PARAMETER, f"{spec.mnemonic}{text}: beyond +/-{MAX_OPERAND:g}")
        return value, False
    if not _INTEGER.match(text):
        raise MM4005Error(PARAMETER, f"not an integer: {text!r}")
    if len(text) > 12 or abs(value := int(text)) > MAX_OPERAND:  # 2^63, 250 digits: C
        raise MM4005Error(PARAMETER, f"{spec.mnemonic}{text[:20]}: beyond +/-{MAX_OPERAND:g}")
    if kind is Operand.MODE and value not in MODES:
        raise MM4005Error(PARAMETER, f"mode {value}")
    return value, False


def parse_command(piece: str, table: Mapping[str, CommandSpec], axis_count: int) -> Command:
    """One ``xxAAnn`` command (blanks already removed)."""
    match = _COMMAND.match(piece)
    if match is None:
        raise MM4005Error(UNKNOWN_MESSAGE, piece)
    digits, mnemonic, rest = match.groups()
    spec = table.get(mnemonic.upper())
    if spec is None:
        raise MM4005Error(UNKNOWN_MESSAGE, mnemonic)
    axis = _axis(spec.axis, digits, axis_count)
    value, query = _operand(spec, rest)
    return Command(spec, axis, value, query)


def parse_line(line: str, table: Mapping[str, CommandSpec], axis_count: int) -> list[Command]:
    """Every command of a line, or MM4005Error for the first malformed one."""
    return [parse_command(piece, table, axis_count) for piece in split_line(line)]
