"""Firmware rules for single-axis commands, kept apart from any machine so that the real
engine and the fake answer the same way. Where the manual pages were not available the
rule is our decision (D) and says so."""

from __future__ import annotations

from .errors import PARAMETER, UNAUTHORIZED, MM4005Error
from .status import AxisStatus


def check_move(status: AxisStatus, limits: tuple[float, float], target: float) -> None:
    """PA/PR: refused with motor power off (D, 'unauthorized execution'), or to a
    destination outside the SL/SR travel limits (D, 'parameter out of limits')."""
    if status.power_off:
        raise MM4005Error(UNAUTHORIZED, "motor power off")
    if not limits[0] <= target <= limits[1]:
        raise MM4005Error(PARAMETER, "destination outside the travel limits")


def check_not_in_trajectory(in_trajectory: bool) -> None:
    """PA/PR/OR on an axis that a running trajectory drives: refused (D)."""
    if in_trajectory:
        raise MM4005Error(UNAUTHORIZED, "axis driven by the running trajectory")


def check_home_search(status: AxisStatus) -> None:
    """OR: needs motor power and a stationary axis (D)."""
    if status.power_off or status.moving:
        raise MM4005Error(UNAUTHORIZED, "power off or axis moving")


def check_define_home(status: AxisStatus) -> None:
    """DH: not while the axis moves (D)."""
    if status.moving:
        raise MM4005Error(UNAUTHORIZED, "axis moving")


MIN_RATE = 1e-6
"""The smallest speed or acceleration accepted, in user units per second (squared) (D: the
manual's ranges were not available; the display shows four decimals, a 1e-300 or
denormal speed makes a one-count move last longer than any clock counts, and a stage
crawling at a micron per ten days is no use to anyone)."""


def check_positive(value: float, what: str) -> None:
    """NI and other counts: must be positive (D)."""
    if not value > 0.0:
        raise MM4005Error(PARAMETER, f"{what} must be positive")


def check_rate(value: float, what: str) -> None:
    """VA, AC, VV, VS: a speed or acceleration must be at least `MIN_RATE` (D)."""
    if not value >= MIN_RATE:
        raise MM4005Error(PARAMETER, f"{what} must be at least {MIN_RATE:g}")


def new_limits(limits: tuple[float, float], left: float | None = None,
               right: float | None = None) -> tuple[float, float]:
    """SL/SR: the left limit must stay below the right one (D)."""
    low = limits[0] if left is None else left
    high = limits[1] if right is None else right
    if not low < high:
        raise MM4005Error(PARAMETER, "left travel limit not below the right one")
    return low, high


def limits_after_define_home(limits: tuple[float, float], position: float,
                             preset: float) -> tuple[float, float]:
    """DH makes the current position read the home preset and moves the software limits
    with the origin (I: a public Tcl MM4005 driver notes 'DH sets a new origin and updates
    the software limits', its log shows limits -25/25 becoming -15/35 after DH at -10)."""
    shift = preset - position
    return limits[0] + shift, limits[1] + shift
