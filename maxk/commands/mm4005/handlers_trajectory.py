"""Handlers for the trajectory commands of manual 5.7 and the synchronized pulses of 6.1.2.

The geometry, the checks and the pulse plan live in maxk.personalities.mm4005; this
module only turns commands into those calls and values into reply text.
"""

from __future__ import annotations

from maxk.personalities.mm4005 import Element, axis_rules
from maxk.personalities.mm4005.errors import (
    PARAMETER,
    TRAJECTORY_EMPTY,
    UNAUTHORIZED,
    MM4005Error,
)
from maxk.personalities.mm4005.geometry import Arc
from maxk.personalities.mm4005.trajectory import check_travel

from . import fmt
from .spec import Command, Context

LT_DECIMALS = 4  # D: element coordinates and lengths in LT/XE




def describe(element: Element) -> str:
    """LT/XE text of one element (our format): the command that built it, end point,
    arc radius and sweep, length."""
    g = element.geometry
    parts = [f"{element.number}LT{element.command}",
             f"X{fmt.fixed(g.end[0], LT_DECIMALS)}", f"Y{fmt.fixed(g.end[1], LT_DECIMALS)}"]
    if isinstance(g, Arc):
        parts += [f"R{fmt.fixed(g.radius, LT_DECIMALS)}", f"A{fmt.fixed(g.sweep, LT_DECIMALS)}"]
    parts.append(f"L{fmt.fixed(g.length, LT_DECIMALS)}")
    return " ".join(parts)


# --- setup -------------------------------------------------------------------------------
def new_trajectory(ctx: Context, cmd: Command) -> list[str]:
    """NT: start defining a new trajectory."""
    ctx.machine.trajectory.new()
    return []


def first_tangent(ctx: Context, cmd: Command) -> list[str]:
    """FA: tangent angle (degrees) of the first point."""
    traj = ctx.machine.trajectory
    if cmd.query:
        return ["FA" + fmt.short(traj.entry_angle)]
    value = cmd.number()
    if not -360.0 <= value <= 360.0:
        raise MM4005Error(PARAMETER, "FA outside -360..360")
    traj.entry_angle = value
    return []


def max_discontinuity(ctx: Context, cmd: Command) -> list[str]:
    """AD: maximum allowed angle of discontinuity, 0.001 to 10 degrees."""
    traj = ctx.machine.trajectory
    if cmd.query:
        return ["AD" + fmt.short(traj.max_discontinuity)]
    traj.set_max_discontinuity(cmd.number())
    return []


def assign_x(ctx: Context, cmd: Command) -> list[str]:
    """xxAX: physical axis xx becomes geometric X; 'AX' or 'AX?' reports it."""
    traj = ctx.machine.trajectory
    if cmd.axis is None or cmd.query:
        return [f"{traj.x_axis}AX"]
    traj.x_axis = cmd.axis
    return []


def assign_y(ctx: Context, cmd: Command) -> list[str]:
    """xxAY: physical axis xx becomes geometric Y; 'AY' or 'AY?' reports it."""
    traj = ctx.machine.trajectory
    if cmd.axis is None or cmd.query:
        return [f"{traj.y_axis}AY"]
    traj.y_axis = cmd.axis
    return []


def vector_velocity(ctx: Context, cmd: Command) -> list[str]:
    """VV: trajectory (vector) velocity, used by ET and the MPN."""
    traj = ctx.machine.trajectory
    if cmd.query:
        return ["VV" + fmt.short(traj.velocity)]
    value = cmd.number()
    axis_rules.check_rate(value, "VV")
    traj.velocity = value
    return []


def vector_acceleration(ctx: Context, cmd: Command) -> list[str]:
    """VS: trajectory (vector) acceleration."""
    traj = ctx.machine.trajectory
    if cmd.query:
        return ["VS" + fmt.short(traj.acceleration)]
    value = cmd.number()
    axis_rules.check_rate(value, "VS")
    traj.acceleration = value
    return []


# --- elements ----------------------------------------------------------------------------
def line_x(ctx: Context, cmd: Command) -> list[str]:
    """LX: line along the tangent to X = nn."""
    ctx.machine.trajectory.line_to_x(cmd.number())
    return []


def line_y(ctx: Context, cmd: Command) -> list[str]:
    """LY: line along the tangent to Y = nn."""
    ctx.machine.trajectory.line_to_y(cmd.number())
    return []


def line_end_x(ctx: Context, cmd: Command) -> list[str]:
    """MX: X of the next MY line's end point ('MX?' reads it)."""
    traj = ctx.machine.trajectory
    if cmd.query:
        return ["MX" + fmt.short(traj.line_x_end or 0.0)]
    traj.set_line_end_x(cmd.number())
    return []


def line_end_y(ctx: Context, cmd: Command) -> list[str]:
    """MY: build the line to (MX, nn)."""
    ctx.machine.trajectory.line_to_point(cmd.number())
    return []


def arc_radius(ctx: Context, cmd: Command) -> list[str]:
    """CR: radius of the next CA arc ('CR?' reads it)."""
    traj = ctx.machine.trajectory
    if cmd.query:
        return ["CR" + fmt.short(traj.radius or 0.0)]
    traj.set_radius(cmd.number())
    return []


def arc_sweep(ctx: Context, cmd: Command) -> list[str]:
    """CA: build the arc of radius CR sweeping nn degrees."""
    ctx.machine.trajectory.arc_by_sweep(cmd.number())
    return []


