"""SERVO_READ(vr_start, p0[, ... p7]): up to 8 parameters read on one servo cycle into
successive VRs, not scaled by UNITS (TrioBASIC help SERVO_READ).

The statement waits for the next servo cycle and reads every parameter there, so the
values belong together (page: "synchronously on the next servo cycle"); the process goes
on after it (I). "Not scaled by UNITS": an axis parameter the emulator gives in user units
(a position, distance, speed, acceleration or jerk: `SCALED`, each from its own page's
unit) is stored times its axis's UNITS, i.e. in counts (per second ...); any other value
(ENCODER, AXISSTATUS, a system parameter, an expression) is stored as read (D: the page
names no list; the parameters in AXIS_UNITS of a FRAME are stored as read too). A
parameter without AXIS(n) reads the axis SERVO_READ's own AXIS(n) names, else BASE (D).
A VR range past the last VR is 'Parameter out of range' with no VR written (D).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Generator, Sequence

from ...personalities.trio.memory import VR_COUNT
from .lexer import TrioError
from .machine import TrioMachine
from .parser import Expr, Param

SCALED = frozenset({
    # positions and distances (user units)
    "DPOS", "MPOS", "FE", "FE_LATCH", "FE_LIMIT", "FE_RANGE", "ENDMOVE", "REMAIN",
    "REG_POS", "REG_POSB", "OPEN_WIN", "CLOSE_WIN", "FS_LIMIT", "RS_LIMIT", "REP_DIST",
    "BACKLASH_DIST", "IN_POS_DIST",
    # speeds (user units/s; REGIST_SPEED user units/ms)
    "SPEED", "VP_SPEED", "MSPEED", "MSPEEDF", "DEMAND_SPEED", "CREEP", "JOGSPEED",
    "FHSPEED", "FORCE_SPEED", "STARTMOVE_SPEED", "ENDMOVE_SPEED", "IN_POS_SPEED",
    "REGIST_SPEED", "REGIST_SPEEDB",
    # accelerations and jerks (user units/s^2, /s^3)
    "ACCEL", "DECEL", "FASTDEC", "VP_ACCEL", "JERK", "VP_JERK",
})
MAX_PARAMETERS = 8


def servo_read(machine: TrioMachine, args: Sequence[Expr], axis: Expr | None,
               number: Callable[[Expr], float], axis_of: Callable[[Expr | None], int]
               ) -> Generator[None, None, None]:
    """Wait for the next servo cycle, then read and store them all (`number` evaluates
    an expression and `axis_of` an AXIS(n) modifier in the asking process)."""
    if not 2 <= len(args) <= MAX_PARAMETERS + 1:
        raise TrioError("Syntax error")
    start = number(args[0])
    if start != int(start) or not 0 <= start <= VR_COUNT - len(args) + 1:
        raise TrioError("Parameter out of range")
    due = machine.servo_tick() + 1
    while machine.servo_tick() < due:
        yield None
    values = []  # (all read before any is written)
    for expr in args[1:]:
        if isinstance(expr, Param) and expr.axis is None and axis is not None \
                and expr.keyword.axis_modifier:
            expr = dataclasses.replace(expr, axis=axis)
        value = number(expr)
        if isinstance(expr, Param) and expr.keyword.name in SCALED:
            value *= machine.axis_parameter("UNITS", axis_of(expr.axis))
        values.append(value)
    for offset, value in enumerate(values):
        machine.vr_write(int(start) + offset, value)
