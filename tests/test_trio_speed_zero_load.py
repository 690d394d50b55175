"""A move loaded while SPEED is 0 loads and waits, held at speed 0, and starts with its
ACCEL ramp at the servo tick SPEED is written above 0 (CONNPATH page, example 2: SPEED 0,
load the moves, then write SPEED so that they start together; MOVE_PA_IDLE page, example
2: a program waits at WAIT IDLE until SPEED is written again from the command line).

Expected positions are worked out here by hand: a trapezoid at ACCEL from the tick of
the write, 1 ms servo ticks.
"""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio.controller import MC405

DT = 0.001


def path(t: float, distance: float, speed: float, accel: float) -> float:
    """A rest-to-rest trapezoid `t` seconds after it started."""
    peak = min(speed, math.sqrt(accel * distance))
    ramp = peak / accel
    cruise = (distance - peak * ramp) / peak
    if t <= 0:
        return 0.0
    if t < ramp:
        return 0.5 * accel * t * t
    if t < ramp + cruise:
        return 0.5 * peak * ramp + peak * (t - ramp)
    if t < 2 * ramp + cruise:
        left = 2 * ramp + cruise - t
        return distance - 0.5 * accel * left * left
    return distance


def test_a_move_loaded_at_speed_zero_waits_then_ramps_from_the_write_tick() -> None:
    trio = MC405()
    assert trio.send("BASE(0): SPEED=0: ACCEL=100: DECEL=100") == []
    assert trio.send("MOVE(10)") == []
    trio.advance(ticks=250)
    assert trio.machine.dpos(0) == 0.0
    assert float(trio.query("?MTYPE")) == 1  # the MOVE is loaded (MTYPE 1), held
    assert float(trio.query("?MSPEED")) == 0
    written = trio.tick
    assert trio.send("SPEED=10") == []
    for k in (1, 2, 50, 100, 101, 500, 1000, 1099, 1100):
        trio.advance(ticks=written + k - trio.tick)
        assert trio.machine.dpos(0) == pytest.approx(path(k * DT, 10, 10, 100), abs=1e-9)
    trio.advance(ticks=5)
    assert float(trio.query("?MTYPE")) == 0


def test_connpath_example_two_pattern_the_path_and_its_link_start_together() -> None:
    """BASE(1, 2) at SPEED 0, MERGE on: MOVE(30, 40) (a 50 path) waits; MOVELINK(60,
    30, 0, 0, 1) AXIS(0) follows axis 1 (60 over its 30, so twice it); SPEED 10 starts
    both at the write tick: axis 1 at 0.6, axis 2 at 0.8 of the path, axis 0 at 1.2."""
    trio = MC405()
    assert trio.send("BASE(1, 2): SPEED=0: ACCEL=40: DECEL=40: MERGE=ON") == []
    assert trio.send("MOVE(30, 40)") == []
    assert trio.send("MOVELINK(60, 30, 0, 0, 1) AXIS(0)") == []
    trio.advance(ticks=100)
    assert [trio.machine.dpos(a) for a in (0, 1, 2)] == [0.0, 0.0, 0.0]
    assert float(trio.query("?MTYPE AXIS(1)")) == 1
    assert float(trio.query("?MTYPE AXIS(0)")) == 22  # the MOVELINK, loaded
    written = trio.tick
    assert trio.send("SPEED=10") == []
    for k in (1, 3, 250, 251, 2000, 5249, 5250, 5300):
        trio.advance(ticks=written + k - trio.tick)
        s = path(k * DT, 50, 10, 40)
        assert trio.machine.dpos(1) == pytest.approx(0.6 * s, abs=1e-9)
        assert trio.machine.dpos(2) == pytest.approx(0.8 * s, abs=1e-9)
        assert trio.machine.dpos(0) == pytest.approx(1.2 * s, abs=1e-9)


def test_wait_idle_does_not_pass_while_the_move_is_held() -> None:
    trio = MC405()
    trio.load("HELDMOVE", "BASE(0)\nACCEL = 50\nDECEL = 50\nSPEED = 0\nMOVE(5)\n"
              "WAIT IDLE\nVR(7) = 1\n")
    assert trio.send('RUN "HELDMOVE"') == []
    trio.advance(ticks=3000)
    assert float(trio.query("?VR(7)")) == 0
    assert trio.machine.dpos(0) == 0.0
    assert trio.send("SPEED=5") == []  # 5 at 50: 0.1 s ramps, 1.1 s in all
    trio.advance(ticks=1050)
    assert float(trio.query("?VR(7)")) == 0
    trio.advance(ticks=100)
    assert float(trio.query("?VR(7)")) == 1
    assert trio.machine.dpos(0) == 5.0


def test_cancel_of_a_held_move_ends_it_where_it_is() -> None:
    trio = MC405()
    assert trio.send("BASE(0): SPEED=0: ACCEL=100: DECEL=100") == []
    assert trio.send("MOVE(10): MOVE(20)") == []
    trio.advance(ticks=10)
    assert float(trio.query("?MOVES_BUFFERED")) == 1
    assert trio.send("CANCEL") == []
    trio.advance(ticks=2)
    assert float(trio.query("?MTYPE")) == 1  # the second MOVE, now loaded, held
    assert trio.send("CANCEL") == []
    trio.advance(ticks=2)
    assert float(trio.query("?MTYPE")) == 0
    assert trio.send("SPEED=10") == []
    trio.advance(ticks=500)
    assert trio.machine.dpos(0) == 0.0  # nothing left to start


def test_accel_or_decel_zero_is_still_refused_and_nothing_loads() -> None:
    trio = MC405()
    assert trio.send("BASE(0): SPEED=0: ACCEL=0: DECEL=100") == []
    assert trio.send("MOVE(10)") != []
    assert trio.send("ACCEL=100: DECEL=0") == []
    assert trio.send("MOVE(10)") != []
    assert float(trio.query("?MTYPE")) == 0


def test_merged_moves_loaded_at_speed_zero_run_as_one_path_from_the_write() -> None:
    """MOVE(5) at SPEED 10 runs; SPEED 0; MOVE(10): MOVE(10) merged wait at 5 (the first
    ends at rest, the held ones do not join it); SPEED 10 at tick w: one 20 path, 0.1 s
    ramps at ACCEL 100, 2.1 s in all."""
    trio = MC405()
    assert trio.send("BASE(0): SPEED=10: ACCEL=100: DECEL=100: MERGE=ON") == []
    assert trio.send("MOVE(5)") == []
    assert trio.send("SPEED=0: MOVE(10): MOVE(10)") == []
    trio.advance(ticks=3000)
    assert trio.machine.dpos(0) == 5.0
    assert float(trio.query("?MTYPE")) == 1
    assert float(trio.query("?MOVES_BUFFERED")) == 1
    written = trio.tick
    assert trio.send("SPEED=10") == []
    for k in (1, 100, 1000, 1100, 2000, 2099, 2100, 2200):
        trio.advance(ticks=written + k - trio.tick)
        assert trio.machine.dpos(0) == pytest.approx(5 + path(k * DT, 20, 10, 100),
                                                     abs=1e-9)
