"""INITIALISE (TrioBASIC help INITIALISE): every axis parameter back to its power-up value.

Each parameter that differs from its power-up value is written through the machine's own
write (`set_axis_parameter`), one by one, axis by axis, as a program writing it would: a
new SPEED reaches the move running, a new PP_STEP keeps MPOS, a new ATYPE makes or drops a
servo loop, a limit input switched off stops acting. Positions, moves, links, TABLE, VR
and the system parameters are left alone (the page names axis parameters only; D). Read
only parameters are the machine's readings and have no power-up value to restore.
"""

from __future__ import annotations

from typing import Any

FIRST = ("ATYPE", "UNITS")
"""Written first (D): what the other parameters' meaning depends on."""
COMMANDS = frozenset({"ENDMOVE", "MOVELINK_MODIFY", "CORNER_STATE"})
"""Parameters whose write is an order to the motion, not a setting (ENDMOVE moves the
axis, MOVELINK_MODIFY reshapes a link, CORNER_STATE answers a corner): not written (D)."""


def initialise(machine: Any) -> None:
    """Every axis parameter of every axis to its power-up value (see the docstring)."""
    defaults: dict[str, float] = machine._axis_defaults
    names = [n for n in FIRST if n in defaults] + [n for n in defaults if n not in FIRST]
    for axis in range(machine.axis_count):
        params = machine.axes[axis].params
        for name in names:
            if name in COMMANDS or params.get(name) == defaults[name]:
                continue
            try:
                machine.set_axis_parameter(name, axis, defaults[name])
            except ValueError:
                continue  # read only: a reading, not a setting (see the docstring)
    machine.changed()


__all__ = ["COMMANDS", "FIRST", "initialise"]
