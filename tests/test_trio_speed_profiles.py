"""Speed profiles of the MC405's moves from their TrioBASIC help pages: jerk-limited ramps
(VP_MODE 5/6, JERK, SRAMP in mode 6) and the SP moves' FORCE_SPEED, STARTMOVE_SPEED and
ENDMOVE_SPEED on merged moves.

Every expected position is hand arithmetic: a jerk-limited ramp from rest rises at J for
A/J seconds (position J t^3 / 6), holds A, and falls; a merged path ramps at ACCEL
between the speeds the pages give.
"""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio import MC405


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def dpos(trio: MC405, axis: int = 0) -> float:
    return trio.machine.dpos(axis)


def end_tick(seconds: float) -> int:
    return math.ceil(seconds * 1000 - 1e-6)


# ---- jerk-limited ramps ----------------------------------------------------------------
JERK_EXAMPLE = "UNITS=1000: SPEED=50000: ACCEL=80000: DECEL=80000: JERK=300000"


def test_jerk_page_example_rises_at_jerk_and_ends_later_than_a_trapezoid() -> None:
    """The JERK page's move in VP_MODE 6: the acceleration rises over 80000/300000 s,
    so a ramp to 50000 lasts 0.625 + 0.2667 s and covers half its time x 50000."""
    j, a, v = 300000.0, 80000.0, 50000.0
    rise = a / j
    ramp = v / a + rise
    total = 2 * ramp + (50000 - v * ramp) / v
    trio = MC405()
    assert trio.send(f"BASE(0): VP_MODE=6: {JERK_EXAMPLE}: MOVE(50000)") == []
    at(trio, 200)  # in the rise: J t^3 / 6
    assert dpos(trio) == pytest.approx(j * 0.2 ** 3 / 6, abs=1e-6)
    at(trio, 500)  # holding ACCEL since the rise ended
    p_rise, v_rise = j * rise ** 3 / 6, j * rise ** 2 / 2
    tau = 0.5 - rise
    assert dpos(trio) == pytest.approx(p_rise + v_rise * tau + a * tau * tau / 2, abs=1e-6)
    end = end_tick(total)
    assert end == 1892
    at(trio, end - 1)
    assert dpos(trio) < 50000
    assert float(trio.query("?MTYPE AXIS(0)")) == 1
    at(trio, end)
    assert dpos(trio) == 50000
    assert float(trio.query("?MTYPE AXIS(0)")) == 0


def test_jerk_is_ignored_in_vp_mode_0() -> None:
    """The same move in VP_MODE 0 (no SRAMP) is the trapezoid: 2 x 0.625 + 0.375 s."""
    trio = MC405()
    assert trio.send(f"BASE(0): VP_MODE=0: {JERK_EXAMPLE}: MOVE(50000)") == []
    at(trio, 200)
    assert dpos(trio) == pytest.approx(80000 * 0.2 ** 2 / 2, abs=1e-6)
    at(trio, 1624)
    assert dpos(trio) < 50000
    at(trio, 1625)
    assert dpos(trio) == 50000


def test_a_speed_below_accel_squared_over_jerk_gives_a_triangle_of_acceleration() -> None:
    """VP_MODE 5, SPEED 100, ACCEL 1000, JERK 5000: ACCEL^2/JERK = 200 > 100, so the
    acceleration peaks at sqrt(100 x 5000) and each ramp lasts 2 sqrt(100/5000) s."""
    trio = MC405()
    assert trio.send("BASE(0): VP_MODE=5: SPEED=100: ACCEL=1000: DECEL=1000: JERK=5000")\
        == []
    assert trio.send("MOVE(100)") == []
    ramp = 2 * math.sqrt(100 / 5000)
    at(trio, 100)  # inside the rise (half the ramp is 0.1414 s)
    assert dpos(trio) == pytest.approx(5000 * 0.1 ** 3 / 6, abs=1e-9)
    at(trio, 200)  # past the ramp's middle: 100 ramp/2 ... by symmetry of the S:
    half = ramp / 2  # the speed at the middle is 50; from there the mirror image
    w = ramp - 0.2  # time left to the ramp's end
    ramp_distance = 100 * ramp / 2
    assert dpos(trio) == pytest.approx(ramp_distance - 100 * w + 5000 * w ** 3 / 6,
                                       abs=1e-9)
    assert half < 0.2 < ramp
    end = end_tick(2 * ramp + (100 - 100 * ramp) / 100)
    at(trio, end - 1)
    assert dpos(trio) < 100
    at(trio, end)
    assert dpos(trio) == 100


