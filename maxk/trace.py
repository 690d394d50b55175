"""CSV traces of a run: positions, velocities and flags per event or every N ticks.

A row is written when the trace starts, at every engine event (a motion ending, a
queued wait expiring) or every N ticks, and after every script step, so a trace shows
both what the host did and what the machine did in between. Rows are deterministic.
Written against the world contract, so every controller traces the same way; a
controller adds its own columns (the MAXk: status string, queue, doorbell).
"""

from __future__ import annotations

import csv
from typing import TextIO

from maxk.controllers.contract import Controller


class TraceWriter:
    """Writes one CSV row per sample; attach with `attach()`."""

    def __init__(self, stream: TextIO, controller: Controller,
                 every_ticks: int | None = None) -> None:
        self.engine = controller.engine
        self.view = controller.world_view()
        self.every_ticks = every_ticks
        self._writer = csv.writer(stream, lineterminator="\n")
        header = ["tick", "time_s"]
        for x in self.view.axis_names:
            header += [f"{x}_position", f"{x}_encoder", f"{x}_velocity",
                       *(f"{x}_{c}" for c in self.view.trace_axis_columns()), f"{x}_done"]
            header += [f"{x}_{c}" for c in self.view.trace_axis_columns(after_done=True)]
        header += [*self.view.trace_columns(), "note"]
        self._writer.writerow(header)
        self.rows = 0

    def attach(self) -> None:
        self.engine.add_observer(self._on_event, self.every_ticks)
        self.sample("start")

    def detach(self) -> None:
        self.engine.remove_observer(self._on_event)

    def _on_event(self, _engine: object) -> None:
        self.sample("event" if self.every_ticks is None else "sample")

    def sample(self, note: str = "") -> None:
        engine, view = self.engine, self.view
        row: list[object] = [engine.tick, f"{engine.time:.9f}"]
        for name in view.axis_names:
            r = view.reading(name)
            row += [r.position, "" if r.encoder is None else r.encoder, round(r.velocity),
                    *view.trace_axis_values(name), int(r.done),
                    *view.trace_axis_values(name, after_done=True)]
        row += [*view.trace_values(), note]
        self._writer.writerow(row)
        self.rows += 1
