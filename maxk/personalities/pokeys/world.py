"""What the pulse engine reads from the machine: switch pins, e-stop, probe and MPG.

The engine samples its inputs at the start of every slot. Levels are pin levels
(True = high). PoKeys switches are normally closed between the pin and ground with a
pull-up, so an open (pressed or broken) switch reads high = tripped, unless the
configuration inverts it. The shared world plugs in behind ``PulseEngineWorld``; the
two ``next_*`` questions let the engine jump over stretches where nothing changes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, NamedTuple, Protocol

from ...firmware_model.world import AxisWorld, Switch, World
from .io import ANALOG_FULL_SCALE, ANALOG_INPUT, ANALOG_PINS, DIGITAL_OUTPUT, INVERT


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


class PoKeysIOWorld:
    """The PoKeys's pins on the shared `World`: what a test, a script, the REPL or the
    world contract drives (inputs, analog volts, keys, encoders on axes) and what the
    device drives (outputs, PWM), read through one object.

    World digital input p is pin p's level (input 0 is the dedicated e-stop, not a pin);
    world analog channel p is pin p's voltage. Counters count the edges the world makes
    on a pin configured as a counter, as its counter options say (`counter_step`, D);
    an input that is a function is sampled every slot by `CounterSampler` (D)."""

    def __init__(self, io: Any, world: World, stage: Callable[[int], int],
                 board: Callable[[], Any] = lambda: None,
                 changed: Callable[[], None] = lambda: None) -> None:
        self.io = io  # a personalities.pokeys.io.DeviceIO
        self.world = world
        self.stage = stage  # axis index -> its stage (physical pulses)
        self.board = board
        self.changed = changed
        self._levels: dict[int, bool] = {}
        self._filtered: dict[int, tuple[int, float]] = {}  # pin -> (slot, filtered volts)

    def now(self) -> int:
        """The device's slot (the board's tick), for the analog filter."""
        return int(getattr(self.board(), "tick", 0))

    # ---- inputs the world drives -----------------------------------------------------
    def set_input(self, pin: int, level: object) -> None:
        """Pin `pin` (1..55; 0 = the e-stop input) at a level or a function of time."""
        if not 0 <= pin <= 55:
            raise ValueError(f"no input {pin} (pins 1..55, 0 the e-stop)")
        self.world.digital[pin] = level  # type: ignore[assignment]
        self.sample(pin)
        self.changed()

    def analog(self, pin: int, volts: object) -> None:
        """Pin `pin`'s voltage (0..3.3 V on the analog pins 41..47)."""
        if pin not in ANALOG_PINS:
            raise ValueError(f"pin {pin} has no analog input (pins 41..47)")
        if not callable(volts):
            v = float(volts)  # type: ignore[arg-type]
            if not math.isfinite(v) or not 0.0 <= v <= ANALOG_FULL_SCALE:
                raise ValueError(f"volts must be a number from 0 to {ANALOG_FULL_SCALE}, "
                                 f"not {volts}")
        self.world.analog[pin] = volts  # type: ignore[assignment]

    def press_key(self, key: int, pressed: bool = True) -> None:
        """Matrix keyboard key (row * 8 + column, D) pressed or released."""
        if not 0 <= key < 128:
            raise ValueError(f"no matrix key {key} (0..127 = row*8 + column)")
        (self.io.matrix_keys.add if pressed else self.io.matrix_keys.discard)(key)

    def press_kbd48(self, key: int, pressed: bool = True) -> None:
        """kbd48CNC key 0..47 on the PoNET bus."""
        if not 0 <= key < 48:
            raise ValueError(f"no kbd48CNC key {key} (0..47)")
        keys = self.io.kbd48.keys
        (keys.add if pressed else keys.discard)(key)

    def attach_encoder(self, encoder: int, axis: int | None, direction: int = 1) -> None:
        """Encoder `encoder` (0..25; 25 the ultra-fast one) counts axis `axis`'s stage from
        now on (None: detached, it keeps its count)."""
        if not 0 <= encoder < len(self.io.encoders):
            raise ValueError(f"no encoder {encoder} (0..{len(self.io.encoders) - 1})")
        e = self.io.encoders[encoder]
        e.base = self.encoder_value(encoder)
        e.axis = axis
        e.direction = -1 if direction < 0 else 1
        e.axis_from = self.stage(axis) if axis is not None else 0

    # ---- what the device reads -------------------------------------------------------
    def input_level(self, pin: int) -> bool:
        return self.world.digital_level(pin, self.board())

    def sample(self, pin: int) -> bool:
        """The pin's level now; an edge since the last sample counts on a counter pin as
        its counter options say (`counter_step`)."""
        level = self.input_level(pin)
        before = self._levels.get(pin, False)
        self._levels[pin] = level
        if level != before and 1 <= pin <= 55 and self.io.counts(pin):
            step = counter_step(self.io.counter_options[pin - 1], level)
            self.io.counters[pin - 1] = (self.io.counters[pin - 1] + step) & 0xFFFFFFFF
        return level

    def timed_counters(self) -> list[int]:
        """Counter pins whose world input is a function (of time or of an axis): their
        edges can come at any slot, so they are sampled every slot (`CounterSampler`)."""
        return [pin for pin, source in self.world.digital.items()
                if callable(source) and 1 <= pin <= 55 and self.io.counts(pin)]

    def pin_level(self, pin: int) -> bool:
        """What DigitalIOGet reports for pin: an output its driven level, an input the
        world's level (inverted when the pin is inverted)."""
        f = self.io.functions[pin - 1]
        if f & DIGITAL_OUTPUT:
            return bool(self.io.output_level(pin))
        level = self.sample(pin) if pin in self.world.digital else False
        return level != bool(f & INVERT)

    def pin_bits(self) -> int:
        """Every pin's level as DigitalIOGet packs them: bit p-1 = pin p."""
        bits = 0
        digital = self.world.digital
        functions = self.io.functions
        for i in range(55):
            f = functions[i]
            if f & DIGITAL_OUTPUT:
                level = self.io.output_level(i + 1)
            else:
                level = (self.sample(i + 1) if i + 1 in digital else False) != bool(f & INVERT)
            if level:
                bits |= 1 << i
        return bits

    def analog_code(self, pin: int) -> int:
        """12-bit code of an analog input pin (0 unless configured as one), through the
        RC filter when one is set (`analog_filtered`)."""
        if not self.io.functions[pin - 1] & ANALOG_INPUT:
            self._filtered.pop(pin, None)
            return 0
        volts = self.analog_filtered(pin, self.world.analog_volts(pin, self.board()))
        return max(0, min(4095, round(volts / ANALOG_FULL_SCALE * 4095)))

    def analog_filtered(self, pin: int, volts: float) -> float:
        """The analog RC filter (0x39): a first-order low-pass with a time constant of
        `analog_filter` slots (ms; 0 = off), sampled once a slot (D for the unit). The
        input is taken as it reads now since the last read (exact for a constant input):
        y = x + (y0 - x) * exp(-slots / tau)."""
        tau = self.io.analog_filter
        now = self.now()
        last = self._filtered.get(pin)
        if tau <= 0 or last is None:
            self._filtered[pin] = (now, volts)
            return volts
        slot, held = last
        filtered = volts + (held - volts) * math.exp(-max(0, now - slot) / tau)
        self._filtered[pin] = (now, filtered)
        return filtered

    def encoder_counting(self, encoder: int) -> bool:
        if encoder == 25:
            return self.io.ultra_fast[0] != 0
        if encoder < 3 and self.io.fast_encoders[0] != 0:
            return True
        return bool(self.io.encoders[encoder].options & 1)

    def encoder_value(self, encoder: int) -> int:
        """The count: the attached stage's pulses are quadrature cycles, counted once at
        1x sampling, twice with option bit 2 (2x), four times with bit 1 (4x; 4x wins
        when both are set) (D: the library names the bits, not the stage's unit)."""
        e = self.io.encoders[encoder]
        if e.axis is None or not self.encoder_counting(encoder):
            return int(e.base)
        per_cycle = 4 if e.options & 0x02 else 2 if e.options & 0x04 else 1
        return int(e.base + e.direction * per_cycle * (self.stage(e.axis) - e.axis_from))

    def load_encoder(self, encoder: int, value: int) -> None:
        e = self.io.encoders[encoder]
        e.base = value
        if e.axis is not None:
            e.axis_from = self.stage(e.axis)

    def freeze_encoders(self) -> list[int]:
        """Before a configuration change: every encoder's count, to restart from."""
        return [self.encoder_value(i) for i in range(len(self.io.encoders))]

    def restart_encoders(self, values: list[int]) -> None:
        for i, v in enumerate(values):
            self.load_encoder(i, v)

    def output_levels(self) -> dict[int, bool]:
        """Every digital output pin's level."""
        return {p: self.io.output_level(p) for p in range(1, 56) if self.io.is_output(p)}


