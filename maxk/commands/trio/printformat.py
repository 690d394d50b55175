"""PRINT's C format strings, ``PRINT x[":%12.2f:"]`` (TrioBASIC help, PRINT).

A format is text, one ``%`` conversion with its flags (``+`` sign, ``-`` left, ``0``
zeroes), width and precision, and more text, both echoed. The conversions: ``f F e E``
a float (4 decimals unless a precision is given, as the page's output shows), ``L`` a
64-bit integer, ``W`` and ``X`` that integer unsigned in decimal and hexadecimal (no sign,
even with ``+``), ``R`` and ``S`` a string (the whole string, width and precision as C's
``%s``), ``C`` a character code (``c`` too: the page's example writes it so).
"""

from __future__ import annotations

import math
import re

from .lexer import TrioError


class Real(float):
    """A FLOAT-typed value. The firmware types its values: PRINT writes a FLOAT with 4
    decimals even when it is whole, an INTEGER bare (help INT, example 2: ROUND(1.79)
    prints 2.0000, INT(ROUND(1.79)) prints 2). A value is FLOAT when it comes from a
    float function (FLOAT_FUNCTIONS), a TABLE value, a number written with a decimal
    point or an exponent, a VR or local variable (docs/trio.md: help VR, DIM), MOD and
    FMOD, or + - * / ^ with a FLOAT operand. Every other value (integer literals,
    parameters, comparisons, bit operations) is untyped and prints as before: bare when
    whole (D: the pages
    disagree on parameters, DPOS prints 5432 on its page and 300.0000 on OFFPOS's;
    atrio needs ?<integer> and ?MPE bare). Python arithmetic on a Real gives a plain
    float, so the interpreter marks each FLOAT result itself (`real`)."""

    __slots__ = ()


# Functions whose result is FLOAT: their pages print whole results with 4 decimals
# (SQR(4) 2.0000, VECTOR_MAG(3, 4) 5.0000, ROUND(PI) 3.0000, SGN(-1.2) -1.0000, FREE
# 47104.0000, DLINK(5, 0, 1) 463.0000, TABLE(1000) 1234.0000) or are the trigonometric
# and exponential family of those pages (I). Those printing bare (INT, ASC, ULPDIFF,
# RND: their pages) are not here.
FLOAT_FUNCTIONS = frozenset({"SQR", "VECTOR_MAG", "ROUND", "SGN", "FRAC", "SIN", "COS",
                             "TAN", "ATAN", "ATAN2", "ASIN", "ACOS", "EXP", "LN", "RNDF",
                             "TABLE", "FREE", "DLINK"})
FLOAT_OPERATORS = frozenset({"MOD", "FMOD"})  # 18 MOD 12 prints 6.0000 (help MOD)
ARITHMETIC = frozenset({"+", "-", "*", "/", "^"})


def real(value: float) -> Real:
    return value if isinstance(value, Real) else Real(value)


def decimal_literal(text: str) -> bool:
    """A number written with a decimal point or an exponent is FLOAT (not $hex)."""
    return not text.startswith("$") and any(c in text for c in ".eE")

_SPEC = re.compile(r"%([-+0]*)(\d*)(?:\.(\d+))?([fFeELWXRSCc])")
_MASK = (1 << 64) - 1


def check_spec(spec: str) -> re.Match[str]:
    """The one conversion of a format; none, or more than one, is a syntax error."""
    found = _SPEC.search(spec)
    if found is None or "%" in spec[found.end():] or "%" in spec[:found.start()]:
        raise TrioError("Syntax error")
    return found


def c_format(spec: str, value: float | str) -> str:
    """``value`` written by the one conversion in ``spec``."""
    found = check_spec(spec)
    flags, width, precision, kind = found.groups()
    before, after = spec[:found.start()], spec[found.end():]
    left = "-" if "-" in flags else ""
    if kind in "RS":
        text = value if isinstance(value, str) else _number_text(value)
        cut = f".{precision}" if precision is not None else ""
        return before + f"%{left}{width}{cut}s" % text + after
    if isinstance(value, str):
        raise TrioError("Type mismatch")
    if not math.isfinite(value):
        raise TrioError("Arithmetic error")
    if kind in "Cc":
        return before + f"%{left}{width}s" % chr(int(value) & 0x10FFFF) + after
    if kind in "fFeE":
        digits = 4 if precision is None else int(precision)
        return before + f"%{flags}{width}.{digits}{kind}" % value + after
    number = int(value)
    if kind == "L":
        return before + f"%{flags}{width}d" % number + after
    unsigned = flags.replace("+", "")
    conversion = "d" if kind == "W" else "X"
    return before + f"%{unsigned}{width}{conversion}" % (number & _MASK) + after


def _number_text(value: float) -> str:
    return f"{value:.4f}"
