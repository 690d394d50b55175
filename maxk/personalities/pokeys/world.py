"""What the pulse engine reads from the machine: switch pins, e-stop, probe and MPG.

The engine samples its inputs at the start of every slot. Levels are pin levels
(True = high). PoKeys switches are normally closed between the pin and ground with a
pull-up, so an open (pressed or broken) switch reads high = tripped, unless the
configuration inverts it. The shared world plugs in behind ``PulseEngineWorld``; the
two ``next_*`` questions let the engine jump over stretches where nothing changes.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, NamedTuple, Protocol

from ...firmware_model.world import AxisWorld, Switch, World


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


ESTOP_INPUT = 0
"""World digital input 0 is the dedicated e-stop input (D: the 57CNC has one; an e-stop
pin set by 0x85/0x06 takes its place). Probe input n is world digital input n."""

POKEYS_HOME = (-1333, -1234)
"""A PoKeys stage's home switch: the MAXk default window mirrored, since PoKeys homing
searches toward negative unless the axis's homing direction is inverted (D)."""

MpgSource = Callable[[Any], int]


def pokeys_world(axes: int) -> World:
    """The shared world as a PoKeys machine sees it at power-up: limit switches far out,
    a home switch a little below the power-up position, every input low."""
    world = World([AxisWorld() for _ in range(axes)])
    for stage in world.axes:
        stage.set_home(*POKEYS_HOME)
    return world


def _edge_distance(switch: Switch, position: int, direction: int) -> int | None:
    best: int | None = None
    for p, _active in switch.transitions():
        # A transition at p: the switch differs at p and p - 1.
        d = p - position if direction > 0 else position - p + 1
        if d >= 1 and (best is None or d < best):
            best = d
    return best


@dataclass
class SharedWorld:
    """The shared machine's `World` behind ``PulseEngineWorld``: each axis's stage gives
    its limit and home switches (active = pressed = the NC contact open = pin high), the
    digital inputs give the e-stop and the probe, MPG encoders count what `mpg` says.

    ``board`` is what an input source is called with: the PoKeys engine (its ``time``)."""

    world: World
    board: Any = None
    estop_input: int = ESTOP_INPUT
    mpg: dict[int, int | MpgSource] = field(default_factory=dict)

    def _stage(self, axis: int) -> AxisWorld | None:
        axes = self.world.axes
        return axes[axis] if axis < len(axes) else None

    def switch_levels(self, axis: int, position: int) -> SwitchLevels:
        stage = self._stage(axis)
        if stage is None:
            return CLOSED
        return SwitchLevels(stage.minus_limit.active(position),
                            stage.plus_limit.active(position), stage.home.active(position))

    def next_switch_edge(self, axis: int, position: int, direction: int) -> int | None:
        stage = self._stage(axis)
        if stage is None:
            return None
        found = [d for sw in (stage.minus_limit, stage.plus_limit, stage.home)
                 if (d := _edge_distance(sw, position, direction)) is not None]
        return min(found) if found else None

    def _digital(self, bit: int) -> bool:
        return self.world.digital_level(bit, self.board)

    def estop_level(self, slot: int) -> bool:
        return self._digital(self.estop_input)

    def probe_level(self, probe_input: int, slot: int, positions: Sequence[int]) -> bool:
        return self._digital(probe_input)

    def mpg_count(self, encoder: int, slot: int) -> int:
        source = self.mpg.get(encoder, 0)
        return int(source(self.board) if callable(source) else source)

    def next_input_change(self, slot: int) -> int | None:
        """A constant input never changes by itself; a function of time may change at
        any slot, so the engine then goes slot by slot."""
        timed = callable(self.world.digital.get(self.estop_input)) or any(
            callable(s) for s in self.mpg.values())
        return slot + 1 if timed else None
