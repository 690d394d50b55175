"""AXIS_MODE's bits (TrioBASIC help AXIS_MODE): the ones the shared machine acts on.

- bit 14 (16384) ignores the axis's software limits: FS_LIMIT and RS_LIMIT neither stop
  its motion nor show in AXISSTATUS (bits 9/10) while it is set (`soft_limits`).
- bit 8 (256) compares DPOS with the software limits: the emulator always does (the
  limits are found on the demand's closed form, exact to the tick); with the bit clear the
  controller compares MPOS, the same on every axis but a servo axis, where MPOS lags DPOS by
  the following error (not modelled: D).
The other bits are stored and read back, each for the reason on AXIS_MODE's table entry.
"""

from __future__ import annotations

import math

DPOS_SOFT_LIMITS = 1 << 8
IGNORE_SOFT_LIMITS = 1 << 14


def soft_limits(params: dict[str, float]) -> tuple[float, float]:
    """(FS_LIMIT, RS_LIMIT) as they act: none at all while AXIS_MODE bit 14 is set."""
    if int(params.get("AXIS_MODE", 0.0)) & IGNORE_SOFT_LIMITS:
        return math.inf, -math.inf
    return params["FS_LIMIT"], params["RS_LIMIT"]


__all__ = ["DPOS_SOFT_LIMITS", "IGNORE_SOFT_LIMITS", "soft_limits"]
