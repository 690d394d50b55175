"""MSPHERICAL and MSPHERICALSP on an MC405: arcs anywhere in the space of three BASE axes,
on the shared path planner. Expected positions come from the circle worked out by hand
(centre, the two unit directions of its plane, the angle s / r) and the trapezoid of the
path speed: at SPEED 10, ACCEL = DECEL 1000, the path has gone 10 t - 0.05 at t seconds
once the 10 ms ramp is over."""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio import MC405

SETUP = "BASE(0, 1, 2, 3): SPEED = 10: ACCEL = 1000: DECEL = 1000"


def machine() -> MC405:
    trio = MC405()
    assert trio.send(SETUP) == []
    return trio


def at(trio: MC405, tick: int) -> list[float]:
    trio.advance(ticks=tick - trio.tick)
    return [trio.machine.dpos(a) for a in range(4)]


def read(trio: MC405, what: str) -> float:
    return float(trio.query(f"?{what}"))


def on_circle(centre: tuple[float, float, float], e1: tuple[float, float, float],
              e2: tuple[float, float, float], r: float, s: float) -> list[float]:
    theta = s / r
    return [centre[i] + r * (math.cos(theta) * e1[i] + math.sin(theta) * e2[i])
            for i in range(3)]


def cruise(tick: int, speed: float = 10.0) -> float:
    """Path distance at `tick` (ms) once the ramp (speed / 1000 s) is over."""
    return speed * tick / 1000 - speed * speed / 2000


def test_page_example_1_a_quarter_circle_up_to_z() -> None:
    """Example 1 of the page: end (30, 0, 30), a point on the way (30 (1 - cos 45),
    0, 30 sin 45): the quarter circle about (30, 0, 0) that leaves along +Z. Its length
    is 15 pi; at 10 units/s it ends 15 pi / 10 + 0.01 s after it starts: on tick 4723."""
    trio = machine()
    assert trio.send("MSPHERICAL(30, 0, 30, 30 * (1 - COS(PI / 4)), 0, "
                     "30 * SIN(PI / 4), 0)") == []
    trio.advance(ticks=1)
    assert read(trio, "MTYPE") == 31  # the MTYPE page: 31 MSPHERICAL
    assert at(trio, 1000)[:3] == pytest.approx(
        on_circle((30, 0, 0), (-1, 0, 0), (0, 0, 1), 30, cruise(1000)), abs=1e-9)
    # half way along (s = 7.5 pi, t = (s + 0.05) / 10: tick 2361, 0.002 units short)
    # it passes the page's mid point
    assert at(trio, 2361)[:3] == pytest.approx([30 * (1 - math.cos(math.pi / 4)), 0,
                                                30 * math.sin(math.pi / 4)], abs=2e-3)
    assert at(trio, 4000)[:3] == pytest.approx(
        on_circle((30, 0, 0), (-1, 0, 0), (0, 0, 1), 30, cruise(4000)), abs=1e-9)
    assert at(trio, 4722)[0] < 30 and read(trio, "IDLE") == 0
    assert at(trio, 4723) == [30, 0, 30, 0]
    assert read(trio, "IDLE") == -1


def test_mode_1_takes_the_short_way_and_gtpi_the_long_way() -> None:
    """End (10, 10, 0) about centre (10, 0, 0): the short way is a quarter circle leaving
    along +Y (length 5 pi); gtpi takes the other three quarters, leaving along -Y (15 pi),
    so it passes (20, 0, 0) half way (7.5 pi along)."""
    trio = machine()
    assert trio.send("MSPHERICAL(10, 10, 0, 10, 0, 0, 1)") == []
    assert at(trio, 1000)[:3] == pytest.approx(
        on_circle((10, 0, 0), (-1, 0, 0), (0, 1, 0), 10, cruise(1000)), abs=1e-9)
    end = math.ceil((5 * math.pi / 10 + 0.01) * 1000)
    assert at(trio, end - 1)[1] < 10
    assert at(trio, end) == [10, 10, 0, 0]
    trio = machine()
    assert trio.send("MSPHERICAL(10, 10, 0, 10, 0, 0, 1, 1)") == []
    for tick in (1000, 3000):
        assert at(trio, tick)[:3] == pytest.approx(
            on_circle((10, 0, 0), (-1, 0, 0), (0, -1, 0), 10, cruise(tick)), abs=1e-9)
    end = math.ceil((15 * math.pi / 10 + 0.01) * 1000)
    assert at(trio, end - 1) != [10, 10, 0, 0]
    assert at(trio, end) == [10, 10, 0, 0]


