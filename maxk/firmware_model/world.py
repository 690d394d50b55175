"""The machine around the board: switches, encoder index marks, inputs and faults.

A board alone never trips a switch; the stage does. Positions here are *physical*:
steps the motor has actually made since power-up, which LP/LO/LPE never change, so a
home switch stays where it is when the host reloads the counters.

Defaults describe a plain stage: limit switches far out (+/-1,000,000,000 steps), a
home switch 100 steps wide a little above the power-up position (steps 1234..1333: a
forward home from power-up finds it, and the round targets of everyday moves do not
land on it), an encoder index mark every 4000 counts (a 1000-line encoder in x4), one
line (4 counts) wide, placed inside the home window at 1280, every digital input low and
every analog input at 0 V. Faults can stick a switch
active or inactive.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from maxk.firmware_model.motor import MotorPlant

Board = Any  # the controller an input source is a function of (its time, its axes)

STUCK_ACTIVE = "active"
STUCK_INACTIVE = "inactive"
FAULTS = (None, STUCK_ACTIVE, STUCK_INACTIVE)

DEFAULT_LIMIT = 1_000_000_000
SWITCHES = {"plus": "plus_limit", "minus": "minus_limit", "home": "home"}
"""Switch names used by the API, scripts and the REPL -> AxisWorld attributes."""


DEFAULT_HOME = (1234, 1333)

# The ranges every world setting is checked against, wherever it comes from (a script's
# @world, the REPL, the control door, the Python API): a value outside is a ValueError
# naming the range, and nothing changes (decisions D, issue 34).
POSITION_LIMIT = 2 ** 53  # |steps| of a switch or index position: whole steps a float holds
COUNT_LIMIT = 2 ** 31 - 1  # steps of play, steps missed at once, index period and width:
# a 32-bit counter's range, far beyond any stage
BOUNCE_LIMIT = 1000  # steps of contact bounce at a switch's edge (a real one chatters a few)


def checked_position(position: float | None, what: str = "a switch position"
                     ) -> float | None:
    """A position in steps (None: no switch there): finite and within POSITION_LIMIT."""
    if position is None:
        return None
    try:
        value = float(position)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{what} must be a number of steps, not {position!r}") from None
    if not math.isfinite(value) or abs(value) > POSITION_LIMIT:
        raise ValueError(f"{what} must be a finite number of steps within "
                         f"+/-{POSITION_LIMIT} (2^53), not {position}")
    return value


def checked_count(value: object, what: str, low: int = 0, high: int = COUNT_LIMIT) -> int:
    """A whole number of steps or counts from `low` to `high`."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ValueError(f"{what} must be a whole number, not {value!r}")
    if isinstance(value, float) and not (math.isfinite(value) and value.is_integer()):
        raise ValueError(f"{what} must be a whole number, not {value}")
    number = int(value)
    if not low <= number <= high:
        raise ValueError(f"{what} must be from {low} to {high}, not {value}")
    return number


_checked = checked_position


@dataclass
class Switch:
    """A switch that is active on one side of a physical position (limits), or inside
    a window (home). ``fault`` sticks it regardless of position."""

    low: float | None  # active at or above this position (None: no lower edge)
    high: float | None  # active at or below this position (None: no upper edge)
    fault: str | None = None
    bounce: int = 0  # chatter zone: within this many steps inside an edge it flips each step

    @property
    def present(self) -> bool:
        return self.low is not None or self.high is not None

    def active(self, steps: int | float) -> bool:
        # (`int | float`: compiled, a `float` would turn the motor's int steps into a float)
        fault = self.fault
        if fault is not None:
            if fault == STUCK_ACTIVE:
                return True
            if fault == STUCK_INACTIVE:
                return False
        low, high = self.low, self.high
        if low is None and high is None:  # (not present)
            return False
        if low is not None and steps < low:
            return False
        if self.high is not None and steps > self.high:
            return False
        if self.bounce:
            # Contact bounce as a function of position: just inside an edge the switch
            # flips on every step, so crossing it makes a burst of edges (deterministic).
            for edge, depth in ((self.low, steps - (self.low or 0)),
                                (self.high, (self.high or 0) - steps)):
                if edge is not None and 0 <= depth < self.bounce:
                    return depth % 2 == 0
        return True

    def transitions(self) -> list[tuple[int, bool]]:
        """Every position p where the switch differs from p - 1, with whether it is
        active at p (so crossing upward there is a rising edge)."""
        if self.fault is not None or not self.present:
            return []
        out = []
        for edge in (self.low, self.high):
            if edge is None:
                continue
            e = int(edge)
            for p in range(e - self.bounce - 1, e + self.bounce + 2):
                now, before = self.active(p), self.active(p - 1)
                if now != before:
                    out.append((p, now))
        return sorted(set(out))


