"""General purpose digital I/O (16 bits), analog inputs and the position-capture ring.

Manual 4.4/4.5 and Table 6-2: 16 digital lines, each an input or an output (factory: 8
inputs and 8 outputs; we take bits 0-7 as inputs and 8-15 as outputs), 4 analog inputs
(16-bit ADC, +/-10 V), and a DAC per axis usable as a general purpose analog output when
the axis is not a servo. Inputs come from the world; outputs are latched here.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from maxk.firmware_model.world import World


class _InWorld(Protocol):
    """A controller with a world around it (whose inputs may be functions of it)."""

    @property
    def world(self) -> World: ...


FACTORY_DIRECTION = 0xFF00  # 1 = output
ADC_FULL_SCALE = 32767


@dataclass
class GeneralIO:
    direction: int = FACTORY_DIRECTION
    outputs: int = 0  # output latch (bits configured as inputs keep their latch too)
    # (tick, latch) after every change: a pulse shorter than a host's poll still shows here
    changes: deque[tuple[int, int]] = field(default_factory=lambda: deque(maxlen=4096))

    def level(self, bit: int, board: _InWorld) -> bool:
        if self.direction >> bit & 1:
            return bool(self.outputs >> bit & 1)
        return board.world.digital_level(bit, board)

    def word(self, board: _InWorld) -> int:
        """The 16 line levels as BX and the shared-memory I/O word report them."""
        return sum(1 << bit for bit in range(16) if self.level(bit, board))

    def set_output(self, bit: int, high: bool, tick: int) -> None:
        mask = 1 << bit
        self.latch((self.outputs | mask) if high else (self.outputs & ~mask), tick)

    def latch(self, word: int, tick: int) -> None:
        """Set the output latch, remembering the change."""
        if word != self.outputs:
            self.outputs = word
            self.changes.append((tick, word))


def volts_to_counts(volts: float) -> int:
    """A +/-10 V reading as the 16-bit ADC's two's-complement count: -10 V is -32768,
    +10 V clips to 32767, 1 count is 10/32768 V."""
    return max(-32768, min(ADC_FULL_SCALE, round(volts / 10.0 * 32768)))
