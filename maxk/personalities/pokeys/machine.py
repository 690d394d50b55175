"""The PoKeys on the shared machine: an `Engine` at 1 ms slots whose event source is the
pulse engine.

The engine's tick is the slot count: at tick T the pulse engine has emitted slots
0..T-1. Its one event source asks the pulse engine for the earliest slot at which
something may change (the buffer runs dry, a move ends, a switch or probe edge is
reached, a timed input changes) and the engine jumps there; the stretch in between is
emitted in one go (buffered slots as one numpy block) by `integrate`, which the engine
calls for every stretch between events, so time standing at any tick (an observer's,
a door's "now") always finds the slots up to it emitted.

The switches, e-stop and probe come from the shared `World` (firmware_model/world.py)
through `SharedWorld`, unless a test gives the pulse engine a world of its own.
"""

from __future__ import annotations

from ...firmware_model.engine import Engine
from ...firmware_model.world import World
from .constants import SLOT_SECONDS
from .engine import PulseEngine
from .plans import AxisPlan
from .world import SharedWorld

AXIS_LETTERS = "XYZABCUV"
"""Axis names for people (console, traces, world inputs): X Y Z A B C U V, as the
PoKeys configuration software labels axes 1-8 (D)."""


class _Pulses:
    """The pulse engine as the engine's event source (it follows a reset's new one)."""

    def __init__(self, machine: SlotEngine) -> None:
        self.machine = machine

    def next_event(self) -> int | None:
        return self.machine.pulse.next_event()

    def on_event(self, now: int) -> None:
        self.machine.pulse.on_event(now)


class _AxisView:
    """What a world input source sees of an axis (`axis_position_source`): its stage."""

    def __init__(self, pulse: PulseEngine, index: int) -> None:
        self.pulse, self.index = pulse, index

    def motor_position(self, board: object) -> int:
        return self.pulse.axes[self.index].stage


class SlotEngine(Engine):
    """Virtual time of one PoKeys device: ticks are its 1 ms time slots."""

    def __init__(self, pulse: PulseEngine) -> None:
        super().__init__(1.0 / SLOT_SECONDS)
        self.pulse = pulse
        self.tick = pulse.slot
        self.add_source(_Pulses(self))
        self._attach_world()

    def _attach_world(self) -> None:
        world = self.pulse.world
        if isinstance(world, SharedWorld):
            world.board = self

    def replace_pulse_engine(self, pulse: PulseEngine) -> None:
        """A reset: the new engine carries on at this slot."""
        pulse.slot = self.tick
        self.pulse = pulse
        self._attach_world()

    @property
    def world(self) -> World | None:
        """The shared world behind the pulse engine (None for a bench world)."""
        world = self.pulse.world
        return world.world if isinstance(world, SharedWorld) else None

    def axis(self, letter: str) -> _AxisView:
        """An axis by letter, for world input sources that depend on a position."""
        index = AXIS_LETTERS.index(letter.upper())
        if index >= len(self.pulse.axes):
            raise KeyError(f"no axis {letter} on this pulse engine")
        return _AxisView(self.pulse, index)

    def motion_plan(self, index: int) -> AxisPlan | None:
        return self.pulse.motion_plan(index)

    # ---- the engine's hooks ------------------------------------------------------------
    def settle(self) -> None:
        # Someone ran the pulse engine directly (a bench test): time follows it.
        if self.pulse.slot > self.tick:
            self.tick = self.pulse.slot

    def integrate(self, limit: int) -> bool:
        """Emit the slots up to `limit` (the next event or the target): quiet stretches
        in one go."""
        if limit > self.pulse.slot:
            self.pulse.run_to(limit)
        return False

    def world_changed(self) -> None:
        """Nothing is cached: the pulse engine asks the world afresh at every stretch."""
