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


# TS (manual 3.139): the controller status byte, one ASCII character.
TS_AXIS_MOVING: Final = (0x01, 0x02, 0x04, 0x08)  # bits 0..3: axis 1..4 in motion
TS_POWER_OFF: Final = 0x10  # bit 4: motor power OFF
TS_SRQ: Final = 0x80  # bit 7: IEEE SRQ sent by RQ (toggles low once read)

# TX (manual 3.142): the controller activity register, one ASCII character.
TX_PROGRAM: Final = 0x01  # bit 0: a program is running
TX_COMMAND_LINE: Final = 0x02  # bit 1: a command line is executing
TX_MANUAL_JOG: Final = 0x04  # bit 2: manual jog mode active
TX_REMOTE: Final = 0x08  # bit 3: remote mode active
TX_TRAJECTORY: Final = 0x10  # bit 4: a trajectory is executing


def controller_status(moving: list[bool], power_off: bool, srq: bool = False) -> str:
    """TS's character: bits 5 (default 0) and 6 (default 1) are the manual's defaults,
    so an idle powered controller reads '@' (as a public MM4006 host expects)."""
    value = DEFAULT_ONE
    for bit, axis_moving in zip(TS_AXIS_MOVING, moving[:4], strict=False):
        if axis_moving:
            value |= bit
    if power_off:
        value |= TS_POWER_OFF
    if srq:
        value |= TS_SRQ
    return chr(value)


def controller_activity(trajectory: bool, program: bool = False) -> str:
    """TX's character while TX itself is answered: remote mode and a command line
    executing are always set ('J', the manual's example); bit 0 while a stored program
    runs (EX); no manual jog exists here; bit 4 while a trajectory (XY or time-based)
    runs."""
    value = DEFAULT_ONE | TX_REMOTE | TX_COMMAND_LINE
    if trajectory:
        value |= TX_TRAJECTORY
    if program:
        value |= TX_PROGRAM
    return chr(value)
