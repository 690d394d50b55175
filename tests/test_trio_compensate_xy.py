"""COMPENSATE_XY from its TrioBASIC help page (and MTYPE's): a correction from a grid of
TABLE values, interpolated linearly in X and Y, superimposed on an axis.

The grids here are our own. Every expected position is the page's arithmetic done in
the test: the cell of each coordinate (values evenly spread over the distance from the
offset, the end points counted), the linear blend in X then Y, the nearest edge value
outside the working area, and the correction at the start taken off.
"""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio.controller import MC405
from maxk.personalities.trio.memory import TABLE_SIZE


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def dpos(trio: MC405, axis: int) -> float:
    return trio.machine.axis_parameter("DPOS", axis)


# The page's layout: axes 0 and 1 are the motors, 8 and 9 virtual axes the program moves;
# ADDAX brings 8 and 9 onto 0 and 1, COMPENSATE_XY adds each motor's correction. A grid of
# 51 x 41 values every 10 mm over a 500 x 400 mm bed, UNITS 1000 (mm).
# Axis 0's grid is 0.001 i j (bilinear: the interpolation is 1e-5 x y everywhere); axis
# 1's is 0.01 i^2 + 0.005 j (the square is interpolated along X within each cell). The
# page puts the second grid at 3000, inside the first (1000 + 2091 values): here at 5000.
PAGE_LAYOUT = """UNITS AXIS(0) = 1000
UNITS AXIS(1) = 1000
UNITS AXIS(8) = UNITS AXIS(0)
UNITS AXIS(9) = UNITS AXIS(1)
FOR j = 0 TO 40
  FOR i = 0 TO 50
    TABLE(1000 + j * 51 + i, 0.001 * i * j)
    TABLE(5000 + j * 51 + i, 0.01 * i * i + 0.005 * j)
  NEXT i
NEXT j
ADDAX(8) AXIS(0)
ADDAX(9) AXIS(1)
COMPENSATE_XY(1000, 0, 8, 51, 500, 0, 9, 41, 400, 0) AXIS(0)
COMPENSATE_XY(5000, 0, 8, 51, 500, 0, 9, 41, 400, 0) AXIS(1)
BASE(8, 9)
SPEED = 100
ACCEL = 1000
DECEL = 1000
VR(0) = 1
"""


def axis1_correction(x: float, y: float) -> float:
    """0.01 i^2 blended linearly between the whole i around x / 10, plus 0.005 y / 10."""
    u = x / 10
    i = math.floor(u)
    f = u - i
    return 0.01 * (i * i * (1 - f) + (i + 1) * (i + 1) * f) + 0.0005 * y


def page_layout() -> MC405:
    trio = MC405()
    assert trio.load("COMP", PAGE_LAYOUT) == []
    assert trio.send('RUN "COMP"') == []
    assert trio.machine.run_until(lambda _m: trio.machine.vr.read(0) == 1, 200_000)
    assert trio.query("?MTYPE AXIS(0)") == "26"  # MTYPE page: COMPENSATE_XY
    assert trio.query("?MTYPE AXIS(1)") == "26"
    return trio


def test_page_layout_moves_the_motors_by_the_virtual_axes_plus_the_correction() -> None:
    trio = page_layout()
    assert trio.send("MOVEABS(15, 25) AXIS(8)") == []
    start = trio.tick
    for tick in (start + 60, start + 137, start + 201):  # during the move, at any tick
        at(trio, tick)
        x, y = dpos(trio, 8), dpos(trio, 9)
        assert 0 < x < 15 and 0 < y < 25
        assert dpos(trio, 0) == pytest.approx(x + 1e-5 * x * y, abs=1e-9)
        assert dpos(trio, 1) == pytest.approx(y + axis1_correction(x, y), abs=1e-9)
    at(trio, start + 2000)
    assert (dpos(trio, 8), dpos(trio, 9)) == (15, 25)
    # axis 0: 0.001 x 1.5 x 2.5; axis 1: between 0.01 and 0.04 halfway, plus 0.005 x 2.5
    assert dpos(trio, 0) == pytest.approx(15.00375, abs=1e-9)
    assert dpos(trio, 1) == pytest.approx(25 + 0.025 + 0.0125, abs=1e-9)
    assert trio.query("?MPOS AXIS(1)") == "25.0375"


SMALL_GRID = "TABLE(100, 0, 0.1, 0.3, 0.2, 0.4, 0.8)"
"""3 x 2 values: X at 0, 50, 100 (x_dist 100, offset 0), Y at -20 and 30 (50, -20)."""


def test_starts_without_a_jump_clamps_outside_the_area_and_cancel_leaves_the_axis() -> None:
    trio = MC405()
    assert trio.send(SMALL_GRID + ": UNITS AXIS(0) = 1000") == []  # (whole counts)
    assert trio.send("BASE(8, 9): SPEED = 1000: ACCEL = 1e5: DECEL = 1e5") == []
    assert trio.send("DEFPOS(120, 100)") == []  # outside: the corner (100, 30), 0.8
    assert trio.send("COMPENSATE_XY(100, 1, 8, 3, 100, 0, 9, 2, 50, -20) AXIS(0)") == []
    assert dpos(trio, 0) == 0  # the correction there is taken off: no jump
    assert trio.send("MOVEABS(50, 5): WAIT IDLE") == []
    # x on the middle column, y halfway between the rows: (0.1 + 0.4) / 2 - 0.8
    assert dpos(trio, 0) == pytest.approx(-0.55, abs=1e-12)
    assert trio.send("MOVEABS(75, 10): WAIT IDLE") == []
    # X: halfway 50..100; Y: 0.6 of -20..30: rows 0.2 and 0.6, blended 0.44
    assert dpos(trio, 0) == pytest.approx(0.2 * 0.4 + 0.6 * 0.6 - 0.8, abs=1e-12)
    assert trio.send("MOVEABS(-10, -30): WAIT IDLE") == []  # clamped to (0, -20): 0
    assert dpos(trio, 0) == pytest.approx(-0.8, abs=1e-12)
    assert trio.send("CANCEL AXIS(0)") == []
    assert trio.query("?MTYPE AXIS(0)") == "0"
    assert trio.send("MOVEABS(50, 5): WAIT IDLE") == []  # no correction any more
    assert dpos(trio, 0) == pytest.approx(-0.8, abs=1e-12)
    assert trio.send("MOVE(1) AXIS(0): WAIT IDLE AXIS(0)") == []
    assert dpos(trio, 0) == pytest.approx(0.2, abs=1e-12)


