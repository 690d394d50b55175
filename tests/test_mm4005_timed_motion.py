"""The time-based trajectory on the shared path planner (`path.plan_timed`): exact at every
element boundary, the speed continuous across the seams, speed changes over UC; and a
limit switch that becomes active at any moment stops the axis (and the run) to the tick."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxk.controllers.mm4005.controller import MM4005Controller
from maxk.firmware_model.path import plan_timed, timed_segments
from maxk.firmware_model.world import STUCK_ACTIVE


def speed(mm: MM4005Controller, axis: int) -> str:
    """The profile's velocity now, units/s to 4 decimals (DV reads the VA programmed)."""
    return f"{mm.engine.desired_velocity(axis):.4f}"


# ---- the planner ------------------------------------------------------------------------
_element = st.tuples(st.floats(0.01, 3.0),
                     st.lists(st.floats(-5.0, 5.0), min_size=2, max_size=2))


@settings(max_examples=40, deadline=None)
@given(elements=st.lists(_element, min_size=1, max_size=8), blend=st.floats(0.001, 2.0))
def test_timed_plan_is_exact_at_every_seam_continuous_and_never_backwards(
        elements: list[tuple[float, list[float]]], blend: float) -> None:
    durations = [d for d, _ in elements]
    segments = timed_segments([m for _, m in elements])
    plan = plan_timed(segments, durations, blend)
    t = 0.0
    here = [0.0, 0.0]
    for seg, duration, (_d, moves) in zip(segments, durations, elements, strict=True):
        t += duration
        here = [h + m for h, m in zip(here, moves, strict=True)]
        s, _v = plan.state(t - 1e-12)
        for k in (0, 1):
            assert plan.point(s, k) == pytest.approx(here[k], abs=1e-6)
        assert s == pytest.approx(seg.s0 + seg.length, abs=1e-6)
    assert plan.end_time == pytest.approx(sum(durations))
    pieces = plan.pieces
    assert pieces[0].v0 == 0.0 and pieces[-1].v(pieces[-1].duration) == pytest.approx(0.0)
    for p, q in zip(pieces, pieces[1:], strict=False):  # no step in the path speed, no gap
        assert q.v0 == pytest.approx(p.v(p.duration), abs=1e-9 * (1 + q.v0))
        assert q.t0 == pytest.approx(p.t0 + p.duration)
        assert q.s0 == pytest.approx(p.s1, abs=1e-9)
    for p in pieces:
        assert p.v0 >= -1e-9 and p.v(p.duration) >= -1e-9


def test_a_speed_change_is_spread_over_uc_across_the_seam() -> None:
    """Element 1: 1 unit in 1 s; element 2: 2 units in 1 s; UC 0.5. The seam speed is
    the lower mean (1); each element ramps over UC/2 at each end and cruises at the speed
    that keeps its end exact: (1 - 0.125) / 0.75 and (2 - 0.125) / 0.75."""
    mm = MM4005Controller("MM4005-2")
    mm.send("NC;1DC1;UC0.5;1DT1;1DX1;2DT1;1DX2;VC;0EC1")
    assert mm.send("TE") == ["TE@"]
    mm.engine.advance(1000)  # 0.5 s: cruising in element 1
    assert speed(mm, 1) == "1.1667"
    mm.engine.advance(1000)  # 1.0 s: on the seam
    assert mm.send("1TH;XC") == ["1TH1.0000", "XC1"] and speed(mm, 1) == "1.0000"
    mm.engine.advance(1)
    assert mm.engine.desired_velocity(1) == pytest.approx(1.0 + 0.0005 * (2.5 - 1) / 0.25,
                                                          abs=1e-9)
    mm.engine.advance(999)
    assert speed(mm, 1) == "2.5000"
    assert mm.run_until_idle()
    assert mm.engine.tick == 4000
    assert mm.send("1TH;1TP;XC;1MS") == ["1TH3.0000", "1TP3.0000", "XC2", "1MSD"]


