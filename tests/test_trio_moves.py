"""The MC405's linked moves and the moves real programs add: CONNECT, MOVELINK, ADDAX,
MHELICAL, MOVEMODIFY, and MTYPE/NTYPE/MOVES_BUFFERED/REMAIN/ENDMOVE reporting them.

Every expected position is worked out here from the kinematics (trapezoids at ACCEL,
the MOVELINK profile, circles), independently of the machine's code, and compared at
exact servo ticks (1 ms each) with the machine's exact demand positions.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from maxk.controllers.trio.controller import MC405

DT = 0.001


def trapezoid(t: float, distance: float, speed: float, accel: float) -> float:
    """Where a rest-to-rest move at `speed` with `accel` both ways is `t` seconds in."""
    sign = 1.0 if distance >= 0 else -1.0
    d = abs(distance)
    peak = min(speed, math.sqrt(accel * d))
    ramp = peak / accel
    cruise = (d - peak * ramp) / peak
    if t <= 0:
        return 0.0
    if t < ramp:
        return sign * 0.5 * accel * t * t
    if t < ramp + cruise:
        return sign * (0.5 * peak * ramp + peak * (t - ramp))
    if t < 2 * ramp + cruise:
        left = 2 * ramp + cruise - t
        return sign * (d - 0.5 * accel * left * left)
    return distance


def link_profile(u: float, distance: float, span: float, acc: float, dec: float) -> float:
    """MOVELINK: the distance moved after u of the link's travel (ramps in link travel)."""
    u = min(max(u, 0.0), span)
    peak = distance / (span - (acc + dec) / 2)
    if u < acc:
        return peak * u * u / (2 * acc)
    if u > span - dec:
        return distance - peak * (span - u) ** 2 / (2 * dec)
    return peak * (u - acc / 2)


def dpos(trio: MC405, axis: int) -> float:
    return trio.machine.dpos(axis)


def read(trio: MC405, what: str) -> float:
    return float(trio.query(f"?{what}"))


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def master(setup: str = "SPEED=1000: ACCEL=10000: DECEL=10000") -> MC405:
    trio = MC405()
    assert trio.send(f"BASE(0): {setup}") == []
    return trio


# ---- CONNECT --------------------------------------------------------------------------------
def test_connect_follows_the_ratio_of_the_masters_demand_at_every_tick() -> None:
    trio = master()
    assert trio.send("UNITS AXIS(1)=10") == []
    assert trio.send("CONNECT(0.25,0) AXIS(1)") == []
    assert trio.send("MOVE(1000) AXIS(0)") == []
    for tick in (0, 1, 37, 100, 101, 550, 1050, 1099, 1100, 1400):
        at(trio, tick)
        m = trapezoid(tick * DT, 1000, 1000, 10000)
        assert dpos(trio, 0) == pytest.approx(m, abs=1e-9), tick
        assert dpos(trio, 1) == pytest.approx(0.25 * m / 10, abs=1e-9), tick  # counts/count
        assert read(trio, "MTYPE AXIS(1)") == 21
        assert read(trio, "LINK_AXIS AXIS(1)") == 0
    assert read(trio, "IDLE AXIS(1)") == 0  # a link never ends by itself
    assert trio.send("CANCEL AXIS(1)") == []
    assert (read(trio, "MTYPE AXIS(1)"), read(trio, "IDLE AXIS(1)")) == (0, -1)
    assert trio.send("MOVE(-500) AXIS(0)") == []
    trio.advance(2.0)
    assert dpos(trio, 1) == pytest.approx(25.0, abs=1e-9)  # cancelled: stays


