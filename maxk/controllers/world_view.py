"""The one world contract: what every controller shows of the machine around it.

A door (a script's `@world` and `@expect`, the REPL's `:world`, the Python API, a control
door) speaks to any controller through a `WorldView`: the controller's axes by the names
its users give them (`X` on a MAXk, `1` on an MM4005, `0` on an MC405, `X` on a PoKeys),
the shared world's switches, index marks, faults, backlash and motor plant for each
axis, the digital and analog inputs, and a reading of each axis (position, encoder,
velocity, done). Each controller maps its own I/O onto it by giving the view its shared
`World`, its axis names, its input ranges and how to read an axis; words only one kind
has (the MAXk's capture set-up, its doorbell) come through `extra_setting` and
`extra_expect`.

Positions are the shared world's: steps (or encoder counts) since power-up, the unit the
switches are placed in, whatever units the controller's host language speaks.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

from maxk.firmware_model.world import (
    BOUNCE_LIMIT,
    COUNT_LIMIT,
    FAULTS,
    POSITION_LIMIT,
    SWITCHES,
    AxisWorld,
    InputSource,
    World,
    checked_count,
)

Setting = Callable[["WorldView"], str]
"""A checked world setting, applied to a controller's view later; returns what it did."""


@dataclass(frozen=True)
class AxisReading:
    """One axis as a door sees it now."""

    name: str
    position: int  # the controller's position counter (steps or counts)
    encoder: int | None  # the encoder count (None: the axis has none)
    velocity: float  # counts per second, signed
    done: bool  # the last motion ended (the controller's own done)
    moving: bool  # a motion is under way
    flags: tuple[str, ...] = ()  # e.g. "plus-limit", "minus-limit", "home", "error"

    def as_dict(self) -> dict[str, Any]:
        return {"name": self.name, "position": self.position, "encoder": self.encoder,
                "velocity": self.velocity, "done": self.done, "moving": self.moving,
                "flags": list(self.flags)}


