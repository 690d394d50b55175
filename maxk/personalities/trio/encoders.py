"""The MC405's encoder feedback as the language reads it: ENCODER and ENCODER_RATIO
(TrioBASIC help ENCODER, ENCODER_RATIO).

- ENCODER is the raw feedback register: the count of the encoder the axis reads, with
  no DEFPOS offset, no UNITS and no ENCODER_RATIO. A servo axis reads its world motor's
  encoder, an encoder input (ATYPE 76 ...) the encoder the world mounts on it, any other
  axis (a stepper, a virtual axis: no feedback) its demand counts, whole (D). The
  register is 32 bits: it wraps at +/-2^31 (D: the page gives no width; MPOS, computed
  from it "allowing for overflows", does not wrap).
- ENCODER_RATIO(mpos_count, input_count) scales what an encoder input's MPOS counts:
  MPOS counts = mpos_count / input_count x the input's counts. Power-up 1:1. It is kept
  per axis as two entries of the axis's parameters (names no program can type), so it
  goes back to 1:1 at power-up with the others.
- PP_STEP (help PP_STEP) is an integer multiplier on the same encoder value: MPOS counts
  = ENCODER_RATIO x PP_STEP x the input's counts; UNITS then divides as for any axis.
"""

from __future__ import annotations

import math
from typing import Protocol

from .runs import TrioAxis

NUMERATOR = "ENCODER_RATIO.mpos"
DENOMINATOR = "ENCODER_RATIO.input"
RATIO_LIMIT = 16777215  # |mpos_count|, input_count (as STEP_RATIO's range: D)
REGISTER = 2 ** 32


class EncoderHost(Protocol):
    axes: list[TrioAxis]

    def raw_encoder(self, axis: int) -> float | None: ...
    def motor(self, axis: int) -> float: ...


def ratio(params: dict[str, float]) -> float:
    """MPOS counts per input count: ENCODER_RATIO times PP_STEP."""
    return params.get(NUMERATOR, 1.0) / params.get(DENOMINATOR, 1.0) \
        * params.get("PP_STEP", 1.0)


def set_pp_step(params: dict[str, float], value: float) -> None:
    """PP_STEP: a whole multiplier in the page's recommended -1024..1023, not 0 (D: 0
    would stop MPOS); refused whole otherwise."""
    if not math.isfinite(value) or value != int(value) or not -1024 <= value <= 1023 \
            or value == 0:
        raise ValueError("Parameter out of range")
    params["PP_STEP"] = float(value)


def set_ratio(params: dict[str, float], mpos_count: float, input_count: float) -> None:
    """ENCODER_RATIO: both whole numbers, input_count above 0, mpos_count not 0 (its
    sign reverses the axis: help ENCODER_RATIO example 3); refused whole otherwise."""
    for value in (mpos_count, input_count):
        if not math.isfinite(value) or value != int(value) or abs(value) > RATIO_LIMIT:
            raise ValueError("Parameter out of range")
    if input_count <= 0 or mpos_count == 0:
        raise ValueError("Parameter out of range")
    params[NUMERATOR] = float(mpos_count)
    params[DENOMINATOR] = float(input_count)


def encoder(machine: EncoderHost, axis: int) -> float:
    """ENCODER: the raw register (see the module docstring)."""
    a = machine.axes[axis]
    loop = a.servo
    if loop is not None:
        counts = float(loop.encoder_counts())
    else:
        raw = machine.raw_encoder(axis)
        counts = math.floor((machine.motor(axis) if raw is None else raw) + 0.5)
    wrapped = (int(counts) + REGISTER // 2) % REGISTER - REGISTER // 2
    return float(wrapped)


def endat(name: str, args: list[float]) -> float:
    """ENCODER_READ(address) / ENCODER_WRITE(address, data) on an axis with no EnDat
    encoder (the world has only incremental encoders): the read returns -1 (encoder not
    initialised), the write FALSE (help ENCODER_READ, ENCODER_WRITE). The address is a
    whole number from 0 (D)."""
    if len(args) != (1 if name == "ENCODER_READ" else 2):
        raise ValueError("Syntax error")
    if not math.isfinite(args[0]) or args[0] != int(args[0]) or args[0] < 0:
        raise ValueError("Parameter out of range")
    return -1.0 if name == "ENCODER_READ" else 0.0


__all__ = ["DENOMINATOR", "NUMERATOR", "encoder", "endat", "ratio", "set_pp_step",
           "set_ratio"]
