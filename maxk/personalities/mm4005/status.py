"""The MS motor status byte (manual 3.75), sent as one ASCII character per axis.

Bit 6 is "not used, default 1" in the manual's table, so every status character lies in
0x40..0x7F and can never be mistaken for the ',' separating the all-axes reply: the
EPICS drivers read axis n's character at the fixed offset (n - 1) * 5 + 3.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

MOVING: Final = 0x01  # axis in motion
POWER_OFF: Final = 0x02  # motor power OFF
DIRECTION_POSITIVE: Final = 0x04  # motion direction positive
PLUS_LIMIT: Final = 0x08  # right (+) travel limit tripped
MINUS_LIMIT: Final = 0x10  # left (-) travel limit tripped
HOME_SIGNAL: Final = 0x20  # mechanical zero signal high
DEFAULT_ONE: Final = 0x40  # bit 6: not used, default 1


@dataclass(frozen=True, slots=True)
class AxisStatus:
    """What MS reports for one axis; ``byte`` is the wire value."""

    moving: bool = False
    power_off: bool = False
    direction_positive: bool = True
    plus_limit: bool = False
    minus_limit: bool = False
    home_signal: bool = False

    @property
    def byte(self) -> int:
        value = DEFAULT_ONE
        if self.moving:
            value |= MOVING
        if self.power_off:
            value |= POWER_OFF
        if self.direction_positive:
            value |= DIRECTION_POSITIVE
        if self.plus_limit:
            value |= PLUS_LIMIT
        if self.minus_limit:
            value |= MINUS_LIMIT
        if self.home_signal:
            value |= HOME_SIGNAL
        return value

    @property
    def char(self) -> str:
        return chr(self.byte)

    @classmethod
    def from_byte(cls, value: int) -> AxisStatus:
        return cls(moving=bool(value & MOVING), power_off=bool(value & POWER_OFF),
                   direction_positive=bool(value & DIRECTION_POSITIVE),
                   plus_limit=bool(value & PLUS_LIMIT), minus_limit=bool(value & MINUS_LIMIT),
                   home_signal=bool(value & HOME_SIGNAL))
