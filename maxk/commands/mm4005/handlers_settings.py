"""Handlers for the per-axis settings (gains, backlash, home speeds, VU, FE, ...) and the
controller reports the hosts read (TS, TN, TA, DV, DA, DF, XB, XI, XP, ZP, ZT).

A setting is ``nXXvalue`` (no reply) or ``nXX?`` (``nXX`` then the value); without an
axis number the query answers every axis, as TP does. Values are checked against the
setting's range (maxk/personalities/mm4005/settings.py) before anything changes.
"""

from __future__ import annotations

from maxk.personalities.mm4005.errors import PARAMETER, MM4005Error
from maxk.personalities.mm4005.settings import RULES

from . import fmt
from .handlers_axis import axes_of
from .spec import Command, Context

UNITS_NAME = "mm"  # TN (D: the stages' units; the units codes of SN are not modelled)


def setting(ctx: Context, cmd: Command) -> list[str]:
    """A stored per-axis setting: set it, or read it back."""
    name = cmd.spec.mnemonic
    axes = axes_of(ctx, cmd)
    settings = ctx.machine.settings
    if cmd.query or cmd.value is None:
        return [",".join(f"{a}{name}{fmt.short(settings[a - 1].get(name))}" for a in axes)]
    assert isinstance(cmd.value, (int, float))
    value = float(cmd.value)
    if not all(settings[a - 1].check(name, value) for a in axes):
        rule = RULES[name]
        raise MM4005Error(PARAMETER, f"{name} outside {rule.low:g}..{rule.high:g}")
    for a in axes:
        settings[a - 1].set(name, value)
    return []


def update_filter(ctx: Context, cmd: Command) -> list[str]:
    """UF: the gains set by KP/KI/KD/KS take effect on the loop."""
    for a in axes_of(ctx, cmd):
        ctx.machine.apply_gains(a)
    return []


def _per_axis(ctx: Context, cmd: Command, value: list[str]) -> list[str]:
    axes = axes_of(ctx, cmd)
    return [",".join(f"{a}{cmd.spec.mnemonic}{value[a - 1]}" for a in axes)]


def _positions(ctx: Context, values: list[float]) -> list[str]:
    m = ctx.machine
    return [fmt.fixed(v, fmt.position_decimals(m.resolution(a + 1)))
            for a, v in enumerate(values)]


def tell_desired_velocity(ctx: Context, cmd: Command) -> list[str]:
    """DV: the desired (profile) velocity now, units/s."""
    m = ctx.machine
    return _per_axis(ctx, cmd, [fmt.fixed(m.desired_velocity(a), 4)
                                for a in range(1, m.axis_count + 1)])


def tell_desired_acceleration(ctx: Context, cmd: Command) -> list[str]:
    """DA: the acceleration the axis is set to move with (AC), units/s2."""
    m = ctx.machine
    return _per_axis(ctx, cmd, [fmt.short(m.acceleration(a))
                                for a in range(1, m.axis_count + 1)])


def tell_following_error(ctx: Context, cmd: Command) -> list[str]:
    """DF: following error, theoretical minus actual position."""
    m = ctx.machine
    return _per_axis(ctx, cmd, _positions(ctx, [m.theoretical_position(a) - m.position(a)
                                                for a in range(1, m.axis_count + 1)]))


def tell_backlash(ctx: Context, cmd: Command) -> list[str]:
    """XB: the backlash compensation BA set."""
    s = ctx.machine.settings
    return _per_axis(ctx, cmd, [fmt.short(x.get("BA")) for x in s])


def tell_units(ctx: Context, cmd: Command) -> list[str]:
    """TN: the axis's units name."""
    return _per_axis(ctx, cmd, [UNITS_NAME] * ctx.machine.axis_count)


def tell_axis_type(ctx: Context, cmd: Command) -> list[str]:
    """TA: the axis's motor type (DC servo)."""
    return _per_axis(ctx, cmd, ["DC"] * ctx.machine.axis_count)


def tell_index(ctx: Context, cmd: Command) -> list[str]:
    """XI: the home preset as the index position (no index modelled)."""
    m = ctx.machine
    return _per_axis(ctx, cmd, _positions(ctx, [m.home_preset(a)
                                                for a in range(1, m.axis_count + 1)]))


def tell_program(ctx: Context, cmd: Command) -> list[str]:
    """XP: the program running (stored programs are not modelled: 0)."""
    return ["XP0"]


def tell_controller_status(ctx: Context, cmd: Command) -> list[str]:
    """TS: controller status character: bit 0 an axis moving, bit 1 a trajectory
    running, bit 2 an error waiting in the register, bit 6 always 1."""
    m = ctx.machine
    bits = 0x40
    if any(m.status(a).moving for a in range(1, m.axis_count + 1)):
        bits |= 0x01
    if m.trajectory_element() or (m.elements_done() < len(m.timed.elements)
                                  and any(m.status(a).moving for a in m.timed.axes)):
        bits |= 0x02
    if ctx.errors.peek().char != "@":
        bits |= 0x04
    return ["TS" + chr(bits)]


def tell_parameters(ctx: Context, cmd: Command) -> list[str]:
    """ZT: every axis's settings, one line per axis."""
    m = ctx.machine
    lines = []
    for a in range(1, m.axis_count + 1):
        s = m.settings[a - 1]
        left, right = m.travel_limits(a)
        parts = [f"{a}ZT", f"VA{fmt.short(m.velocity(a))}", f"AC{fmt.short(m.acceleration(a))}",
                 f"TL{fmt.short(left)}", f"TR{fmt.short(right)}"]
        parts += [f"{name}{fmt.short(s.get(name))}" for name in RULES]
        lines.append(" ".join(parts))
    return lines


def tell_pulse_setup(ctx: Context, cmd: Command) -> list[str]:
    """ZP: the time-based trajectory's pulse set-up (MB, ME, MN) and trace count."""
    t = ctx.machine.timed
    return [f"ZP MB{t.pulse_start} ME{t.pulse_end} MN{t.pulse_request} "
            f"NQ{ctx.machine.pulse_trace.total}"]


def synchronize(ctx: Context, cmd: Command) -> list[str]:
    """SY: accepted; nothing to synchronise on one controller."""
    return []


def encoder_resolution(ctx: Context, cmd: Command) -> list[str]:
    """SU: the encoder resolution, read as TU; it is fixed here."""
    if cmd.query or cmd.value is None:
        m = ctx.machine
        return [",".join(f"{a}SU{fmt.short(m.resolution(a))}" for a in axes_of(ctx, cmd))]
    raise MM4005Error(PARAMETER, "the resolution is fixed (TU)")


def jog(ctx: Context, cmd: Command) -> list[str]:
    """MV: move toward the travel limit on the operand's side (+ or -) at VA."""
    assert isinstance(cmd.value, float) and cmd.axis is not None
    if cmd.value == 0:
        raise MM4005Error(PARAMETER, "MV needs a direction")
    left, right = ctx.machine.travel_limits(cmd.axis)
    ctx.machine.move_to(cmd.axis, right if cmd.value > 0 else left)
    return []


def to_limit(ctx: Context, cmd: Command) -> list[str]:
    """ML: move to the travel limit on the operand's side."""
    return jog(ctx, cmd)
