"""A PoKeys slot trace: one CSV row per 1 ms slot, and a plot of it (position and pulse
rate per axis over time, the buffer's fill level).

`maxk/trace.py` and `maxk/pathplot.py` are written around a MAXk board (its axis letters,
status strings, doorbell and output bits), so the pulse engine's trace lives here: it
hangs on the pulse engine's per-slot `trace` hook (which makes the engine emit slot by
slot while it is attached) and reads positions and the buffer after each slot.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import TextIO

from maxk.personalities.pokeys import AXIS_LETTERS, EngineState, SlotRecord
from maxk.personalities.pokeys.constants import SLOT_SECONDS
from maxk.personalities.pokeys.engine import PulseEngine

PLOT_MISSING = ("the plot needs matplotlib: pip install 'maxk[plot]' "
                "(or pip install matplotlib)")


class SlotRecorder:
    """Writes each slot to CSV (if given a stream) and keeps it for a plot."""

    def __init__(self, engine: PulseEngine, stream: TextIO | None = None,
                 axes: int | None = None) -> None:
        self.engine = engine
        self.axes = axes if axes is not None else len(engine.axes)
        self.stream = stream
        self._writer = None if stream is None else csv.writer(stream, lineterminator="\n")
        self.time: list[float] = []
        self.positions: list[list[int]] = [[] for _ in range(self.axes)]
        self.pulses: list[list[int]] = [[] for _ in range(self.axes)]
        self.fill: list[int] = []
        self.slots = 0
        if self._writer is not None:
            header = ["slot", "time_s", "engine_state", "buffer_fill"]
            for x in AXIS_LETTERS[:self.axes]:
                header += [f"{x}_pulses", f"{x}_dir", f"{x}_position", f"{x}_state"]
            self._writer.writerow(header)

    def attach(self) -> None:
        self._before = self.engine.trace
        self.engine.trace = self

    def detach(self) -> None:
        if self.engine.trace is self:
            self.engine.trace = self._before
        if self.stream is not None:
            self.stream.close()
            self.stream = None
            self._writer = None

    def __call__(self, record: SlotRecord) -> None:
        e = self.engine
        fill = e.buffer.count
        self.slots += 1
        self.time.append((record.slot + 1) * SLOT_SECONDS)
        self.fill.append(fill)
        for i in range(self.axes):
            self.positions[i].append(e.axes[i].position)
            self.pulses[i].append(record.pulses[i])
        if self._writer is not None:
            row: list[object] = [record.slot, f"{record.slot * SLOT_SECONDS:.3f}",
                                 EngineState(record.engine_state).name, fill]
            for i in range(self.axes):
                row += [record.pulses[i], int(record.directions[i]), e.axes[i].position,
                        record.axis_states[i]]
            self._writer.writerow(row)

    def plot(self, path: str | Path, title: str = "") -> Path:
        """Three panels over time: positions, pulse rates (pulses/s), buffer fill.
        ImportError with advice when matplotlib is not installed."""
        try:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError as exc:
            raise ImportError(PLOT_MISSING) from exc
        path = Path(path)
        moving = [i for i in range(self.axes) if any(self.pulses[i])] or [0]
        fig, (pos, rate, fill) = plt.subplots(3, 1, sharex=True, figsize=(9, 8))
        for i in moving:
            x = AXIS_LETTERS[i]
            pos.step(self.time, self.positions[i], where="post", label=x)
            rate.step(self.time, [p / SLOT_SECONDS for p in self.pulses[i]], where="post",
                      label=x)
        fill.step(self.time, self.fill, where="post", color="tab:gray")
        pos.set_ylabel("position, pulses")
        rate.set_ylabel("pulse rate, pulses/s")
        fill.set_ylabel("buffer fill, slots")
        fill.set_ylim(0, self.engine.buffer.depth + 4)
        fill.set_xlabel("time, s")
        for ax in (pos, rate, fill):
            ax.grid(True, alpha=0.3)
        pos.legend(loc="best")
        pos.set_title(title or "PoKeys slot trace")
        fig.tight_layout()
        fig.savefig(path, dpi=100)
        plt.close(fig)
        return path
