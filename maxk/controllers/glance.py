"""What the consoles' status lines share: numbers shortened for a glance."""

from __future__ import annotations


def short_position(value: int) -> str:
    """A position in at most four characters, for a glance: 1234, -999, 12k, -.1M, -2G."""
    text = str(value)
    if len(text) <= 4:
        return text
    for suffix, scale in (("k", 1e3), ("M", 1e6), ("G", 1e9)):
        for decimals in (1, 0):
            number = f"{value / scale:.{decimals}f}"
            if number.startswith(("0.", "-0.")):
                number = number.replace("0.", ".", 1)
            if len(number) + 1 <= 4:
                return number + suffix
    return text
