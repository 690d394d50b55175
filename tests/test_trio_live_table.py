"""TABLE edits while a CAMBOX runs: the cam reads its TABLE live.

The TABLE_POINTER help page loads new cam values into the locations the running cam has
passed, for its next cycle; the CAMBOX page makes the values positions from the
profile's start. So the model: the cycle the link is in follows the TABLE as it is now,
cycles already done keep what they moved, a buffered CAMBOX takes the TABLE it finds
when it starts.

The link axis 1 runs FORWARD at 1000 counts/s (UNITS 1, ACCEL 1e6) from tick 0, so its
DPOS at tick t >= 1 is t - 0.5 (v t - v^2 / 2a). A CAMBOX over a link distance of 100
with five TABLE values has four intervals of 25 link units each; every expected
position below is that linear interpolation, worked out by hand.
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio.controller import MC405


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def dpos(trio: MC405, axis: int) -> float:
    return trio.machine.axis_parameter("DPOS", axis)


def cam(options: str = ", 4", multiplier: float = 1) -> MC405:
    trio = MC405()
    assert trio.send("TABLE(1000, 0, 10, 20, 30, 40)") == []
    assert trio.send(f"CAMBOX(1000, 1004, {multiplier:g}, 100, 1{options}) AXIS(0)") == []
    assert trio.send("BASE(1): SPEED=1000: ACCEL=1e6: DECEL=1e6: FORWARD") == []
    assert trio.tick == 0
    return trio


def test_values_behind_the_link_change_the_next_cycle_not_this_one() -> None:
    trio = cam()
    at(trio, 60)  # link 59.5: interval 2 (20..30), 0.38 of it
    assert dpos(trio, 0) == pytest.approx(23.8, abs=1e-9)
    assert trio.send("TABLE(1001, 5)") == []  # passed already: no change now
    assert dpos(trio, 0) == pytest.approx(23.8, abs=1e-9)
    assert trio.send("TABLE(1004, 60)") == []  # ahead: this cycle ends at 60
    assert dpos(trio, 0) == pytest.approx(23.8, abs=1e-9)
    at(trio, 90)  # link 89.5: interval 3 (30..60), 0.58 of it
    assert dpos(trio, 0) == pytest.approx(30 + 0.58 * 30, abs=1e-9)
    at(trio, 110)  # second cycle from 60, link 9.5 in: interval 0 (0..5), 0.38
    assert dpos(trio, 0) == pytest.approx(60 + 0.38 * 5, abs=1e-9)
    at(trio, 330)  # fourth cycle from 180, link 29.5 in: interval 1 (5..20), 0.18
    assert dpos(trio, 0) == pytest.approx(180 + 5 + 0.18 * 15, abs=1e-9)
    assert trio.query("?TABLE_POINTER AXIS(0)") == "1001.1800"
    assert trio.send("TABLE(1004, 100)") == []  # the three cycles done keep their 60
    assert dpos(trio, 0) == pytest.approx(180 + 5 + 0.18 * 15, abs=1e-9)
    at(trio, 390)  # link 89.5 into the fourth: interval 3 (30..100), 0.58
    assert dpos(trio, 0) == pytest.approx(180 + 30 + 0.58 * 70, abs=1e-9)
    at(trio, 410)  # fifth cycle from 280: interval 0 (0..5), 0.38
    assert dpos(trio, 0) == pytest.approx(280 + 0.38 * 5, abs=1e-9)


def test_a_value_of_the_interval_the_link_is_in_moves_the_axis_at_once() -> None:
    """Positions from the profile's start (CAMBOX page): the new value acts now (D)."""
    trio = cam()
    at(trio, 150)  # second cycle from 40, link 49.5 in: interval 1 (10..20), 0.98
    assert dpos(trio, 0) == pytest.approx(40 + 19.8, abs=1e-9)
    assert trio.send("TABLE(1002, 50)") == []
    assert dpos(trio, 0) == pytest.approx(40 + 10 + 0.98 * 40, abs=1e-9)
    at(trio, 151)  # interval 2 (50..30), 0.02 of it
    assert dpos(trio, 0) == pytest.approx(40 + 50 - 0.02 * 20, abs=1e-9)


