"""One pulse-engine axis: its settings (the v2 axis configuration, also used for v1's
three axes) and its runtime (position counter, what drives it this slot)."""

from __future__ import annotations

from dataclasses import dataclass, field

from .constants import AxisConfigBits, AxisState, SwitchBits
from .motion import SlotMotion
from .world import SwitchLevels

# Plain ints: the slot loop tests these bits often, and IntFlag operations are slow.
_INTERNAL = int(AxisConfigBits.INTERNAL_PLANNER)
_POSITION = int(AxisConfigBits.POSITION_MODE)
_SOFT = int(AxisConfigBits.SOFT_LIMIT_ENABLED)
_INV_N, _INV_P, _INV_H = (int(SwitchBits.INVERT_LIMIT_N), int(SwitchBits.INVERT_LIMIT_P),
                          int(SwitchBits.INVERT_HOME))
_HOME_N, _HOME_P = int(SwitchBits.HOME_ON_LIMIT_N), int(SwitchBits.HOME_ON_LIMIT_P)
_ANY_HOME = int(SwitchBits.HOME) | _HOME_N | _HOME_P


@dataclass
class AxisSettings:
    """Field names follow PoKeysLib's sPoKeysPEv2 arrays; speeds in pulses/ms."""

    config: int = 0  # AxisConfigBits
    switches: int = 0  # SwitchBits
    pin_home: int = 0
    pin_limit_n: int = 0
    pin_limit_p: int = 0
    homing_speed: int = 0  # % of max speed (0 -> 10 %, the v1 seed's value)
    homing_return_speed: int = 0  # % of the homing speed (0 -> 50 %, the v2 seed's 'half')
    mpg_encoder: int = 0
    max_speed: float = 0.0  # pulses/ms
    max_acceleration: float = 0.0  # pulses/ms^2
    max_deceleration: float = 0.0
    soft_limit_min: int = 0
    soft_limit_max: int = 0
    mpg_multiplier: int = 1
    raw: bytearray = field(default_factory=lambda: bytearray(45))  # request [8..52] as sent

    def __setattr__(self, name: str, value: object) -> None:
        if name in ("config", "switches"):
            value = int(value)  # type: ignore[call-overload]
        object.__setattr__(self, name, value)

    @property
    def internal(self) -> bool:
        return bool(self.config & _INTERNAL)

    @property
    def position_mode(self) -> bool:
        return bool(self.config & _POSITION)

    @property
    def soft_limits(self) -> bool:
        return bool(self.config & _SOFT)

    def tripped(self, levels: SwitchLevels) -> tuple[bool, bool, bool]:
        """(limit-, limit+, home) activated: high unless inverted (NC switches)."""
        sw = self.switches
        lim_n = levels.limit_n != bool(sw & _INV_N)
        lim_p = levels.limit_p != bool(sw & _INV_P)
        home = levels.home != bool(sw & _INV_H)
        if sw & _HOME_N:
            home = lim_n
        elif sw & _HOME_P:
            home = lim_p
        return lim_n, lim_p, home

    def homing_input_available(self) -> bool:
        return bool(self.switches & _ANY_HOME)


@dataclass
class Axis:
    index: int
    settings: AxisSettings = field(default_factory=AxisSettings)
    position: int = 0  # the position counter the host reads (pulses)
    counter_offset: int = 0  # counter - physical: PositionSet and homing move the counter only
    motion: SlotMotion | None = None  # internal controller, homing or probing motion
    target: float | None = None  # last position or speed given to the internal controller
    held_state: AxisState | None = None  # homing/probing/limit/error; None = from the mode
    home_offset: int = 0
    probe_limit: int | None = None  # probing: the max position, where probing fails
    mpg_last: int | None = None
    mpg_pending: int = 0
    direction_out: bool = False  # the direction pin, held between pulses
    # backlash compensation (v2 0x85 0x41): half the play, pulses a slot, the register
    backlash_width: int = 0
    backlash_rate: int = 0  # pulses per slot the register moves (0: at once, D)
    backlash_register: int = 0  # extra pulses out: the stage is the counter's plus these

    @property
    def stage(self) -> int:
        """Physical position: the pulses emitted since power-up, where the switches are
        (setting the counter does not move the stage; backlash compensation pulses do)."""
        return self.position - self.counter_offset + self.backlash_register

    def take_up_backlash(self, direction: int, slots: int) -> None:
        """The axis moved `direction` for `slots` slots: the register heads for
        direction * width at its rate, so the motor takes up the play on a reversal
        while the counter counts only the commanded pulses."""
        if not self.backlash_width or not direction:
            return
        target = self.backlash_width if direction > 0 else -self.backlash_width
        gap = target - self.backlash_register
        if self.backlash_rate > 0:
            reach = self.backlash_rate * slots
            gap = max(-reach, min(reach, gap))
        self.backlash_register += gap

    def backlash_settled(self, direction: int) -> bool:
        """Is the play already taken up for motion this way?"""
        target = self.backlash_width if direction > 0 else -self.backlash_width
        return not self.backlash_width or not direction or self.backlash_register == target

    def set_counter(self, value: int) -> None:
        """Load the position counter; the stage stays where it is."""
        self.counter_offset += value - self.position
        self.position = value