def arc_end_x(ctx: Context, cmd: Command) -> list[str]:
    """CX: X of the next CY arc's end point ('CX?' reads it)."""
    traj = ctx.machine.trajectory
    if cmd.query:
        return ["CX" + fmt.short(traj.arc_x or 0.0)]
    traj.set_arc_end_x(cmd.number())
    return []


def arc_end_y(ctx: Context, cmd: Command) -> list[str]:
    """CY: build the tangent arc ending at (CX, nn)."""
    ctx.machine.trajectory.arc_to_point(cmd.number())
    return []


def erase_last(ctx: Context, cmd: Command) -> list[str]:
    """EL: erase the last element."""
    ctx.machine.trajectory.erase_last()
    return []


# --- reports -------------------------------------------------------------------------------
def list_trajectory(ctx: Context, cmd: Command) -> list[str]:
    """LT: one line per element, or only element xx."""
    elements = ctx.machine.trajectory.elements
    if not elements:
        raise MM4005Error(TRAJECTORY_EMPTY)
    if cmd.axis is not None:
        if cmd.axis > len(elements):
            raise MM4005Error(PARAMETER, f"no element {cmd.axis}")
        return [describe(elements[cmd.axis - 1])]
    return [describe(element) for element in elements]


def tell_last_element(ctx: Context, cmd: Command) -> list[str]:
    """XE: the current (last defined) element, as LT lists it but echoed as XE."""
    elements = ctx.machine.trajectory.elements
    if not elements:
        raise MM4005Error(TRAJECTORY_EMPTY)
    return ["XE" + describe(elements[-1])]


def tell_element_count(ctx: Context, cmd: Command) -> list[str]:
    """XT: number of elements."""
    return [f"XT{len(ctx.machine.trajectory.elements)}"]


def tell_discontinuity(ctx: Context, cmd: Command) -> list[str]:
    """XA: the current maximum allowed angle of discontinuity."""
    return ["XA" + fmt.short(ctx.machine.trajectory.max_discontinuity)]


def tell_velocity(ctx: Context, cmd: Command) -> list[str]:
    """XV: trajectory velocity."""
    return ["XV" + fmt.short(ctx.machine.trajectory.velocity)]


def tell_acceleration(ctx: Context, cmd: Command) -> list[str]:
    """XU: trajectory acceleration."""
    return ["XU" + fmt.short(ctx.machine.trajectory.acceleration)]


def tell_executing(ctx: Context, cmd: Command) -> list[str]:
    """AT: element under execution, 0 when none."""
    return [f"AT{ctx.machine.trajectory_element()}"]


# --- synchronized pulses ---------------------------------------------------------------
def _element_number(cmd: Command, name: str) -> int:
    value = cmd.integer()
    if value < 0:
        raise MM4005Error(PARAMETER, f"{name} negative")
    return value


def pulse_start(ctx: Context, cmd: Command) -> list[str]:
    """NB: element where the pulses start (checked by ET)."""
    pulses = ctx.machine.trajectory.pulses
    if cmd.query:
        return [f"NB{pulses.start_element}"]
    pulses.start_element = _element_number(cmd, "NB")
    return []


def pulse_end(ctx: Context, cmd: Command) -> list[str]:
    """NE: element where the pulses end (checked by ET)."""
    pulses = ctx.machine.trajectory.pulses
    if cmd.query:
        return [f"NE{pulses.end_element}"]
    pulses.end_element = _element_number(cmd, "NE")
    return []


def pulse_step(ctx: Context, cmd: Command) -> list[str]:
    """NI: curvilinear step between pulses; NI? reads the MPN after ET replaced NN."""
    pulses = ctx.machine.trajectory.pulses
    if cmd.query:
        return ["NI" + fmt.short(pulses.reported_step())]
    value = cmd.number()
    axis_rules.check_positive(value, "NI")
    pulses.set_step(value)
    return []


def pulse_count(ctx: Context, cmd: Command) -> list[str]:
    """NN: number of pulses (steps + 1), checked against the MPN by ET."""
    pulses = ctx.machine.trajectory.pulses
    if cmd.query:
        return [f"NN{pulses.count}"]
    pulses.set_count(_element_number(cmd, "NN"))
    return []


def pulse_arm(ctx: Context, cmd: Command) -> list[str]:
    """NS: generate the pulses on the next ET (its effect ends with that trajectory)."""
    ctx.machine.trajectory.pulses.armed = True
    return []


# --- ET ---------------------------------------------------------------------------------
def execute_trajectory(ctx: Context, cmd: Command) -> list[str]:
    """ET: verify the definition, the pulse conditions, the axes and the travel, then
    run. An MPN substitution is reported through TE while the trajectory runs."""
    m = ctx.machine
    traj = m.trajectory
    if m.trajectory_element() != 0:
        raise MM4005Error(UNAUTHORIZED, "a trajectory is running")  # (D)
    x, y = traj.x_axis, traj.y_axis
    if x == y or not (1 <= x <= m.axis_count and 1 <= y <= m.axis_count):
        raise MM4005Error(PARAMETER, "X and Y must be two different installed axes")
    verified = traj.verify(max(m.resolution(x), m.resolution(y)), m.trajectory_base_period)
    for axis in (x, y):
        status = m.status(axis)
        if status.power_off or status.moving:
            raise MM4005Error(UNAUTHORIZED, f"axis {axis} off or moving")
    origin = (m.theoretical_position(x), m.theoretical_position(y))
    check_travel(verified.geometries, origin, m.travel_limits(x), m.travel_limits(y))
    m.start_trajectory(traj.commit(verified, origin))
    if verified.warning is not None:
        ctx.errors.record(verified.warning)
    return []