@dataclass
class AxisWorld:
    """What one axis's stage looks like to the board."""

    plus_limit: Switch = field(default_factory=lambda: Switch(DEFAULT_LIMIT, None))
    minus_limit: Switch = field(default_factory=lambda: Switch(None, -DEFAULT_LIMIT))
    home: Switch = field(default_factory=lambda: Switch(DEFAULT_HOME[0], DEFAULT_HOME[1]))
    index_period: int = 4000  # encoder counts between index marks (0: no index)
    index_width: int = 4  # counts the index pulse stays high
    index_offset: int = 1280  # physical position of an index mark (inside the home window)
    motor: MotorPlant = field(default_factory=MotorPlant)  # what a servo (PSM) axis drives
    lost_steps: int = 0  # steps a stepper's stage lags its motor by (missed-steps fault)
    backlash: int = 0  # play between a stepper and its stage: after a reversal the stage
    # does not follow the motor's first `backlash` steps (BC on the board compensates)

    def set_plus_limit(self, position: float | None) -> None:
        self.plus_limit = Switch(_checked(position), None, self.plus_limit.fault,
                                 self.plus_limit.bounce)

    def set_minus_limit(self, position: float | None) -> None:
        self.minus_limit = Switch(None, _checked(position), self.minus_limit.fault,
                                  self.minus_limit.bounce)

    def set_home(self, low: float | None, high: float | None) -> None:
        low, high = _checked(low), _checked(high)
        if low is not None and high is not None and low > high:
            raise ValueError(f"the home switch runs from low to high: {low:g} > {high:g}")
        self.home = Switch(low, high, self.home.fault, self.home.bounce)

    def index_active(self, steps: int) -> bool:
        if self.index_period <= 0:
            return False
        return (steps - self.index_offset) % self.index_period < self.index_width


@dataclass(frozen=True)
class EncoderMount:
    """An encoder on the shaft of another axis's motor (a stepper with an encoder
    feeding the controller's encoder input on a second axis). It reads the motor's
    physical steps (the steps a missed-steps fault lost are not turned) times
    `counts_per_step`, negative when it counts the other way."""

    motor: int  # the axis whose motor the encoder turns with
    counts_per_step: int | float = 1.0  # (as given: compiled, a `float` would convert)

    def counts(self, motor_steps: int | float) -> int | float:
        return motor_steps * self.counts_per_step


InputSource = Callable[["Board"], float]
"""A digital or analog source: called with the board, returns a level (bool-ish or volts)."""


@dataclass
class World:
    """Every axis's stage, plus the board's digital and analog inputs."""

    axes: list[AxisWorld]
    digital: dict[int, bool | InputSource] = field(default_factory=dict)  # bit -> level/source
    analog: dict[int, float | InputSource] = field(default_factory=dict)  # channel -> volts/src
    # the controller's digital outputs, as it last drove them (bit -> level): written by a
    # personality that keeps its outputs in the world (the MM4005's SB), read by every door
    outputs: dict[int, bool] = field(default_factory=dict)
    encoders: dict[int, EncoderMount] = field(default_factory=dict)  # encoder input (axis)
    # -> the motor it is mounted on (none: an axis's encoder is its own, as before)

    @classmethod
    def default(cls, axis_count: int) -> World:
        return cls([AxisWorld() for _ in range(axis_count)])

    def digital_level(self, bit: int, board: Board) -> bool:
        source = self.digital.get(bit, False)
        return bool(source(board) if callable(source) else source)

    def analog_volts(self, channel: int, board: Board) -> float:
        source = self.analog.get(channel, 0.0)
        volts = float(source(board) if callable(source) else source)
        if math.isnan(volts):
            return 0.0  # a broken source reads as an open input
        return max(-10.0, min(10.0, volts))

    def inputs_time_dependent(self) -> bool:
        """True when some digital input is a function (it may change at any tick)."""
        return any(callable(s) for s in self.digital.values())


def axis_position_source(letter: str, fn: Callable[[int], float]) -> InputSource:
    """An input that depends on an axis's motor position (e.g. a cam or a sensor)."""

    def source(board: Board) -> float:
        axis = board.axis(letter)
        return fn(axis.motor_position(board))

    return source


def time_source(fn: Callable[[float], float]) -> InputSource:
    """An input that depends on virtual time in seconds."""

    def source(board: Board) -> float:
        return fn(board.time)

    return source
