"""The PoKeys personality: pulse engine v1 (PoKeys56E) and v2 (PoKeys57E/57CNC)."""

from .constants import PEV1, PEV2, AxisConfigBits, AxisState, EngineState, SwitchBits
from .device import MODELS, Identity, NetworkConfig, PoKeysDevice
from .engine import PulseEngine, SlotRecord
from .pev1 import PulseEngineV1
from .pev2 import PulseEngineV2
from .world import BenchWorld, PulseEngineWorld, SwitchLevels, Zone

__all__ = [
    "MODELS", "PEV1", "PEV2", "AxisConfigBits", "AxisState", "BenchWorld", "EngineState",
    "Identity", "NetworkConfig", "PoKeysDevice", "PulseEngine", "PulseEngineV1",
    "PulseEngineV2", "PulseEngineWorld", "SlotRecord", "SwitchBits", "SwitchLevels", "Zone",
]