def test_a_reversal_passes_through_rest_and_a_dwell_stands_still() -> None:
    """A turn of 90 degrees or more (here a reversal) has seam speed 0: no axis reverses at
    speed. An element that moves nothing (a dwell) stands still for its time."""
    mm = MM4005Controller("MM4005-2")
    mm.send("NC;1DC1;UC0.2;1DT1;1DX1;2DT0.5;3DT1;1DX-1;MB1,ME3,MN4;VC;0EC1")
    assert mm.send("TE") == ["TE@"]
    mm.engine.advance(2000)
    assert mm.send("1TH;1MS") == ["1TH1.0000", "1MSE"]
    assert abs(mm.engine.desired_velocity(1)) < 1e-9  # at rest at the reversal
    mm.engine.advance(500)
    assert mm.send("1TH") == ["1TH1.0000"] and abs(mm.engine.desired_velocity(1)) < 1e-9
    mm.run_until_idle()
    assert mm.engine.tick == 5000
    ticks = [p.tick for p in mm.engine.trace_points]
    assert ticks == [0, 1667, 3334]  # MN4: 3 pulses every 2.5 s / 3 from the start of 1


# ---- limits --------------------------------------------------------------------------------
def test_a_limit_stuck_active_mid_move_stops_the_move_at_that_tick() -> None:
    """1PA5 at VA 1, AC 4: cruising at 1 unit/s from 0.25 s. The + limit sticks active at
    1 s (0.875 units): the axis brakes at AC from that very tick, 0.25 s and 0.125 units,
    and MS shows the + limit (moving, then stopped on it)."""
    mm = MM4005Controller("MM4005-2")
    view = mm.world_view()
    mm.send("1VA1;1AC4;1PA5")
    mm.engine.advance(2000)
    view.fault("1", "plus", STUCK_ACTIVE)  # (outside the engine: acts at once)
    assert mm.send("1MS;1DP") == ["1MSM", "1DP1.0000"]  # moving, +, + limit; stops at 1
    mm.engine.advance(1)
    assert speed(mm, 1) == "0.9980"  # 1 - 4 x 0.5 ms: braking since tick 2000
    assert mm.run_until_idle() and mm.engine.tick == 2500
    assert mm.send("1TH;1TP;1MS") == ["1TH1.0000", "1TP1.0000", "1MSL"]
    assert mm.send("1PA6") == [] and mm.send("TE") == ["TED"]  # into the pressed limit
    assert mm.send("1PA0.5") == [] and mm.run_until_idle()  # away from it: allowed
    assert mm.send("1TP;1MS") == ["1TP0.5000", "1MSH"]  # still stuck active; direction -


def test_a_limit_set_inside_the_engine_pass_stops_the_move_on_its_tick() -> None:
    """A control-door trigger applies a world setting from inside the engine's pass (an
    observer due at tick 3001): the move brakes from that tick, not the next event."""
    mm = MM4005Controller("MM4005-2")
    view = mm.world_view()
    mm.send("2VA1;2AC4;2PA-5")
    mm.engine.add_observer(lambda _e: view.fault("2", "minus", STUCK_ACTIVE), 3001)
    mm.engine.advance(3001)
    assert mm.send("2TH") == ["2TH-1.3755"] and speed(mm, 2) == "-1.0000"  # braking from here
    mm.engine.advance(1)
    assert speed(mm, 2) == "-0.9980"
    assert mm.run_until_idle() and mm.engine.tick == 3501
    assert mm.send("2TH;2MS") == ["2TH-1.5010", "2MSP"]  # on the - limit, dir -; whole counts


def test_a_limit_in_a_time_based_run_aborts_it_and_its_pulses() -> None:
    """4 elements of 0.5 s, each 1 unit on axes 1 and 2 (2 units/s), a pulse at each
    element's start. Axis 2's - limit sticking active behind it changes nothing; its +
    limit sticking active at 0.75 s (1.5 units) ends the run there: no more pulses, XC
    stays 1, each axis brakes at its AC (4) from 2 units/s: 0.5 units in 0.5 s (1000 ticks)."""
    mm = MM4005Controller("MM4005-2")
    view = mm.world_view()
    mm.send("NC;1DC1;2DC1;1DT0.5;1DX1;2DX1;2DT0.5;1DX1;2DX1;3DT0.5;1DX1;2DX1;"
            "4DT0.5;1DX1;2DX1;MB1,ME4,MN5;VC;0EC1")
    mm.engine.advance(1100)
    view.fault("2", "minus", STUCK_ACTIVE)
    mm.engine.advance(400)
    assert mm.send("XC;NQ;1TH;2TH") == ["XC1", "NQ2", "1TH1.5000", "2TH1.5000"]
    view.fault("2", "plus", STUCK_ACTIVE)
    assert mm.run_until_idle() and mm.engine.tick == 2500
    # axis 2: both limits stuck active, direction +
    assert mm.send("XC;NQ;MS;1TH;2TH") == ["XC1", "NQ2", "1MSD,2MS\\", "1TH2.0000",
                                           "2TH2.0000"]
    assert mm.send("TE") == ["TE@"]