def test_sramp_in_vp_mode_6_sets_jerk_from_accel_so_a_slower_decel_ramps_shorter() -> None:
    """VP_MODE 6, ACCEL 1000, DECEL 500, SRAMP 40: JERK = 1000/0.04 = 25000 for both
    ramps: up 0.1 + 0.04 s, down 0.2 + 500/25000 s (the SRAMP page: with another DECEL
    the deceleration differs). In VP_MODE 0 the down ramp would be 0.2 + 0.04 s."""
    for mode, down_rise in ((6, 500 / 25000), (0, 0.04)):
        trio = MC405()
        assert trio.send(f"BASE(0): VP_MODE={mode}: UNITS=1000: SPEED=100: ACCEL=1000: "
                         "DECEL=500: SRAMP=40") == []
        assert trio.send("MOVE(100.25)") == []
        at(trio, 40)
        assert dpos(trio) == pytest.approx(25000 * 0.04 ** 3 / 6, abs=1e-9)
        up, down = 0.1 + 0.04, 0.2 + down_rise
        end = end_tick(up + down + (100.25 - 100 * (up + down) / 2) / 100)
        at(trio, end - 1)
        assert dpos(trio) < 100.25
        at(trio, end)
        assert dpos(trio) == 100.25, mode


def test_vp_mode_takes_only_the_pages_modes() -> None:
    trio = MC405()
    assert trio.send("BASE(0): VP_MODE=5") == []
    assert trio.send("VP_MODE=3")[0].endswith("Parameter out of range")
    assert float(trio.query("?VP_MODE")) == 5
    assert float(trio.query("?STARTMOVE_SPEED")) == -1
    assert float(trio.query("?ENDMOVE_SPEED")) == -1
    assert trio.send("ENDMOVE_SPEED=-2")[0].endswith("Parameter out of range")
    assert float(trio.query("?ENDMOVE_SPEED")) == -1


# ---- FORCE_SPEED, STARTMOVE_SPEED, ENDMOVE_SPEED on merged moves -------------------------
def test_endmove_speed_page_example_1() -> None:
    """FORCE_SPEED 15 ENDMOVE_SPEED 10 MOVESP(20), then FORCE_SPEED 10 ENDMOVE_SPEED 5
    MOVESP(5), ACCEL 100: the first ramps 0 -> 15 (1.125 units), cruises, and slows to
    10 at its end (0.625 units); the second runs at 10 and, the last buffered, stops
    (its ENDMOVE_SPEED becomes 0)."""
    trio = MC405()
    assert trio.send("BASE(0): MERGE=ON: ACCEL=100: DECEL=100: SPEED=1") == []
    assert trio.send("FORCE_SPEED=15: ENDMOVE_SPEED=10: MOVESP(20): FORCE_SPEED=10: "
                     "ENDMOVE_SPEED=5: MOVESP(5)") == []
    cruise = (20 - 1.125 - 0.625) / 15
    slow_from = 0.15 + cruise
    seam = slow_from + 0.05
    at(trio, 1400)
    tau = 1.4 - slow_from
    assert dpos(trio) == pytest.approx(1.125 + 18.25 + 15 * tau - 50 * tau * tau, abs=1e-9)
    at(trio, 1600)
    assert dpos(trio) == pytest.approx(20 + 10 * (1.6 - seam), abs=1e-9)
    end = end_tick(seam + 4.5 / 10 + 0.1)
    assert end == 1967
    at(trio, end - 1)
    assert dpos(trio) < 25
    at(trio, end)
    assert dpos(trio) == 25


