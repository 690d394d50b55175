"""General purpose digital I/O (up to 16 bits), analog inputs and the position-capture ring.

Manual 4.4/4.5 and Table 6-2: 16 digital lines on boards of six axes or more (8 on the
smaller ones, 6 on the MAXk-2000), each an input or an output (factory: half inputs,
half outputs; we take the lower half as inputs), 4 analog inputs (2 on five axes or
fewer; 16-bit ADC, +/-10 V), and a DAC per axis usable as a general purpose analog output when
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


def factory_direction(lines: int) -> int:
    """The factory split of a model's lines: the lower half inputs, the upper half
    outputs (16 lines: 0xff00 as the manual's 8 and 8; 8 lines: 0x00f0; 6: 0x0038). D:
    the manual gives the counts, not which lines."""
    half = lines // 2
    return ((1 << lines) - 1) & ~((1 << half) - 1)


@dataclass
class GeneralIO:
    direction: int = FACTORY_DIRECTION
    outputs: int = 0  # output latch (bits configured as inputs keep their latch too)
    # (tick, latch) after every change: a pulse shorter than a host's poll still shows here
    changes: deque[tuple[int, int]] = field(default_factory=lambda: deque(maxlen=4096))
    lines: int = 16  # the model's lines (Table 6-2); the bits above read 0, stay 0

    @classmethod
    def for_lines(cls, lines: int) -> GeneralIO:
        return cls(direction=factory_direction(lines), lines=lines)

    @property
    def mask(self) -> int:
        return (1 << self.lines) - 1

    def level(self, bit: int, board: _InWorld) -> bool:
        if self.direction >> bit & 1:
            return bool(self.outputs >> bit & 1)
        return board.world.digital_level(bit, board)

    def word(self, board: _InWorld) -> int:
        """The 16 line levels as BX and the shared-memory I/O word report them."""
        return sum(1 << bit for bit in range(self.lines) if self.level(bit, board))

    def set_output(self, bit: int, high: bool, tick: int) -> None:
        mask = 1 << bit
        self.latch((self.outputs | mask) if high else (self.outputs & ~mask), tick)

    def latch(self, word: int, tick: int) -> None:
        """Set the output latch, remembering the change (lines the model lacks stay 0)."""
        word &= self.mask
        if word != self.outputs:
            self.outputs = word
            self.changes.append((tick, word))


def volts_to_counts(volts: float) -> int:
    """A +/-10 V reading as the 16-bit ADC's two's-complement count: -10 V is -32768,
    +10 V clips to 32767, 1 count is 10/32768 V."""
    return max(-32768, min(ADC_FULL_SCALE, round(volts / 10.0 * 32768)))