def test_a_switch_moved_onto_a_moving_axis_stops_it_there() -> None:
    """The + limit moved to count 500 while the axis passes 875 going up: pressed under an
    axis travelling into it, it acts on that tick (as a fault would)."""
    mm = MM4005Controller("MM4005-2")
    mm.send("1VA1;1AC4;1PA5")
    mm.engine.advance(2000)
    mm.world_view().set_limits("1", plus=500)
    assert mm.run_until_idle() and mm.engine.tick == 2500
    assert mm.send("1TP;1MS") == ["1TP1.0000", "1MSL"]


def test_the_xy_trajectory_ramps_down_along_its_path_at_a_limit_stuck_mid_path() -> None:
    """VV 1, VS 10: 0.1 s up to speed, then 1 unit/s along X. At 0.5 s (0.45 units) X's +
    limit sticks active: the path ramps down at VS, 0.05 units in 0.1 s; AT then 0."""
    mm = MM4005Controller("MM4005-2")
    assert mm.send("NT;VV1;VS10;LX2;CR1;CA90;LY3;ET;TE") == ["TE@"]
    mm.engine.advance(1000)
    assert mm.send("AT;1TP") == ["AT1", "1TP0.4500"]
    mm.world_view().fault("1", "plus", STUCK_ACTIVE)
    assert mm.run_until_idle() and mm.engine.tick == 1200
    assert mm.send("AT;1TP;2TP;MS") == ["AT0", "1TP0.5000", "2TP0.0000", "1MSL,2MSD"]


def test_time_scale_stretches_every_element_and_keeps_the_boundaries() -> None:
    """0EC2: each element lasts twice its DT; the axes still stand on every point."""
    mm = MM4005Controller("MM4005-2")
    mm.send("NC;1DC1;2DC1;1DT0.5;1DX1;2DX-1;2DT0.5;1DX0.5;2DX-1;MB1,ME2,MN3;VC;0EC2")
    assert mm.send("TE") == ["TE@"]
    mm.engine.advance(2000)
    assert mm.send("XC;1TH;2TH") == ["XC1", "1TH1.0000", "2TH-1.0000"]
    assert mm.run_until_idle() and mm.engine.tick == 4000
    assert mm.send("XC;1TH;2TH") == ["XC2", "1TH1.5000", "2TH-2.0000"]
    assert [p.tick for p in mm.engine.trace_points] == [0, 2000]


@settings(max_examples=15, deadline=None)
@given(elements=st.lists(st.tuples(st.integers(-300, 300), st.integers(-300, 300)),
                         min_size=1, max_size=12),
       dt=st.sampled_from([0.05, 0.1, 0.25, 0.3, 1.0]),
       uc=st.sampled_from([0.001, 0.1, 0.5, 2.0]))
def test_every_element_boundary_is_exact_and_every_pulse_marks_one(
        elements: list[tuple[int, int]], dt: float, uc: float) -> None:
    """Whatever the elements and UC, TH stands on the sum of the displacements at every
    element's end tick (displacements in whole counts: TP equals it too), XC counts it,
    and with MN = elements + 1 (equal times) pulse k fires on element k's start tick."""
    mm = MM4005Controller("MM4005-2")
    lines = ["NC", "1DC1", "2DC1", f"UC{uc}", "1VU1000", "2VU1000"]
    for i, (dx, dy) in enumerate(elements, start=1):
        lines.append(f"{i}DT{dt};1DX{dx / 1000};2DX{dy / 1000}")
    lines += [f"MB1,ME{len(elements)},MN{len(elements) + 1}", "VC", "0EC1"]
    for line in lines:
        assert mm.send(line) == [], line
    assert mm.send("TE") == ["TE@"]
    start, x, y, tick = mm.engine.tick, 0, 0, 0
    starts = []
    for number, (dx, dy) in enumerate(elements, start=1):
        starts.append(tick)
        tick += round(dt / 0.0005)
        x, y = x + dx, y + dy
        mm.engine.advance_to(start + tick)
        assert mm.send("1TH;2TH;1TP;2TP;XC") == [
            f"1TH{x / 1000:.4f}", f"2TH{y / 1000:.4f}", f"1TP{x / 1000:.4f}",
            f"2TP{y / 1000:.4f}", f"XC{number}"]
    assert mm.run_until_idle()
    assert [p.tick - start for p in mm.engine.trace_points] == starts
