"""Trajectory definition (manual 5.7), ET checks and pulses synchronized to a trajectory
(manual 6.1.2, the seed), through the language and on the personality directly."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from maxk.commands.mm4005 import FakeMM4005, MM4005Session
from maxk.personalities.mm4005 import Arc, Line, Trajectory, maximum_pulse_number
from maxk.personalities.mm4005.geometry import arc_to_point, wrap_deg
from maxk.personalities.mm4005.pulses import pulse_points

SEED = ["NT", "LX10", "CR10, CA90", "LY20", "CX10, CY30", "NB2, NE3, NI10.1, NN11"]
QUARTER = 10.0 * math.pi / 2.0  # a 90-degree arc of radius 10


def _session(axes: int = 2) -> tuple[FakeMM4005, MM4005Session]:
    machine = FakeMM4005(axis_count=axes)
    return machine, MM4005Session(machine)


def _ask(session: MM4005Session, *lines: str) -> bytes:
    for line in lines:
        session.feed(line.encode() + b"\r")
    return session.read()


def _seed() -> tuple[FakeMM4005, MM4005Session]:
    machine, s = _session()
    assert _ask(s, *SEED) == b""
    assert _ask(s, "TE") == b"TE@\r"
    return machine, s


# --- geometry of the seed example --------------------------------------------------------
def test_seed_elements_are_exact_lines_and_arcs() -> None:
    machine, _ = _seed()
    g = [e.geometry for e in machine.trajectory.elements]
    assert g[0] == Line((0.0, 0.0), (10.0, 0.0))
    assert isinstance(g[1], Arc) and g[1].centre == (10.0, 10.0) and g[1].radius == 10.0
    assert (g[1].start_angle, g[1].sweep, g[1].end) == (-90.0, 90.0, (20.0, 10.0))
    assert g[2] == Line((20.0, 10.0), (20.0, 20.0))
    assert isinstance(g[3], Arc) and g[3].centre == (10.0, 20.0) and g[3].radius == 10.0
    assert (g[3].start_angle, g[3].sweep, g[3].end) == (0.0, 90.0, (10.0, 30.0))
    assert [x.length for x in g] == [10.0, QUARTER, 10.0, QUARTER]
    assert g[3].exit_angle == 180.0


def test_seed_listing_and_counts() -> None:
    _, s = _seed()
    assert _ask(s, "XT") == b"XT4\r"
    assert _ask(s, "LT") == (
        b"1LTLX X10.0000 Y0.0000 L10.0000\r"
        b"2LTCA X20.0000 Y10.0000 R10.0000 A90.0000 L15.7080\r"
        b"3LTLY X20.0000 Y20.0000 L10.0000\r"
        b"4LTCY X10.0000 Y30.0000 R10.0000 A90.0000 L15.7080\r")
    assert _ask(s, "3LT") == b"3LTLY X20.0000 Y20.0000 L10.0000\r"
    assert _ask(s, "XE") == b"XE4LTCY X10.0000 Y30.0000 R10.0000 A90.0000 L15.7080\r"
    assert _ask(s, "NB?;NE?;NN?;NI?") == b"NB2\rNE3\rNN11\rNI10.1\r"


def test_seed_pulses_are_equally_spaced_from_start_of_nb_to_end_of_ne() -> None:
    """NN11 over elements 2..3: CPTL = 5*pi + 10, ten equal steps. The seed's 'NI10.1 ...
    each 0.1 unit' cannot hold (10 x 0.1 != CPTL); the step follows from the geometry."""
    machine, s = _seed()
    assert _ask(s, "NS", "ET", "TE") == b"TE@\r"
    plan = machine.runs[-1].pulses
    assert plan is not None
    cptl = QUARTER + 10.0
    assert plan.count == 11 and plan.cptl == pytest.approx(cptl)
    assert plan.step == pytest.approx(cptl / 10)
    distances = [p.pulsed_distance for p in plan.points]
    assert distances[0] == 0.0 and distances[-1] == pytest.approx(cptl)
    steps = [b - a for a, b in zip(distances, distances[1:], strict=False)]
    assert steps == pytest.approx([cptl / 10] * 10)
    assert [p.path_distance - 10.0 for p in plan.points] == pytest.approx(distances)
    assert plan.points[0].point == (10.0, 0.0) and plan.points[-1].point == (20.0, 20.0)
    on_arc = [p for p in plan.points if p.element == 2]
    on_line = [p for p in plan.points if p.element == 3]
    assert len(on_arc) == 7 and len(on_line) == 4
    for p in on_arc:
        assert math.hypot(p.point[0] - 10.0, p.point[1] - 10.0) == pytest.approx(10.0)
    for p in on_line:
        assert p.point[0] == 20.0 and 10.0 <= p.point[1] <= 20.0
    # the 4th pulse on the arc: 3 steps of (5 pi + 10) / 10 from its start
    angle = -90.0 + math.degrees(3 * cptl / 10 / 10.0)
    expected = (10.0 + 10.0 * math.cos(math.radians(angle)),
                10.0 + 10.0 * math.sin(math.radians(angle)))
    assert plan.points[3].point == pytest.approx(expected)


