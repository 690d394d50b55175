"""SYNC from its TrioBASIC help pages (SYNC, SYNC_CONTROL, SYNC_TIMER, SYNC_PAUSE,
SYNC_DWELL): a base array synchronised with a point on a moving conveyor axis.

The conveyor, axis 10, runs FORWARD at 100 units/s (UNITS 1, ACCEL 1e6) from tick 0: at
tick t >= 1 it is at 0.1 t - 0.005. Once synchronised the first base axis is at pos1
plus the conveyor's travel since sync pos, the second at pos2 (the page). Over the sync
time each axis takes the share s(z) = z - sin(2 pi z) / 2 pi of the way (our decision,
on the entry); SYNC(4) lets the conveyor's pull fade as 1 - s, cycle by cycle. The
expected numbers below are that arithmetic, done here.
"""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio.controller import MC405


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def dpos(trio: MC405, axis: int) -> float:
    return trio.machine.axis_parameter("DPOS", axis)


def conveyor(tick: int) -> float:
    return 0.1 * tick - 0.005


def s(z: float) -> float:
    z = min(max(z, 0.0), 1.0)
    return z - math.sin(2 * math.pi * z) / (2 * math.pi)


def running() -> MC405:
    trio = MC405()
    assert trio.send("BASE(10): SPEED=100: ACCEL=1e6: DECEL=1e6: FORWARD: BASE(0, 1)") == []
    at(trio, 100)
    return trio


def test_sync_blends_onto_the_conveyor_point_then_follows_it_and_stops() -> None:
    trio = running()
    assert trio.send("SYNC(1, 1000, 50, 10, 200, 30)") == []
    assert trio.query("?SYNC_CONTROL AXIS(0)") == "2"
    for tick in (350, 600, 1099):
        at(trio, tick)
        z = (tick - 100) / 1000
        assert dpos(trio, 0) == pytest.approx(s(z) * (200 + conveyor(tick) - 50), abs=1e-9)
        assert dpos(trio, 1) == pytest.approx(s(z) * 30, abs=1e-9)
    assert trio.query("?SYNC_TIMER AXIS(0)") == "999"
    at(trio, 1100)
    assert trio.query("?SYNC_CONTROL AXIS(1)") == "3"
    assert trio.query("?SYNC_TIMER AXIS(0)") == "1000"
    assert trio.send("MOVE(10) AXIS(1): CANCEL AXIS(0)") == []  # moves add; CANCEL: not it
    at(trio, 2000)
    assert dpos(trio, 0) == pytest.approx(200 + conveyor(2000) - 50, abs=1e-9)
    assert dpos(trio, 1) == pytest.approx(40, abs=1e-9)
    assert trio.send("SYNC(4, 500)") == []
    assert trio.query("?SYNC_CONTROL AXIS(0)") == "4"
    stopped = 200 + conveyor(2000) - 50
    for j in range(1, 501):  # cycle j: the conveyor's 0.1, times 1 - s(j / 500)
        stopped += 0.1 * (1 - s(j / 500))
        if j in (1, 250, 499, 500):
            at(trio, 2000 + j)
            assert dpos(trio, 0) == pytest.approx(stopped, abs=1e-9), j
    assert stopped == pytest.approx(349.995 + 24.95, abs=1e-9)  # 0.1 x (500 - 250.5)
    at(trio, 3000)
    assert dpos(trio, 0) == pytest.approx(stopped, abs=1e-9)
    assert dpos(trio, 1) == pytest.approx(40, abs=1e-9)
    assert trio.query("?SYNC_CONTROL AXIS(0)") == "0"


def test_pause_and_dwell_put_an_axis_motion_inside_the_sync_time() -> None:
    """SYNC_PAUSE 200 and SYNC_DWELL 300 on axis 1: it moves from 300 to 700 ms in."""
    trio = running()
    trio.send("SYNC_PAUSE AXIS(1) = 200: SYNC_DWELL AXIS(1) = 300")
    trio.send("SYNC(1, 1000, 50, 10, 200, 30)")
    for tick in (250, 300, 500, 650, 800, 1200):
        at(trio, tick)
        assert dpos(trio, 1) == pytest.approx(30 * s((tick - 300) / 500), abs=1e-9), tick
        z = (tick - 100) / 1000
        assert dpos(trio, 0) == pytest.approx(s(z) * (200 + conveyor(tick) - 50), abs=1e-9)


