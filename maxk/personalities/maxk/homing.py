"""Homing: HM/HR (load the counter at home) and KM/KR (find home, keep the counter).

The search, as modelled (manual 4.3 and 4.8 name the behaviour, not the steps):

1. If the home condition is already true, home is found at once: no motion.
2. Otherwise the axis jogs in the search direction (HM/KM forward, HR/KR reverse) at VL,
   starting at VB and ramping at AC, as a JG would.
3. On the update cycle the home condition becomes true, HM/HR load the motor counter with
   their operand (0 when none is given) at that exact position, and the axis ramps to a
   stop at DC (so it comes to rest a little past home, as the manual describes).
4. If a limit switch trips first, the limit wins: overtravel flag, the queue is flushed,
   home is not found. The MAXk does not turn round to search the other way.

The home condition is the home switch alone after HS (the factory mode), or the manual's
encoder logic after HE: Phase +A * Phase -B * Index * Home switch, each term selectable by
the EH pattern (1 required true, 0 required false, X ignored; factory EH1111).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from maxk.firmware_model.world import AxisWorld
    from maxk.personalities.maxk.config import AxisConfig

SCAN_LIMIT = 200_000
"""Positions examined when looking for the next encoder-logic home position."""


@dataclass
class Homing:
    direction: int  # +1 HM/KM, -1 HR/KR
    load_value: int | None  # counter value at home (None: KM/KR keep the counter)


def quadrature(steps: int) -> tuple[bool, bool]:
    """Phase A and B levels at a count (x4 decoding: 0 = A high B low, then A B, B, none)."""
    q = steps % 4
    return q in (0, 1), q in (1, 2)


def home_condition(config: AxisConfig, world: AxisWorld, steps: int) -> bool:
    """Is the configured home condition true at this physical position?"""
    home = world.home.active(steps)
    if not config.home_encoder:
        return home
    a, b = quadrature(steps)
    terms = (a, not b, world.index_active(steps), home)
    for term, want in zip(terms, config.home_pattern, strict=True):
        if want == "1" and not term:
            return False
        if want == "0" and term:
            return False
    return True


def next_home_position(config: AxisConfig, world: AxisWorld, start: int,
                       direction: int) -> int | None:
    """The nearest position after `start` in `direction` where the home condition holds."""
    home = world.home
    if not config.home_encoder:
        # The switch's own transitions (bounce included): where it becomes active moving
        # this way.
        if direction > 0:
            ahead = [p for p, active in home.transitions() if active and p > start]
            return min(ahead) if ahead else None
        behind = [p - 1 for p, active in home.transitions() if not active and p - 1 < start]
        return max(behind) if behind else None
    pattern = config.home_pattern
    p = start + direction
    if pattern[3] == "1" and home.fault is None and home.present:
        # The home switch is required: jump straight to its window.
        low = home.low if home.low is not None else -math.inf
        high = home.high if home.high is not None else math.inf
        if direction > 0:
            if p > high:
                return None
            p = max(p, int(low))
        else:
            if p < low:
                return None
            p = min(p, int(high))
    scanned = 0
    while scanned < SCAN_LIMIT:
        if home_condition(config, world, p):
            return p
        if pattern[2] == "1" and world.index_period > 0:
            rel = (p - world.index_offset) % world.index_period
            if rel >= world.index_width:  # outside a mark: jump to the next one
                jump = world.index_period - rel if direction > 0 else rel - world.index_width + 1
                p += direction * jump
                scanned += 1
                continue
        p += direction
        scanned += 1
    return None
