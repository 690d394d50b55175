"""Handlers for the axis, status and error commands the EPICS MM4000/MM4005 drivers send.

Replies echo the axis number and mnemonic, then the value ('1TP5.0120'); an all-axes
query answers 'n' + mnemonic + value for every axis joined by ',' ('1MSD,2MSD'). Only
queries reply.
"""

from __future__ import annotations

from collections.abc import Callable

from maxk.personalities.mm4005 import axis_rules
from maxk.personalities.mm4005.errors import ErrorRegister

from . import fmt
from .spec import Command, Context


def axes_of(ctx: Context, cmd: Command) -> list[int]:
    """The addressed axis, or every axis for a missing/0 axis number."""
    return [cmd.axis] if cmd.axis is not None else list(range(1, ctx.machine.axis_count + 1))


def _per_axis(ctx: Context, cmd: Command, value: Callable[[int], str]) -> list[str]:
    mnemonic = cmd.spec.mnemonic
    return [",".join(f"{axis}{mnemonic}{value(axis)}" for axis in axes_of(ctx, cmd))]


def _position_text(ctx: Context, axis: int, value: float) -> str:
    return fmt.fixed(value, fmt.position_decimals(ctx.machine.resolution(axis)))


def _required_axis(cmd: Command) -> int:
    assert cmd.axis is not None  # the lexer enforces AxisRule.REQUIRED
    return cmd.axis


def _in_trajectory(ctx: Context, axis: int) -> bool:
    m = ctx.machine
    return m.trajectory_element() != 0 and axis in (m.trajectory.x_axis, m.trajectory.y_axis)



# --- tell commands ---------------------------------------------------------------------
def tell_position(ctx: Context, cmd: Command) -> list[str]:
    """TP: actual position(s)."""
    m = ctx.machine
    return _per_axis(ctx, cmd, lambda a: _position_text(ctx, a, m.position(a)))


def tell_theoretical(ctx: Context, cmd: Command) -> list[str]:
    """TH: theoretical position(s) (model 1 takes its readback from here)."""
    m = ctx.machine
    return _per_axis(ctx, cmd, lambda a: _position_text(ctx, a, m.theoretical_position(a)))


def tell_desired(ctx: Context, cmd: Command) -> list[str]:
    """DP: destination of the motion."""
    m = ctx.machine
    return _per_axis(ctx, cmd, lambda a: _position_text(ctx, a, m.target(a)))


def tell_status(ctx: Context, cmd: Command) -> list[str]:
    """MS: one status character per axis."""
    return _per_axis(ctx, cmd, lambda a: ctx.machine.status(a).char)


def tell_resolution(ctx: Context, cmd: Command) -> list[str]:
    """TU: the axis step, shortest form ('1TU0.001')."""
    return _per_axis(ctx, cmd, lambda a: fmt.short(ctx.machine.resolution(a)))


def tell_loop_type(ctx: Context, cmd: Command) -> list[str]:
    """TC: control loop type as an integer ('1TC0')."""
    return _per_axis(ctx, cmd, lambda a: str(ctx.machine.loop_type(a)))


def tell_home_preset(ctx: Context, cmd: Command) -> list[str]:
    """XH: home preset position."""
    return _per_axis(ctx, cmd, lambda a: _position_text(ctx, a, ctx.machine.home_preset(a)))


def tell_left_limit(ctx: Context, cmd: Command) -> list[str]:
    """TL: left (negative) software travel limit."""
    m = ctx.machine
    return _per_axis(ctx, cmd, lambda a: _position_text(ctx, a, m.travel_limits(a)[0]))


def tell_right_limit(ctx: Context, cmd: Command) -> list[str]:
    """TR: right (positive) software travel limit."""
    m = ctx.machine
    return _per_axis(ctx, cmd, lambda a: _position_text(ctx, a, m.travel_limits(a)[1]))


def tell_error(ctx: Context, cmd: Command) -> list[str]:
    """TE: the error character, then the register is clear."""
    return ["TE" + ctx.errors.take().char]


def tell_error_message(ctx: Context, cmd: Command) -> list[str]:
    """TB: the current error and its text (clearing it), or TBaa: translate code aa
    without touching the register (manual 3.126)."""
    if isinstance(cmd.value, str):
        return [f"TB{cmd.value} {ErrorRegister.describe(cmd.value)}"]
    code = ctx.errors.take()
    return [f"TB{code.char} {code.text}"]


def tell_version(ctx: Context, cmd: Command) -> list[str]:
    """VE: 'VE ' + version text; EPICS needs 'MM4005' in it (atoi after 'MM')."""
    return ["VE " + ctx.machine.version]


