"""CSV traces of a run: positions, velocities and flags per event or every N ticks.

A row is written when the trace starts, at every board event (a motion ending, a
queued wait expiring) or every N ticks, and after every script step, so a trace shows
both what the host did and what the machine did in between. Rows are deterministic.
"""

from __future__ import annotations

import csv
from typing import TextIO

from maxk.personalities.maxk.board import Board
from maxk.personalities.maxk.flags import AXIS_DONE


class TraceWriter:
    """Writes one CSV row per sample; attach with `attach(board)`."""

    def __init__(self, stream: TextIO, board: Board, every_ticks: int | None = None) -> None:
        self.board = board
        self.every_ticks = every_ticks
        self._writer = csv.writer(stream, lineterminator="\n")
        header = ["tick", "time_s"]
        for axis in board.axes:
            x = axis.letter
            header += [f"{x}_position", f"{x}_encoder", f"{x}_velocity", f"{x}_status",
                       f"{x}_done", f"{x}_queued"]
        header += ["doorbell", "command_error", "note"]
        self._writer.writerow(header)
        self._last_tick: int | None = None
        self.rows = 0

    def attach(self) -> None:
        self.board.add_observer(self._on_event, self.every_ticks)
        self.sample("start")

    def detach(self) -> None:
        self.board.remove_observer(self._on_event)

    def _on_event(self, board: Board) -> None:
        self.sample("event" if self.every_ticks is None else "sample")

    def sample(self, note: str = "") -> None:
        b = self.board
        row: list[object] = [b.tick, f"{b.time:.9f}"]
        for axis in b.axes:
            row += [axis.motor_position(b), axis.encoder_position(b), round(axis.velocity(b)),
                    axis.status_string(b), int(bool(axis.flags & AXIS_DONE)), len(axis.queue)]
        row += [f"0x{b.doorbell:08x}", int(b.command_error), note]
        self._writer.writerow(row)
        self.rows += 1
