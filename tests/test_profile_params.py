"""The profiles' parameters acting on the curves: PN# (parabolic degree), SS#/PR# (the
S-curve's jerk share on acceleration / deceleration ramps). Every parameter keeps the
closed forms exact: moves end exactly on target, velocity is continuous, within VL, and
the acceleration within AC/DC."""

import math

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from maxk import MAXk
from maxk.firmware_model.profiles import (
    RampShape,
    plan_jog,
    plan_move,
    plan_stop,
    ramp_knots,
    shape_constants,
    shape_f,
    shape_integral,
)

jerk_shares = st.floats(0.01, 1.0)
degrees = st.integers(1, 8).map(float)
shaped = st.one_of(
    st.tuples(st.just(RampShape.SCURVE), jerk_shares, jerk_shares),
    st.tuples(st.just(RampShape.PARABOLIC), degrees, st.none()).map(lambda t: (t[0], t[1], t[1])),
    st.tuples(st.sampled_from(list(RampShape)), st.none(), st.none()),
)
distances = st.integers(-5_000_000, 5_000_000).filter(lambda d: d != 0)
peaks = st.integers(1, 4_176_000)
accels = st.integers(1_000, 8_000_000)


@settings(max_examples=200, deadline=None)
@given(st.sampled_from([RampShape.SCURVE, RampShape.PARABOLIC]), st.floats(0.01, 1.0),
       st.integers(1, 8), st.floats(0.0, 1.0))
def test_integral_is_the_exact_integral_of_the_curve(shape, share, degree, u):
    param = share if shape is RampShape.SCURVE else float(degree)
    k, total = shape_constants(shape, param)
    assert shape_f(shape, 0.0, param) == pytest.approx(0.0, abs=1e-12)
    assert shape_f(shape, 1.0, param) == pytest.approx(1.0, abs=1e-12)
    assert shape_integral(shape, 1.0, param) == pytest.approx(total, abs=1e-12)
    points = [x for x in ramp_knots(shape, param) if 0 < x < u]
    numeric, _ = quad(lambda x: shape_f(shape, x, param), 0.0, u, points=points or None,
                      epsabs=1e-13, epsrel=1e-12)
    assert shape_integral(shape, u, param) == pytest.approx(numeric, abs=1e-10)
    # the peak slope k is the curve's steepest
    h = 1e-6
    slope = max((shape_f(shape, min(1.0, x + h), param) - shape_f(shape, x, param)) / h
                for x in [i / 2000 for i in range(2000)])
    assert slope <= k * (1 + 1e-4)
    assert slope >= k * 0.99


@settings(max_examples=100, deadline=None)
@given(st.floats(0.01, 0.99))
def test_scurve_acceleration_is_continuous_at_its_knots(share):
    """Jerk-limited: the acceleration (f') has no step at the knots, unlike a trapezoid."""
    k, _ = shape_constants(RampShape.SCURVE, share)
    h = 1e-7
    for knot in ramp_knots(RampShape.SCURVE, share):
        left = (shape_f(RampShape.SCURVE, knot, share)
                - shape_f(RampShape.SCURVE, knot - h, share)) / h
        right = (shape_f(RampShape.SCURVE, knot + h, share)
                 - shape_f(RampShape.SCURVE, knot, share)) / h
        assert left == pytest.approx(right, abs=1e-4 * k)
        assert left == pytest.approx(k, rel=1e-4)  # the middle runs at the peak


def test_factory_parameters_are_the_factory_curves():
    for shape, param in ((RampShape.SCURVE, 1.0), (RampShape.PARABOLIC, 2.0)):
        a = plan_move(123_457, 100, 50_000, 300_000, 200_000, shape)
        b = plan_move(123_457, 100, 50_000, 300_000, 200_000, shape, param, param)
        assert a.phases == b.phases and a.end_time == b.end_time
    # a linear or cosine ramp ignores a parameter
    a = plan_move(5000, 0, 1000, 10_000, 10_000, RampShape.COSINE)
    b = plan_move(5000, 0, 1000, 10_000, 10_000, RampShape.COSINE, 0.3, 0.3)
    assert a.phases == b.phases