COUNT_FALLING = 0x02  # counter options: bit 0 rising, bit 1 falling edges (D)
COUNT_DOWN = 0x04  # counter options: the count goes down (D)


def counter_step(options: int, level: bool) -> int:
    """What an edge to `level` adds to a counter with these options (D: the library
    stores the byte without naming its bits): edges 0 or 1 rising (power-up: rising),
    2 falling, 3 both; bit 2 counts down."""
    edges = options & 0x03
    counted = (level and edges != COUNT_FALLING) or (not level and edges >= COUNT_FALLING)
    if not counted:
        return 0
    return -1 if options & COUNT_DOWN else 1


class CounterSampler:
    """An event source of the device's engine: while a counter pin follows a function,
    its input is sampled at every slot boundary, so the counter sees each edge the world
    makes (one a slot at most, as the pulse engine reads its inputs once a slot, D)."""

    def __init__(self, pins: PoKeysIOWorld, tick: Callable[[], int]) -> None:
        self.pins = pins
        self.sampled = tick()  # the slot last sampled

    def next_event(self) -> int | None:
        return self.sampled + 1 if self.pins.timed_counters() else None

    def on_event(self, now: int) -> None:
        for pin in self.pins.timed_counters():
            self.pins.sample(pin)
        self.sampled = now