def test_seed_runs_and_reports_the_element_under_execution() -> None:
    machine, s = _seed()
    _ask(s, "VV10", "NS", "ET")
    assert _ask(s, "AT", "MS") == b"AT1\r1MSE,2MSE\r"
    machine.advance(1500)  # 15 units along: in the first arc
    assert _ask(s, "AT") == b"AT2\r"
    machine.advance(1500)  # 30 units: on the LY line
    assert _ask(s, "AT") == b"AT3\r"
    machine.advance(3000)  # past the end (51.4 units)
    assert _ask(s, "AT", "TP", "MS") == b"AT0\r1TP10.0000,2TP30.0000\r1MSD,2MSD\r"


def test_moves_on_trajectory_axes_are_refused_while_it_runs_and_st_stops_it() -> None:
    machine, s = _seed()
    _ask(s, "ET")
    machine.advance(5000)
    assert _ask(s, "1PA0", "TE") == b"TED\r"
    assert _ask(s, "2OR", "TE") == b"TED\r"
    assert _ask(s, "ST", "AT", "TP") == b"AT0\r1TP5.0000,2TP0.0000\r"
    machine.advance(5000)
    assert _ask(s, "MS", "TP") == b"1MSD,2MSD\r1TP5.0000,2TP0.0000\r"


# --- ET conditions ---------------------------------------------------------------------------
def test_et_without_elements_is_refused() -> None:
    machine, s = _session()
    assert _ask(s, "NT", "ET", "TE") == b"TEK\r"
    assert machine.runs == []


@pytest.mark.parametrize(("nb", "ne"), [(0, 3), (3, 3), (3, 2), (2, 5), (5, 6)])
def test_et_refuses_pulse_elements_out_of_order_or_range(nb: int, ne: int) -> None:
    machine, s = _seed()
    assert _ask(s, f"NB{nb}", f"NE{ne}", "NS", "ET", "TE") == b"TEN\r"
    assert machine.runs == []
    assert machine.trajectory.pulses.armed  # nothing changed: NS still armed


def test_et_accepts_ne_equal_to_the_element_count() -> None:
    machine, s = _seed()
    assert _ask(s, "NB1", "NE4", "NS", "ET", "TE") == b"TE@\r"
    plan = machine.runs[-1].pulses
    assert plan is not None and plan.points[-1].point == (10.0, 30.0)


@pytest.mark.parametrize("nn", [1, 2])
def test_too_few_pulses_are_replaced_by_the_mpn(nn: int) -> None:
    machine, s = _seed()
    assert _ask(s, f"NN{nn}", "NS", "ET", "TE") == b"TEP\r"
    mpn = maximum_pulse_number(QUARTER + 10.0, 0.001, 1.0, 0.001)
    assert mpn == 12853
    assert machine.runs[-1].pulses is not None and machine.runs[-1].pulses.count == mpn
    assert _ask(s, "NN?", "NI?") == f"NN{mpn}\rNI{mpn}\r".encode()