def test_mode_2_full_circle_through_two_points_in_a_tilted_plane() -> None:
    """Points (10, 10, 0) then (20, 0, 0) with the start: the circle about (10, 0, 0),
    radius 10, in the plane z = 0, leaving toward +Y first (20 pi long). Then one in the
    upright plane through the diagonal x = y: centre (c, c, 0), c = 10 / sqrt 2, radius
    10, leaving upward toward its first point (c, c, 10)."""
    trio = machine()
    # first point (u, v, w) = (10, 10, 0), second (x, y, z) = (20, 0, 0)
    assert trio.send("MSPHERICAL(20, 0, 0, 10, 10, 0, 2)") == []
    assert at(trio, 2000)[:3] == pytest.approx(
        on_circle((10, 0, 0), (-1, 0, 0), (0, 1, 0), 10, cruise(2000)), abs=1e-9)
    end = math.ceil((20 * math.pi / 10 + 0.01) * 1000)
    assert at(trio, end - 1) != [0, 0, 0, 0]
    assert at(trio, end) == [0, 0, 0, 0]
    c = 10 / math.sqrt(2)
    trio = machine()
    assert trio.send(f"MSPHERICAL({2 * c}, {2 * c}, 0, {c}, {c}, 10, 2)") == []
    e1 = (-1 / math.sqrt(2), -1 / math.sqrt(2), 0.0)
    assert at(trio, 1500)[:3] == pytest.approx(
        on_circle((c, c, 0), e1, (0, 0, 1), 10, cruise(1500)), abs=1e-6)


def test_mode_3_full_circle_from_a_point_and_the_centre() -> None:
    """Point (5, 0, 5) and centre (5, 0, 0): radius 5 in the XZ plane, leaving the short
    way toward the point (+Z); a whole turn, 10 pi long, back on the start."""
    trio = machine()
    assert trio.send("MSPHERICAL(5, 0, 5, 5, 0, 0, 3)") == []
    assert at(trio, 1000)[:3] == pytest.approx(
        on_circle((5, 0, 0), (-1, 0, 0), (0, 0, 1), 5, cruise(1000)), abs=1e-9)
    end = math.ceil((10 * math.pi / 10 + 0.01) * 1000)
    assert at(trio, end) == [0, 0, 0, 0]


def test_rotau_moves_a_fourth_axis_in_proportion_along_the_arc() -> None:
    """rotau = 8: axis 3 moves 8 while the arc is travelled, the path length the arc's
    alone (the end tick is the plain arc's)."""
    trio = machine()
    assert trio.send("MSPHERICAL(10, 10, 0, 10, 0, 0, 1, 0, 8)") == []
    length = 5 * math.pi
    got = at(trio, 1000)
    assert got[3] == pytest.approx(8 * cruise(1000) / length, abs=1e-9)
    end = math.ceil((length / 10 + 0.01) * 1000)
    assert at(trio, end) == [10, 10, 0, 8]


def test_msphericalsp_runs_at_force_speed() -> None:
    """The MSPHERICALSP page's example: FORCE_SPEED 30, the quarter circle of radius 30
    (15 pi long) takes 15 pi / 30 + 0.03 s; MTYPE 40."""
    trio = machine()
    assert trio.send("FORCE_SPEED = 30: MSPHERICALSP(30, 0, 30, 8.7868, 0, 21.2132, 0)") == []
    trio.advance(ticks=1)
    assert read(trio, "MTYPE") == 40
    end = math.ceil((15 * math.pi / 30 + 0.03) * 1000)
    assert at(trio, end - 1)[0] < 30
    assert at(trio, end)[:3] == pytest.approx([30, 0, 30], abs=1e-9)