def test_it_waits_in_the_buffer_behind_a_move_and_starts_where_that_ends() -> None:
    trio = MC405()
    assert trio.send(SMALL_GRID) == []
    assert trio.send("SPEED AXIS(0) = 10: ACCEL AXIS(0) = 1e6: DECEL AXIS(0) = 1e6") == []
    assert trio.send("MOVE(10) AXIS(0)") == []
    assert trio.send("COMPENSATE_XY(100, 1, 8, 3, 100, 0, 9, 2, 50, -20) AXIS(0)") == []
    assert trio.query("?MTYPE AXIS(0)") == "1"
    assert trio.query("?NTYPE AXIS(0)") == "26"
    assert trio.send("MOVEABS(100, 30) AXIS(8)") == []
    at(trio, 2000)  # the move is done (1 s), its correction from (100, 30): 0.8 - 0.2
    assert trio.query("?MTYPE AXIS(0)") == "26"
    assert dpos(trio, 0) == pytest.approx(10.0, abs=1e-12)
    assert trio.send("MOVEABS(0, -20) AXIS(8)") == []
    at(trio, 4000)
    assert dpos(trio, 0) == pytest.approx(10.0 + 0.0 - 0.8, abs=1e-12)


def test_bad_arguments_are_refused_with_nothing_loaded() -> None:
    trio = MC405()
    assert trio.send(SMALL_GRID) == []
    good = [100, 1, 8, 3, 100, 0, 9, 2, 50, -20]
    cases = {0: (2, "Invalid axis number"),  # x_axis the axis itself
             6: (16, "Invalid axis number"),
             3: (0, "Parameter out of range"),  # a division count
             7: (1.5, "Parameter out of range"),
             4: (0, "Parameter out of range"),  # a distance
             8: (-50, "Parameter out of range"),
             1: (2, "Parameter out of range"),  # opt
             9: (None, "Parameter out of range")}
    for index, (value, error) in cases.items():
        args = list(good)
        if index == 9:
            args[0] = TABLE_SIZE - 5  # 6 values from there run past TABLE's end
        elif index == 0:
            args[2] = value
        else:
            args[index] = value
        text = ", ".join(f"{v:g}" for v in args)
        assert trio.send(f"COMPENSATE_XY({text}) AXIS(2)") == [f"! {error}"], (index, text)
        assert trio.query("?MTYPE AXIS(2)") == "0"
    assert trio.send("COMPENSATE_XY(100, 1, 8, 3, 100, 0, 9, 2, 50, -20) AXIS(0)") == []
    # axis 8 following axis 0 would make the correction follow itself
    assert trio.send("ADDAX(0) AXIS(9)") == ["! Parameter out of range"]
    assert trio.send("CONNECT(1, 0) AXIS(8)") == ["! Parameter out of range"]


def test_rapidstop_ends_it_like_cancel_and_it_can_be_given_again() -> None:
    trio = MC405()
    assert trio.send(SMALL_GRID + ": UNITS AXIS(0) = 1000") == []
    assert trio.send("COMPENSATE_XY(100, 1, 8, 3, 100, 0, 9, 2, 50, -20) AXIS(0)") == []
    assert trio.send("MOVEABS(50, 30) AXIS(8): WAIT IDLE AXIS(8)") == []
    # from (0, 0): 0.08 (row -20: 0, row 30: 0.2, 0.4 of the way) to 0.4
    assert dpos(trio, 0) == pytest.approx(0.4 - 0.08, abs=1e-12)
    assert trio.send("RAPIDSTOP") == []
    assert trio.query("?MTYPE AXIS(0)") == "0"
    assert trio.send("MOVEABS(100, 30) AXIS(8): WAIT IDLE AXIS(8)") == []
    assert dpos(trio, 0) == pytest.approx(0.32, abs=1e-12)
    # given again at (100, 30): the correction there (0.8) is its new zero
    assert trio.send("COMPENSATE_XY(100, 1, 8, 3, 100, 0, 9, 2, 50, -20) AXIS(0)") == []
    assert trio.send("MOVEABS(0, -20) AXIS(8): WAIT IDLE AXIS(8)") == []
    assert dpos(trio, 0) == pytest.approx(0.32 - 0.8, abs=1e-12)


def test_the_screw_table_example_runs_with_its_hand_worked_replies() -> None:
    """examples/mc405_compensate_xy.maxk under `maxk run`: its expected replies (worked
    out by hand in its header) must come back exactly."""
    from pathlib import Path

    from maxk.cli import main

    script = Path(__file__).parent.parent / "examples" / "mc405_compensate_xy.maxk"
    assert main(["run", str(script)]) == 0
