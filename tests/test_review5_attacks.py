"""Review 5A: S-curve paths and their neighbours attacked as a user and a real program
would; each test reproduces a defect found (it failed before its fix) or pins a limit
the review checked. Expected values are hand arithmetic, written out in each test."""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio import MC405
from maxk.personalities.trio import runs

SET_UP = "BASE(0,1): UNITS AXIS(0)=1000: UNITS AXIS(1)=1000: SPEED=10: ACCEL=100: DECEL=100"


def _load_chain(trio: MC405, count: int) -> None:
    """`count` merged moves of 0.01 units round a slow curve, each loaded as soon as the
    move buffer takes it (as a program's loop of MOVEs does)."""
    for k in range(count):
        while not trio.machine.can_load([0, 1]):
            trio.advance(ticks=1)
        angle = k * 0.01
        assert trio.send(f"MOVE({0.01 * math.cos(angle):.5f},"
                         f"{0.01 * math.sin(angle):.5f})") == []


@pytest.mark.parametrize("mode", ["", ": SRAMP=50", ": VP_MODE=6: JERK=1000"])
def test_a_long_merged_chain_costs_a_bounded_work_per_move(
        mode: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """A contour of 400 merged tiny moves: each move loaded works out the seams of the
    moves it adds, not of the whole chain again (was: every load rebuilt every move's
    definition, n^2/2 = 80,000 seam look-ups here, and converted every segment to arrays
    again: a 10,000-move contour took half an hour to load). At most 2 look-ups a move
    (its own seam and the one before it, re-read as it merges) and one array row each."""
    calls = 0
    seam = runs.Run.seam

    def counted(self: runs.Run, j: int) -> float:
        nonlocal calls
        calls += 1
        return seam(self, j)

    monkeypatch.setattr(runs.Run, "seam", counted)
    trio = MC405()
    assert trio.send(SET_UP + ": MERGE=ON" + mode) == []
    _load_chain(trio, 400)
    run = trio.machine.queues[0][0]
    assert len(run.segments) == 400
    assert calls <= 2 * 400
    arrays = run.arrays
    assert arrays is not None and arrays.table.count == 400  # one table, grown in place
    assert len(arrays.seg_s0) == 400
    trio.advance(ticks=60_000)
    assert trio.machine.axis_idle(0)
    # (each move whole counts: the text's value x UNITS, rounded)
    x = sum(round(float(f"{0.01 * math.cos(k * 0.01):.5f}") * 1000) for k in range(400))
    y = sum(round(float(f"{0.01 * math.sin(k * 0.01):.5f}") * 1000) for k in range(400))
    assert (trio.machine.dpos(0), trio.machine.dpos(1)) == (x / 1000, y / 1000)
