"""STEP_RATIO (TrioBASIC help STEP_RATIO): a stepper's demand counts to the steps it outputs.

The page passes every servo cycle's change of demand through an integer ratio before the
step output, so the motor turns output_count steps for each dpos_count counts of DPOS;
UNITS is untouched (DPOS, speeds and moves stay in the program's counts). Here the
world's motor of the axis turns ``counts x output_count / dpos_count`` steps: its limit
switches, the encoder the world mounts on its shaft and its inputs see that position
(`motor_steps`). The ratio is kept per axis in two parameter entries no program can type,
so it goes back to 1:1 at power-up with the others.

Decisions (D): the world's steps are the step generator's counts (the page's divide by 16
is not applied: the world has always taken one demand count as one of its steps); when
the ratio changes the motor stays where it is (an offset takes up the difference, so a
STEP_RATIO at rest never moves the stage); dpos_count 0 is refused (a ratio with no
demand), output_count 0 is taken (the motor stands still, as the page's range allows).

A negative output_count reverses the step output: the STEP_RATIO page's range is 0 and up,
but the ENCODER_RATIO page (example 4) and the AXESDIFF page reverse an axis with
STEP_RATIO(-1, 1), the encoder's ENCODER_RATIO negative too (I: the pages' examples; the
magnitude keeps the page's limit). The world's motor then turns against the demand; its
limit switches are read as levels where the motor stands, not found ahead of a run to the
tick (D: `demand_for`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

OUTPUT = "STEP_RATIO.output"
DPOS = "STEP_RATIO.dpos"
OFFSET = "STEP_RATIO.offset"  # world steps the motor is ahead of counts x ratio
LIMIT = 16777215  # either count (the page's range)


def ratio(params: dict[str, float]) -> float:
    """Motor steps per demand count (1 at power-up)."""
    return params.get(OUTPUT, 1.0) / params.get(DPOS, 1.0)


def checked(args: Sequence[float]) -> tuple[float, float]:
    """STEP_RATIO's arguments: none is 1:1 (as ENCODER_RATIO, D); two whole counts,
    output_count in -16777215..16777215 (negative reverses: see the module docstring),
    dpos_count in 1..16777215; one or three are a 'Syntax error' (D)."""
    if not args:
        return 1.0, 1.0
    if len(args) != 2:
        raise ValueError("Syntax error")
    for value in args:
        if not math.isfinite(value) or value != int(value) or not abs(value) <= LIMIT:
            raise ValueError("Parameter out of range")
    if args[1] <= 0:
        raise ValueError("Parameter out of range")
    return float(args[0]), float(args[1])


def set_ratio(params: dict[str, float], args: Sequence[float], counts: float) -> None:
    """Take a new ratio with the axis's demand at `counts` (plus any compensation the
    motor carries): the motor keeps its position (see the module docstring)."""
    output, dpos = checked(args)
    before = counts * ratio(params) + params.get(OFFSET, 0.0)
    params[OUTPUT], params[DPOS] = output, dpos
    params[OFFSET] = before - counts * ratio(params)


def motor(params: dict[str, float], counts: np.ndarray) -> np.ndarray:
    """The world steps the motor has turned for demand `counts` (with compensation)."""
    r = ratio(params)
    offset = params.get(OFFSET, 0.0)
    if r == 1.0 and offset == 0.0:
        return counts
    return counts * r + offset


def demand_for(params: dict[str, float], steps: float, side: int) -> float:
    """The demand count at which the motor first reaches world position `steps` moving
    towards `side` (+1 forward): infinitely far when it does not turn (output_count 0)
    or turns against the demand (a negative output_count: D, see the module docstring)."""
    r = ratio(params)
    if r <= 0:
        return math.inf * side
    counts = (steps - params.get(OFFSET, 0.0)) / r
    if r == 1.0:
        return counts
    return float(math.ceil(counts - 1e-9) if side > 0 else math.floor(counts + 1e-9))


__all__ = ["checked", "demand_for", "motor", "ratio", "set_ratio"]