def test_force_speed_page_example_1_ramps_up_before_the_sp_move_and_down_after() -> None:
    """SPEED 15: MOVE(100), MOVESP(20) at FORCE_SPEED 30 (ENDMOVE_SPEED -1), MOVE(101),
    merged, ACCEL 100: the MOVE reaches 30 at its end (3.375 units of ramp), the MOVESP
    runs at 30 throughout, the last MOVE ramps back to 15 and stops."""
    trio = MC405()
    assert trio.send("BASE(0): MERGE=ON: ACCEL=100: DECEL=100: SPEED=15") == []
    assert trio.send("MOVE(100): FORCE_SPEED=30: ENDMOVE_SPEED=-1: MOVESP(20): MOVE(101)")\
        == []
    cruise1 = (100 - 1.125 - 3.375) / 15
    up_from = 0.15 + cruise1
    sp_start = up_from + 0.15
    at(trio, 6600)
    tau = 6.6 - up_from
    assert dpos(trio) == pytest.approx(1.125 + 95.5 + 15 * tau + 50 * tau * tau, abs=1e-9)
    at(trio, 7000)
    assert dpos(trio) == pytest.approx(100 + 30 * (7.0 - sp_start), abs=1e-9)
    third = sp_start + 20 / 30
    at(trio, 7400)
    tau = 7.4 - third
    assert dpos(trio) == pytest.approx(120 + 30 * tau - 50 * tau * tau, abs=1e-9)
    end = end_tick(third + 0.15 + (101 - 3.375 - 1.125) / 15 + 0.15)
    assert end == 14067
    at(trio, end - 1)
    assert dpos(trio) < 221
    at(trio, end)
    assert dpos(trio) == 221


def test_startmove_speed_slows_the_move_before_to_it() -> None:
    """FORCE_SPEED 20: MOVESP(10), then STARTMOVE_SPEED 5 MOVESP(10), ACCEL 100: the first
    slows 20 -> 5 at its end (1.875 units), the second starts at 5 and climbs to 20."""
    trio = MC405()
    assert trio.send("BASE(0): MERGE=ON: ACCEL=100: DECEL=100: FORCE_SPEED=20") == []
    assert trio.send("MOVESP(10): STARTMOVE_SPEED=5: MOVESP(10)") == []
    cruise = (10 - 2 - 1.875) / 20
    slow_from = 0.2 + cruise
    at(trio, 600)
    tau = 0.6 - slow_from
    assert dpos(trio) == pytest.approx(8.125 + 20 * tau - 50 * tau * tau, abs=1e-9)
    seam = slow_from + 0.15
    at(trio, 700)
    tau = 0.7 - seam
    assert dpos(trio) == pytest.approx(10 + 5 * tau + 50 * tau * tau, abs=1e-9)
    end = end_tick(2 * seam)
    assert end == 1313
    at(trio, end - 1)
    assert dpos(trio) < 20
    at(trio, end)
    assert dpos(trio) == 20


def test_interpolated_movesp_with_endmove_speed_slows_at_each_seam() -> None:
    """ENDMOVE_SPEED page example 2 on two axes: FORCE_SPEED 1000, ENDMOVE_SPEED 500,
    ACCEL 1e5, three vectors: each seam is crossed at 500; the path ends at rest."""
    trio = MC405()
    assert trio.send("BASE(0, 1): MERGE=ON: ACCEL=100000: DECEL=100000: "
                     "FORCE_SPEED=1000: ENDMOVE_SPEED=500") == []
    assert trio.send("MOVESP(100, 10): MOVESP(70, -10): MOVESP(120, 15)") == []
    a = 1e5
    lengths = [math.hypot(100, 10), math.hypot(70, 10), math.hypot(120, 15)]
    up0, down, up = 1000 ** 2 / (2 * a), (1000 ** 2 - 500 ** 2) / (2 * a), \
        (1000 ** 2 - 500 ** 2) / (2 * a)
    t1 = 1000 / a + (lengths[0] - up0 - down) / 1000 + 500 / a
    t2 = t1 + 500 / a + (lengths[1] - up - down) / 1000 + 500 / a
    t3 = t2 + 500 / a + (lengths[2] - up - up0) / 1000 + 1000 / a
    # the first tick past the first seam: the second vector entered at 500, climbing
    tick = end_tick(t1)
    at(trio, tick)
    tau = tick / 1000 - t1
    along = 500 * tau + a * tau * tau / 2
    assert 0 < tau < 500 / a
    assert dpos(trio, 0) == pytest.approx(100 + 70 * along / lengths[1], abs=1e-9)
    end = end_tick(t3)
    at(trio, end - 1)
    assert dpos(trio, 0) < 290
    at(trio, end)
    assert (dpos(trio, 0), dpos(trio, 1)) == (290, 15)


