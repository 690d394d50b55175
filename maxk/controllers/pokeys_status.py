"""What the PoKeys API and its console share: decoded status, axis names, errors."""

from __future__ import annotations

from dataclasses import dataclass

from maxk.personalities.pokeys import AXIS_LETTERS, AxisState, EngineState

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
