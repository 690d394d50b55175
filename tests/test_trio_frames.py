"""Robot frames on an MC405 (TrioBASIC help FRAME, AXIS_DPOS, AXIS_UNITS, WORLD_DPOS,
FRAME_TRANS, FRAME_GROUP): moves command the world position (DPOS), the motors follow the
frame's inverse transform (AXIS_DPOS, MPOS) at every servo tick.

Every expected number is hand arithmetic: the move's path distance at tick k (1 ms) with
SPEED 100 and ACCEL = DECEL 1e6 is 100 t - 0.005 once the 0.1 ms ramp is over (the ramp
loses v^2 / 2a), and the FRAME page's equations applied to it.
"""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio import MC405

SPEED, ACCEL = 100.0, 1e6
LOSS = SPEED * SPEED / (2 * ACCEL)  # 0.005


def path(tick: int, start: int = 0) -> float:
    """Distance a move loaded on tick `start` has gone on tick `tick` (cruising)."""
    return SPEED * (tick - start) / 1000 - LOSS


def machine(units: str = "") -> MC405:
    trio = MC405()
    if units:
        assert trio.send(units) == []
    assert trio.send(f"BASE(0, 1): SPEED = {SPEED:g}: ACCEL = {ACCEL:g}: "
                     f"DECEL = {ACCEL:g}") == []
    return trio


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def world(trio: MC405) -> list[float]:
    return [trio.machine.dpos(a) for a in (0, 1)]


def motors(trio: MC405, name: str = "AXIS_DPOS") -> list[float]:
    return [trio.machine.axis_parameter(name, a) for a in (0, 1)]


def test_frame_2_single_belt_raises_the_load_with_both_motors() -> None:
    """The page's example: DEFPOS(150, 50), FRAME = 2: the world is ((150 + 50) / 2,
    (150 - 50) / 2) = (100, 50); MOVE(0, 100) then moves both motors, motor 0 by +Y
    and motor 1 by -Y (X = (A0 + A1) / 2, Y = (A0 - A1) / 2)."""
    trio = machine()
    assert trio.send("DEFPOS(150, 50)") == []
    assert trio.send("FRAME = 2") == []
    assert world(trio) == [100.0, 50.0]
    assert motors(trio) == [150.0, 50.0]
    assert motors(trio, "MPOS") == [150.0, 50.0]
    assert trio.query("?FRAME AXIS(1)") == "2"
    start = trio.tick
    assert trio.send("MOVE(0, 100)") == []
    for tick in (start + 1, start + 250, start + 731):
        at(trio, tick)
        y = 50 + path(tick, start)
        assert world(trio) == pytest.approx([100.0, y], abs=1e-9)
        assert motors(trio) == pytest.approx([100 + y, 100 - y], abs=1e-9)
        assert motors(trio, "MPOS") == pytest.approx([100 + y, 100 - y], abs=1e-9)
        assert motors(trio, "WORLD_DPOS") == pytest.approx([100.0, y], abs=1e-9)
    assert trio.run_until_idle()
    assert motors(trio) == pytest.approx([250.0, -50.0], abs=1e-9)
    assert float(trio.query("?FE AXIS(0)")) == 0
    # FRAME = 0: DPOS becomes the motors' positions again
    assert trio.send("FRAME = 0") == []
    assert world(trio) == pytest.approx([250.0, -50.0], abs=1e-9)
    assert motors(trio) == pytest.approx([250.0, -50.0], abs=1e-9)
    assert trio.send("MOVE(-50, 50)") == [] and trio.run_until_idle()
    assert world(trio) == pytest.approx([200.0, 0.0], abs=1e-9)


def test_units_scale_the_world_and_axis_units_the_motors() -> None:
    """UNITS 10 on the world, AXIS_UNITS 4 on the motors: DEFPOS(15, 5) is raw (150, 50),
    so after FRAME = 2 DPOS = (100, 50) / 10 and AXIS_DPOS = (150, 50) / 4; MOVE(0, 2)
    is 20 raw on Y: the motors end at (170, 30) / 4."""
    trio = machine("UNITS AXIS(0) = 10: UNITS AXIS(1) = 10: AXIS_UNITS AXIS(0) = 4: "
                   "AXIS_UNITS AXIS(1) = 4")
    assert trio.send("DEFPOS(15, 5)") == []
    assert motors(trio) == [15.0, 5.0]  # FRAME 0: AXIS_DPOS is DPOS
    assert trio.send("FRAME AXIS(0) = 2") == []
    assert world(trio) == pytest.approx([10.0, 5.0])
    assert motors(trio) == pytest.approx([37.5, 12.5])
    assert motors(trio, "MPOS") == pytest.approx([37.5, 12.5])
    assert trio.send("MOVE(0, 2)") == [] and trio.run_until_idle()
    assert world(trio) == pytest.approx([10.0, 7.0])
    assert motors(trio) == pytest.approx([42.5, 7.5])
    assert trio.query("?AXIS_DPOS AXIS(0)") == "42.5000"


ROTATE = """theta = {degrees} * 2 * PI / 360
GOSUB matrix
DEFPOS(10, 0)
FRAME = 5
MOVE({dx}, {dy})
WAIT IDLE
STOP
matrix:
  TABLE(0, COS(theta), -SIN(theta), SIN(theta), COS(theta))
  det = TABLE(0) * TABLE(3) - TABLE(2) * TABLE(1)
  TABLE(4, TABLE(3) / det, -TABLE(1) / det, -TABLE(2) / det, TABLE(0) / det)
RETURN
"""


def test_frame_5_rotated_axes_from_a_program() -> None:
    """The page's FRAME 5 example shape, run as a program: the matrix and its inverse in
    TABLE, the motors at (10, 0) when the frame goes on, so the world starts at
    (10, 0) * [[T4, T5], [T6, T7]] = (10 cos, 10 sin); MOVE(40, 30) (path length 50)
    then drives the motors at (x, y) * [[cos, -sin], [sin, cos]]."""
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    trio = machine()
    trio.load("ROT", ROTATE.format(degrees=30, dx=40, dy=30))
    assert trio.send('RUN "ROT"') == []
    x0, y0 = 10 * c, 10 * s
    for _ in range(50):  # the program's first cycles: the move's first tick
        framed = trio.machine.axis_parameter("FRAME", 0) == 5
        if framed and world(trio) != pytest.approx([x0, y0], abs=1e-12):
            break
        at(trio, trio.tick + 1)
    start = trio.tick - 1  # moving on its first tick: 0.1 - 0.005 gone
    for tick in (start + 1, start + 100, start + 400):
        at(trio, tick)
        d = path(tick, start)
        x, y = x0 + 0.8 * d, y0 + 0.6 * d
        assert world(trio) == pytest.approx([x, y], abs=1e-9)
        assert motors(trio) == pytest.approx([x * c + y * s, -x * s + y * c], abs=1e-9)
    assert trio.run_until_idle()
    x, y = x0 + 40, y0 + 30
    assert world(trio) == pytest.approx([x, y], abs=1e-9)
    assert motors(trio) == pytest.approx([x * c + y * s, -x * s + y * c], abs=1e-9)
