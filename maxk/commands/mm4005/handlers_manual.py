"""Handlers for what the table knows but the emulator runs differently: the simulated
execution ``1EC`` and the commands that cannot be modelled on this machine.

A command that cannot be modelled is still known (never error A, which says the mnemonic
does not exist): it is refused with Q "Function not authorized" (the French firmware's
'Fonction non autorisee', I) and a detail naming why, so TB, the console and a host all
see it; nothing changes (our decision, D).
"""

from __future__ import annotations

from maxk.personalities.mm4005.errors import (
    IO_CHANNEL,
    NOT_AUTHORIZED_FUNCTION,
    PARAMETER,
    TRAJECTORY_NOT_VERIFIED,
    TRAJECTORY_VELOCITY,
    TRAVEL_LIMITS,
    UNAUTHORIZED,
    MM4005Error,
)

from . import fmt
from . import handlers_timed as tm
from .spec import Command, Context

REAL = 0  # '0EC': run the motors
SIMULATE = 1  # '1EC': the scan's SimMode 1


def execute(ctx: Context, cmd: Command) -> list[str]:
    """EC: execute the verified time-based trajectory (0EC) or simulate it (1EC)."""
    if cmd.axis not in (None, REAL, SIMULATE):
        raise MM4005Error(PARAMETER, "EC prefix 0 (real) or 1 (simulation)")
    if cmd.axis != SIMULATE:
        return tm.execute_timed(ctx, cmd)
    scale = 1.0 if cmd.value is None else float(cmd.value)  # type: ignore[arg-type]
    if not tm.MIN_TIME_SCALE <= scale <= tm.MAX_TIME_SCALE:
        raise MM4005Error(PARAMETER,
                          f"time scale out of {tm.MIN_TIME_SCALE:g}..{tm.MAX_TIME_SCALE:g}")
    simulate(ctx, scale)
    return []


def simulate(ctx: Context, scale: float) -> None:
    """1EC (D: the page was not found): every check 0EC makes, in the same order and with
    the same letters (J not verified, D an axis off or moving, H faster than VU at this
    time scale, R leaving TL..TR from where the axes stand), and nothing else: no axis
    moves, no pulse fires, XC, NQ and TQ keep the last real run. A host learns whether
    the real run would start, as the EPICS scan's SimMode=1 asks."""
    m = ctx.machine
    timed = m.timed
    if not timed.verified:
        raise MM4005Error(TRAJECTORY_NOT_VERIFIED, "VC first")
    for number in sorted(timed.axes):
        state = m.status(number)
        if state.power_off or state.moving:
            raise MM4005Error(UNAUTHORIZED, f"axis {number} off or moving")
    for number, figures in timed.figures.items():
        if figures.velocity / scale > m.settings[number - 1].get("VU"):
            raise MM4005Error(TRAJECTORY_VELOCITY, f"axis {number} at this time scale")
    for number in sorted(timed.axes):
        left, right = m.travel_limits(number)
        position = low = high = m.theoretical_position(number)
        for element in timed.elements:
            position += element.moves.get(number, 0.0)
            low, high = min(low, position), max(high, position)
        if low < left - 1e-9 or high > right + 1e-9:
            raise MM4005Error(TRAVEL_LIMITS, f"axis {number} would leave TL..TR")


def not_modelled(ctx: Context, cmd: Command) -> list[str]:
    """A known command this emulator cannot carry out: refused with Q (see the note)."""
    raise MM4005Error(NOT_AUTHORIZED_FUNCTION,
                      f"{cmd.spec.mnemonic} is not modelled: {cmd.spec.note or 'see the table'}")


def master_slave(ctx: Context, cmd: Command) -> list[str]:
    """SS: master-slave mode; every axis is its own master here ('xxSS?' reads 0)."""
    assert cmd.axis is not None
    if cmd.query:
        return [f"{cmd.axis}SS0"]
    raw = 0.0 if cmd.value is None else float(cmd.value)  # type: ignore[arg-type]
    if raw != int(raw):
        raise MM4005Error(PARAMETER, "SS takes whole numbers")
    value = int(raw)
    master, mode = (value // 10, value % 10) if value >= 10 else (value, 0)
    if not (0 <= master <= ctx.machine.axis_count and mode in (0, 1) and value < 100):
        raise MM4005Error(PARAMETER, "SS: master 0..axis count, mode 0 or 1")
    if master not in (0, cmd.axis):
        raise MM4005Error(NOT_AUTHORIZED_FUNCTION,
                          "SS is not modelled: an axis cannot be slaved to another here")
    return []


GR_RANGE = (0.0001, 10000.0)  # manual 3.60


def reduction_ratio(ctx: Context, cmd: Command) -> list[str]:
    """GR: the master-slave reduction ratio of a slave axis (missing: 1.0)."""
    assert cmd.axis is not None
    settings = ctx.machine.settings[cmd.axis - 1]
    if cmd.query:
        return [f"{cmd.axis}GR{fmt.short(settings.get('GR'))}"]
    value = 1.0 if cmd.value is None else float(cmd.value)  # type: ignore[arg-type]
    if not GR_RANGE[0] <= value <= GR_RANGE[1]:
        raise MM4005Error(PARAMETER, "GR outside 0.0001..10000")
    settings.set("GR", value)
    return []


IO_BITS = range(1, 9)  # manual 3.103: the GPIO connector's 8 input bits


def read_inputs(ctx: Context, cmd: Command) -> list[str]:
    """RB: one GPIO input bit (xx 1..8: 0 or 1) or the whole byte (xx 0 or missing)."""
    bit = cmd.axis or 0
    if bit == 0:
        byte = sum(1 << (b - 1) for b in IO_BITS if ctx.machine.input_level(b))
        return [f"RB{byte}"]
    if bit not in IO_BITS:
        raise MM4005Error(IO_CHANNEL, f"I/O bit {bit}")
    return [f"{bit}RB{int(ctx.machine.input_level(bit))}"]