# ---- feed hold -------------------------------------------------------------------------
def held_machine(extra: str = "") -> MC405:
    trio = MC405()
    trio.world_view().set_input(7, True)  # the feed-hold input is active low: released
    assert trio.send(f"BASE(0): SPEED=10: ACCEL=100: DECEL=100: FHOLD_IN=7{extra}") == []
    return trio


def test_feed_hold_at_fhspeed_0_pauses_the_move_and_release_resumes_it() -> None:
    """SPEED 10, ACCEL 100, MOVE(100): at 1.05 s (10 units) the input goes low: the move
    slows to rest over 0.1 s (0.5 units) and waits, still MTYPE 1; released at 3 s it
    ramps back to 10 and ends 0.1 + (89.5 - 1) / 10 + 0.1 s later."""
    trio = held_machine()
    assert float(trio.query("?FHSPEED")) == 0
    assert trio.send("MOVE(100)") == []
    at(trio, 1050)
    assert dpos(trio) == pytest.approx(10.0, abs=1e-9)
    trio.world_view().set_input(7, False)
    at(trio, 1100)
    assert dpos(trio) == pytest.approx(10.0 + 10 * 0.05 - 50 * 0.05 ** 2, abs=1e-9)
    at(trio, 2000)
    assert dpos(trio) == pytest.approx(10.5, abs=1e-9)
    assert float(trio.query("?MTYPE AXIS(0)")) == 1
    assert int(float(trio.query("?AXISSTATUS AXIS(0)"))) & 128  # feedhold active (h)
    at(trio, 3000)
    assert dpos(trio) == pytest.approx(10.5, abs=1e-9)
    trio.world_view().set_input(7, True)
    at(trio, 3050)
    assert dpos(trio) == pytest.approx(10.5 + 50 * 0.05 ** 2, abs=1e-9)
    end = 3000 + end_tick(0.1 + (89.5 - 1.0) / 10 + 0.1)
    at(trio, end - 1)
    assert dpos(trio) < 100
    at(trio, end)
    assert dpos(trio) == 100
    assert float(trio.query("?MTYPE AXIS(0)")) == 0
    assert not int(float(trio.query("?AXISSTATUS AXIS(0)"))) & 128


def test_feed_hold_runs_the_move_at_fhspeed_while_the_input_is_low() -> None:
    """FHSPEED 2: held at 1.05 s the move slows 10 -> 2 over 0.08 s (0.48 units), runs at
    2, and released at 2.05 s climbs back to 10 over 0.08 s (0.48 units)."""
    trio = held_machine(": FHSPEED=2")
    assert trio.send("MOVE(100)") == []
    at(trio, 1050)
    trio.world_view().set_input(7, False)
    at(trio, 1500)
    assert dpos(trio) == pytest.approx(10.0 + 0.48 + 2 * (0.45 - 0.08), abs=1e-9)
    at(trio, 2050)
    here = 10.0 + 0.48 + 2 * (1.0 - 0.08)
    assert dpos(trio) == pytest.approx(here, abs=1e-9)
    trio.world_view().set_input(7, True)
    end = 2050 + end_tick(0.08 + (100 - here - 0.48 - 0.5) / 10 + 0.1)
    at(trio, end - 1)
    assert dpos(trio) < 100
    at(trio, end)
    assert dpos(trio) == 100


def test_a_move_loaded_under_feed_hold_waits_and_a_link_goes_on() -> None:
    """Input low before MOVE(5) on axis 0 (FHSPEED 0): it does not move; CONNECT on axis 2
    to axis 1's FORWARD is not speed controlled and follows (axis 1 has no feed hold)."""
    trio = held_machine()
    trio.world_view().set_input(7, False)
    assert trio.send("MOVE(5)") == []
    assert trio.send("BASE(1): SPEED=10: ACCEL=1e6: DECEL=1e6: FORWARD") == []
    assert trio.send("CONNECT(1, 1) AXIS(2)") == []
    at(trio, 500)
    assert dpos(trio, 0) == 0
    assert float(trio.query("?MTYPE AXIS(0)")) == 1
    assert dpos(trio, 2) == pytest.approx(dpos(trio, 1), abs=1e-9)
    assert dpos(trio, 1) > 4
    trio.world_view().set_input(7, True)
    end = 500 + end_tick(0.1 + (5 - 1.0) / 10 + 0.1)
    at(trio, end)
    assert dpos(trio, 0) == 5


