"""Names and numbers of the PoKeys pulse engine, as PoKeysLib spells them.

Engine and axis state codes are the library's ePK_PEState / ePK_PEAxisState values
(reference section 7); the v1 engine shares the enum (peINTERNAL and peBUFFER are its own).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum, IntFlag
from typing import Final

SLOT_SECONDS: Final = 1e-3
"""One time slot: the pulse frequency is constant for 1 ms (seed v1, 'Operating principles')."""

BUFFER_DEPTH: Final = 128
"""Slot buffer depth on both engines: 128 slots = 128 ms of motion (seeds v1 and v2)."""


class EngineState(IntEnum):
    STOPPED = 0
    INTERNAL = 1  # v1 only: internal motion controller in use
    BUFFER = 2  # v1 only: buffered operation
    RUNNING = 3  # v2: per-axis buffer or internal controller
    JOGGING = 10
    STOPPING = 11
    HOME = 20
    HOMING = 21
    PROBE_COMPLETE = 30
    PROBE = 31
    PROBE_ERROR = 32
    HYBRID_PROBE_STOPPING = 40
    HYBRID_PROBE_COMPLETE = 41
    STOP_LIMIT = 100
    STOP_EMERGENCY = 101


class AxisState(IntEnum):
    STOPPED = 0
    READY = 1
    RUNNING = 2
    HOMING_RESET = 8
    HOMING_BACKOFF = 9
    HOME = 10
    HOMING_START = 11
    HOMING_SEARCH = 12
    HOMING_BACK = 13
    PROBED = 14
    PROBE_START = 15
    PROBE_SEARCH = 16
    ERROR = 20
    LIMIT = 30


class AxisConfigBits(IntFlag):
    """v2 axis configuration byte [8] (ePK_PEv2_AxisConfig)."""

    ENABLED = 0x01
    INVERTED = 0x02
    INTERNAL_PLANNER = 0x04
    POSITION_MODE = 0x08
    INVERTED_HOME = 0x10
    SOFT_LIMIT_ENABLED = 0x20
    FAST_OUTPUT = 0x40
    ENABLED_MASKED = 0x80


class SwitchBits(IntFlag):
    """v2 axis switch configuration byte [9] (ePK_PEv2_AxisSwitchOptions)."""

    LIMIT_N = 0x01
    LIMIT_P = 0x02
    HOME = 0x04
    HOME_ON_LIMIT_N = 0x08
    HOME_ON_LIMIT_P = 0x10
    INVERT_LIMIT_N = 0x20
    INVERT_LIMIT_P = 0x40
    INVERT_HOME = 0x80


# Engine states in which the engine may emit pulses, so a tripped switch stops it.
GENERATING: Final = frozenset({
    EngineState.INTERNAL, EngineState.BUFFER, EngineState.RUNNING, EngineState.JOGGING,
    EngineState.HOMING, EngineState.PROBE,
})


@dataclass(frozen=True)
class EngineSpec:
    """What differs in size between the two engines."""

    version: int
    axes: int
    max_pulses_per_slot: int  # 25 on v1 (25 kHz), 125 on v2 (status [57] = 125 kHz)
    pulse_bits: int  # 7 on v1 (8-bit entries), 15 on v2 (16-bit entries)

    @property
    def max_speed_per_ms(self) -> float:
        return float(self.max_pulses_per_slot)


PEV1: Final = EngineSpec(version=1, axes=3, max_pulses_per_slot=25, pulse_bits=7)
PEV2: Final = EngineSpec(version=2, axes=8, max_pulses_per_slot=125, pulse_bits=15)
