"""Number formatting on the wire.

Positions use one decimal more than the axis resolution TU has (TU 0.001 -> '5.0120'),
our decision matching the replies the EPICS drivers were observed to accept
(1TP0.0000, 1TL-100.0000 with TU 0.001); the drivers parse with atof, so any width
works for them. Settings without an axis resolution print in their shortest form.
"""

from __future__ import annotations


def resolution_decimals(resolution: float) -> int:
    """How many decimals the resolution itself needs (0.001 -> 3, 0.5 -> 1, 1 -> 0)."""
    for digits in range(10):
        scaled = resolution * 10**digits
        if abs(scaled - round(scaled)) <= 1e-9 * max(1.0, scaled):
            return digits
    return 10


def position_decimals(resolution: float) -> int:
    return resolution_decimals(resolution) + 1


def fixed(value: float, decimals: int) -> str:
    """Fixed decimals, never '-0.000'."""
    text = f"{value:.{decimals}f}"
    if float(text) == 0.0:
        text = f"{0.0:.{decimals}f}"
    return text


def short(value: float) -> str:
    """Shortest plain form: 0.001 -> '0.001', 2.0 -> '2', 12853 -> '12853'."""
    if float(value).is_integer():
        return str(int(value))
    text = f"{value:.10f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text
