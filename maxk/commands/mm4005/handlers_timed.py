"""Handlers for the time-based trajectory the EPICS MM4005 trajectory scan sends (NC, DC,
UC, DT, DX, MB/ME/MN, VC, RC, GC, LS, EC, XC, NQ, TQ) and AB.

Reply layouts are the ones the scan parses (reference mm4005-trajectory-scan.md): a
number from offset 3 of ``nGC``/``nRC`` replies, from offset 2 of ``XC``/``NQ``, and
``iTQ,1THa,1TPb,2THc,2TPd,...`` with a TH and a TP token for every installed axis.
"""

from __future__ import annotations

from maxk.personalities.mm4005.errors import PARAMETER, MM4005Error

from . import fmt
from .spec import Command, Context

MIN_TIME_SCALE = 0.01  # EC's time scale, 0.01..1000 (D)
MAX_TIME_SCALE = 1000.0





def _position(ctx: Context, axis: int, value: float) -> str:
    return fmt.fixed(value, fmt.position_decimals(ctx.machine.resolution(axis)))


def new_timed(ctx: Context, cmd: Command) -> list[str]:
    """NC: initialise a new time-based trajectory."""
    ctx.machine.timed.new()
    return []


def take_part(ctx: Context, cmd: Command) -> list[str]:
    """DC: axis n takes part in the time-based trajectory (1) or not (0)."""
    value = cmd.integer()
    if value not in (0, 1):
        raise MM4005Error(PARAMETER, "DC takes 0 or 1")
    ctx.machine.timed.take_part(cmd.axis_number(), value == 1)
    return []


def accel_time(ctx: Context, cmd: Command) -> list[str]:
    """UC: the acceleration time of the time-based trajectory, seconds."""
    timed = ctx.machine.timed
    if cmd.query:
        return ["UC" + fmt.short(timed.accel_time)]
    value = cmd.number()
    if not 0.001 <= value <= 100.0:  # (D) so the acceleration VC reports stays finite
        raise MM4005Error(PARAMETER, "UC out of 0.001..100 s")
    timed.accel_time = value
    timed.verified = False
    return []


def element_time(ctx: Context, cmd: Command) -> list[str]:
    """DT: element i's duration, seconds (creates the next element)."""
    if cmd.axis is None:
        raise MM4005Error(PARAMETER, "DT needs an element number")
    value = cmd.number()
    if value > 1e6:
        raise MM4005Error(PARAMETER, "DT beyond 1e6 s")
    ctx.machine.timed.set_duration(cmd.axis, value)
    return []


def displacement(ctx: Context, cmd: Command) -> list[str]:
    """DX: axis n's displacement in the element the last DT named, controller units."""
    ctx.machine.timed.set_displacement(cmd.axis_number(), cmd.number())
    return []


def pulse_first(ctx: Context, cmd: Command) -> list[str]:
    """MB: first element of the pulse output."""
    timed = ctx.machine.timed
    if cmd.query:
        return ["MB" + str(timed.pulse_start)]
    timed.set_pulses(start=cmd.integer())
    return []


def pulse_last(ctx: Context, cmd: Command) -> list[str]:
    """ME: last element of the pulse output."""
    timed = ctx.machine.timed
    if cmd.query:
        return ["ME" + str(timed.pulse_end)]
    timed.set_pulses(end=cmd.integer())
    return []


def pulse_number(ctx: Context, cmd: Command) -> list[str]:
    """MN: pulses asked for; the controller puts out one fewer."""
    timed = ctx.machine.timed
    if cmd.query:
        return ["MN" + str(timed.pulse_request)]
    timed.set_pulses(count=cmd.integer())
    return []


def verify_timed(ctx: Context, cmd: Command) -> list[str]:
    """VC: verify the time-based trajectory (TB then tells the outcome)."""
    ctx.machine.verify_timed()
    return []


def verify_report(ctx: Context, cmd: Command) -> list[str]:
    """RC: what VC found for axis n (1/2 speed change, 3/4 velocity, 5/6 acceleration)."""
    if cmd.value is None:  # 'nRC?' or 'nRC': which figure is missing
        raise MM4005Error(PARAMETER, "RC needs 1..6")
    which = cmd.integer()
    if not 1 <= which <= 6:
        raise MM4005Error(PARAMETER, "RC1..RC6")
    axis = cmd.axis_number()
    figures = ctx.machine.timed.figures.get(axis)
    value = 0.0 if figures is None else figures.report(which)
    text = str(int(value)) if which % 2 else fmt.fixed(value, 6)
    return [f"{axis}RC{text}"]


def speed_error_limit(ctx: Context, cmd: Command) -> list[str]:
    """GC: axis n's maximum speed change between elements (0: not checked)."""
    axis = cmd.axis_number()
    limits = ctx.machine.timed.speed_error_limits
    if cmd.query:
        return [f"{axis}GC{fmt.short(limits[axis - 1])}"]
    value = cmd.number()
    if value < 0.0:
        raise MM4005Error(PARAMETER, "GC must not be negative")
    limits[axis - 1] = value
    ctx.machine.timed.verified = False
    return []


def load_sequence(ctx: Context, cmd: Command) -> list[str]:
    """LS: accepted before EC, no effect here."""
    return []


def execute_timed(ctx: Context, cmd: Command) -> list[str]:
    """EC: execute the verified time-based trajectory at a time scale (0EC real)."""
    if cmd.axis not in (None, 0):
        raise MM4005Error(PARAMETER, "only 0EC (real execution) is modelled")
    scale = 1.0 if cmd.value is None else cmd.number()
    if not MIN_TIME_SCALE <= scale <= MAX_TIME_SCALE:
        raise MM4005Error(PARAMETER, f"time scale out of {MIN_TIME_SCALE:g}..{MAX_TIME_SCALE:g}")
    ctx.machine.execute_timed(scale)
    return []


def elements_done(ctx: Context, cmd: Command) -> list[str]:
    """XC: the last element of the time-based trajectory completed."""
    return ["XC" + str(ctx.machine.elements_done())]


def trace_count(ctx: Context, cmd: Command) -> list[str]:
    """NQ: the number of trace points (pulses recorded) of the last run."""
    return ["NQ" + str(ctx.machine.pulse_trace.total)]


def trace_point(ctx: Context, cmd: Command) -> list[str]:
    """TQ: trace point i: every axis's theoretical and actual position at pulse i."""
    from maxk.personalities.mm4005.timed import TracePoint
    if cmd.axis is None:
        raise MM4005Error(PARAMETER, "TQ needs a trace point number")
    point = ctx.machine.pulse_trace.get(cmd.axis)
    if not isinstance(point, TracePoint):
        raise MM4005Error(PARAMETER, f"no trace point {cmd.axis}")
    tokens = [f"{cmd.axis}TQ"]
    for axis, (th, tp) in enumerate(zip(point.theoretical, point.actual, strict=True),
                                    start=1):
        tokens.append(f"{axis}TH{_position(ctx, axis, th)}")
        tokens.append(f"{axis}TP{_position(ctx, axis, tp)}")
    return [",".join(tokens)]


def abort_motion(ctx: Context, cmd: Command) -> list[str]:
    """AB: abort every motion and trajectory at once."""
    ctx.machine.abort()
    return []