# --- settings with an optional '?' -------------------------------------------------------
def velocity(ctx: Context, cmd: Command) -> list[str]:
    """VA: velocity for the next moves."""
    axis = _required_axis(cmd)
    if cmd.query:
        return [f"{axis}VA{_position_text(ctx, axis, ctx.machine.velocity(axis))}"]
    value = cmd.number()
    axis_rules.check_rate(value, "VA")
    ctx.machine.set_velocity(axis, value)
    return []


def acceleration(ctx: Context, cmd: Command) -> list[str]:
    """AC: acceleration for the next moves."""
    axis = _required_axis(cmd)
    if cmd.query:
        return [f"{axis}AC{_position_text(ctx, axis, ctx.machine.acceleration(axis))}"]
    value = cmd.number()
    axis_rules.check_rate(value, "AC")
    ctx.machine.set_acceleration(axis, value)
    return []


def left_limit(ctx: Context, cmd: Command) -> list[str]:
    """SL: set the left software travel limit ('SL?' reads it)."""
    axis = _required_axis(cmd)
    limits = ctx.machine.travel_limits(axis)
    if cmd.query:
        return [f"{axis}SL{_position_text(ctx, axis, limits[0])}"]
    ctx.machine.set_travel_limits(axis, *axis_rules.new_limits(limits, left=cmd.number()))
    return []


def right_limit(ctx: Context, cmd: Command) -> list[str]:
    """SR: set the right software travel limit ('SR?' reads it)."""
    axis = _required_axis(cmd)
    limits = ctx.machine.travel_limits(axis)
    if cmd.query:
        return [f"{axis}SR{_position_text(ctx, axis, limits[1])}"]
    ctx.machine.set_travel_limits(axis, *axis_rules.new_limits(limits, right=cmd.number()))
    return []


def set_home(ctx: Context, cmd: Command) -> list[str]:
    """SH: set the home preset ('SH?' reads it, as XH does)."""
    axis = _required_axis(cmd)
    if cmd.query:
        return [f"{axis}SH{_position_text(ctx, axis, ctx.machine.home_preset(axis))}"]
    ctx.machine.set_home_preset(axis, cmd.number())
    return []


# --- actions ------------------------------------------------------------------------------
def define_home(ctx: Context, cmd: Command) -> list[str]:
    """DH: the current position becomes the home preset, the limits shift with it."""
    axis = _required_axis(cmd)
    m = ctx.machine
    axis_rules.check_define_home(m.status(axis))
    limits = axis_rules.limits_after_define_home(m.travel_limits(axis), m.position(axis),
                                                 m.home_preset(axis))
    m.define_home(axis, limits)
    return []


def move_absolute(ctx: Context, cmd: Command) -> list[str]:
    """PA: move to an absolute position."""
    axis = _required_axis(cmd)
    target = cmd.number()
    m = ctx.machine
    axis_rules.check_not_in_trajectory(_in_trajectory(ctx, axis))
    axis_rules.check_move(m.status(axis), m.travel_limits(axis), target)
    m.move_to(axis, target)
    return []


def move_relative(ctx: Context, cmd: Command) -> list[str]:
    """PR: move relative to the current destination (DP), so successive PRs add up."""
    axis = _required_axis(cmd)
    m = ctx.machine
    target = m.target(axis) + cmd.number()
    axis_rules.check_not_in_trajectory(_in_trajectory(ctx, axis))
    axis_rules.check_move(m.status(axis), m.travel_limits(axis), target)
    m.move_to(axis, target)
    return []


def stop(ctx: Context, cmd: Command) -> list[str]:
    """ST: stop one axis, or all axes without a number (model 1 init sends 'ST;')."""
    for axis in axes_of(ctx, cmd):
        ctx.machine.stop(axis)
    return []


def search_home(ctx: Context, cmd: Command) -> list[str]:
    """OR: home search on one axis or all; every addressed axis is checked first."""
    axes = axes_of(ctx, cmd)
    for axis in axes:
        axis_rules.check_not_in_trajectory(_in_trajectory(ctx, axis))
        axis_rules.check_home_search(ctx.machine.status(axis))
    mode = cmd.value if isinstance(cmd.value, int) else 0
    for axis in axes:
        ctx.machine.search_home(axis, mode)
    return []


def motor_on(ctx: Context, cmd: Command) -> list[str]:
    """MO: motor power on (one axis or all)."""
    for axis in axes_of(ctx, cmd):
        ctx.machine.set_power(axis, True)
    return []


def motor_off(ctx: Context, cmd: Command) -> list[str]:
    """MF: motor power off (one axis or all); MS then shows bit 1 (0x02)."""
    for axis in axes_of(ctx, cmd):
        ctx.machine.set_power(axis, False)
    return []