# ---- CORNER_MODE -----------------------------------------------------------------------
def cornering(mode: int, extra: str) -> MC405:
    trio = MC405()
    assert trio.send("BASE(0, 1): MERGE=ON: ACCEL=100: DECEL=100: FORCE_SPEED=8: "
                     f"CORNER_MODE={mode}{extra}") == []
    assert trio.send("MOVESP(10, 0): MOVESP(0, 10)") == []
    return trio


def test_corner_beyond_stop_angle_stops_at_the_junction() -> None:
    """CORNER_MODE 2, STOP_ANGLE 25 degrees, a 90-degree corner at FORCE_SPEED 8: the
    first vector ends at rest (0.08 s and 0.32 units each ramp), the second starts from
    rest; without CORNER_MODE the path would turn at 8."""
    trio = cornering(2, ": STOP_ANGLE=25 * PI / 180")
    corner = 0.08 + (10 - 0.64) / 8 + 0.08
    at(trio, end_tick(corner))
    assert (dpos(trio, 0), dpos(trio, 1)) == (pytest.approx(10, abs=1e-9),
                                             pytest.approx(0, abs=1e-9))
    tick = end_tick(corner) + 40
    at(trio, tick)
    tau = tick / 1000 - corner
    assert dpos(trio, 1) == pytest.approx(50 * tau * tau, abs=1e-9)
    end = end_tick(2 * corner)
    at(trio, end - 1)
    assert dpos(trio, 1) < 10
    at(trio, end)
    assert (dpos(trio, 0), dpos(trio, 1)) == (10, 10)


def test_corner_between_decel_and_stop_angle_slows_in_proportion() -> None:
    """DECEL_ANGLE 30, STOP_ANGLE 120 degrees: a 90-degree corner is crossed at
    8 x (120 - 90) / (120 - 30) = 8/3."""
    trio = cornering(2, ": DECEL_ANGLE=30 * PI / 180: STOP_ANGLE=120 * PI / 180")
    v = 8 / 3
    slow = (8 - v) / 100
    d_slow = (64 - v * v) / 200
    cruise = (10 - 0.32 - d_slow) / 8
    corner = 0.08 + cruise + slow
    at(trio, 1300)  # slowing toward the corner
    tau = 1.3 - 0.08 - cruise
    assert dpos(trio, 0) == pytest.approx(0.32 + 8 * cruise + 8 * tau - 50 * tau * tau,
                                          abs=1e-9)
    at(trio, 1320)  # past it, climbing from 8/3 on the second vector
    tau = 1.32 - corner
    assert dpos(trio, 1) == pytest.approx(v * tau + 50 * tau * tau, abs=1e-9)
    end = end_tick(2 * corner)
    at(trio, end - 1)
    assert dpos(trio, 1) < 10
    at(trio, end)
    assert dpos(trio, 1) == 10


def test_no_corner_mode_turns_at_full_speed() -> None:
    trio = cornering(0, ": STOP_ANGLE=25 * PI / 180")
    end = end_tick(0.08 + (20 - 0.64) / 8 + 0.08)
    at(trio, end - 1)
    assert dpos(trio, 1) < 10
    at(trio, end)
    assert dpos(trio, 1) == 10


