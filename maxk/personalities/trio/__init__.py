"""The Trio MC405 personality: the machine on the shared engine (`machine.MC405Machine`:
axes, buffered and merged moves, CONNPATH, CAMBOX), PWM outputs with their gating FIFO
tied to the motion, traces, TABLE and VR memory.

Pure firmware logic with no wire format: the TrioBASIC language (maxk.commands.trio)
calls it through its `TrioMachine` protocol. (The machine is imported from its module,
so the language's keyword table does not pull in the engine.)
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