@pytest.mark.parametrize("line", [
    "MSPHERICAL(20, 0, 0, 10, 0, 0, 1)",  # centre in line with start and end (page)
    "MSPHERICAL(20, 0, 0, 10, 0, 0, 0)",  # mid point in line: no circle
    "MSPHERICAL(10, 0, 0, 10, 0, 0, 3)",  # point in line with the centre
    "MSPHERICAL(10, 10, 0, 10, 0, 0, 5)",  # no mode 5
    "MSPHERICAL(10, 10, 0, 10, 0, 0, 2049)",  # bit 11: MOVETURN, not modelled
    "MSPHERICAL(10, 30, 0, 10, 0, 0, 1)",  # the end is not on the circle
])
def test_bad_spherical_moves_are_refused_and_load_nothing(line: str) -> None:
    trio = machine()
    reply = trio.send(line)
    assert len(reply) == 1 and "Parameter out of range" in reply[0], reply
    trio.advance(ticks=10)
    for axis in range(4):
        assert read(trio, f"MTYPE AXIS({axis})") == 0
        assert trio.machine.dpos(axis) == 0


def test_a_program_merges_an_mspherical_between_moves() -> None:
    """With MERGE on, MOVE - MSPHERICAL - MOVE is one path: the end comes when the whole
    length has been travelled at SPEED, with one ramp up and one down."""
    trio = machine()
    trio.load("ARC", "\n".join([
        "BASE(0, 1, 2)",
        "MERGE = ON",
        "MOVE(0, 0, -10)",
        "MSPHERICAL(10, 10, 0, 10, 0, 0, 1)",
        "MOVE(0, 0, 10)",
        "WAIT IDLE",
        "VR(1) = 1",
    ]))
    trio.send('RUN "ARC"')
    length = 10 + 5 * math.pi + 10
    end = math.ceil((length / 10 + 0.01) * 1000)
    # (the arc's sqrt(A r) = 100 units/s is above SPEED: no slowing on it); the program
    # loads its first move on the tick after RUN: the path starts a tick later
    assert at(trio, 500)[:3] == pytest.approx([0, 0, -cruise(499)], abs=1e-9)
    assert at(trio, 1500)[:3] == pytest.approx(
        [*on_circle((10, 0, -10), (-1, 0, 0), (0, 1, 0), 10, cruise(1499) - 10)[:2], -10],
        abs=1e-9)
    assert at(trio, end)[2] < 0
    assert at(trio, end + 1)[:3] == [10, 10, 0]
    assert read(trio, "VR(1)") == 1


# ---- TANG_DIRECTION and MOVETANG -------------------------------------------------------------
def test_tang_direction_follows_the_path_tangent_and_keeps_it_at_rest() -> None:
    """The page's table: +Y 0, +X PI/2, -Y PI, -X -PI/2 (atan2(X, Y)). On MOVECIRC's
    clockwise circle about (10, 0) from the origin the path leaves along +Y and turns
    toward +X by s / r: at tick 1000, s = 9.95, the direction is 0.995."""
    trio = machine()
    assert read(trio, "TANG_DIRECTION") == 0
    for move, expected in (("MOVE(10, 0)", math.pi / 2), ("MOVE(0, -10)", math.pi),
                           ("MOVE(-10, 0)", -math.pi / 2), ("MOVE(10, 10)", math.pi / 4)):
        assert trio.send(move) == []
        trio.advance(ticks=500)
        assert trio.machine.axis_parameter("TANG_DIRECTION", 0) == pytest.approx(expected)
        trio.advance(ticks=2000)  # ended: the direction is kept
        assert read(trio, "IDLE") == -1
        assert trio.machine.axis_parameter("TANG_DIRECTION", 0) == pytest.approx(expected)
    start = trio.tick
    assert trio.send("MOVECIRC(10, 10, 10, 0, 1)") == []
    at(trio, start + 1000)
    assert trio.machine.axis_parameter("TANG_DIRECTION", 0) == pytest.approx(0.995,
                                                                            abs=1e-12)
    reply = trio.send("TANG_DIRECTION = 1")
    assert len(reply) == 1 and "read only" in reply[0]


