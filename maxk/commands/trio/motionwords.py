"""SET_MOTION and SET_MOTIONSP: one command that writes a move's rates on a named axis.

Both are newer than the MC405's token table (helpwords.NEWER_WORDS). The axis is their first
argument (no BASE, no AXIS modifier: their pages); every value is checked as its parameter
would be before any is written, so a refused value leaves the axis as it was (D)."""

from __future__ import annotations

from collections.abc import Callable

from .keywords import KEYWORDS
from .lexer import TrioError

SET_MOTION_WORDS: dict[str, tuple[str, ...]] = {
    "SET_MOTION": ("SPEED", "ACCEL", "DECEL", "JERK"),
    "SET_MOTIONSP": ("FORCE_SPEED", "STARTMOVE_SPEED", "ENDMOVE_SPEED", "FORCE_ACCEL",
                     "FORCE_DECEL", "FORCE_JERK", "FORCE_RAMP", "FORCE_DWELL"),
}
_RATES = frozenset({"SPEED", "ACCEL", "DECEL"})  # refused on a negative-UNITS axis (UNITS)


def set_motion(name: str, args: list[float], axis_count: int,
               units: Callable[[int], float],
               write: Callable[[str, int, float], None]) -> None:
    """Check SET_MOTION(SP)(axis, v1[, v2...]) whole, then write v1.. to its parameters."""
    names = SET_MOTION_WORDS[name]
    if not 2 <= len(args) <= len(names) + 1:
        raise TrioError("Syntax error")
    axis = args[0]
    if axis != int(axis) or not 0 <= axis < axis_count:
        raise TrioError("Invalid axis number")
    pairs = list(zip(names[:len(args) - 1], args[1:], strict=True))
    for parameter, value in pairs:
        KEYWORDS[parameter].check(value)
        if parameter in _RATES and value > 0 and units(int(axis)) < 0:
            raise TrioError("Parameter out of range")
    for parameter, value in pairs:
        write(parameter, int(axis), value)