def test_connect_again_changes_the_ratio_from_where_both_are() -> None:
    trio = master()
    trio.send("CONNECT(2,0) AXIS(1)")
    trio.send("MOVE(1000) AXIS(0)")
    at(trio, 300)
    m300 = trapezoid(0.3, 1000, 1000, 10000)
    assert trio.send("CONNECT(-0.5,0) AXIS(1)") == []  # same link axis: a new ratio
    assert trio.send("CONNECT(7,3) AXIS(1)") == []  # another link axis: ignored (manual)
    for tick in (300, 301, 700, 1100, 1500):
        at(trio, tick)
        m = trapezoid(tick * DT, 1000, 1000, 10000)
        assert dpos(trio, 1) == pytest.approx(2 * m300 - 0.5 * (m - m300), abs=1e-9)


@given(ratio=st.floats(-8, 8).filter(lambda r: abs(r) > 1e-3),
       units=st.sampled_from([1.0, 4.0, 1000.0, 0.5]),
       link_units=st.sampled_from([1.0, 10.0, 2048.0]),
       moves=st.lists(st.integers(-3000, 3000), min_size=1, max_size=3),
       speed=st.integers(50, 5000), probes=st.lists(st.integers(0, 4000), max_size=6))
def test_connect_ratio_holds_over_any_master_moves(ratio: float, units: float,
                                                   link_units: float, moves: list[int],
                                                   speed: int, probes: list[int]) -> None:
    """CONNECT's rule: slave counts = ratio x master counts moved, at every tick."""
    trio = MC405()
    trio.send(f"BASE(2): UNITS={link_units}: SPEED={speed / link_units}: "
              f"ACCEL={speed * 20 / link_units}: DECEL={speed * 20 / link_units}")
    trio.send(f"UNITS AXIS(5)={units}")
    trio.send(f"CONNECT({ratio},2) AXIS(5)")
    for counts in moves:
        assert trio.send(f"MOVE({counts / link_units}) AXIS(2)") == []
    for tick in sorted(probes):
        at(trio, max(tick, trio.tick))
        master_counts = dpos(trio, 2) * link_units
        assert dpos(trio, 5) * units == pytest.approx(ratio * master_counts, abs=1e-6)


# ---- MOVELINK ----------------------------------------------------------------------------
def test_movelink_ramps_over_the_link_distance_and_ends_on_the_exact_tick() -> None:
    trio = master()
    assert trio.send("MOVELINK(300, 600, 100, 200, 0) AXIS(1)") == []
    assert trio.send("MOVELINK(-300, 300, 0, 0, 0) AXIS(1)") == []  # buffered behind it
    assert (read(trio, "MTYPE AXIS(1)"), read(trio, "NTYPE AXIS(1)"),
            read(trio, "MOVES_BUFFERED AXIS(1)")) == (22, 22, 1)
    assert trio.send("MOVE(1000) AXIS(0)") == []
    # the master: a 0.1 s ramp of 50, then 1000/s: at 600 on tick 650, at 900 on tick 950
    for tick in (0, 60, 100, 200, 400, 500, 600, 649):
        at(trio, tick)
        m = trapezoid(tick * DT, 1000, 1000, 10000)
        assert dpos(trio, 1) == pytest.approx(link_profile(m, 300, 600, 100, 200),
                                              abs=1e-9), tick
        assert read(trio, "MTYPE AXIS(1)") == 22
    assert read(trio, "REMAIN AXIS(1)") == pytest.approx(300 - dpos(trio, 1), abs=1e-3)
    assert read(trio, "ENDMOVE AXIS(1)") == 300
    at(trio, 650)  # the first MOVELINK is done: the second takes over at link 600
    assert (read(trio, "MTYPE AXIS(1)"), read(trio, "NTYPE AXIS(1)")) == (22, 0)
    for tick in (650, 700, 800, 949):
        at(trio, tick)
        m = trapezoid(tick * DT, 1000, 1000, 10000)
        assert dpos(trio, 1) == pytest.approx(300 + link_profile(m - 600, -300, 300, 0, 0),
                                              abs=1e-9), tick
    at(trio, 950)
    assert (dpos(trio, 1), read(trio, "MTYPE AXIS(1)"), read(trio, "IDLE AXIS(1)")) == (
        0.0, 0, -1)