def test_too_many_pulses_are_replaced_by_the_mpn_and_ni_reads_it() -> None:
    machine, s = _seed()
    assert _ask(s, "NN20000", "NS", "ET", "TE") == b"TEP\r"
    assert _ask(s, "NI?") == b"NI12853\r"
    assert _ask(s, "NI0.5", "NI?") == b"NI0.5\r"  # a new NI forgets the substitution


def test_nn_equal_to_the_mpn_is_accepted() -> None:
    machine, s = _seed()
    assert _ask(s, "NN12853", "NS", "ET", "TE") == b"TE@\r"
    assert _ask(s, "NI?") == b"NI10.1\r"  # smaller than MPN: NI? returns the specified value


def test_mpn_is_bound_by_resolution_or_by_velocity_times_base_period() -> None:
    cptl = 25.0
    assert maximum_pulse_number(cptl, 0.001, 1.0, 0.001) == 12500  # 2 x 0.001 wins
    assert maximum_pulse_number(cptl, 0.001, 10.0, 0.001) == 2500  # 10 x 0.001 wins
    assert maximum_pulse_number(cptl, 0.0001, 1.0, 0.001) == 25000
    machine, s = _seed()
    machine.axes[1].resolution = 0.01  # the larger of X and Y counts: spacing 0.02
    assert _ask(s, "NN2000", "NS", "ET", "TE") == b"TEP\r"
    assert _ask(s, "NN?") == f"NN{math.floor((QUARTER + 10.0) / 0.02)}\r".encode()


def test_mpn_too_small_for_any_pulse_refuses_et() -> None:
    machine, s = _session()
    _ask(s, "NT", "LX0.003", "LX0.004", "NB1", "NE2", "NN3", "NS", "ET")
    assert _ask(s, "TE") == b"TEP\r"
    assert machine.runs == []


def test_nn_derived_from_ni_when_nn_is_unset() -> None:
    machine, s = _session()
    _ask(s, "NT", "LX10", "LX20", "NB1", "NE2", "NI2.5", "NS", "ET")
    plan = machine.runs[-1].pulses
    assert plan is not None and plan.count == 9 and plan.step == 2.5


def test_ns_is_taken_by_et_and_et_without_ns_makes_no_pulses() -> None:
    machine, s = _seed()
    _ask(s, "NS", "ET")
    assert machine.runs[-1].pulses is not None
    assert not machine.trajectory.pulses.armed
    machine.advance(100_000)
    _ask(s, "1PA0;2PA0")
    machine.advance(100_000)
    _ask(s, "ET")
    assert machine.runs[-1].pulses is None


def test_et_refused_with_power_off_or_moving_axes() -> None:
    machine, s = _seed()
    assert _ask(s, "2MF", "ET", "TE") == b"TED\r"
    assert _ask(s, "2MO", "1PA5", "ET", "TE") == b"TED\r"
    assert machine.runs == []


def test_et_refused_when_the_path_leaves_the_travel_limits() -> None:
    machine, s = _seed()
    _ask(s, "2SR25")  # the path reaches Y = 30
    assert _ask(s, "NS", "ET", "TE") == b"TER\r"
    assert machine.runs == [] and machine.trajectory.pulses.armed


def test_et_checks_the_angle_discontinuity_of_mx_my_lines() -> None:
    machine, s = _session()
    _ask(s, "NT", "LX10", "MX20", "MY0.01")  # about 0.057 degrees off the tangent
    assert _ask(s, "ET", "TE") == b"TEM\r"
    assert _ask(s, "AD0.1", "XA", "ET", "TE") == b"XA0.1\rTE@\r"
    assert len(machine.runs) == 1


def test_trajectory_axes_follow_ax_ay() -> None:
    machine, s = _session(4)
    assert _ask(s, "AX", "AY") == b"1AX\r2AY\r"
    _ask(s, "3AX", "4AY", "NT", "LX5", "ET")
    assert _ask(s, "AX?") == b"3AX\r"
    machine.advance(10_000)
    assert _ask(s, "TP") == b"1TP0.0000,2TP0.0000,3TP5.0000,4TP0.0000\r"
    assert _ask(s, "3AY", "ET", "TE") == b"TEC\r"  # X and Y on the same axis


