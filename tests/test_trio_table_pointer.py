"""TABLE_POINTER from its TrioBASIC help page: the TABLE location a running CAMBOX or CAM
is at, with the share of the interval to the next location done as its fraction.

The page's example: ten TABLE values at 1000, CAMBOX(1000, 1009, 10, 100, 1, 4) on axis 0
(repeat, link distance 100) and the link axis 1 FORWARD at SPEED 10 (UNITS 1, ACCEL 1e6).
At servo tick k (1 ms) the link stands at 0.01 k - 0.00005 (the ramp's 0.01 ms loses
v^2 / 2a), so the pointer is 1000 + 9 x (link mod 100) / 100: the expected values are
that arithmetic.
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio.controller import MC405

SPEED, ACCEL = 10.0, 1e6
LOSS = SPEED * SPEED / (2 * ACCEL)
POINTS = "0, 0.8808, 6.5485, 19.5501, 39.001, 60.999, 80.4499, 93.4515, 99.1192, 100"


def link(tick: int) -> float:
    t = tick / 1000
    return SPEED * t - LOSS if t >= SPEED / ACCEL else 0.5 * ACCEL * t * t


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def pointer(trio: MC405) -> float:
    return trio.machine.axis_parameter("TABLE_POINTER", 0)


def cambox_machine() -> MC405:
    trio = MC405()
    assert trio.send(f"TABLE(1000, {POINTS})") == []
    assert trio.send(f"BASE(1): SPEED={SPEED:g}: ACCEL={ACCEL:g}: DECEL={ACCEL:g}") == []
    assert trio.send("CAMBOX(1000, 1009, 10, 100, 1, 4, 0) AXIS(0)") == []
    assert trio.send("FORWARD AXIS(1)") == []
    return trio


def test_the_pointer_of_the_pages_cambox_runs_through_the_table_and_repeats() -> None:
    trio = cambox_machine()
    assert pointer(trio) == 1000.0  # the link has not moved yet
    for tick in (1000, 5000, 11112, 9999, 10001, 23456):  # (9999 after 11112: see below)
        if tick < trio.tick:
            continue
        at(trio, tick)
        travelled = link(tick) % 100
        assert pointer(trio) == pytest.approx(1000 + 9 * travelled / 100, abs=1e-9)
    at(trio, 25000)  # the link at 249.99995: the third cycle, 49.99995 in
    assert trio.query("?TABLE_POINTER AXIS(0)") == "1004.5000"
    assert trio.query("?INT(TABLE_POINTER AXIS(0))") == "1004"


def test_a_program_sees_the_pointer_step_from_one_location_to_the_next() -> None:
    """As the page's loop: INT(TABLE_POINTER) changes when the link passes 100/9 each."""
    trio = cambox_machine()
    trio.send("BASE(0)")
    assert trio.send("WAIT UNTIL INT(TABLE_POINTER) = 1001: VR(1) = TICKS") == []
    # 1001 is reached when link >= 100/9: 0.01 k - 0.00005 >= 11.111...: k = 1111.116..
    assert trio.tick == 1112
    assert trio.query("?TABLE_POINTER") == f"{1000 + 9 * (11.12 - LOSS) / 100:.4f}"


def test_a_cam_in_time_points_into_its_table() -> None:
    """CAM(1000, 1009, 10, 100) at SPEED 50: 2 s for the profile, 2/9 s a location."""
    trio = MC405()
    assert trio.send(f"TABLE(1000, {POINTS})") == []
    assert trio.send("BASE(0): SPEED=50: CAM(1000, 1009, 10, 100)") == []
    trio.advance(ticks=1)
    start = trio.tick - 1  # the tick the CAM loaded and started on
    for tick in (start + 500, start + 1000, start + 1999):
        at(trio, tick)
        assert pointer(trio) == pytest.approx(1000 + (tick - start) / 1000 / (2 / 9), abs=1e-9)
    at(trio, start + 2001)
    assert pointer(trio) == 0.0  # the CAM has ended: no CAM, 0 (D)
    assert trio.send("TABLE_POINTER = 3") == ["! Parameter is read only"]  # (D)