def test_repeated_movelinks_never_drift_off_the_link() -> None:
    """A flying shear's cycle of MOVELINKs, the link's speed not a whole number of units
    per servo tick: each cycle takes over at the exact link position the one before
    ended on, so cycle k is the same function of the master's position as cycle 0."""
    trio = master("SPEED=777.7: ACCEL=1e6: DECEL=1e6")
    trio.send("FORWARD AXIS(0)")
    at(trio, 5)
    start = dpos(trio, 0)
    span = 123.45
    for _ in range(6):  # sync 80 over 123.45 of the link, back over 0 (a jump back: D)
        trio.send(f"MOVELINK(40, {span}, 30, 30, 0) AXIS(1)")
        trio.send(f"MOVELINK(-40, {span}, 30, 30, 0) AXIS(1)")
    for tick in range(5, 1900, 37):
        at(trio, tick)
        u = dpos(trio, 0) - start
        cycle, rest = divmod(u, 2 * span)
        expected = (link_profile(rest, 40, span, 30, 30) if rest < span
                    else 40 + link_profile(rest - span, -40, span, 30, 30))
        if cycle >= 6:
            expected = 0.0
        assert dpos(trio, 1) == pytest.approx(expected, abs=1e-6), tick


@given(distance=st.integers(-500, 500), span=st.integers(1, 400),
       ramps=st.tuples(st.floats(0, 1), st.floats(0, 1)),
       moves=st.lists(st.integers(0, 600), min_size=1, max_size=3),
       probes=st.lists(st.integers(0, 3000), max_size=8))
def test_movelink_follows_its_profile_over_any_link_moves(
        distance: int, span: int, ramps: tuple[float, float], moves: list[int],
        probes: list[int]) -> None:
    """MOVELINK's rule at every tick: the profile of the link axis's travel since it
    started (forward moves of the link here), held at the end once the link has
    travelled the whole distance."""
    acc, dec = ramps[0] * span, ramps[1] * span
    if acc + dec > span:  # both shortened in proportion (as the manual says)
        acc, dec = acc * span / (acc + dec), dec * span / (acc + dec)
    trio = master("SPEED=700: ACCEL=9000: DECEL=9000")
    assert trio.send(f"MOVELINK({distance}, {span}, {ramps[0] * span!r}, "
                     f"{ramps[1] * span!r}, 0) AXIS(3)") == []
    for counts in moves:
        trio.send(f"MOVE({counts}) AXIS(0)")
    for tick in sorted(probes):
        at(trio, max(tick, trio.tick))
        u = dpos(trio, 0)
        expected = link_profile(u, distance, span, acc, dec)
        assert dpos(trio, 3) == pytest.approx(expected, abs=1e-6), (tick, u)
        assert read(trio, "MTYPE AXIS(3)") == (22 if u < span - 1e-6 else 0)


def test_movelink_options_start_at_a_link_position_and_repeat() -> None:
    trio = master("SPEED=1000: ACCEL=1e6: DECEL=1e6")
    trio.send("MOVELINK(100, 100, 0, 0, 0, 2, 400) AXIS(1)")  # waits for link 400
    trio.send("MOVELINK(10, 100, 50, 0, 0, 4) AXIS(2)")  # again and again, both ways
    trio.send("MOVE(600) AXIS(0)")
    for tick in range(0, 800, 25):
        at(trio, tick)
        m = dpos(trio, 0)
        assert dpos(trio, 1) == pytest.approx(link_profile(m - 400, 100, 100, 0, 0),
                                              abs=1e-9), tick
        cycles, rest = divmod(m, 100)
        assert dpos(trio, 2) == pytest.approx(10 * cycles
                                              + link_profile(rest, 10, 100, 50, 0), abs=1e-9)
    assert read(trio, "IDLE AXIS(1)") == -1 and read(trio, "MTYPE AXIS(2)") == 22
    trio.send("MOVE(-250) AXIS(0)")  # the repeating link runs backwards with it
    trio.advance(1.0)
    assert dpos(trio, 2) == pytest.approx(30 + link_profile(50, 10, 100, 50, 0), abs=1e-9)


