"""The wait commands: a line (or a program) holds at them until the machine is ready.

WS, wait for motion stop: the ESP300's program example (p. 3-3: ``1PA+30``, ``1WS``,
``2PR-10``: axis 2 moves once axis 1 has stopped) and ESP-family hosts (``3MT+``
then ``3WS``; ``1 WS 0`` commented "wait for motion stop"), I. The wait ends on the tick
the axis's motion ends, however it ends (its target, ST, AB, a limit). nn: a delay in
milliseconds after the stop (D: the host's ``WS 0`` shows an operand; its meaning as a
delay is the ESP family's, not found on a page here).
"""

from __future__ import annotations

import math

from maxk.personalities.mm4005.errors import PARAMETER, MM4005Error
from maxk.personalities.mm4005.programs import MotionStop

from .spec import Command, Context

MAX_DELAY_MS = 3_600_000  # an hour (D)


def wait_motion_stop(ctx: Context, cmd: Command) -> list[str]:
    """WS: wait until axis xx (missing or 0: every axis) has stopped, then nn ms."""
    machine = ctx.machine
    delay_ms = 0.0 if cmd.value is None else cmd.number()
    if not 0 <= delay_ms <= MAX_DELAY_MS or delay_ms != math.floor(delay_ms):
        raise MM4005Error(PARAMETER, f"WS delay 0..{MAX_DELAY_MS} ms, whole")
    axes = (range(1, machine.axis_count + 1) if cmd.axis is None else (cmd.axis,))
    ticks = math.ceil(delay_ms / 1000.0 / machine.tick_period - 1e-9)

    def moving() -> bool:
        return any(machine.status(a).moving for a in axes)

    ctx.wait = MotionStop(moving, ticks)
    return []