@pytest.mark.parametrize(("mode", "speed"), [
    (0, 10.0),  # no radius control
    (8, 10.0 * 3 / 6),  # the ratio of the radius to FULL_SP_RADIUS
    (8 + 16, math.sqrt(10.0 ** 2 / 6 * 3)),  # v^2/r within that at FULL_SP_RADIUS
])
def test_radius_speed_control_slows_a_tight_arc(mode: int, speed: float) -> None:
    """FULL_SP_RADIUS 6, FORCE_SPEED 10: a quarter circle of radius 3 (3 pi / 2 long),
    ACCEL 1e6 (ramps of microseconds)."""
    trio = MC405()
    assert trio.send("BASE(0, 1): ACCEL=1e6: DECEL=1e6: FORCE_SPEED=10: "
                     f"FULL_SP_RADIUS=6: CORNER_MODE={mode}") == []
    assert trio.send("MOVECIRCSP(3, 3, 3, 0, 1)") == []
    end = end_tick(3 * math.pi / 2 / speed + speed / 1e6)
    at(trio, end - 1)
    assert float(trio.query("?MTYPE AXIS(0)")) == 4
    at(trio, end)
    assert (dpos(trio, 0), dpos(trio, 1)) == (3, 3)


def test_an_arc_tangent_to_the_line_before_it_is_no_corner() -> None:
    """STOP_ANGLE 25 degrees: MOVESP(10, 0) then a quarter circle starting along +x
    (centre 5 above its start, anticlockwise): no change of direction, no stop; the
    path (10 + 5 pi / 2) runs at 8 throughout."""
    trio = MC405()
    assert trio.send("BASE(0, 1): MERGE=ON: ACCEL=100: DECEL=100: FORCE_SPEED=8: "
                     "CORNER_MODE=2: STOP_ANGLE=25 * PI / 180") == []
    assert trio.send("MOVESP(10, 0): MOVECIRCSP(5, 5, 0, 5, 0)") == []
    end = end_tick(0.08 + (10 + 5 * math.pi / 2 - 0.64) / 8 + 0.08)
    at(trio, end - 1)
    assert dpos(trio, 1) < 5
    at(trio, end)
    assert (dpos(trio, 0), dpos(trio, 1)) == (15, 5)


# ---- what the profiler reports ------------------------------------------------------------
def test_directions_of_the_sp_moves_loaded() -> None:
    """The pages' examples: MOVESP(10000, 10000) starts at 45 degrees from Y, MOVESP(0,
    10000) at 0; MOVESP(10000, -10000) ends at 135; MOVESP(0, 100) then MOVESP(100, 0)
    turns 90 degrees. Plain moves leave them."""
    trio = MC405()
    assert trio.send("BASE(0, 1): SPEED=1: FORCE_SPEED=1: MERGE=ON") == []

    def read(name: str) -> float:
        return float(trio.query(f"?{name}"))

    trio.send("MOVESP(10000, 10000)")
    assert read("START_DIR_LAST") == pytest.approx(math.pi / 4, abs=1e-4)
    trio.send("MOVESP(0, 10000)")
    assert read("START_DIR_LAST") == pytest.approx(0, abs=1e-4)
    trio.send("MOVESP(10000, -10000)")
    assert read("END_DIR_LAST") == pytest.approx(3 * math.pi / 4, abs=1e-4)
    trio.send("MOVESP(0, 100): MOVESP(100, 0)")
    assert read("CHANGE_DIR_LAST") == pytest.approx(math.pi / 2, abs=1e-4)
    trio.send("MOVE(-5, -5)")
    assert read("END_DIR_LAST") == pytest.approx(math.pi / 2, abs=1e-4)
    trio.send("MOVECIRCSP(0, 10, 0, 5, 1)")  # a half circle clockwise, centre above
    assert read("START_DIR_LAST") == pytest.approx(-math.pi / 2, abs=1e-4)
    assert read("END_DIR_LAST") == pytest.approx(math.pi / 2, abs=1e-4)
    assert read("CHANGE_DIR_LAST") == pytest.approx(math.pi, abs=1e-4)
    assert trio.send("START_DIR_LAST=1")[0].endswith("read only")


def test_endmove_buffer_is_the_end_of_every_move_buffered() -> None:
    trio = MC405()
    assert trio.send("BASE(0): SPEED=1: DEFPOS(10)") == []
    assert trio.send("MOVE(100): MOVE(150): MOVE(25)") == []
    assert float(trio.query("?ENDMOVE_BUFFER")) == 10 + 275
    trio.advance(1.0)
    assert float(trio.query("?ENDMOVE_BUFFER")) == 10 + 275