def test_cancel_ends_the_running_link_and_the_buffered_one_starts() -> None:
    trio = master()
    trio.send("MOVELINK(100, 1000, 0, 0, 0) AXIS(1)")
    trio.send("MOVELINK(50, 100, 0, 0, 0) AXIS(1)")
    trio.send("MOVE(1000) AXIS(0)")
    at(trio, 300)
    here = dpos(trio, 1)
    link = dpos(trio, 0)
    assert trio.send("CANCEL AXIS(1)") == []
    at(trio, 350)
    assert dpos(trio, 1) == pytest.approx(here + 0.5 * (dpos(trio, 0) - link), abs=1e-9)
    assert trio.send("RAPIDSTOP") == []
    assert read(trio, "IDLE AXIS(1)") == -1


@pytest.mark.parametrize(("line", "error"), [
    ("MOVELINK(10, 0, 0, 0, 0) AXIS(1)", "Parameter out of range"),
    ("MOVELINK(10, 100, -1, 0, 0) AXIS(1)", "Parameter out of range"),
    ("MOVELINK(10, 100, 0, 0, 0, 512) AXIS(1)", "Parameter out of range"),  # R_MARK
    ("MOVELINK(10, 100, 0, 0, 0, 2) AXIS(1)", "Parameter out of range"),  # no position
    ("MOVELINK(10, 100, 0, 0, 1) AXIS(1)", "Invalid axis number"),
    ("MOVELINK(10, 100, 0, 0, 99) AXIS(1)", "Invalid axis number"),
    ("CONNECT(1, 1) AXIS(1)", "Invalid axis number"),
    ("CONNECT(1, 2.5) AXIS(1)", "Invalid axis number"),
    ("ADDAX(1) AXIS(1)", "Invalid axis number"),
    ("MHELICAL(10, 0, 5, 0, 2, 3)", "Parameter out of range"),
    ("MHELICAL(10, 0, 5, 0, 0, 3, 2)", "Parameter out of range"),
    ("MHELICAL(10, 0, 0, 0, 0, 3)", "Parameter out of range"),
])
def test_bad_linked_moves_are_refused_and_load_nothing(line: str, error: str) -> None:
    trio = master()
    reply = trio.send(line)
    assert len(reply) == 1 and error in reply[0], reply
    for axis in (0, 1, 2):
        assert read(trio, f"IDLE AXIS({axis})") == -1
        assert read(trio, f"MTYPE AXIS({axis})") == 0


def test_a_loop_of_links_is_refused() -> None:
    trio = master()
    assert trio.send("CONNECT(1,0) AXIS(1)") == []
    assert trio.send("MOVELINK(1, 10, 0, 0, 1) AXIS(2)") == []
    for line in ("CONNECT(1,2) AXIS(0)", "ADDAX(2) AXIS(0)", "CAMBOX(0,1,1,10,1) AXIS(0)",
                 "MOVELINK(1, 10, 0, 0, 2) AXIS(0)"):
        reply = trio.send(line)
        assert len(reply) == 1 and "Parameter out of range" in reply[0], (line, reply)
    assert read(trio, "IDLE AXIS(0)") == -1


