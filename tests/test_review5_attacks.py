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


# ---- CANCEL and RAPIDSTOP at FASTDEC (CANCEL, RAPIDSTOP and FASTDEC pages) ----------------
ONE = "BASE(0): UNITS=1000: SPEED=10: ACCEL=100: DECEL=50"
TWO = "BASE(0,1): UNITS AXIS(0)=1000: UNITS AXIS(1)=1000: SPEED=10: ACCEL=100: DECEL=50"


def _stop_at_500(program: str, stop: str) -> MC405:
    trio = MC405()
    assert trio.send(program) == []
    trio.advance(ticks=500)
    assert trio.send(stop) == []
    return trio


@pytest.mark.parametrize("stop", ["CANCEL", "RAPIDSTOP"])
@pytest.mark.parametrize(("fastdec", "end", "tick"), [
    # 0.5 s in: ramped up over 0.1 s (0.5 units), cruised 0.4 s: at 4.5, speed 10.
    (200, 4.75, 550),  # FASTDEC 200: 10/200 = 0.05 s, 10 x 0.05 / 2 = 0.25 units
    (0, 5.5, 700),     # none: DECEL 50, 0.2 s, 1.0 unit
    (40, 5.5, 700),    # below DECEL: DECEL (FASTDEC page)
])
def test_a_cancelled_move_ramps_down_at_fastdec(stop: str, fastdec: float, end: float,
                                               tick: int) -> None:
    trio = _stop_at_500(f"{ONE}: FASTDEC={fastdec}: MOVE(100)", stop)
    trio.advance(ticks=tick - 1 - trio.tick)
    assert trio.machine.dpos(0) < end
    trio.advance(ticks=1)
    assert trio.machine.dpos(0) == pytest.approx(end, abs=1e-9)
    trio.advance(ticks=50)
    assert trio.machine.dpos(0) == pytest.approx(end, abs=1e-9)


@pytest.mark.parametrize("stop", ["CANCEL", "RAPIDSTOP"])
def test_a_cancelled_s_curve_move_ramps_down_at_fastdec(stop: str) -> None:
    """SRAMP 20 ms: up over 10/100 + 0.02 s covering 0.6, so at 0.5 s it is at
    0.6 + 10 x 0.38 = 4.4; down at FASTDEC 200 over 10/200 + 0.02 = 0.07 s covering
    10 x 0.07 / 2 = 0.35: at rest on 4.75 at tick 570 (at DECEL 50 it would be
    0.22 s and 1.1 units)."""
    trio = _stop_at_500(f"{ONE}: SRAMP=20: FASTDEC=200: MOVE(100)", stop)
    trio.advance(ticks=69)
    assert trio.machine.dpos(0) < 4.75
    trio.advance(ticks=1)
    assert trio.machine.dpos(0) == pytest.approx(4.75, abs=1e-9)


@pytest.mark.parametrize("stop", ["CANCEL", "RAPIDSTOP"])
@pytest.mark.parametrize(("extra", "s_end", "tick"), [
    ("", 4.75, 550),          # linear: at 4.5, 0.05 s and 0.25 at FASTDEC 200
    (": SRAMP=20", 4.75, 570),  # S-curve: at 4.4, 0.07 s and 0.35 (as above)
])
def test_a_cancelled_path_ramps_down_at_fastdec(stop: str, extra: str, s_end: float,
                                               tick: int) -> None:
    """MOVE(300,400): the vector as the single axis above; X carries 3/5, Y 4/5."""
    trio = _stop_at_500(f"{TWO}{extra}: FASTDEC=200: MOVE(300,400)", stop)
    trio.advance(ticks=tick - 1 - trio.tick)
    assert trio.machine.dpos(1) < 0.8 * s_end
    trio.advance(ticks=1)
    assert trio.machine.dpos(0) == pytest.approx(0.6 * s_end, abs=1e-9)
    assert trio.machine.dpos(1) == pytest.approx(0.8 * s_end, abs=1e-9)


def test_a_released_jog_still_ramps_at_decel() -> None:
    """FASTDEC is CANCEL's, RAPIDSTOP's and a limit's: a jog input going high stops the
    jog at DECEL (FWD_JOG entry). JOGSPEED 10 reached after 0.1 s: released at 0.5 s it
    is at 4.5 and stops 10^2 / (2 x 50) = 1.0 further."""
    trio = MC405()
    trio.world_view().set_input(7, True)
    assert trio.send(f"{ONE}: JOGSPEED=10: FASTDEC=200: FWD_JOG=7") == []
    trio.world_view().set_input(7, False)
    trio.advance(ticks=500)
    assert trio.machine.dpos(0) == pytest.approx(4.5, abs=1e-9)
    trio.world_view().set_input(7, True)
    trio.advance(ticks=300)
    assert trio.machine.dpos(0) == pytest.approx(5.5, abs=1e-9)
