"""AXIS_MODE's bits (TrioBASIC help AXIS_MODE): the ones the shared machine acts on.

- bit 14 (16384) ignores the axis's software limits: FS_LIMIT and RS_LIMIT neither stop
  its motion nor show in AXISSTATUS (bits 9/10) while it is set (`soft_limits`).
- bit 8 (256) compares DPOS with the software limits (found on the demand's closed
  form, exact to the tick); with the bit clear (power-up) the controller compares MPOS,
  the same on every axis but a servo axis, where MPOS lags DPOS by the following error:
  there the servo loop's own measured position is watched on every cycle of a move
  (`first_reached`, following.py), and the move is cancelled on the cycle MPOS reaches
  the limit; AXISSTATUS bits 9/10 then read MPOS too.
The other bits are stored and read back, each for the reason on AXIS_MODE's table entry.
"""

from __future__ import annotations

import math
from typing import Any

DPOS_SOFT_LIMITS = 1 << 8
IGNORE_SOFT_LIMITS = 1 << 14


def soft_limits(params: dict[str, float]) -> tuple[float, float]:
    """(FS_LIMIT, RS_LIMIT) as they act: none at all while AXIS_MODE bit 14 is set."""
    if int(params.get("AXIS_MODE", 0.0)) & IGNORE_SOFT_LIMITS:
        return math.inf, -math.inf
    return params["FS_LIMIT"], params["RS_LIMIT"]





# ---- bit 8 clear on a servo axis: the software limits compare MPOS ------------------------
def mpos_compared(params: dict[str, float], servo: bool) -> bool:
    """Do the software limits compare MPOS (a servo axis with bit 8 clear) rather than
    DPOS (bit 8 set, or an axis without a loop, where MPOS is DPOS)?"""
    return servo and not int(params.get("AXIS_MODE", 0.0)) & DPOS_SOFT_LIMITS


def compared_position(drive: Any, axis: int) -> float:
    """The position (user units) the software limits are compared with: MPOS on a servo
    axis with bit 8 clear, else DPOS."""
    m = drive.m
    a = m.axes[axis]
    if mpos_compared(a.params, a.servo is not None):
        return float(drive.axis_parameter("MPOS", axis))
    return float(m.dpos(axis))


def stop_where_mpos_met(machine: Any) -> None:
    """The servo loops stopped where an axis's MPOS met a software limit (following.py's
    `soft`): its own move is cancelled there, as at a limit on its demand (unless it is
    already stopping: a stop is never lengthened)."""
    drive = machine.drive
    for axis, side in drive.following.soft.items():
        queue = machine.queues[axis]
        if queue and queue[0].started and not queue[0].stopping:
            drive.on_limit(machine.axes[axis], side, machine.tick)
    drive.following.soft = {}


def mpos_bounds(params: dict[str, float], units: float, datum: float
                ) -> tuple[float, float]:
    """The counts (the loop's, DEFPOS not applied) MPOS reaches FS_LIMIT at going forward
    and RS_LIMIT at going in reverse (infinite where there is none)."""
    fs, rs = soft_limits(params)
    forward = fs * units - datum
    reverse = rs * units - datum
    return (math.ceil(forward) if abs(forward) < 2.0 ** 62 else math.inf,
            math.floor(reverse) if abs(reverse) < 2.0 ** 62 else -math.inf)


def first_reached(positions: list[tuple[int, float]], bounds: tuple[float, float],
                  scale: float, start: float) -> tuple[int, int] | None:
    """The first servo tick (of `positions`: the loop's measured position, its counts, on
    each tick of a stretch after its first) on which MPOS reaches a bound it was inside
    of at `start` (MPOS counts), and the side (+1 FS_LIMIT, -1 RS_LIMIT); MPOS is the
    encoder's whole edges x the feedback scale."""
    forward, reverse = bounds
    watch_fwd, watch_rev = start < forward, start > reverse
    if not (watch_fwd or watch_rev):
        return None
    for tick, p in positions:
        mpos = scale * math.floor(p / scale + 0.5)
        if watch_fwd and mpos >= forward:
            return tick, 1
        if watch_rev and mpos <= reverse:
            return tick, -1
    return None


__all__ = ["DPOS_SOFT_LIMITS", "IGNORE_SOFT_LIMITS", "compared_position", "first_reached",
           "mpos_bounds", "mpos_compared", "soft_limits", "stop_where_mpos_met"]