# ---- ADDAX ---------------------------------------------------------------------------------
def test_addax_superimposes_and_keeps_what_it_added() -> None:
    trio = master("SPEED=100: ACCEL=1000: DECEL=1000")
    trio.send("BASE(1): SPEED=50: ACCEL=1000: DECEL=1000")
    assert trio.send("ADDAX(0) AXIS(1)") == []
    assert read(trio, "ADDAX_AXIS AXIS(1)") == 0
    trio.send("MOVE(100) AXIS(0)")
    trio.send("MOVE(30) AXIS(1)")
    for tick in (0, 50, 400, 700, 1100, 1500):
        at(trio, tick)
        own = trapezoid(tick * DT, 30, 50, 1000)
        added = trapezoid(tick * DT, 100, 100, 1000)
        assert dpos(trio, 1) == pytest.approx(own + added, abs=1e-9), tick
    assert trio.send("ADDAX(-1) AXIS(1)") == []
    assert read(trio, "ADDAX_AXIS AXIS(1)") == -1
    trio.send("MOVE(-100) AXIS(0)")
    trio.advance(2.0)
    assert dpos(trio, 1) == pytest.approx(130.0, abs=1e-9)
    assert trio.send("MOVEABS(0) AXIS(1)") == []  # MOVEABS aims DPOS, the shift included
    trio.advance(3.0)
    assert dpos(trio, 1) == pytest.approx(0.0, abs=1e-9)


def test_addax_corrects_a_connected_axis() -> None:
    """The registration pattern: the slave is CONNECTed to the line, and corrections
    moved on a virtual axis are added to it."""
    trio = master()
    trio.send("CONNECT(1,0) AXIS(1)")
    trio.send("ADDAX(7) AXIS(1)")
    trio.send("BASE(7): SPEED=20: ACCEL=1000: DECEL=1000")
    trio.send("MOVE(1000) AXIS(0)")
    at(trio, 200)
    trio.send("MOVE(5) AXIS(7)")
    for tick in (200, 250, 300, 600, 1200):
        at(trio, tick)
        line = trapezoid(tick * DT, 1000, 1000, 10000)
        correction = trapezoid((tick - 200) * DT, 5, 20, 1000)
        assert dpos(trio, 1) == pytest.approx(line + correction, abs=1e-9), tick


# ---- MHELICAL -----------------------------------------------------------------------------
def test_mhelical_runs_the_circle_and_rises_along_it() -> None:
    trio = MC405()
    trio.send("BASE(0,1,2): SPEED=100: ACCEL=1000: DECEL=1000")
    # a clockwise quarter from (0,0) about (100,0) to (100,100), the third axis 30 up
    # following (mode 1: the path speed is the circle's, help MHELICAL)
    assert trio.send("MHELICAL(100, 100, 100, 0, 1, 30, 1)") == []
    length = math.pi * 100 / 2
    end_tick = math.ceil(round((length / 100 + 0.1) / DT, 6))
    for tick in (1, 50, 100, 800, 1500, end_tick - 1):
        at(trio, tick)
        s = trapezoid(tick * DT, length, 100, 1000)
        angle = math.pi - s / 100
        assert dpos(trio, 0) == pytest.approx(100 + 100 * math.cos(angle), abs=1e-9), tick
        assert dpos(trio, 1) == pytest.approx(100 * math.sin(angle), abs=1e-9), tick
        assert dpos(trio, 2) == pytest.approx(30 * s / length, abs=1e-9), tick
        assert read(trio, "MTYPE AXIS(0)") == 3
        assert read(trio, "VP_SPEED AXIS(0)") == pytest.approx(
            (trapezoid(tick * DT + 1e-7, length, 100, 1000)
             - trapezoid(tick * DT - 1e-7, length, 100, 1000)) / 2e-7, abs=1e-3)
    at(trio, end_tick)
    assert [dpos(trio, a) for a in (0, 1, 2)] == [100.0, 100.0, 30.0]
    assert read(trio, "MTYPE AXIS(0)") == 0


def test_mhelical_merges_with_moves_on_the_same_three_axes() -> None:
    trio = MC405()
    trio.send("BASE(0,1,2): SPEED=100: ACCEL=1000: MERGE=ON")
    trio.send("MOVE(50, 0, 0)")
    trio.send("MHELICAL(0, 0, 0, 20, 0, -10)")  # a whole turn about (50,20), 10 down
    trio.send("MOVE(-50, 0, 10)")
    assert (read(trio, "MTYPE AXIS(0)"), read(trio, "NTYPE AXIS(0)"),
            read(trio, "MOVES_BUFFERED AXIS(0)")) == (1, 3, 2)
    at(trio, 700)
    assert read(trio, "MTYPE AXIS(0)") == 3
    assert (dpos(trio, 0) - 50) ** 2 + (dpos(trio, 1) - 20) ** 2 == pytest.approx(400)
    trio.advance(5.0)
    assert [dpos(trio, a) for a in (0, 1, 2)] == [0.0, 0.0, 0.0]