class WorldView:
    """A controller's world behind the contract. Subclasses give `reading`; the rest has
    defaults that act on the shared `World` and tell the controller (`changed`) so that a
    running motion sees a switch moved under it."""

    def __init__(self, world: World, axis_names: Sequence[str], *,
                 inputs: Sequence[int] = range(16), analog: Sequence[int] = range(4),
                 changed: Callable[[], None] = lambda: None,
                 analog_volts: tuple[float, float] = (-10.0, 10.0),
                 source_owner: Any = None) -> None:
        self.world = world
        self.source_owner = source_owner  # what an input that is a function is called with
        self.axis_names: tuple[str, ...] = tuple(axis_names)
        self.inputs: Sequence[int] = inputs
        self.analog: Sequence[int] = analog
        self.analog_volts = analog_volts
        self._changed = changed
        self._by_name = {name.upper(): i for i, name in enumerate(self.axis_names)}

    # ---- naming ----------------------------------------------------------------------
    def index(self, name: str) -> int:
        """The axis's index in the world; KeyError naming the axes there are."""
        i = self._by_name.get(str(name).strip().upper())
        if i is None:
            raise KeyError(f"no axis {name!r} (axes: {', '.join(self.axis_names)})")
        return i

    def stage(self, name: str) -> AxisWorld:
        return self.world.axes[self.index(name)]

    def changed(self) -> None:
        self._changed()

    # ---- what each controller gives ----------------------------------------------------
    def reading(self, name: str) -> AxisReading:  # pragma: no cover - every view has one
        raise NotImplementedError

    def extra_setting(self, name: str | None, words: list[str]) -> str | None:
        """A setting only this kind knows (None: not one of its words)."""
        return None

    def extra_expect(self, words: list[str]) -> str | None | bool:
        """An expectation only this kind knows: None holds, a text is what was found,
        False means not one of its words."""
        return False

    def output_level(self, number: int) -> bool | None:
        """A digital output's level (None: no such output)."""
        return None

    def trace_axis_columns(self, after_done: bool = False) -> list[str]:
        """A trace's own columns per axis, before its done column or after it."""
        return []

    def trace_axis_values(self, name: str, after_done: bool = False) -> list[object]:
        return []

    def trace_columns(self) -> list[str]:
        """A trace's own columns for the whole controller."""
        return []

    def trace_values(self) -> list[object]:
        return []

    # ---- the shared words ----------------------------------------------------------------
    def set_limits(self, name: str, *, plus: float | None | str = "keep",
                   minus: float | None | str = "keep") -> None:
        """Place the limit switches (None: no switch on that side)."""
        stage = self.stage(name)
        if plus != "keep":
            stage.set_plus_limit(plus)  # type: ignore[arg-type]
        if minus != "keep":
            stage.set_minus_limit(minus)  # type: ignore[arg-type]
        self.changed()

    def set_home(self, name: str, low: float | None, high: float | None) -> None:
        self.stage(name).set_home(low, high)
        self.changed()

    def set_index(self, name: str, period: int, width: int = 4, offset: int = 0) -> None:
        period = checked_count(period, "the index period")
        width = checked_count(width, "the index width")
        offset = checked_count(offset, "the index offset", -POSITION_LIMIT, POSITION_LIMIT)
        stage = self.stage(name)
        stage.index_period, stage.index_width, stage.index_offset = period, width, offset
        self.changed()

    def fault(self, name: str, switch: str, state: str | None) -> None:
        if state not in FAULTS:
            raise ValueError("fault SWITCH active|inactive|none")
        getattr(self.stage(name), _switch(switch)).fault = state
        self.changed()

    def bounce(self, name: str, switch: str, steps: int) -> None:
        steps = checked_count(steps, "bounce (steps)", 0, BOUNCE_LIMIT)
        getattr(self.stage(name), _switch(switch)).bounce = steps
        self.changed()

    def miss_steps(self, name: str, steps: int) -> None:
        steps = checked_count(steps, "missed steps", -COUNT_LIMIT, COUNT_LIMIT)
        stage = self.stage(name)
        lost = stage.lost_steps + steps
        if abs(lost) > POSITION_LIMIT:
            raise ValueError(f"the stage would have missed {lost} steps in all: beyond "
                             f"+/-{POSITION_LIMIT} (2^53)")
        stage.lost_steps = lost
        self.changed()

    def set_backlash(self, name: str, steps: int) -> None:
        self.stage(name).backlash = checked_count(steps, "backlash (steps)")
        self.changed()

    def set_motor(self, name: str, **parameters: object) -> None:
        stage = self.stage(name)
        stage.motor = replace(stage.motor, **parameters)  # type: ignore[arg-type]
        self.changed()

    def set_input(self, number: int, level: bool | InputSource) -> None:
        if number not in self.inputs:
            raise ValueError(f"no input {number} (inputs {_span(self.inputs)})")
        self.world.digital[number] = level
        self.changed()

    def set_analog(self, channel: int, volts: float | InputSource) -> None:
        if channel not in self.analog:
            raise ValueError(f"no analog input {channel} (inputs {_span(self.analog)})")
        if not callable(volts):
            low, high = self.analog_volts
            if not math.isfinite(volts) or not low <= volts <= high:
                raise ValueError(f"volts must be a number from {low:g} to {high:g}, "
                                 f"not {volts}")
        self.world.analog[channel] = volts
        self.changed()

    def input_level(self, number: int) -> bool:
        return self.world.digital_level(number, self.source_owner)

    # ---- pictures ------------------------------------------------------------------------
    def describe(self) -> list[str]:
        """`:world` with no words: every axis's stage and the inputs set."""
        lines = []
        for name, stage in zip(self.axis_names, self.world.axes, strict=False):
            home = stage.home
            home_text = ("none" if not home.present
                         else f"{_at(home.low)}..{_at(home.high)}")
            if home.fault:
                home_text += f" (stuck {home.fault})"
            reading = self.reading(name)
            lines.append(
                f"{name}: at {reading.position} steps; limits "
                f"{_side(stage.plus_limit, stage.plus_limit.low)} / "
                f"{_side(stage.minus_limit, stage.minus_limit.high)}; home {home_text}; "
                f"index every {stage.index_period} from {stage.index_offset}"
                + (f"; backlash {stage.backlash}" if stage.backlash else ""))
        for number, level in sorted(self.world.digital.items()):
            if not callable(level):
                lines.append(f"input {number} {'high' if level else 'low'}")
        for channel, volts in sorted(self.world.analog.items()):
            if not callable(volts):
                lines.append(f"analog {channel} {volts:g} V")
        return lines

    def snapshot(self) -> dict[str, Any]:
        """Everything a program may want at once, as plain data (JSON-able)."""
        axes = []
        for name, stage in zip(self.axis_names, self.world.axes, strict=False):
            reading = self.reading(name).as_dict()
            reading["switches"] = {
                "plus": {"at": stage.plus_limit.low, "fault": stage.plus_limit.fault},
                "minus": {"at": stage.minus_limit.high, "fault": stage.minus_limit.fault},
                "home": {"low": stage.home.low, "high": stage.home.high,
                         "fault": stage.home.fault},
            }
            axes.append(reading)
        return {
            "axes": axes,
            "inputs": {str(n): bool(self.input_level(n)) for n in self.inputs},
            "analog": {str(c): v for c, v in self.world.analog.items() if not callable(v)},
        }


def _switch(name: str) -> str:
    key = name.lower()
    if key not in SWITCHES:
        raise ValueError(f"switches are {', '.join(SWITCHES)}, not {name!r}")
    return SWITCHES[key]


def _span(numbers: Sequence[int]) -> str:
    values = list(numbers)
    if not values:
        return "none"
    return f"{values[0]}..{values[-1]}" if values == list(range(values[0], values[-1] + 1)) \
        else ", ".join(map(str, values))


def _at(x: float | None) -> str:
    return "none" if x is None else f"{x:.0f}"


def _side(switch: Any, edge: float | None) -> str:
    return _at(edge) + (f" (stuck {switch.fault})" if switch.fault else "")
