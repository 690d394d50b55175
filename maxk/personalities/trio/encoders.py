"""The MC405's encoder feedback as the language reads it: ENCODER and ENCODER_RATIO
(TrioBASIC help ENCODER, ENCODER_RATIO).

- ENCODER is the raw feedback register: the count of the encoder the axis reads, with
  no DEFPOS offset, no UNITS and no ENCODER_RATIO. A servo axis reads its world motor's
  encoder, an encoder input (ATYPE 76 ...) the encoder the world mounts on it, any other
  axis (a stepper, a virtual axis: no feedback) its demand counts, whole (D); an
  absolute-feedback servo (ATYPE 46/47/48/92) the count in ENCODER_BITS's data bits. The
  register is 32 bits: it wraps at +/-2^31 (D: the page gives no width; MPOS, computed
  from it "allowing for overflows", does not wrap).
- ENCODER_RATIO(mpos_count, input_count) scales what an encoder input's MPOS counts:
  MPOS counts = mpos_count / input_count x the input's counts. Power-up 1:1. It is kept
  per axis as two entries of the axis's parameters (names no program can type), so it
  goes back to 1:1 at power-up with the others.
- PP_STEP (help PP_STEP) is an integer multiplier on the same encoder value: MPOS counts
  = ENCODER_RATIO x PP_STEP x the input's counts; UNITS then divides as for any axis.
- On a servo axis the same product scales the loop's feedback: the shared loop runs in
  MPOS counts (its feedback scale, `ServoLoop.feedback_scale`), so the loop closes on
  MPOS as the page says ("affects all motion commands"; the gains act per MPOS count).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Protocol

from maxk.firmware_model.servo import ServoLoop

from .axistypes import absolute_register
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


def servo_rescale(a: TrioAxis, change: Callable[[dict[str, float]], None]) -> None:
    """ENCODER_RATIO (or PP_STEP) on a servo axis: its loop runs in MPOS counts (the
    shared loop's feedback scale), so the new ratio rescales the loop's position while
    the motor stays where it is; the demand moves with it by whole counts (the following
    error changes by less than a count) and DEFPOS's offset takes both up, so DPOS keeps
    its value and MPOS its value to within half a count (exactly, for a whole ratio: D).
    Refused with 'Parameter out of range' while the axis moves (D: a step of its frame
    mid-move)."""
    loop = a.servo
    assert loop is not None
    if a.motion is not None or a.link is not None:
        raise ValueError("Parameter out of range")
    change(a.params)
    before, p = measured(loop), loop.p
    loop.set_feedback_scale(ratio(a.params))
    moved = round(measured(loop) - before)
    a.steps += moved
    a.datum -= moved
    loop.counters_moved(moved, loop.p - p)


def measured(loop: ServoLoop) -> float:
    """A servo axis's MPOS counts (DEFPOS not applied): its encoder's whole edges times
    ENCODER_RATIO (the loop's feedback scale)."""
    scale = loop.feedback_scale
    if scale == 1.0:
        return float(loop.encoder_counts())
    return scale * math.floor(loop.p / scale + 0.5)


def encoder(machine: EncoderHost, axis: int) -> float:
    """ENCODER: the raw register (see the module docstring)."""
    a = machine.axes[axis]
    loop = a.servo
    if loop is not None:  # (its counts are MPOS counts: ENCODER_RATIO's edges back)
        counts = float(math.floor(loop.p / loop.feedback_scale + 0.5))
        held = absolute_register(int(a.params["ATYPE"]), a.params.get("ENCODER_BITS", 0.0),
                                 int(counts))
        if held is not None:  # an absolute servo's data bits (axistypes.py)
            return float(held)
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


__all__ = ["DENOMINATOR", "NUMERATOR", "encoder", "endat", "measured", "ratio",
           "servo_rescale", "set_pp_step", "set_ratio"]