def tangential() -> MC405:
    trio = MC405()
    assert trio.send("BASE(2): REP_DIST = 2000: SPEED = 1000: ACCEL = 100000: "
                     "DECEL = 100000") == []
    return trio


def axis2(trio: MC405, tick: int) -> float:
    trio.advance(ticks=tick - trio.tick)
    return trio.machine.dpos(2)


def test_movetang_goes_the_short_way_and_retargets_on_the_fly() -> None:
    """REP_DIST 2000 is half a turn. MOVETANG(1000) from 0, then at tick 500 (at full speed,
    at 495) MOVETANG(1500): the move goes on to 1500 without a stop, ending on tick 1510
    as a single 1500 move would (1.5 s at 1000/s plus a 10 ms ramp)."""
    trio = tangential()
    assert trio.send("MOVETANG(1000)") == []
    assert axis2(trio, 500) == pytest.approx(495, abs=1e-9)
    assert read(trio, "MTYPE AXIS(2)") == 30  # the MTYPE page: 30 MOVETANG
    assert trio.send("MOVETANG(1500)") == []
    assert axis2(trio, 1200) == pytest.approx(1195, abs=1e-9)
    assert axis2(trio, 1509) < 1500
    assert axis2(trio, 1510) == 1500
    # from 1500 to -1900: forward through the fold, 600 (not back 3400)
    assert trio.send("MOVETANG(-1900)") == []
    assert axis2(trio, 1510 + 300) == pytest.approx(1500 + 300 - 5, abs=1e-9)
    axis2(trio, 1510 + 610)
    assert trio.machine.dpos(2) == 2100
    assert read(trio, "DPOS AXIS(2)") == -1900
    assert read(trio, "IDLE AXIS(2)") == -1


@pytest.mark.parametrize("line", [
    "MOVETANG(2500)",  # outside -REP_DIST..REP_DIST
    "MOVETANG(0, 0)",  # the link_axis form: not modelled
])
def test_bad_movetang_is_refused(line: str) -> None:
    trio = tangential()
    reply = trio.send(line)
    assert len(reply) == 1 and "Parameter out of range" in reply[0], reply
    trio.advance(ticks=10)
    assert read(trio, "MTYPE AXIS(2)") == 0 and read(trio, "MTYPE AXIS(3)") == 0


def test_movetang_while_another_move_runs_is_refused() -> None:
    trio = tangential()
    assert trio.send("MOVE(100)") == []
    reply = trio.send("MOVETANG(5)")
    assert len(reply) == 1 and "Parameter out of range" in reply[0], reply
    trio.advance(ticks=1000)
    assert trio.machine.dpos(2) == 100


# ---- SPHERE_CENTRE and FILLET --------------------------------------------------------------
def table(trio: MC405, start: int, count: int) -> list[float]:
    return [trio.machine.table_read(start + i) for i in range(count)]


def test_sphere_centre_of_the_page_example() -> None:
    """Mid (-200, 400, 0), end (-500, 500, 0) from the start: both 500 from (-500, 0, 0)
    (3-4-5 triangles), the end a quarter turn round from the start."""
    trio = MC405()
    trio.send("TABLE(10, -200, 400, 0)")
    trio.send("TABLE(20, -500, 500, 0)")
    assert trio.send("SPHERE_CENTRE(10, 20, 30)") == []
    assert table(trio, 30, 6) == pytest.approx([-500, 0, 0, math.pi / 2, 500, 0], abs=1e-9)
    trio.send("TABLE(20, -400, 800, 0)")  # in line with the mid point: the error flag
    assert trio.send("SPHERE_CENTRE(10, 20, 30)") == []
    assert table(trio, 30, 6) == [0, 0, 0, 0, 0, 1]