def test_a_cambox_ends_on_its_tables_last_value_as_it_is_then() -> None:
    """Once (no repeat), multiplier 2: the last value raised to 100 ends it at 200."""
    trio = cam("", 2)
    at(trio, 50)
    assert dpos(trio, 0) == pytest.approx(2 * (10 + 0.98 * 10), abs=1e-9)
    assert trio.send("TABLE(1004, 100)") == []
    at(trio, 90)  # interval 3 (30..100), link 89.5: 0.58
    assert dpos(trio, 0) == pytest.approx(2 * (30 + 0.58 * 70), abs=1e-9)
    at(trio, 150)
    assert dpos(trio, 0) == pytest.approx(200, abs=1e-9)
    assert trio.query("?MTYPE AXIS(0)") == "0"
    assert trio.send("TABLE(1004, 0)") == []  # ended: no longer read
    assert dpos(trio, 0) == pytest.approx(200, abs=1e-9)


def test_a_buffered_cambox_takes_the_table_it_finds_when_it_starts() -> None:
    trio = MC405()
    trio.send("TABLE(1000, 0, 10, 20, 30, 40)")
    trio.send("BASE(0): SPEED=1000: ACCEL=1e6: DECEL=1e6: MOVE(10)")
    trio.send("CAMBOX(1000, 1004, 1, 100, 1) AXIS(0)")
    assert trio.send("TABLE(1000, 100, 110, 140, 170, 200)") == []  # offset by the first
    at(trio, 100)  # the MOVE is done; the CAMBOX waits for the link
    assert dpos(trio, 0) == pytest.approx(10, abs=1e-9)
    trio.send("BASE(1): SPEED=1000: ACCEL=1e6: DECEL=1e6: FORWARD")
    at(trio, 170)  # link 69.5: interval 2 (40..70), 0.78
    assert dpos(trio, 0) == pytest.approx(10 + 40 + 0.78 * 30, abs=1e-9)


def test_a_running_cam_reads_its_table_live_over_the_same_time() -> None:
    """CAM(1000, 1004, 1, 100) at SPEED 50: 2 s, 0.5 s (500 ticks) an interval, loaded
    and started on tick 0 (the CAM page's profile in time). TABLE(1003) raised while the
    CAM is in its second interval: the third and fourth intervals run to the new value;
    the end, on the last value, is where it was."""
    trio = MC405()
    trio.send("TABLE(1000, 0, 10, 20, 30, 40)")
    assert trio.send("BASE(0): SPEED=50: CAM(1000, 1004, 1, 100)") == []
    assert trio.tick == 0
    at(trio, 600)  # interval 1 (10..20), 0.2 of it
    assert dpos(trio, 0) == pytest.approx(12, abs=1e-9)
    assert trio.send("TABLE(1003, 70)") == []
    assert dpos(trio, 0) == pytest.approx(12, abs=1e-9)
    at(trio, 1250)  # interval 2 (20..70), 0.5 of it
    assert dpos(trio, 0) == pytest.approx(45, abs=1e-9)
    at(trio, 1750)  # interval 3 (70..40), 0.5 of it
    assert dpos(trio, 0) == pytest.approx(55, abs=1e-9)
    at(trio, 2100)
    assert dpos(trio, 0) == pytest.approx(40, abs=1e-9)
    assert trio.query("?MTYPE") == "0"


def test_a_buffered_cam_takes_the_table_it_finds_when_it_starts() -> None:
    trio = MC405()
    trio.send("TABLE(1000, 0, 10, 20, 30, 40)")
    trio.send("BASE(0): SPEED=50: ACCEL=1e6: DECEL=1e6: MOVE(5)")  # 0.1 s and a bit
    trio.send("CAM(1000, 1004, 2, 100)")
    assert trio.send("TABLE(1004, 100)") == []
    assert trio.run_until_idle(10.0)
    assert dpos(trio, 0) == pytest.approx(5 + 200, abs=1e-9)
