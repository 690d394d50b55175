"""Velocity profiles: property tests on the closed forms the tick engine relies on."""

import math

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from maxk.firmware_model.profiles import RampShape, plan_jog, plan_move, plan_stop

shapes = st.sampled_from(list(RampShape))
distances = st.integers(-5_000_000, 5_000_000).filter(lambda d: d != 0)
peaks = st.integers(1, 4_176_000)
accels = st.integers(1_000, 8_000_000)


def samples(motion, n=400):
    end = motion.end_time
    return [end * i / n for i in range(n + 1)]


@settings(max_examples=300, deadline=None)
@given(distances, st.integers(0, 100_000), peaks, accels, accels, shapes)
def test_move_properties(distance, base, peak, accel, decel, shape):
    assume(base < peak)
    m = plan_move(distance, base, peak, accel, decel, shape)
    direction = 1 if distance > 0 else -1
    # exact distance at the end
    assert m.offset(m.end_time) == distance
    assert m.final_offset == distance
    prev = 0.0
    for t in samples(m):
        v = m.velocity(t)
        # never negative in the direction of travel, never above VL
        assert direction * v >= -1e-6
        assert abs(v) <= peak * (1 + 1e-9) + 1e-6
        s = m.offset(t)
        # continuous and monotonic toward the target, never past it
        assert direction * (s - prev) >= -1e-6
        assert abs(s) <= abs(distance) + 1e-6
        prev = s
    # continuity just before the end: the last stretch closes the gap smoothly
    gap = abs(distance) - abs(m.offset(m.end_time * (1 - 1e-12)))
    assert gap <= max(1e-3, abs(distance) * 1e-9) + peak * m.end_time * 1e-12 * 10


@settings(max_examples=200, deadline=None)
@given(distances, peaks, accels, shapes)
def test_peak_acceleration_is_the_programmed_one(distance, peak, accel, shape):
    m = plan_move(distance, 0, peak, accel, accel, shape)
    assume(m.end_time > 1e-3)
    h = m.end_time / 4000
    worst = max(abs(m.velocity(t + h) - m.velocity(t)) / h for t in samples(m, 3000)[:-1])
    assert worst <= accel * 1.02


def test_trapezoid_time_is_analytic():
    m = plan_move(10_000, 0, 5_000, 50_000, 50_000, RampShape.LINEAR)
    assert m.end_time == pytest.approx(2.1)
    assert m.peak_speed == 5_000


def test_triangle_when_the_move_is_short():
    m = plan_move(100, 0, 5_000, 50_000, 50_000, RampShape.LINEAR)
    assert m.peak_speed == pytest.approx(math.sqrt(100 * 50_000))
    assert m.end_time == pytest.approx(2 * math.sqrt(100 * 50_000) / 50_000)


def test_separate_deceleration_shapes_the_triangle():
    m = plan_move(10_000, 0, 1_000_000, 10_000, 40_000, RampShape.LINEAR)
    # vp^2 = 2 d a dd / (a + dd)
    vp = math.sqrt(2 * 10_000 * 10_000 * 40_000 / 50_000)
    assert m.peak_speed == pytest.approx(vp)
    assert m.end_time == pytest.approx(vp / 10_000 + vp / 40_000)


@pytest.mark.parametrize("shape,factor", [(RampShape.LINEAR, 1.0), (RampShape.PARABOLIC, 2.0),
                                          (RampShape.SCURVE, 2.0),
                                          (RampShape.COSINE, math.pi / 2)])
def test_ramp_time_per_shape(shape, factor):
    m = plan_move(1_000_000, 0, 10_000, 100_000, 100_000, shape)
    assert m.ramp_end_time == pytest.approx(factor * 10_000 / 100_000)


def test_parabolic_deceleration_mirrors_the_acceleration():
    m = plan_move(1_000_000, 0, 10_000, 100_000, 100_000, RampShape.PARABOLIC)
    up, down = m.phases[0], m.phases[-1]
    assert up.length == pytest.approx(down.length)
    # acceleration is AC at low speed (start, and mirrored at the end) and ~0 at the top
    h = 1e-4
    assert m.velocity(h) / h == pytest.approx(100_000, rel=1e-3)
    assert m.velocity(m.end_time - h) / h == pytest.approx(100_000, rel=1e-3)
    top = (m.velocity(0.2) - m.velocity(0.2 - h)) / h
    assert top < 100_000 * 2e-3


@given(st.floats(-0.99, 0.99), st.integers(-100_000, 100_000).filter(lambda v: v != 0),
       st.integers(0, 500), accels, shapes)
def test_stop_decelerates_to_vb_and_ends_on_the_nearest_step(residual, velocity, base, decel,
                                                              shape):
    m = plan_stop(residual, velocity, base, decel, shape)
    speed, direction = abs(velocity), (1 if velocity > 0 else -1)
    # the analytic stopping distance from speed to VB, plus the residual carried in
    _k, integral = {RampShape.LINEAR: (1, 0.5), RampShape.PARABOLIC: (2, 2 / 3),
                    RampShape.SCURVE: (2, 0.5), RampShape.COSINE: (math.pi / 2, 0.5)}[shape]
    if speed > base:
        duration = _k * (speed - base) / decel
        distance = duration * (base + integral * (speed - base))
    else:
        duration = distance = 0.0
    assert m.end_time == pytest.approx(duration)
    assert abs(m.final_offset - (residual + direction * distance)) <= 0.5 + 1e-6
    if m.phases:
        assert m.velocity(0.0) == pytest.approx(velocity)
        assert abs(m.velocity(m.end_time * (1 - 1e-9))) == pytest.approx(max(base, 0), abs=1)


def test_jog_reversal_without_base_velocity_passes_through_zero():
    m = plan_jog(0.0, 5_000, -5_000, 0, 50_000, 50_000, RampShape.LINEAR)
    assert m.end_time is None
    assert m.velocity(0.05) == pytest.approx(2_500)
    assert m.velocity(0.15) == pytest.approx(-2_500)
    assert m.velocity(10.0) == -5_000
    assert m.ramp_end_time == pytest.approx(0.2)
