"""Per-axis settings the MM4005 stores and reports but whose effect is modelled elsewhere
or not at all: the servo gains, backlash, home search speeds, the maximum speed VU,
the following-error limit. Each has a default and a range; a value outside it is refused
(C) with nothing changed. Meanings and defaults are recorded per command in the table
(maxk/commands/mm4005/table.py); where the MM4005 page was not found they are marked I/D.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final


@dataclass(frozen=True, slots=True)
class SettingRule:
    """A stored setting: default, inclusive range, whole numbers only or not."""

    default: float
    low: float
    high: float
    integer: bool = False


# The shared filter's KP, KI, KD that the manual's full scale 1.0 stands for (D: the
# MM4005's own hardware scale is not published). Chosen so that the whole range 0..1 gives a
# stable loop on the world's default motor and KP 0.1, KI 0.1, KD 0.16 is the well-damped
# tuning the servo tests use; a host that writes a motor record's PCOF/ICOF/DCOF (0..1, as
# the EPICS model 1 driver sends them with UF) gets a loop that follows.
FULL_SCALE: Final[tuple[float, float, float]] = (100.0, 10.0, 1000.0)

RULES: Final[dict[str, SettingRule]] = {
    # the gains in the manual's range 0 to 1 (KD/KI pages 3.63/3.64, C); 0 = factory (profile
    # only); FULL_SCALE maps them onto the shared servo filter's gains (D)
    "KP": SettingRule(0.0, 0.0, 1.0),  # proportional gain
    "KI": SettingRule(0.0, 0.0, 1.0),  # integral gain
    "KD": SettingRule(0.0, 0.0, 1.0),  # derivative gain
    "KS": SettingRule(1.0, 0.0, 1.0),  # integral saturation, fraction of full output
    "FE": SettingRule(1.0, 0.0, 1e6),  # following-error limit, units (FE checks 2 TU..travel)
    "FF": SettingRule(1.0, 0.0, 1e6),  # master-slave following-error limit (stored only)
    "GR": SettingRule(1.0, 0.0001, 10000.0),  # master-slave reduction ratio (stored only)
    "BA": SettingRule(0.0, 0.0, 1e3),  # backlash (manual 3.25: BA checks 10000 x TU itself)
    "OH": SettingRule(1.0, 1e-6, 1e6),  # home search high speed, units/s
    "OL": SettingRule(0.1, 1e-6, 1e6),  # home search low speed, units/s
    "VU": SettingRule(100.0, 1e-6, 1e6),  # maximum speed, units/s
    "SN": SettingRule(2.0, 0.0, 11.0, integer=True),  # displacement units code, 2 = mm
    "SD": SettingRule(100.0, 1e-6, 100.0),  # reduced speed, percent (the controller's one
    # value, kept with axis 1's settings so that a reset restores it; not applied)
    "SY": SettingRule(0.0, 0.0, 1.0, integer=True),  # synchronisation flag (stored only)
}


class AxisSettings:
    """One axis's stored settings (as set, or their defaults) and the gains in force."""

    def __init__(self) -> None:
        self.values = {name: rule.default for name, rule in RULES.items()}
        # the gains the loop uses: KP/KI/KD/KS as of the last UF (D: UF applies them)
        self.active_gains = (0.0, 0.0, 0.0, 1.0)
        # the following-error limit the loop checks: FE as of the last UF (manual 3.56)
        self.following_limit = RULES["FE"].default

    def get(self, name: str) -> float:
        return self.values[name]

    def check(self, name: str, value: float) -> bool:
        rule = RULES[name]
        if not rule.low <= value <= rule.high:
            return False
        return not (rule.integer and value != int(value))

    def set(self, name: str, value: float) -> None:
        self.values[name] = value

    def update_filter(self) -> None:
        """UF: the gains set by KP/KI/KD/KS and the limit FE take effect."""
        v = self.values
        self.active_gains = (v["KP"], v["KI"], v["KD"], v["KS"])
        self.following_limit = v["FE"]

    @property
    def servo_on(self) -> bool:
        """Factory gains (KP 0 in force): the exact, profile-only axis (D)."""
        return self.active_gains[0] > 0.0