def test_vp_accel_and_vp_jerk_follow_the_profile() -> None:
    """A jerk-limited ramp (VP_MODE 5, JERK 50000, ACCEL 1000, SPEED 100): VP_JERK reads
    50000 while the acceleration rises (0.02 s), VP_ACCEL 1000 while it holds, 0 at
    speed, -1000 while slowing."""
    trio = MC405()
    assert trio.send("BASE(0): VP_MODE=5: SPEED=100: ACCEL=1000: DECEL=1000: JERK=50000: "
                     "MOVE(100)") == []
    at(trio, 10)
    assert float(trio.query("?VP_JERK")) == pytest.approx(50000, rel=1e-6)
    assert float(trio.query("?VP_ACCEL")) == pytest.approx(50000 * 0.0095, rel=1e-6)
    at(trio, 50)
    assert float(trio.query("?VP_ACCEL")) == pytest.approx(1000, rel=1e-6)
    assert float(trio.query("?VP_JERK")) == pytest.approx(0, abs=1e-3)
    at(trio, 500)
    assert float(trio.query("?VP_ACCEL")) == pytest.approx(0, abs=1e-6)
    ramp = 100 / 1000 + 1000 / 50000
    slowing = end_tick(2 * ramp + (100 - 100 * ramp) / 100) - 60
    at(trio, slowing)
    assert float(trio.query("?VP_ACCEL")) == pytest.approx(-1000, rel=1e-6)


# ---- SPEED changed while a move runs ----------------------------------------------------
def test_speed_written_during_a_move_acts_at_once() -> None:
    """SPEED 10, ACCEL 100, MOVE(100): at 2 s (19.5 units) SPEED=20: it climbs to 20 over
    0.1 s (1.5 units) and ends 0.1 + (80.5 - 1.5 - 2) / 20 + 0.2 s later."""
    trio = MC405()
    assert trio.send("BASE(0): SPEED=10: ACCEL=100: DECEL=100: MOVE(100)") == []
    at(trio, 2000)
    assert dpos(trio) == pytest.approx(19.5, abs=1e-9)
    assert trio.send("SPEED=20") == []
    at(trio, 2050)
    assert dpos(trio) == pytest.approx(19.5 + 10 * 0.05 + 50 * 0.05 ** 2, abs=1e-9)
    end = 2000 + end_tick(0.1 + (80.5 - 1.5 - 2.0) / 20 + 0.2)
    at(trio, end - 1)
    assert dpos(trio) < 100
    at(trio, end)
    assert dpos(trio) == 100


def test_a_forward_slows_when_speed_is_lowered() -> None:
    trio = MC405()
    assert trio.send("BASE(0): SPEED=10: ACCEL=100: DECEL=100: FORWARD") == []
    at(trio, 1000)
    assert trio.send("SPEED=5") == []
    at(trio, 2000)
    assert dpos(trio) == pytest.approx(9.5 + (100 - 25) / 200 + 5 * 0.95, abs=1e-9)


def test_an_sp_move_keeps_the_speed_it_was_loaded_with() -> None:
    trio = MC405()
    assert trio.send("BASE(0): SPEED=1: FORCE_SPEED=10: ACCEL=100: DECEL=100: "
                     "MOVESP(100)") == []
    at(trio, 1000)
    assert trio.send("SPEED=20") == []
    at(trio, 10099)
    assert dpos(trio) < 100
    at(trio, 10100)
    assert dpos(trio) == 100


def test_in_pos_needs_the_move_done_and_the_error_and_speed_within_their_limits() -> None:
    """A stepper axis (FE 0): with IN_POS_DIST and IN_POS_SPEED at their power-up 0 it is
    never in position (strictly less); set, it is once the moves end."""
    trio = MC405()
    assert trio.send("BASE(0): SPEED=10: ACCEL=100: DECEL=100") == []
    assert float(trio.query("?IN_POS")) == 0
    assert trio.send("IN_POS_DIST=0.01: IN_POS_SPEED=0.1") == []
    assert float(trio.query("?IN_POS")) == -1
    assert trio.send("MOVE(1): MOVE(1)") == []
    at(trio, 150)
    assert float(trio.query("?IN_POS")) == 0
    trio.advance(1.0)
    assert float(trio.query("?IN_POS")) == -1