# ---- MOVEMODIFY ---------------------------------------------------------------------------
def test_movemodify_moves_the_end_further_on() -> None:
    trio = master("SPEED=100: ACCEL=1000: DECEL=1000")
    trio.send("MOVE(1000) AXIS(0)")
    at(trio, 1000)  # cruising at 100 after the 5-unit ramp: at 95
    assert dpos(trio, 0) == pytest.approx(95.0)
    assert trio.send("MOVEMODIFY(200) AXIS(0)") == []
    assert (read(trio, "MTYPE AXIS(0)"), read(trio, "ENDMOVE AXIS(0)")) == (5, 200)
    for tick in (1000, 1500, 2000, 2050, 2099):  # 100 more at 100/s, then a 0.1 s stop
        at(trio, tick)
        t = (tick - 1000) * DT
        expected = 95 + 100 * t if t <= 1.0 else 200 - 0.5 * 1000 * (1.1 - t) ** 2
        assert dpos(trio, 0) == pytest.approx(expected, abs=1e-9), tick
    at(trio, 2100)
    assert (dpos(trio, 0), read(trio, "IDLE AXIS(0)")) == (200.0, -1)


def test_movemodify_behind_the_axis_stops_and_comes_back() -> None:
    trio = master("SPEED=100: ACCEL=1000: DECEL=1000")
    trio.send("MOVE(1000) AXIS(0)")
    at(trio, 1000)
    assert trio.send("MOVEMODIFY(50) AXIS(0)") == []
    assert read(trio, "NTYPE AXIS(0)") == 5  # the way back is held behind the stop
    for tick in (1050, 1100, 1400, 1650):
        at(trio, tick)
        t = (tick - 1000) * DT
        expected = (95 + 100 * t - 500 * t * t if t <= 0.1
                    else 100 - trapezoid(t - 0.1, 50, 100, 1000))
        assert dpos(trio, 0) == pytest.approx(expected, abs=1e-9), tick
    at(trio, 1700)
    assert (dpos(trio, 0), read(trio, "MTYPE AXIS(0)")) == (50.0, 0)


def test_movemodify_on_an_idle_axis_is_an_absolute_move_and_endmove_steps() -> None:
    trio = master("SPEED=100: ACCEL=1000: DECEL=1000")
    assert trio.send("DEFPOS(10) AXIS(0)") == []
    assert trio.send("MOVEMODIFY(60) AXIS(0)") == []
    assert read(trio, "MTYPE AXIS(0)") == 5
    trio.advance(2.0)
    assert dpos(trio, 0) == 60.0
    assert trio.send("ENDMOVE AXIS(0)=75.5") == []  # idle: a step change of the demand
    assert (dpos(trio, 0), read(trio, "ENDMOVE AXIS(0)")) == (75.5, 75.5)
    trio.send("CONNECT(1,3) AXIS(0)")
    reply = trio.send("MOVEMODIFY(0) AXIS(0)")
    assert len(reply) == 1 and "Parameter out of range" in reply[0]


