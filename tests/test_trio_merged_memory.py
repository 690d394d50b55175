"""An endless merged program (MERGE ON, moves loaded forever) keeps a bounded run: the
moves it has completed are let go (runs.py, `drop_complete`), and every reading is the
same as when they were kept: positions by hand, and each reading at every tick against
the same program with dropping turned off."""

from __future__ import annotations

import pytest

import maxk.personalities.trio.runs as runs
from maxk.controllers.trio import MC405

SETUP = ("UNITS AXIS(0) = 1\nUNITS AXIS(1) = 1\nSPEED = 1000\nACCEL = 1000000\n"
         "DECEL = 1000000\nMERGE = ON\n")
BACK_AND_FORTH = "BASE(0, 1)\n" + SETUP + "WHILE TRUE\nMOVE(1, 0)\nMOVE(-1, 0)\nWEND"
BOUND = 100  # moves a run may hold: 64 complete ones gathered, the buffer's, the running one
READINGS = ("?DPOS AXIS(0), MPOS AXIS(0), REMAIN AXIS(0), VECTOR_BUFFERED AXIS(0), "
            "MOVES_BUFFERED AXIS(0), MTYPE AXIS(0), NTYPE AXIS(0), MOVE_COUNT AXIS(0), "
            "VP_SPEED AXIS(0), MOVE_PA AXIS(0), DPOS AXIS(1), CORNER_STATE AXIS(0), "
            "MOVE_FORCE_SPEED AXIS(0), REMAIN_TIME AXIS(0)")


def _start(program: str) -> MC405:
    trio = MC405()
    assert trio.load("LOOP", program) == []
    assert trio.send('RUN "LOOP", 3') == []
    return trio


def _run_of(trio: MC405) -> runs.Run:
    queue = trio.machine.queues[0]
    assert len(queue) == 1
    return queue[0]


def test_endless_back_and_forth_keeps_a_bounded_run() -> None:
    """The reviewer's loop: 2000 moves done, the run never holds more than BOUND moves
    (it held all 2000 before)."""
    trio = _start(BACK_AND_FORTH)
    biggest = 0
    for _ in range(20):
        trio.advance(ticks=100)
        biggest = max(biggest, len(_run_of(trio).segments))
    run = _run_of(trio)
    assert int(trio.query("?MOVE_COUNT AXIS(0)")) >= 1990  # about one move a servo tick here
    assert run.dropped >= 1800
    assert biggest <= BOUND
    assert len(run.segments) == len(run.deltas)


def test_straight_endless_run_is_where_the_arithmetic_says() -> None:
    """MOVE(100) forever at 1000 counts/s, ramp 1 ms (ACCEL 10^6): 0.5 count in the
    ramp's tick, then one count a tick, for 300 moves: DPOS at n ticks after the start
    is n - 0.5, its speed 1000, and no more than the bound of moves is held."""
    trio = _start("BASE(0)\n" + SETUP + "WHILE TRUE\nMOVE(100)\nWEND")
    first = None
    for _ in range(10):  # the run starts within the program's first few servo cycles
        trio.advance(ticks=1)
        if trio.query("?DPOS AXIS(0)") != "0":
            first = trio.machine.tick
            break
    assert first is not None
    assert trio.query("?DPOS AXIS(0)") == "0.5000"
    for n in (2, 101, 1000, 12345, 30000):
        trio.advance(ticks=first + n - 1 - trio.machine.tick)
        assert trio.send("?DPOS AXIS(0), VP_SPEED AXIS(0)") == [f"{n - 0.5:.4f}\t1000"]
    run = _run_of(trio)
    assert run.dropped > 200 and len(run.segments) <= BOUND


def _readings(program: str, ticks: int, respeed_at: int, cancel_at: int
              ) -> tuple[list[str], int]:
    """Every reading at every tick, and the moves the run had dropped before CANCEL."""
    trio = _start(program)
    seen = []
    dropped = 0
    for n in range(ticks):
        trio.advance(ticks=1)
        if n == respeed_at:  # a SPEED change re-plans the run from where it is
            assert trio.send("SPEED AXIS(0) = 700") == []
        if n == cancel_at:
            dropped = _run_of(trio).dropped
            assert trio.send("CANCEL AXIS(0)") == []
        seen += trio.send(READINGS)
    return seen, dropped


@pytest.mark.parametrize("program", [
    BACK_AND_FORTH,
    "BASE(0, 1)\n" + SETUP + "WHILE TRUE\nMOVE(3, 4)\nMOVE(-3, 0)\nMOVE(0, -4)\nWEND",
    # S-ramps: a re-plan carries the ramp running
    "BASE(0, 1)\n" + SETUP + "SRAMP = 4\nWHILE TRUE\nMOVE(5, 0)\nMOVE(0, 5)\n"
    "MOVE(-5, -5)\nWEND",
    # arcs (their lengths in VECTOR_BUFFERED), a zero-length move, MOVE_PA carried
    "BASE(0, 1)\n" + SETUP + "n = 0\nWHILE TRUE\nMOVE_PA = n\nn = n + 1\n"
    "MOVECIRC(4, 0, 2, 0, 1)\nMOVE(0, 0)\nMOVECIRC(-4, 0, -2, 0, 1)\nWEND",
    # SP moves at FORCE_SPEED, each move's own (MOVE_FORCE_SPEED reads the one running)
    "BASE(0, 1)\n" + SETUP + "n = 0\nWHILE TRUE\nFORCE_SPEED = 600 + (n MOD 7)\n"
    "n = n + 1\nMOVESP(2, 1)\nMOVESP(-2, -1)\nWEND",
])
def test_readings_at_every_tick_are_those_of_a_run_that_keeps_every_move(
        program: str, monkeypatch: pytest.MonkeyPatch) -> None:
    dropping, dropped = _readings(program, 1500, respeed_at=900, cancel_at=1400)
    monkeypatch.setattr(runs, "DROP_AFTER", 10 ** 9)
    keeping, kept = _readings(program, 1500, respeed_at=900, cancel_at=1400)
    assert dropped >= 64 and kept == 0  # the first did drop moves, the second none
    assert len(dropping) == 1500
    assert dropping == keeping
