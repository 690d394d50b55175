"""What the PoKeys API and its console share: decoded status, axis names, errors."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol

from maxk.firmware_model.world import World
from maxk.personalities.pokeys import AXIS_LETTERS, AxisState, EngineState, SlotEngine, SwitchBits
from maxk.personalities.pokeys.device import PoKeysDevice
from maxk.personalities.pokeys.engine import PulseEngine

V1_STATES = {"stopped": 0, "internal": 1, "buffer": 2, "jogging": 10}
V2_STATES = {"stopped": 0, "running": 3, "jogging": 10}


class PoKeysError(Exception):
    """The device did not answer a request the API expected it to answer."""


@dataclass(frozen=True)
class EngineStatus:
    """A decoded status reply (0x85/0x00 on v2, 0x80/0x00 on v1)."""

    state: int
    axis_states: tuple[int, ...]
    positions: tuple[int, ...]
    limit_plus: int
    limit_minus: int
    home: int
    soft_limit: int = 0
    enabled_axes: int = 3

    @property
    def state_name(self) -> str:
        return EngineState(self.state).name if self.state in EngineState._value2member_map_ \
            else str(self.state)

    def axis_state_name(self, axis: int) -> str:
        s = self.axis_states[axis]
        return AxisState(s).name if s in AxisState._value2member_map_ else str(s)


def axis_index(name: str | int, axes: int) -> int:
    """An axis by letter (X Y Z A B C U V) or number 1..8."""
    if isinstance(name, int):
        index = name
    elif name.isdigit():
        index = int(name) - 1
    elif len(name) == 1 and name.upper() in AXIS_LETTERS:
        index = AXIS_LETTERS.index(name.upper())
    else:
        raise ValueError(f"no axis {name!r}: say {' '.join(AXIS_LETTERS[:axes])} or 1..{axes}")
    if not 0 <= index < axes:
        raise ValueError(f"no axis {name!r} on this device ({axes} axes)")
    return index


class PoKeysControls(Protocol):
    """The PoKeys API the console uses (maxk.controllers.pokeys.PoKeys)."""

    @property
    def model(self) -> str: ...
    @property
    def version(self) -> int: ...
    @property
    def axes(self) -> int: ...
    @property
    def engine(self) -> SlotEngine: ...
    @property
    def pulse_engine(self) -> PulseEngine: ...
    @property
    def world(self) -> World: ...
    @property
    def last_refused(self) -> bool: ...

    def status(self) -> EngineStatus: ...
    def setup(self, axes: int) -> None: ...
    def set_state(self, state: str | int, limit_override: int = 0) -> None: ...
    def configure_axis(self, axis: int, *, enabled: bool = True, internal: bool = False,
                       position_mode: bool = True, max_speed: float | None = None,
                       accel: float | None = None, decel: float | None = None,
                       switches: int | None = None, invert: bool | None = None,
                       invert_home: bool | None = None,
                       soft_limits: tuple[int, int] | None = None,
                       homing: tuple[int, int] | None = None) -> None: ...
    def move(self, targets: Mapping[int, int | float], fraction: float = 1.0) -> None: ...
    def set_positions(self, positions: Mapping[int, int]) -> None: ...
    def fill(self, entries: Sequence[Sequence[int]], *, wide: bool | None = None,
             large: bool = False) -> int: ...
    def clear_buffer(self) -> None: ...
    def home(self, axes: Sequence[int], offsets: Mapping[int, int] | None = None) -> None: ...
    def homing_finish(self, state: str | int = "stopped") -> None: ...
    def probe(self, targets: Mapping[int, int], speed: float = 0.5, probe_input: int = 1,
              polarity: int = 1) -> None: ...
    def probing_finish(self) -> tuple[tuple[int, ...], int]: ...
    def request(self, command: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0,
                payload: bytes = b"") -> bytes | None: ...
    def set_limits(self, axis: int, *, plus: float | None | str = "keep",
                   minus: float | None | str = "keep") -> None: ...
    def set_home(self, axis: int, low: float | None, high: float | None) -> None: ...
    def set_input(self, number: int, level: object) -> None: ...
    def press_estop(self, pressed: bool = True) -> None: ...
    def is_idle(self) -> bool: ...
    def reboot(self) -> None: ...
    @property
    def device(self) -> PoKeysDevice: ...
    def pin_functions(self) -> list[int]: ...
    def set_pin_function(self, pin: int, function: int) -> None: ...
    def digital_inputs(self) -> list[bool]: ...
    def set_output(self, pin: int, level: bool) -> None: ...
    def analog_inputs(self) -> dict[int, int]: ...
    def counters(self, pins: Sequence[int]) -> dict[int, int]: ...
    def clear_counters(self) -> None: ...
    def pwm(self) -> tuple[int, list[int], int]: ...
    def set_pwm(self, enabled: int, duties: Sequence[int], period: int) -> None: ...
    def encoder_values(self) -> list[int]: ...
    def set_encoder_options(self, encoder: int, options: int) -> None: ...
    def set_encoder(self, encoder: int, value: int) -> None: ...
    def rtc(self) -> str: ...
    def save_configuration(self) -> None: ...
    def set_ultra_fast(self, configuration: int, options: int = 0, filter: int = 0) -> None: ...


class ConsoleError(ValueError):
    """A line the console cannot read."""


SWITCH_WORDS = {"lim-": int(SwitchBits.LIMIT_N), "lim+": int(SwitchBits.LIMIT_P),
                 "home": int(SwitchBits.HOME), "none": 0}


def on_off(word: str) -> bool:
    if word.lower() not in ("on", "off"):
        raise ConsoleError(f"say on or off, not {word!r}")
    return word.lower() == "on"


def letters_of(bits: int) -> str:
    return "".join(AXIS_LETTERS[i] for i in range(8) if bits >> i & 1)


def show_number(value: float | None) -> str:
    return "none" if value is None else f"{value:g}"


STATE_SHORT = {"STOPPED": "STOP", "RUNNING": "RUN", "JOGGING": "JOG", "STOPPING": "STPG",
                "HOMING": "HMNG", "INTERNAL": "INT", "BUFFER": "BUF", "PROBE": "PRB",
                "PROBE_COMPLETE": "PRBD", "PROBE_ERROR": "PRB!", "STOP_LIMIT": "LIM!",
                "STOP_EMERGENCY": "EST!", "HYBRID_PROBE_STOPPING": "HPRB",
                "HYBRID_PROBE_COMPLETE": "HPRD"}


