"""The Trio MC405 personality: PWM outputs with their gating FIFO, TABLE and VR memory.

Pure firmware logic with no wire format: the TrioBASIC language (maxk.commands.trio)
calls it, and the engine drives it each servo cycle.
"""

from .memory import TABLE_SIZE, VR_COUNT, TableMemory, VrMemory
from .pwm import (
    GATE_FIFO_DEPTH,
    PWM_AXES,
    PWM_CLOCK_HZ,
    PWM_ENCODER_MODULUS,
    PWM_REGISTER_MAX,
    GateEntry,
    PwmBank,
    PwmError,
    PwmMode,
    PwmOutput,
)

__all__ = [
    "GATE_FIFO_DEPTH",
    "PWM_AXES",
    "PWM_CLOCK_HZ",
    "PWM_ENCODER_MODULUS",
    "PWM_REGISTER_MAX",
    "TABLE_SIZE",
    "VR_COUNT",
    "GateEntry",
    "PwmBank",
    "PwmError",
    "PwmMode",
    "PwmOutput",
    "TableMemory",
    "VrMemory",
]