# --- element commands and their errors ----------------------------------------------------
@pytest.mark.parametrize(("lines", "code"), [
    (["NT", "FA90", "LX5"], b"L"),  # LX along a vertical tangent
    (["NT", "LX-5"], b"L"),  # behind the tangent
    (["NT", "LY5"], b"L"),  # LY along a horizontal tangent
    (["NT", "CA90"], b"L"),  # CA without CR
    (["NT", "CR-1"], b"C"),
    (["NT", "CR5", "CA0"], b"C"),
    (["NT", "CR5", "CA361"], b"C"),
    (["NT", "CY5"], b"L"),  # CY without CX
    (["NT", "CX5", "CY0"], b"L"),  # end point on the tangent line
    (["NT", "MY5"], b"L"),  # MY without MX
    (["NT", "MX0", "MY0"], b"L"),  # zero length
    (["NT", "EL"], b"K"),
    (["NT", "LT"], b"K"),
    (["AD20"], b"C"),
    (["FA400"], b"C"),
])
def test_element_errors(lines: list[str], code: bytes) -> None:
    machine, s = _session()
    _ask(s, *lines)
    assert _ask(s, "TE") == b"TE" + code + b"\r"
    assert machine.trajectory.elements == []


def test_el_erases_the_last_element_and_nt_starts_over() -> None:
    machine, s = _seed()
    assert _ask(s, "EL", "XT") == b"XT3\r"
    assert _ask(s, "CY30", "XT") == b"XT4\r"  # CX10 is remembered
    assert _ask(s, "NT", "XT") == b"XT0\r"


def test_clockwise_arcs_and_trajectory_settings() -> None:
    machine, s = _session()
    _ask(s, "NT", "FA90", "CR5", "CA-180")
    arc = machine.trajectory.elements[0].geometry
    assert isinstance(arc, Arc) and arc.centre == (5.0, 0.0) and arc.end == (10.0, 0.0)
    assert arc.exit_angle == -90.0
    assert _ask(s, "FA?", "CR?", "VV2.5", "VS20", "XV", "XU", "VV?") == (
        b"FA90\rCR5\rXV2.5\rXU20\rVV2.5\r")
    assert _ask(s, "VV0", "TE") == b"TEC\r"


# --- properties ---------------------------------------------------------------------------
coordinate = st.floats(min_value=-50, max_value=50, allow_nan=False).map(lambda v: round(v, 3))


@given(st.floats(min_value=-180, max_value=180), coordinate, coordinate)
def test_arc_to_point_is_tangent_and_ends_on_the_point(angle: float, x: float, y: float) -> None:
    arc = arc_to_point((0.0, 0.0), angle, (x, y))
    if arc is None:
        return
    assert arc.start == pytest.approx((0.0, 0.0), abs=1e-9)
    assert arc.end == pytest.approx((x, y), abs=1e-7)
    assert abs(wrap_deg(arc.entry_angle - angle)) < 1e-7


@given(st.lists(st.tuples(st.sampled_from(["LX", "CA"]), st.floats(1, 40)),
                min_size=2, max_size=6),
       st.integers(min_value=3, max_value=60))
def test_pulses_are_equally_spaced_on_any_path(steps: list[tuple[str, float]],
                                               count: int) -> None:
    traj = Trajectory()
    traj.set_radius(7.0)
    for kind, value in steps:
        cos = math.cos(math.radians(traj.tangent))
        if kind == "CA" or abs(cos) < 0.1:
            traj.arc_by_sweep(value)
        else:
            traj.line_to_x(traj.end_point[0] + math.copysign(value, cos))
    geometries = [e.geometry for e in traj.elements]
    points = pulse_points(geometries, 1, len(geometries), count)
    total = sum(g.length for g in geometries)
    distances = [p.path_distance for p in points]
    assert distances[0] == 0.0 and distances[-1] == pytest.approx(total)
    gaps = [b - a for a, b in zip(distances, distances[1:], strict=False)]
    assert gaps == pytest.approx([total / (count - 1)] * (count - 1))
    assert points[-1].point == geometries[-1].end
