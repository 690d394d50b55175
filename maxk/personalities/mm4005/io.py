"""The MM4005's GPIO connector and analog inputs, on the shared world.

The world is the single source of every I/O level: the inputs a door sets
(`@world input 3 high`) are read from `World.digital`, the analog inputs from
`World.analog` (volts), and the outputs the controller drives are written to
`World.outputs`, where `:world`, the trace, the control door and the panel read them.
Nothing here keeps a copy of a level.

Numbering (manual 3.103 RB: the I/O bits are 1 to 8, C): bit 1 is the least significant
bit of the port byte. Analog inputs 1 to 4 (manual 3.137 TQ: 'analog values of inputs 1,
2, 3 and 4', C).
"""

from __future__ import annotations

from typing import Final

from maxk.firmware_model.world import World

IO_BITS: Final = range(1, 9)  # manual 3.103: the GPIO connector's 8 bits
ANALOG_INPUTS: Final = range(1, 5)  # manual 3.137 TQ: analog inputs 1 to 4
PORT_MAX: Final = (1 << len(IO_BITS)) - 1  # 255: every output bit high


class GpioPort:
    """The outputs and analog inputs as the language reads and drives them."""

    def __init__(self, world: World, owner: object) -> None:
        self.world = world
        self.owner = owner  # what a world input that is a function is called with

    def output_level(self, bit: int) -> bool:
        """An output bit's level (low until the controller drives it high)."""
        return self.world.outputs.get(bit, False)

    def output_port(self) -> int:
        """Every output bit as one byte, bit 1 least significant."""
        return sum(1 << (bit - 1) for bit in IO_BITS if self.output_level(bit))

    def set_output_port(self, byte: int) -> None:
        """Drive all 8 outputs at once from a byte 0..255 (bit 1 least significant)."""
        if not 0 <= byte <= PORT_MAX:
            raise ValueError(f"output port byte {byte} outside 0..{PORT_MAX}")
        for bit in IO_BITS:
            self.world.outputs[bit] = bool(byte >> (bit - 1) & 1)

    def clear(self) -> None:
        """Power-up: every output low (D)."""
        self.set_output_port(0)

    def analog_volts(self, channel: int) -> float:
        """An analog input's voltage in the world (clamped to +/-10 V, an open input 0 V)."""
        return self.world.analog_volts(channel, self.owner)
