"""One benchmark figure: a ratio or a latency, with its unit, the target beside it for
the reader (never enforced), and a note on how it was measured."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass
class Figure:
    name: str
    value: float
    unit: str
    target: float | None = None
    note: str = ""


def is_rate(unit: str) -> bool:
    """Figures read as multiples of the naive loop (issue 19's table): simulated seconds
    per wall second, and commands per second taken at face value against it."""
    return "wall s" in unit or unit == "commands/s"
