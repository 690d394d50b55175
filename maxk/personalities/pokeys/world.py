"""What the pulse engine reads from the machine: switch pins, e-stop, probe and MPG.

The engine samples its inputs at the start of every slot. Levels are pin levels
(True = high). PoKeys switches are normally closed between the pin and ground with a
pull-up, so an open (pressed or broken) switch reads high = tripped, unless the
configuration inverts it. The shared world plugs in behind ``PulseEngineWorld``; the
two ``next_*`` questions let the engine jump over stretches where nothing changes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import NamedTuple, Protocol


class SwitchLevels(NamedTuple):
    """Pin levels of one axis's switches (True = high = open NC contact)."""

    limit_n: bool
    limit_p: bool
    home: bool


CLOSED = SwitchLevels(False, False, False)


class PulseEngineWorld(Protocol):
    def switch_levels(self, axis: int, position: int) -> SwitchLevels:
        """Levels of axis's limit-/limit+/home pins with the axis at position."""
        ...

    def next_switch_edge(self, axis: int, position: int, direction: int) -> int | None:
        """Smallest d >= 1 with switch_levels(position + direction*d) differing from the
        levels at position + direction*(d-1); None if none in that direction."""
        ...

    def estop_level(self, slot: int) -> bool:
        """E-stop pin level at the start of slot."""
        ...

    def probe_level(self, probe_input: int, slot: int, positions: Sequence[int]) -> bool:
        """Probe input level at the start of slot, with the axes at positions."""
        ...

    def mpg_count(self, encoder: int, slot: int) -> int:
        """MPG encoder count at the start of slot."""
        ...

    def next_input_change(self, slot: int) -> int | None:
        """Earliest slot > slot at which a time-driven input (e-stop, MPG, a probe that
        does not depend on position) may change; None if never."""
        ...


@dataclass
class Zone:
    """Positions lo..hi (inclusive) of one axis where a switch is pressed (pin high)."""

    axis: int
    switch: str  # "limit_n", "limit_p" or "home"
    lo: int
    hi: int


@dataclass
class BenchWorld:
    """A simple machine: switches pressed over position zones, timed e-stop presses,
    a probe touching at a position of one axis, MPG counts from a schedule.

    Every switch is wired normally closed; outside its zones it reads low.
    """

    zones: list[Zone] = field(default_factory=list)
    estop_pressed: list[tuple[int, int]] = field(default_factory=list)  # [start, end) slots
    probe_axis: int | None = None
    probe_at: int = 0  # probe pin reads high once probe_axis is at or beyond this...
    probe_direction: int = 1  # ...in this direction
    mpg: dict[int, list[tuple[int, int]]] = field(default_factory=dict)  # enc -> (slot, count)

    def switch_levels(self, axis: int, position: int) -> SwitchLevels:
        levels = {"limit_n": False, "limit_p": False, "home": False}
        for z in self.zones:
            if z.axis == axis and z.lo <= position <= z.hi:
                levels[z.switch] = True
        return SwitchLevels(levels["limit_n"], levels["limit_p"], levels["home"])

    def next_switch_edge(self, axis: int, position: int, direction: int) -> int | None:
        best: int | None = None
        for z in self.zones:
            if z.axis != axis:
                continue
            # Edges sit between lo-1|lo and hi|hi+1.
            for edge_pos in ((z.lo, z.hi + 1) if direction > 0 else (z.hi, z.lo - 1)):
                d = (edge_pos - position) * direction
                if d >= 1 and (best is None or d < best):
                    best = d
        return best

    def estop_level(self, slot: int) -> bool:
        return any(a <= slot < b for a, b in self.estop_pressed)

    def probe_level(self, probe_input: int, slot: int, positions: Sequence[int]) -> bool:
        if self.probe_axis is None:
            return False
        return (positions[self.probe_axis] - self.probe_at) * self.probe_direction >= 0

    def mpg_count(self, encoder: int, slot: int) -> int:
        count = 0
        for at, value in self.mpg.get(encoder, []):
            if at <= slot:
                count = value
        return count

    def next_input_change(self, slot: int) -> int | None:
        times = [t for a, b in self.estop_pressed for t in (a, b)]
        times += [at for schedule in self.mpg.values() for at, _ in schedule]
        later = [t for t in times if t > slot]
        return min(later) if later else None