@settings(max_examples=300, deadline=None)
@given(distances, st.integers(0, 100_000), peaks, accels, accels, shaped)
def test_every_shape_and_parameter_ends_exactly_within_vl_and_ac(distance, base, peak,
                                                                   accel, decel, curve):
    shape, up, down = curve
    assume(base < peak)
    m = plan_move(distance, base, peak, accel, decel, shape, up, down)
    direction = 1 if distance > 0 else -1
    assert m.offset(m.end_time) == distance and m.final_offset == distance
    n = 1500
    times = [m.end_time * i / n for i in range(n + 1)]
    prev_s, prev_v = 0.0, m.velocity(0.0)
    for t in times:
        v = m.velocity(t)
        assert direction * v >= -1e-6
        assert abs(v) <= peak * (1 + 1e-9) + 1e-6
        s = m.offset(t)
        assert direction * (s - prev_s) >= -1e-6
        assert abs(s) <= abs(distance) + 1e-6
        prev_s = s
    # velocity continuous (beyond the jump to VB at the start and from VB at the end) and
    # the acceleration never above AC/DC: sampled finely inside each phase
    for phase in m.phases:
        if phase.v1 == phase.v2 or phase.duration < 1e-9:
            continue
        h = phase.duration / 4000
        limit = (accel if phase.v2 > phase.v1 else decel) * (1 + 1e-6)
        prev_v = phase.speed(0.0)
        assert prev_v == pytest.approx(phase.v1, rel=1e-9, abs=1e-9)
        for i in range(1, 4001):
            v = phase.speed(i * h)
            assert abs(v - prev_v) <= limit * h + 1e-6 * peak
            prev_v = v
        assert prev_v == pytest.approx(phase.v2, rel=1e-9, abs=1e-6)
    for a, b in zip(m.phases, m.phases[1:], strict=False):
        assert a.speed(a.duration) == pytest.approx(b.speed(0.0), rel=1e-9, abs=1e-6)
        assert a.s0 + a.direction * a.length == pytest.approx(b.s0, abs=1e-6)


@settings(max_examples=200, deadline=None)
@given(st.floats(-0.99, 0.99), st.integers(-100_000, 100_000).filter(lambda v: v != 0),
       st.integers(1_000, 2_000_000), shaped)
def test_stops_and_jogs_with_parameters_end_on_whole_steps(residual, velocity, decel, curve):
    shape, up, down = curve
    stop = plan_stop(residual, velocity, 0, decel, shape, down)
    assert stop.offset(stop.end_time) == stop.final_offset == round(
        stop.phases[-1].s0 + stop.phases[-1].direction * stop.phases[-1].length)
    assert abs(stop.velocity(stop.end_time * (1 - 1e-9))) < abs(velocity) * 1e-3 + 1
    jog = plan_jog(residual, velocity, -2 * velocity, 0, decel, decel, shape, up, down)
    # reverses through zero, then slews at the new speed
    assert jog.velocity(jog.ramp_end_time + 1.0) == -2 * velocity
    for a, b in zip(jog.phases, jog.phases[1:], strict=False):
        assert a.s0 + a.direction * a.length == pytest.approx(b.s0, abs=1e-6)


def test_jerk_share_changes_the_ramp_time():
    """SC with SS50: ramps last 2/(2 - 0.5) = 4/3 of a linear ramp; the full S twice."""
    for share, k in ((None, 2.0), (0.5, 4.0 / 3.0), (0.25, 8.0 / 7.0)):
        m = plan_move(1_000_000, 0, 10_000, 100_000, 100_000, RampShape.SCURVE, share, share)
        ramp = k * 10_000 / 100_000
        assert m.ramp_end_time == pytest.approx(ramp)
        # each ramp covers half of VL times its time (the S is symmetric)
        assert m.end_time == pytest.approx(2 * ramp + (1_000_000 - 10_000 * ramp) / 10_000)


def test_separate_jerk_shares_for_acceleration_and_deceleration():
    m = plan_move(1_000_000, 0, 10_000, 100_000, 100_000, RampShape.SCURVE, 0.5, None)
    up, _slew, down = m.phases
    assert up.duration == pytest.approx(4 / 3 * 0.1)
    assert down.duration == pytest.approx(2 * 0.1)
    # a triangle with unequal ramps still meets in the middle and ends on target
    t = plan_move(700, 0, 100_000, 100_000, 50_000, RampShape.SCURVE, 0.2, 1.0)
    assert len(t.phases) == 2 and t.offset(t.end_time) == 700
    assert t.phases[0].v2 == pytest.approx(t.phases[1].v1)
    assert t.phases[0].length + t.phases[1].length == pytest.approx(700)


def _run(setup: str, move: str = "MR100000") -> tuple[MAXk, int, int]:
    b = MAXk()
    b.send(f"AX; {setup}; VL10000; AC100000; {move}; GO; ID;")
    start = b.engine.tick
    b.run_until_done("X", timeout=60)
    return b, start, b.engine.tick


