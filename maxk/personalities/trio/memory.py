"""TABLE and VR memory of the Motion Coordinator.

TABLE is the large shared array that CAMBOX profiles and PWM_CONTROL(3, ...) gate
positions are read from; VR is the smaller array of global variables every process
shares. Both hold floating-point values that start at zero.

Sizes (decision D, recorded in the keyword table): the seed does not give them. TABLE
holds 512,000 values (the MC4xx family's documented TSIZE order of magnitude: the
Omron/Trio MC64 manual gives 500,000 usable), VR 65,536 (I: public programs for MC4 and
MC6 controllers clear VR(0) to VR(65535) and keep data at VR(17000)).
"""

from __future__ import annotations

from collections.abc import Sequence

TABLE_SIZE = 512_000
VR_COUNT = 65536


class MemoryRangeError(ValueError):
    """An index outside the array: the whole access is refused, nothing written."""


class TableMemory:
    """TABLE(i) reads, TABLE(start, v1, v2, ...) writes a run of values."""

    def __init__(self, size: int = TABLE_SIZE) -> None:
        self.size = size
        self._values: dict[int, float] = {}  # sparse: most of the table stays zero

    def _check(self, start: int, count: int) -> None:
        if start < 0 or start + count > self.size:
            raise MemoryRangeError("TABLE index out of range")

    def read(self, index: int) -> float:
        self._check(index, 1)
        return self._values.get(index, 0.0)

    def read_run(self, start: int, end: int) -> list[float]:
        """Values start..end inclusive (start <= end)."""
        self._check(start, end - start + 1)
        return [self._values.get(i, 0.0) for i in range(start, end + 1)]

    def write(self, start: int, values: Sequence[float]) -> None:
        self._check(start, len(values))
        for offset, value in enumerate(values):
            self._values[start + offset] = float(value)


class VrMemory:
    """VR(i): global variables shared by every process and the command line."""

    def __init__(self, count: int = VR_COUNT) -> None:
        self.count = count
        self._values = [0.0] * count

    def _check(self, index: int) -> None:
        if not 0 <= index < self.count:
            raise MemoryRangeError("VR index out of range")

    def read(self, index: int) -> float:
        self._check(index)
        return self._values[index]

    def write(self, index: int, value: float) -> None:
        self._check(index)
        self._values[index] = float(value)

    def values(self) -> list[float]:
        """A copy of every VR (the flash archive keeps them across runs)."""
        return list(self._values)
