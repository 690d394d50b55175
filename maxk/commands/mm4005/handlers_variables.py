"""The variables (manual 3.3.1: ``$Ypp``, 1 to 100 integers and 101 to 120 floats, in
place of a command's value; 3.145 TY reads one: 0 until YS sets it).

YS and the other commands that set or compute a variable (YA..YY, AS, CS) were not found:
they answer Q, so every variable reads its power-up 0 here.
"""

from __future__ import annotations

from maxk.personalities.mm4005.errors import VARIABLE_NUMBER, MM4005Error
from maxk.personalities.mm4005.programs import Variables

from . import fmt
from .spec import Command, Context


def read_variable(ctx: Context, cmd: Command) -> list[str]:
    """TY: read variable xx (1..100 integers, 101..120 floats)."""
    number = cmd.axis
    if number is None or not Variables.valid(number):
        raise MM4005Error(VARIABLE_NUMBER, f"variable {number}")
    value = ctx.machine.variables.get(number)
    text = fmt.short(value) if isinstance(value, float) else str(value)
    return [f"{number}TY{text}"]
