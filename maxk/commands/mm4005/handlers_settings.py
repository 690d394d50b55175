"""Handlers for the per-axis settings (gains, backlash, home speeds, VU, FE, ...) and the
controller reports the hosts read (TS, TN, TA, DV, DA, DF, XB, XI, XP, ZP, ZT).

A setting is ``nXXvalue`` (no reply) or ``nXX?`` (``nXX`` then the value); without an
axis number the query answers every axis, as TP does. Values are checked against the
setting's range (maxk/personalities/mm4005/settings.py) before anything changes.
"""

from __future__ import annotations

from maxk.personalities.mm4005 import axis_rules, status
from maxk.personalities.mm4005.errors import PARAMETER, MM4005Error
from maxk.personalities.mm4005.settings import RULES

from . import fmt
from .handlers_axis import axes_of
from .spec import Command, Context

MAX_BACKLASH_COUNTS = 10000  # manual 3.25: BA up to the distance of 10000 encoder counts
UNIT_NAMES = ("counts", "steps", "mm", "um", "in", "milli-in", "micro-in", "deg", "grad",
              "rad", "mrad", "urad")  # TN: the name of SN's code (the names are ours, D)


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
    """DV: the velocity VA set; 'xxDV1' the maximum allowed velocity (manual 3.43)."""
    assert cmd.axis is not None
    pp = 0.0 if cmd.value is None else float(cmd.value)  # type: ignore[arg-type]
    if pp < 0 or pp != int(pp):
        raise MM4005Error(PARAMETER, "DV's parameter is 0 or 1")
    m = ctx.machine
    value = m.velocity(cmd.axis) if pp == 0 else m.settings[cmd.axis - 1].get("VU")
    return [f"{cmd.axis}DV{fmt.fixed(value, 4)}"]


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
    return _per_axis(ctx, cmd, [UNIT_NAMES[int(x.get("SN"))] for x in ctx.machine.settings])


def tell_axis_type(ctx: Context, cmd: Command) -> list[str]:
    """TA: the axis's motor type (DC servo)."""
    return _per_axis(ctx, cmd, ["DC"] * ctx.machine.axis_count)


GAINS = {"XP": 0, "XI": 1, "XD": 2}  # index into the gains in force (KP, KI, KD, KS)


def tell_gain(ctx: Context, cmd: Command) -> list[str]:
    """XP/XI/XD: a gain the servo loop uses, as of the last UF (manual 3.169-3.177)."""
    assert cmd.axis is not None
    gains = ctx.machine.settings[cmd.axis - 1].active_gains
    return [f"{cmd.axis}{cmd.spec.mnemonic}{fmt.short(gains[GAINS[cmd.spec.mnemonic]])}"]


def following_error_limit(ctx: Context, cmd: Command) -> list[str]:
    """FE: set the maximum following error; it takes effect at the next UF (3.56)."""
    assert cmd.axis is not None and isinstance(cmd.value, float)
    m = ctx.machine
    left, right = m.travel_limits(cmd.axis)
    low = 2 * m.resolution(cmd.axis)
    if not low <= cmd.value <= right - left:
        raise MM4005Error(PARAMETER, f"FE outside {fmt.short(low)}..{fmt.short(right - left)}")
    m.settings[cmd.axis - 1].set("FE", cmd.value)
    return []


def master_slave_limit(ctx: Context, cmd: Command) -> list[str]:
    """FF: the maximum master-slave following error (stored; no master-slave here)."""
    assert cmd.axis is not None
    m = ctx.machine
    settings = m.settings[cmd.axis - 1]
    if cmd.query:
        return [f"{cmd.axis}FF{fmt.short(settings.get('FF'))}"]
    assert isinstance(cmd.value, float)
    left, right = m.travel_limits(cmd.axis)
    low = 2 * m.resolution(cmd.axis)
    if not low <= cmd.value <= right - left:
        raise MM4005Error(PARAMETER, f"FF outside {fmt.short(low)}..{fmt.short(right - left)}")
    settings.set("FF", cmd.value)
    return []


def tell_following_limit(ctx: Context, cmd: Command) -> list[str]:
    """XF: the maximum following error the loop uses (FE as of the last UF)."""
    assert cmd.axis is not None
    return [f"{cmd.axis}XF{fmt.short(ctx.machine.settings[cmd.axis - 1].following_limit)}"]


def tell_filter(ctx: Context, cmd: Command) -> list[str]:
    """TF: the filter parameters the loop uses: KP, KI, KD, KS and FE."""
    assert cmd.axis is not None
    s = ctx.machine.settings[cmd.axis - 1]
    kp, ki, kd, ks = s.active_gains
    values = ",".join(f"{name}{fmt.short(v)}" for name, v in
                      (("KP", kp), ("KI", ki), ("KD", kd), ("KS", ks),
                       ("FE", s.following_limit)))
    return [f"{cmd.axis}TF{values}"]


def tell_controller_status(ctx: Context, cmd: Command) -> list[str]:
    """TS: the controller status character: axes 1-4 moving, motor power off.

    Manual 3.139: bits 0-3 axes 1-4 moving, bit 4 motor power off, bit 6 always 1 (idle
    and powered: 'TS@')."""
    m = ctx.machine
    statuses = [m.status(a) for a in range(1, m.axis_count + 1)]
    return ["TS" + status.controller_status([s.moving for s in statuses],
                                            any(s.power_off for s in statuses))]


def tell_controller_activity(ctx: Context, cmd: Command) -> list[str]:
    """TX: the controller activity character: remote, command line, trajectory running.

    Manual 3.142: remote mode and this command line executing ('TXJ'), bit 4 while a
    trajectory runs ('TXZ')."""
    m = ctx.machine
    timed_running = (m.elements_done() < len(m.timed.elements)
                     and any(m.status(a).moving for a in m.timed.axes))
    return ["TX" + status.controller_activity(bool(m.trajectory_element()) or timed_running,
                                              m.tasks.program is not None)]


def backlash(ctx: Context, cmd: Command) -> list[str]:
    """BA: set the backlash compensation of an axis (0 or nothing disables it).

    Manual 3.25: at most the distance of 10000 encoder counts."""
    assert cmd.axis is not None
    value = 0.0 if cmd.value is None else float(cmd.value)  # type: ignore[arg-type]
    limit = MAX_BACKLASH_COUNTS * ctx.machine.resolution(cmd.axis)
    if not 0.0 <= value <= limit * (1 + 1e-12):
        raise MM4005Error(PARAMETER, f"BA outside 0..{fmt.short(limit)}")
    ctx.machine.settings[cmd.axis - 1].set("BA", value)
    return []


def speed_reduction(ctx: Context, cmd: Command) -> list[str]:
    """SD: the controller's reduced speed in percent ('SD?' reads it)."""
    holder = ctx.machine.settings[0]  # one value for the controller (see settings.py)
    if cmd.query:
        return ["SD" + fmt.short(holder.get("SD"))]
    assert isinstance(cmd.value, float)
    if not 0.0 < cmd.value <= 100.0:
        raise MM4005Error(PARAMETER, "SD outside 0..100 %")
    holder.set("SD", cmd.value)
    return []


def zero_position(ctx: Context, cmd: Command) -> list[str]:
    """ZP: the present position of the axis becomes 0; the travel limits stay."""
    assert cmd.axis is not None
    m = ctx.machine
    axis_rules.check_define_home(m.status(cmd.axis))
    preset = m.home_preset(cmd.axis)
    m.set_home_preset(cmd.axis, 0.0)
    m.define_home(cmd.axis, m.travel_limits(cmd.axis))
    m.set_home_preset(cmd.axis, preset)
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