def test_fillet_option_2_gives_the_page_example_output() -> None:
    """The page prints this exact output for A = (10, 0, 0), B = (0, -5, 5)."""
    trio = MC405()
    trio.send("TABLE(100, 10, 0, 0, 0, -5, 5)")
    assert trio.send("FILLET(100, 200, 2)") == []
    h = math.sqrt(0.5)
    assert table(trio, 200, 14) == pytest.approx(
        [0.5, -h / 2, h / 2, 1, 0, 0, 0, -h, h, 0, 10, 5 * math.sqrt(2), 0, 0], abs=1e-12)


def test_fillet_option_0_blends_a_right_angle_and_mspherical_runs_it() -> None:
    """A = (100, 0, 0) then B = (0, 100, 0), radius 10: the arc starts 10 before the corner
    (A remain 90), ends (10, 10, 0) further, its centre (0, 10, 0) from its start, its mid
    point 10 from the centre at 45 degrees; B remain 90; a quarter turn, 5 pi long. The
    page's way to run it: MOVE, MSPHERICAL (end, mid, mode 0), MOVE: it ends on A + B."""
    trio = MC405()
    trio.send("TABLE(300, 100, 0, 0, 0, 100, 0, 10)")
    assert trio.send("FILLET(300, 400, 0)") == []
    h = 10 * math.sqrt(0.5)
    assert table(trio, 400, 19) == pytest.approx(
        [90, 0, 0, 10, 10, 0, h, 10 - h, 0, 0, 10, 0, 0, 10, 0, 90, 0, math.pi / 2,
         5 * math.pi], abs=1e-9)
    trio.load("FIL", "\n".join([
        "BASE(0, 1, 2)",
        "SPEED = 100: ACCEL = 10000: DECEL = 10000: MERGE = ON",
        "MOVE(TABLE(400), TABLE(401), TABLE(402))",
        "MSPHERICAL(TABLE(403), TABLE(404), TABLE(405), TABLE(406), TABLE(407), "
        "TABLE(408), 0)",
        "MOVE(TABLE(414), TABLE(415), TABLE(416))",
    ]))
    trio.send('RUN "FIL"')
    trio.advance(ticks=3000)
    assert [trio.machine.dpos(a) for a in range(3)] == [100, 100, 0]
    # a radius too large for the lines: the largest that fits, min(100, 100) / tan 45
    trio.send("TABLE(300, 100, 0, 0, 0, 100, 0, 150)")
    assert trio.send("FILLET(300, 400, 0)") == []
    assert table(trio, 400, 19)[13] == pytest.approx(100)
    trio.send("TABLE(300, 100, 0, 0, -50, 0, 0, 10)")  # in line (back on itself)
    assert trio.send("FILLET(300, 400, 0)") == []
    assert table(trio, 412, 1) == [2]
    trio.send("TABLE(300, 0, 0, 0)")  # a zero vector
    assert trio.send("FILLET(300, 400, 0)") == []
    assert table(trio, 412, 1) == [1]
    reply = trio.send("FILLET(300, 400, 1)")  # two 2D arcs: not modelled
    assert len(reply) == 1 and "Parameter out of range" in reply[0]


# ---- MOVEABSSEQ and MOVESEQ ------------------------------------------------------------------
def o_shape(sequence: str) -> MC405:
    trio = MC405()
    assert trio.send("BASE(0, 1): MERGE = ON: SPEED = 100: ACCEL = 10000: "
                     "DECEL = 10000") == []
    assert trio.send("DEFPOS(100, 30)") == []
    trio.send("TABLE(1000, 100, 120, 180, 120, 180, 0, 100, 0, 100, 30)")
    trio.send("TABLE(2000, 0, 90, 80, 0, 0, -120, -80, 0, 0, 30)")
    for line in sequence.split(";"):
        assert trio.send(line) == [], line
    return trio