# ---- the reports --------------------------------------------------------------------------
def test_mtype_ntype_and_moves_buffered_follow_the_buffer() -> None:
    trio = master("SPEED=1000: ACCEL=10000: DECEL=10000")
    assert [read(trio, f"{p} AXIS(0)") for p in ("MTYPE", "NTYPE", "MOVES_BUFFERED")] == [
        0, 0, 0]
    trio.send("MOVE(100) AXIS(0)")
    trio.send("MOVEABS(0) AXIS(0)")
    trio.send("BASE(0,1): MOVECIRC(0, 0, 10, 0, 1)")
    assert [read(trio, f"{p} AXIS(0)") for p in ("MTYPE", "NTYPE", "MOVES_BUFFERED")] == [
        1, 2, 2]
    assert [read(trio, f"{p} AXIS(1)") for p in ("MTYPE", "NTYPE", "MOVES_BUFFERED")] == [
        0, 4, 1]
    at(trio, 200)  # the first move is done on tick 200, the second runs
    assert [read(trio, f"{p} AXIS(0)") for p in ("MTYPE", "NTYPE", "MOVES_BUFFERED")] == [
        2, 4, 1]
    at(trio, 400)
    assert read(trio, "MTYPE AXIS(1)") == 4
    trio.advance(2.0)
    trio.send("FORWARD AXIS(0)")
    trio.send("CONNPATH(0) AXIS(3)")
    assert (read(trio, "MTYPE AXIS(0)"), read(trio, "MTYPE AXIS(3)"),
            read(trio, "LINK_AXIS AXIS(3)")) == (10, 23, 0)
    trio.send("CANCEL AXIS(0)")
    trio.advance(1.0)
    trio.send("REVERSE AXIS(0)")
    assert read(trio, "MTYPE AXIS(0)") == 11
    at(trio, trio.tick + 10)  # 10 ms into its ramp: the last servo cycle's mean speed
    assert read(trio, "MSPEED AXIS(0)") == pytest.approx(-5000 * (0.01 ** 2 - 0.009 ** 2)
                                                         / DT)


def test_a_flying_shear_program_runs_as_written() -> None:
    """A program as people write them: a virtual line axis CONNECTed from an encoder
    axis, the shear synchronised by MOVELINKs each cut, waiting on NTYPE."""
    trio = MC405()
    program = "\n".join([
        "BASE(0): SPEED=500: ACCEL=5000: DECEL=5000",
        "CONNECT(2, 0) AXIS(4)",
        "cuts = 0",
        "BASE(1)",
        "REPEAT",
        "  MOVELINK(0, 50, 0, 0, 4)",
        "  MOVELINK(30, 60, 30, 0, 4)",
        "  MOVELINK(-30, 90, 45, 45, 4)",
        "  IF cuts = 0 THEN FORWARD AXIS(0)",
        "  WAIT UNTIL NTYPE = 0",
        "  cuts = cuts + 1",
        "UNTIL cuts = 3",
        "WAIT IDLE",
        'PRINT "shear at "; DPOS AXIS(1); " after "; cuts',
        "CANCEL AXIS(0)",
    ])
    assert trio.load("SHEAR", program) == []
    session = trio.open_session()
    assert trio.send('RUN "SHEAR"') == []
    trio.advance(0.05)
    start = 0.0  # the line was at rest when the first MOVELINK took it up
    samples = []
    for _ in range(60):
        trio.advance(ticks=20)
        samples.append((dpos(trio, 4) - start, dpos(trio, 1)))
    for u, shear in samples:
        cycle, rest = divmod(u, 200)
        if cycle >= 3:
            continue
        expected = (0.0 if rest < 50 else link_profile(rest - 50, 30, 60, 30, 0) if rest < 110
                    else 30 + link_profile(rest - 110, -30, 90, 45, 45))
        assert shear == pytest.approx(expected, abs=1e-6), u
    trio.advance(2.0)
    assert b"shear at 0 after 3" in session.read()