def test_resync_moves_from_one_point_to_another_over_its_time() -> None:
    """SYNC(10): the blend from following the first point to following the second."""
    trio = running()
    trio.send("SYNC(1, 100, 50, 10, 200, 30)")
    at(trio, 300)
    assert trio.send("SYNC(10, 400, 0, 10, 40, -250)") == []
    assert trio.query("?SYNC_CONTROL AXIS(0)") == "11"
    for tick in (400, 500, 700):
        at(trio, tick)
        z = (tick - 300) / 400
        old = 200 + conveyor(tick) - 50
        new = 40 + conveyor(tick)
        assert dpos(trio, 0) == pytest.approx(old + s(z) * (new - old), abs=1e-9)
        assert dpos(trio, 1) == pytest.approx(30 + s(z) * (-250 - 30), abs=1e-9)
    assert trio.query("?SYNC_CONTROL AXIS(0)") == "3"


def test_what_sync_refuses() -> None:
    trio = running()
    assert trio.send("SYNC(1, 1000, 50, 0, 200)") == ["! Parameter out of range"]
    assert trio.send("SYNC(2, 1000, 50, 10, 200)") == ["! Parameter out of range"]
    assert trio.send("SYNC(1, 0, 50, 10, 200)") == ["! Parameter out of range"]
    assert trio.send("SYNC_CONTROL AXIS(0) = 3") == ["! Parameter is read only"]
    assert trio.query("?SYNC_CONTROL AXIS(0)") == "0"
    assert dpos(trio, 0) == 0.0


def test_a_program_waits_for_the_sync_as_the_pages_example() -> None:
    trio = running()
    program = "BASE(0, 1)\nSYNC(1, 500, 20, 10, 100, 5)\n" \
              "WAIT UNTIL SYNC_CONTROL AXIS(0) = 3\nVR(7) = SYNC_TIMER AXIS(0)\n"
    assert trio.load("PICK", program) == []
    assert trio.send('RUN "PICK"') == []
    start = trio.tick
    at(trio, start + 490)
    assert trio.query("?VR(7)") == "0.0000"  # still waiting (a VR is a FLOAT)
    at(trio, start + 510)
    assert trio.query("?VR(7)") == "500.0000"
    assert dpos(trio, 0) == pytest.approx(100 + conveyor(trio.tick) - 20, abs=1e-9)


def test_after_a_sync_moveabs_goes_to_the_absolute_place_and_a_new_sync_cuts_a_stop() -> None:
    trio = running()
    trio.send("SYNC(1, 100, 50, 10, 200, 30)")
    at(trio, 300)
    trio.send("SYNC(4, 200)")
    at(trio, 350)  # stopping: cycle j adds 0.1 x (1 - s(j / 200))
    stopped = 200 + conveyor(300) - 50 + sum(0.1 * (1 - s(j / 200)) for j in range(1, 51))
    assert dpos(trio, 0) == pytest.approx(stopped, abs=1e-9)
    assert trio.send("SYNC(1, 100, 60, 10, 0, 0)") == []  # the stop ends where it is (D)
    at(trio, 450)
    assert dpos(trio, 0) == pytest.approx(0 + conveyor(450) - 60, abs=1e-9)
    assert dpos(trio, 1) == pytest.approx(0, abs=1e-9)
    trio.send("SYNC(4, 100)")
    at(trio, 600)
    assert trio.query("?SYNC_CONTROL AXIS(0)") == "0"
    assert trio.send("MOVEABS(5, 7) AXIS(0)") == []
    at(trio, 5000)
    # to the whole count nearest the place (UNITS 1: a move is whole counts; the SYNC
    # left the axis between counts)
    assert (dpos(trio, 0), dpos(trio, 1)) == (pytest.approx(5, abs=0.5),
                                              pytest.approx(7, abs=1e-9))


def test_a_movelink_on_a_stopping_sync_axis_finds_its_end() -> None:
    """Axis 3 MOVELINKs over 10 of axis 0's travel while axis 0's SYNC stops (its end is
    searched ahead through the stop): axis 0 stops 24.95 on, so it ends on the cycle j
    where 0.1 x sum(1 - s(i / 500), i <= j) first reaches 10."""
    trio = running()
    trio.send("SYNC(1, 100, 50, 10, 200, 30)")
    at(trio, 300)
    trio.send("SYNC(4, 500)")
    assert trio.send("MOVELINK(7, 10, 0, 0, 0) AXIS(3)") == []
    moved, j = 0.0, 0
    while moved < 10 - 1e-9:
        j += 1
        moved += 0.1 * (1 - s(j / 500))
    at(trio, 300 + j - 1)
    assert trio.query("?MTYPE AXIS(3)") == "22"
    at(trio, 300 + j)
    assert trio.query("?MTYPE AXIS(3)") == "0"
    assert dpos(trio, 3) == pytest.approx(7, abs=1e-9)