@pytest.mark.parametrize("setup,k,integral", [
    ("SC", 2.0, 0.5), ("SC; SS0", 2.0, 0.5), ("SC; SS100", 2.0, 0.5),
    ("SC; SS50", 4 / 3, 0.5), ("SC; SS20; PR20", 2 / 1.8, 0.5),
    ("PN", 2.0, 2 / 3), ("PN0", 2.0, 2 / 3), ("PN2", 2.0, 2 / 3), ("PN1", 1.0, 0.5),
    ("PN3", 3.0, 0.75), ("PN8", 8.0, 8 / 9), ("PN4; PN", 4.0, 0.8), ("LA; SS50", 1.0, 0.5)])
def test_board_moves_with_parameters_end_on_target_on_the_analytic_tick(setup, k, integral):
    b, start, end = _run(setup)
    assert not b.command_error
    assert b.position("X") == 100000
    ramp = k * 10000 / 100000
    analytic = 2 * ramp + (100000 - 2 * integral * 10000 * ramp) / 10000
    period = b.engine.period
    assert b.board.axes[0].rest_since == start + math.ceil(analytic / period - 1e-9)
    assert end >= b.board.axes[0].rest_since


def test_pr_shapes_only_the_deceleration():
    _b, start, _ = _run("SC; SS50; PR100")
    b2, start2, _ = _run("SC; SS50")
    b3, start3, _ = _run("SC; SS100; PR50")
    # SS50 PR100 = full-S deceleration: longer than SS50 alone, same as SS100 PR50
    assert (_b.board.axes[0].rest_since - start) > (b2.board.axes[0].rest_since - start2)
    assert (_b.board.axes[0].rest_since - start) == (b3.board.axes[0].rest_since - start3)


@pytest.mark.parametrize("command", ["SS101", "PR101", "PN9", "SS-1"])
def test_out_of_range_parameters_are_command_errors(command):
    b = MAXk()
    b.send("AX; SC; SS30; PR40; PN7;")
    b.send(f"AX; {command};")
    assert b.command_error
    c = b.board.axes[0].config
    assert (c.scurve_factor, c.ramp_parameter, c.ramp_factor) == (30, 40, 7)


def test_stop_and_jog_use_the_deceleration_share():
    b = MAXk()
    b.send("AX; SC; SS10; PR100; VL10000; AC100000; JG10000;")
    b.advance(0.5)
    b.send("AX; ST;")
    phases = b.board.axes[0].motion.phases
    assert phases[0].param is None  # PR100: the full S (factory curve) on the stop
    b.run_until_done("X", timeout=60)
    b.send("AX; SS10; PR0; JG10000;")
    motion = b.board.axes[0].motion
    assert motion.phases[0].param == pytest.approx(0.1)


@pytest.mark.parametrize("ramp", ["SC; SS30; PR60;", "SC; SS100;", "PN3;", "PN1;"])
def test_servo_closed_form_jumps_follow_the_shaped_ramps(ramp):
    """A servo following shaped ramps (S-curve pieces between knots, parabolic ramps of
    degree 3 that are no cubic): the closed-form jumps agree with tick-by-tick stepping."""
    def run(tick_by_tick: bool) -> list[tuple[float, float]]:
        board = MAXk()
        board.send("AX PSM;")
        loop = board.board.axis("X").servo
        if tick_by_tick:
            loop.recorder = []
        board.send(f"AX LP0; KP1; KD0; KI0; CL1; {ramp} AC100000; VL5000; MR6000; GO;")
        states = []
        for _ in range(30):
            board.advance(0.05)
            states.append((loop.p, loop.w))
        return states

    fast, slow = run(False), run(True)
    for (p1, w1), (p2, w2) in zip(fast, slow, strict=True):
        assert p1 == pytest.approx(p2, abs=1e-3)
        assert w1 == pytest.approx(w2, abs=1e-2 + 1e-6 * abs(w2))


def test_linear_moves_take_the_first_axis_ramp_and_its_parameters():
    b = MAXk()
    b.send("AX; SC; SS40; AY; LA;")
    b.send("AM; VL5000,5000; AC50000,50000; MT1000,3000; GO; ID;")
    x, y = b.board.axis("X").motion, b.board.axis("Y").motion
    assert x.phases[0].param == y.phases[0].param == pytest.approx(0.4)
    assert b.run_until_idle(timeout=60)
    assert b.query("AM; RP").startswith("1000,3000")
