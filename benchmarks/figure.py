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
