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
