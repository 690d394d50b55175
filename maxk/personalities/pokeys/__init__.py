"""The PoKeys personality: pulse engine v1 (PoKeys56E) and v2 (PoKeys57E/57CNC)."""

from .constants import PEV1, PEV2, AxisConfigBits, AxisState, EngineState, SwitchBits
from .device import MODELS, Identity, NetworkConfig, PoKeysDevice
from .engine import PulseEngine, SlotRecord
from .machine import AXIS_LETTERS, SlotEngine
from .pev1 import PulseEngineV1
from .pev2 import PulseEngineV2
from .plans import AxisPlan, PulsePlan, SegmentPlan
from .world import (
    ESTOP_INPUT,
    BenchWorld,
    PulseEngineWorld,
    SharedWorld,
    SwitchLevels,
    Zone,
    pokeys_world,
)

__all__ = [
    "AXIS_LETTERS", "ESTOP_INPUT", "MODELS", "PEV1", "PEV2", "AxisConfigBits", "AxisPlan",
    "AxisState", "BenchWorld", "EngineState", "Identity", "NetworkConfig", "PoKeysDevice",
    "PulseEngine", "PulseEngineV1", "PulseEngineV2", "PulseEngineWorld", "PulsePlan",
    "SegmentPlan", "SharedWorld", "SlotEngine", "SlotRecord", "SwitchBits", "SwitchLevels",
    "Zone", "pokeys_world",
]