def test_vector_buffered_is_the_path_length_left() -> None:
    """BASE(0, 1), SPEED 10, ACCEL 1e6: MOVE(30, 40) and MOVE(0, 20) hold 50 + 20; after
    2 s (20 of the first run) 50 are left; the MERGE OFF moves are separate runs."""
    trio = MC405()
    assert trio.send("BASE(0, 1): SPEED=10: ACCEL=1e6: DECEL=1e6") == []
    assert trio.send("MOVE(30, 40): MOVE(0, 20)") == []
    assert float(trio.query("?VECTOR_BUFFERED")) == pytest.approx(70, abs=1e-4)
    at(trio, 2000)
    assert float(trio.query("?VECTOR_BUFFERED")) == pytest.approx(50 + 10 * 10 / 2e6,
                                                                  abs=1e-4)
    trio.advance(10.0)
    assert float(trio.query("?VECTOR_BUFFERED")) == 0


def test_mspeedf_reads_mspeed_with_the_power_up_filter() -> None:
    trio = MC405()
    assert trio.send("BASE(0): SPEED=10: ACCEL=100: DECEL=100: MOVE(100)") == []
    at(trio, 50)
    assert float(trio.query("?MSPEED_FILTER")) == 1
    assert float(trio.query("?MSPEEDF")) == pytest.approx(100 * 0.0495, abs=1e-4)
    assert float(trio.query("?MSPEEDF")) == float(trio.query("?MSPEED"))


def test_force_speed_powers_up_at_1000() -> None:
    """The FORCE_SPEED page: 1000 at UNITS 1; MOVESP(10) with ACCEL 1e6 takes 10 ms."""
    trio = MC405()
    assert float(trio.query("?FORCE_SPEED")) == 1000
    assert trio.send("BASE(0): ACCEL=1e6: DECEL=1e6: MOVESP(10)") == []
    end = end_tick(10 / 1000 + 1000 / 1e6)
    at(trio, end - 1)
    assert dpos(trio) < 10
    at(trio, end)
    assert dpos(trio) == 10


def test_speed_changed_under_feed_hold_keeps_fhspeed() -> None:
    """FHSPEED 2 holding a move programmed at 10; SPEED=20 meanwhile: still 2 while held."""
    trio = held_machine(": FHSPEED=2")
    assert trio.send("MOVE(100)") == []
    at(trio, 1050)
    trio.world_view().set_input(7, False)
    at(trio, 1500)
    assert trio.send("SPEED=20") == []
    at(trio, 2000)
    assert float(trio.query("?VP_SPEED")) == pytest.approx(2, abs=1e-9)


def test_move_count_counts_each_move_as_it_becomes_the_running_one() -> None:
    """Three merged moves on axes 0 and 1 at 10 units/s (ACCEL 1e6): the first counts as
    it starts, each other as the path reaches it; a zero-length move and a jog do not."""
    trio = MC405()
    assert trio.send("BASE(0, 1): SPEED=10: ACCEL=1e6: DECEL=1e6: MERGE=ON") == []
    assert trio.send("MOVE_COUNT=5: MOVE_COUNT AXIS(1)=0") == []
    assert trio.send("MOVE(10, 0): MOVE(0, 10): MOVE(10, 0)") == []
    assert float(trio.query("?MOVE_COUNT")) == 6
    at(trio, 999)
    assert float(trio.query("?MOVE_COUNT AXIS(1)")) == 1
    at(trio, 1001)
    assert float(trio.query("?MOVE_COUNT AXIS(1)")) == 2
    trio.advance(3.0)
    assert float(trio.query("?MOVE_COUNT")) == 8
    assert trio.send("MERGE=OFF: MOVE(0, 0)") == []
    trio.advance(0.1)
    assert float(trio.query("?MOVE_COUNT")) == 8
    trio.world_view().set_input(7, True)
    assert trio.send("BASE(2): SPEED=10: JOGSPEED=5: FWD_JOG=7: MOVE(1)") == []
    trio.advance(0.5)
    assert float(trio.query("?MOVE_COUNT AXIS(2)")) == 1
    trio.world_view().set_input(7, False)
    trio.advance(0.5)
    assert float(trio.query("?MTYPE AXIS(2)")) == 14
    assert float(trio.query("?MOVE_COUNT AXIS(2)")) == 1
