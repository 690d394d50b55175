"""Handlers of the MM4005's inputs and outputs (SB, RA) and its global trace mode (GQ,
SQ): the levels live in the shared world and the samples in the controller's trace
buffer (personalities/mm4005/io.py, trace_mode.py); these only check and format.
"""

from __future__ import annotations

from maxk.personalities.mm4005.errors import IO_CHANNEL, PARAMETER, UNAUTHORIZED, MM4005Error
from maxk.personalities.mm4005.io import ANALOG_INPUTS, PORT_MAX
from maxk.personalities.mm4005.trace_mode import MAX_PERIOD, MAX_SAMPLES

from . import fmt
from .spec import Command, Context

ANALOG_DECIMALS = 4  # volts, 0.1 mV (D: the RA page with its format was not found)


def output_port(ctx: Context, cmd: Command) -> list[str]:
    """SB: drive the 8 GPIO outputs at once from a byte (SB? reads it back)."""
    gpio = ctx.machine.gpio
    if cmd.query:
        return [f"SB{gpio.output_port()}"]
    byte = cmd.integer()
    if not 0 <= byte <= PORT_MAX:
        raise MM4005Error(PARAMETER, f"SB takes 0..{PORT_MAX}, one bit an output")
    gpio.set_output_port(byte)
    return []


def read_analog(ctx: Context, cmd: Command) -> list[str]:
    """RA: an analog input's voltage (xx 1..4), or every input's without xx."""
    gpio = ctx.machine.gpio
    if cmd.axis is None:
        return [",".join(f"{n}RA{fmt.fixed(gpio.analog_volts(n), ANALOG_DECIMALS)}"
                         for n in ANALOG_INPUTS)]
    if cmd.axis not in ANALOG_INPUTS:
        raise MM4005Error(IO_CHANNEL, f"analog input {cmd.axis}")
    return [f"{cmd.axis}RA{fmt.fixed(gpio.analog_volts(cmd.axis), ANALOG_DECIMALS)}"]


def global_trace(ctx: Context, cmd: Command) -> list[str]:
    """GQ: acquire nn samples of every axis's TH and TP (GQ0 ends it; GQ? reads nn)."""
    trace = ctx.machine.global_trace
    if cmd.query:
        return [f"GQ{trace.requested}"]
    count = cmd.integer()
    if not 0 <= count <= MAX_SAMPLES:
        raise MM4005Error(PARAMETER, f"GQ takes 0..{MAX_SAMPLES} samples")
    if count == 0:
        trace.stop()
    else:
        trace.start(count)
    return []


def sample_rate(ctx: Context, cmd: Command) -> list[str]:
    """SQ: servo cycles (0.5 ms each) between two global trace samples (SQ? reads it)."""
    trace = ctx.machine.global_trace
    if cmd.query:
        return [f"SQ{trace.period}"]
    period = cmd.integer()
    if not 1 <= period <= MAX_PERIOD:
        raise MM4005Error(PARAMETER, f"SQ takes 1..{MAX_PERIOD} servo cycles")
    if trace.acquiring:
        raise MM4005Error(UNAUTHORIZED, "SQ while a global trace acquires")
    trace.period = period
    return []


# ---- the trace mode: TM, SP, TT, XN (manual 3.140 TT) --------------------------------------
MIN_TRACE_PERIOD = 0.0005  # one servo cycle (manual 7.1.1)
MAX_TRACE_PERIOD = MAX_PERIOD * MIN_TRACE_PERIOD  # 5 s (D)


def trace_mode(ctx: Context, cmd: Command) -> list[str]:
    """TM: trace axis xx's TH and TP for nn samples, one every SP (xxTM0 ends it)."""
    trace = ctx.machine.axis_trace
    axis = cmd.axis_number()
    if cmd.query:
        return [f"{axis}TM{trace.requested if trace.axis == axis else 0}"]
    count = cmd.integer()
    if not 0 <= count <= MAX_SAMPLES:
        raise MM4005Error(PARAMETER, f"TM takes 0..{MAX_SAMPLES} samples")
    if count == 0:
        if trace.axis == axis:
            trace.stop()
        return []
    trace.start_axis(axis, count)
    return []


def trace_period(ctx: Context, cmd: Command) -> list[str]:
    """SP: the trace mode's sample period in seconds (whole servo cycles)."""
    trace = ctx.machine.axis_trace
    tick = ctx.machine.tick_period
    if cmd.query:
        return [f"SP{fmt.short(round(trace.period * tick, 6))}"]
    seconds = cmd.number()
    cycles = round(seconds / tick)
    if not MIN_TRACE_PERIOD - 1e-12 <= seconds <= MAX_TRACE_PERIOD or cycles < 1:
        raise MM4005Error(PARAMETER, f"SP takes {MIN_TRACE_PERIOD:g}..{MAX_TRACE_PERIOD:g} s")
    if trace.acquiring:
        raise MM4005Error(UNAUTHORIZED, "SP while the trace mode acquires")
    trace.period = cycles
    return []


def read_trace(ctx: Context, cmd: Command) -> list[str]:
    """TT: trace sample xx as 'xxTT,THa,TPb' (xx 0 or missing: every sample, a line each)."""
    trace = ctx.machine.axis_trace
    decimals = fmt.position_decimals(ctx.machine.resolution(trace.axis))

    def line(number: int) -> str:
        _tick, th, tp = trace.samples[number - 1]
        return f"{number}TT,TH{fmt.fixed(th, decimals)},TP{fmt.fixed(tp, decimals)}"

    number = cmd.axis or 0
    if number == 0:
        return [line(n) for n in range(1, len(trace.samples) + 1)]
    if number > trace.requested:
        raise MM4005Error(PARAMETER, f"TT: {trace.requested} samples set by TM")
    if number > len(trace.samples):
        raise MM4005Error(UNAUTHORIZED, f"TT: sample {number} not taken yet")
    return [line(number)]


def trace_count(ctx: Context, cmd: Command) -> list[str]:
    """XN: how many samples the trace mode has taken."""
    return [f"XN{len(ctx.machine.axis_trace.samples)}"]
