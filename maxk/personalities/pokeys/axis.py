"""One pulse-engine axis: its settings (the v2 axis configuration, also used for v1's
three axes) and its runtime (position counter, what drives it this slot)."""

from __future__ import annotations

from dataclasses import dataclass, field

from .constants import AxisConfigBits, AxisState, SwitchBits
from .motion import SlotMotion
from .world import SwitchLevels


@dataclass
class AxisSettings:
    """Field names follow PoKeysLib's sPoKeysPEv2 arrays; speeds in pulses/ms."""

    config: AxisConfigBits = AxisConfigBits(0)
    switches: SwitchBits = SwitchBits(0)
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

    @property
    def internal(self) -> bool:
        return AxisConfigBits.INTERNAL_PLANNER in self.config

    @property
    def position_mode(self) -> bool:
        return AxisConfigBits.POSITION_MODE in self.config

    @property
    def soft_limits(self) -> bool:
        return AxisConfigBits.SOFT_LIMIT_ENABLED in self.config

    def tripped(self, levels: SwitchLevels) -> tuple[bool, bool, bool]:
        """(limit-, limit+, home) activated: high unless inverted (NC switches)."""
        sw = self.switches
        lim_n = levels.limit_n != (SwitchBits.INVERT_LIMIT_N in sw)
        lim_p = levels.limit_p != (SwitchBits.INVERT_LIMIT_P in sw)
        home = levels.home != (SwitchBits.INVERT_HOME in sw)
        if SwitchBits.HOME_ON_LIMIT_N in sw:
            home = lim_n
        elif SwitchBits.HOME_ON_LIMIT_P in sw:
            home = lim_p
        return lim_n, lim_p, home

    def homing_input_available(self) -> bool:
        return bool(self.switches & (SwitchBits.HOME | SwitchBits.HOME_ON_LIMIT_N
                                     | SwitchBits.HOME_ON_LIMIT_P))


@dataclass
class Axis:
    index: int
    settings: AxisSettings = field(default_factory=AxisSettings)
    position: int = 0
    motion: SlotMotion | None = None  # internal controller, homing or probing motion
    target: float | None = None  # last position or speed given to the internal controller
    held_state: AxisState | None = None  # homing/probing/limit/error; None = from the mode
    home_offset: int = 0
    probe_limit: int | None = None  # probing: the max position, where probing fails
    mpg_last: int | None = None
    mpg_pending: int = 0
    direction_out: bool = False  # the direction pin, held between pulses
    clipped_pulses: int = 0  # pulses asked for beyond the engine's per-slot maximum
