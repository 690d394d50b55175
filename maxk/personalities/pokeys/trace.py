"""A slot trace as CSV: one row per 1 ms slot (set as the engine's ``trace`` hook)."""

from __future__ import annotations

import csv
from typing import TextIO

from .engine import SlotRecord


class CsvSlotTrace:
    """Columns: slot, engine_state, then per axis pulses, direction pin and axis state."""

    def __init__(self, out: TextIO, axes: int) -> None:
        self._writer = csv.writer(out, lineterminator="\n")
        self._axes = axes
        header = ["slot", "engine_state"]
        for i in range(axes):
            header += [f"pulses{i}", f"dir{i}", f"state{i}"]
        self._writer.writerow(header)

    def __call__(self, record: SlotRecord) -> None:
        row: list[int] = [record.slot, record.engine_state]
        for i in range(self._axes):
            row += [record.pulses[i], int(record.directions[i]), record.axis_states[i]]
        self._writer.writerow(row)
