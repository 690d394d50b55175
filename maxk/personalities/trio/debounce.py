"""IN_DEBOUNCE: a program's IN reads an input's new level only once its voltage has held
it for IN_DEBOUNCE servo cycles (TrioBASIC help IN_DEBOUNCE; newer than the MC405's token
table, helpwords.NEWER_WORDS).

The raw level (before INVERT_IN) of each of the MC405's inputs is noted with the servo tick
it changed on, whenever the world changes; IN then reads the new level from that tick +
IN_DEBOUNCE on, and until then the last level that held long enough (a glitch shorter than
IN_DEBOUNCE is never seen). Registration, limits, jogs and feed hold read the inputs
undebounced (C: the page, "registration input functionality is not affected"; D for the
others: the page names only programs' IN). 0 (power-up): no debounce (D).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

INPUTS = 32  # the MC405's own inputs (the interpreter's IO_POINTS): expansion I/O is raw


@dataclass
class _Level:
    level: bool  # the raw level now
    since: int  # the servo tick it changed to it
    held: bool  # the last level that held for IN_DEBOUNCE cycles


class Debounce:
    def __init__(self, machine: Any) -> None:
        self.m = machine
        self.levels: dict[int, _Level] = {}

    def reset(self) -> None:
        self.levels.clear()

    def note(self) -> None:
        """Take the levels now as held (IN_DEBOUNCE written: D), keeping those known."""
        for number in range(INPUTS):
            if number not in self.levels:
                level = self.m.raw_input(number)
                self.levels[number] = _Level(level, -(2 ** 62), level)

    def world_changed(self) -> None:
        """Note every input whose raw level changed on this servo tick."""
        m = self.m
        cycles = self._cycles()
        for number in range(INPUTS):
            level = m.raw_input(number)
            known = self.levels.get(number)
            if known is None:
                self.levels[number] = _Level(level, -(2 ** 62), level)
            elif level != known.level:
                if m.tick - known.since >= cycles:
                    known.held = known.level
                known.level, known.since = level, m.tick

    def read(self, number: int) -> bool:
        """IN(n) of a program: the debounced level, INVERT_IN applied."""
        m = self.m
        raw = m.raw_input(number)
        known = self.levels.get(number)
        cycles = self._cycles()
        if cycles <= 0 or known is None or known.level != raw:
            level = raw  # (no debounce, or a level the world changed unseen: D)
        else:
            level = known.level if m.tick - known.since >= cycles else known.held
        return level != (number in m.inverted_inputs)

    def _cycles(self) -> float:
        return float(self.m.system.get("IN_DEBOUNCE", 0.0))