PAGE_O = ("MOVE(0, 60); MOVECIRC(30, 30, 30, 0, 1); MOVE(20, 0); "
          "MOVECIRC(30, -30, 0, -30, 1); MOVE(0, -60); MOVECIRC(-30, -30, -30, 0, 1); "
          "MOVE(-20, 0); MOVECIRC(-30, 30, 0, 30, 1)")


@pytest.mark.parametrize("sequence", ["MOVEABSSEQ(1000, 2, 5, 0, 30)",
                                      "MOVESEQ(2000, 2, 5, 0, 30)"])
def test_moveabsseq_draws_the_pages_o_as_its_move_and_movecirc_sequence(
        sequence: str) -> None:
    """The page's example 1: the five corner points with radius 30 load the same moves as
    its MOVE / MOVECIRC 'O' (four sides, four quarter arcs): the two paths agree at every
    tick looked at, and both end back on (100, 30) at the same tick. MOVESEQ takes the
    same points as increments."""
    by_hand, by_table = o_shape(PAGE_O), o_shape(sequence)
    length = 60 + 20 + 60 + 20 + 4 * (30 * math.pi / 2)
    end = math.ceil((length / 100 + 0.01) * 1000)
    for tick in (300, 900, 1500, 2100, 2700, 3300, end - 1):
        here = [dpos_of(by_hand, tick, a) for a in (0, 1)]
        assert [dpos_of(by_table, tick, a) for a in (0, 1)] == pytest.approx(here, abs=1e-6)
    assert read(by_table, "MTYPE") != 0
    assert [dpos_of(by_table, end, a) for a in (0, 1)] == [100, 30]
    assert read(by_table, "IDLE") == -1


def dpos_of(trio: MC405, tick: int, axis: int) -> float:
    if trio.tick < tick:
        trio.advance(ticks=tick - trio.tick)
    return trio.machine.dpos(axis)


def test_moveabsseq_reduces_a_radius_too_big_and_loads_as_room_frees() -> None:
    """A staircase of 20 points 10 apart with radius 50: each corner may take only half
    of a side (5), so the radius is 5 / tan(45) = 5 for these right angles; the program
    loads the 20 moves through the 16-move buffer, waiting for room, and ends on the
    last point."""
    trio = MC405()
    points = []
    for i in range(20):
        points += [10 * ((i + 1) // 2), 10 * (i // 2)]
    trio.send("TABLE(500, " + ", ".join(str(p) for p in points) + ")")
    trio.load("ZIG", "\n".join([
        "BASE(0, 1)",
        "MERGE = ON: SPEED = 1000: ACCEL = 100000: DECEL = 100000",
        "MOVEABSSEQ(500, 2, 20, 0, 50)",
        "VR(5) = 1",
        "WAIT IDLE",
        "VR(6) = 1",
    ]))
    trio.send('RUN "ZIG"')
    trio.advance(ticks=5)
    assert read(trio, "VR(5)") == 0  # still loading: the buffer is full
    trio.advance(ticks=2000)
    assert read(trio, "VR(6)") == 1
    assert [trio.machine.dpos(a) for a in (0, 1)] == points[-2:]
    # the moves themselves: the first point is the start (a side of no length, no
    # corner); 18 right-angle corners, each arc meeting the next half way along a side
    # (no straight move between), a straight move in and one out
    from maxk.personalities.trio.sequences import plan
    moves = plan("MOVEABSSEQ", [500, 2, 20, 0, 50], [0.0, 0.0], trio.machine.table_read)
    assert len(moves) == 1 + 18 + 1
    assert moves[0] == ("MOVEABS", [5.0, 0.0])
    assert moves[1][0] == "MOVECIRC"  # left turn: anticlockwise (0)
    assert moves[1][1] == pytest.approx([5, 5, 0, 5, 0], abs=1e-12)
    assert moves[2][1] == pytest.approx([5, 5, 5, 0, 1], abs=1e-12)  # right: clockwise
    assert moves[-1] == ("MOVEABS", [100.0, 90.0])