def test_extreme_linked_moves_stay_finite_or_are_refused() -> None:
    trio = master("SPEED=1000: ACCEL=1e6: DECEL=1e6")
    reply = trio.send("MOVELINK(1e15, 1e-300, 0, 0, 0, 4) AXIS(1)")
    assert len(reply) == 1 and "Parameter out of range" in reply[0]
    for line in ("MOVELINK(1e20, 10, 0, 0, 0) AXIS(1)", "CONNECT(1e300, 0) AXIS(1)",
                 "MHELICAL(1, 0, 1, 0, 0, 1e300)", "MOVEMODIFY(1e300) AXIS(0)",
                 "ENDMOVE AXIS(0) = 1e300"):
        reply = trio.send(line)
        assert len(reply) == 1 and "Parameter out of range" in reply[0], (line, reply)
    assert trio.send("MOVELINK(5e14, 1e-6, 0, 0, 0, 4) AXIS(2)") == []  # the shortest
    assert trio.send("CONNECT(1e15, 0) AXIS(3)") == []
    trio.send("MOVE(1000) AXIS(0)")
    trio.advance(2.0)
    for axis in (2, 3):
        assert math.isfinite(dpos(trio, axis))
        assert math.isfinite(read(trio, f"MSPEED AXIS({axis})"))
    assert trio.query("?PWM_ENCODER AXIS(3)") != ""
    trio.reset()  # a restart (EX) drops every link and ADDAX
    assert [read(trio, f"MTYPE AXIS({a})") for a in (1, 2, 3)] == [0, 0, 0]


def test_a_program_loading_links_endlessly_waits_on_the_buffer() -> None:
    """A program that loads MOVELINKs faster than they run holds at 16 per axis."""
    trio = MC405()
    assert trio.load("FILL", "\n".join([
        "BASE(1)", "n = 0", "WHILE n < 100", "  MOVELINK(1, 10, 0, 0, 0)", "  n = n + 1",
        "WEND"])) == []
    assert trio.send('RUN "FILL"') == []
    trio.advance(1.0)
    assert read(trio, "MOVES_BUFFERED AXIS(1)") == 15 and read(trio, "MTYPE AXIS(1)") == 22
    trio.send("BASE(0): SPEED=1000: ACCEL=1e6: DECEL=1e6: MOVE(1000)")
    trio.advance(2.0)
    assert dpos(trio, 1) == pytest.approx(100.0, abs=1e-9)  # every one ran, in order
    assert read(trio, "IDLE AXIS(1)") == -1


def test_a_cambox_on_a_connected_axis_ends_and_a_movelink_behind_it_starts() -> None:
    """A CAMBOX linked to an axis that is itself CONNECTed ends on the tick the link
    has travelled its distance; the MOVELINK buffered behind it then takes over."""
    trio = master("SPEED=100: ACCEL=1e6: DECEL=1e6")
    trio.send("TABLE(0, 0, 40, 80)")
    trio.send("CONNECT(2,0) AXIS(5)")  # the cam's master runs at twice axis 0
    assert trio.send("CAMBOX(0, 2, 1, 100, 5) AXIS(6)") == []
    assert trio.send("MOVELINK(10, 20, 0, 0, 5) AXIS(6)") == []
    assert (read(trio, "MTYPE AXIS(6)"), read(trio, "NTYPE AXIS(6)")) == (20, 22)
    trio.send("MOVE(100) AXIS(0)")
    for tick in (0, 100, 300, 499):
        at(trio, tick)
        travel = dpos(trio, 5)
        assert dpos(trio, 6) == pytest.approx(80 * travel / 100, abs=1e-9), tick
        assert read(trio, "MTYPE AXIS(6)") == 20
    # axis 0 ramps in 0.1 ms (0.005 of travel lost), so the cam's master, 200 t - 0.01,
    # passes 100 between ticks 500 and 501
    at(trio, 500)
    assert read(trio, "MTYPE AXIS(6)") == 20
    at(trio, 501)
    assert (read(trio, "MTYPE AXIS(6)"), dpos(trio, 6)) == (22, 80.0)
    taken_up = dpos(trio, 5)  # (not a MOVELINK before it: from the tick's position)
    at(trio, 550)
    assert dpos(trio, 6) == pytest.approx(80 + 10 * (dpos(trio, 5) - taken_up) / 20,
                                          abs=1e-9)
    trio.advance(1.0)
    assert (dpos(trio, 6), read(trio, "IDLE AXIS(6)")) == (pytest.approx(90.0), -1)
