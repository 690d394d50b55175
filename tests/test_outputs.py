"""Outputs tied to motion, the shared mechanism (firmware_model/outputs.py), checked
against brute force tick by tick: position triggers, periodic marks, path triggers and
computed outputs give exactly the ticks and values a per-tick loop would."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from maxk.firmware_model.axis import MotionAxis
from maxk.firmware_model.engine import Engine
from maxk.firmware_model.outputs import (
    ComputedOutput,
    EvenlySpaced,
    PositionTrigger,
    axis_position,
    axis_speed,
    next_periodic_marks,
    path_trigger_ticks,
    periodic_marks_passed,
    trigger_ticks,
)
from maxk.firmware_model.path import Segment, SegmentDef, plan_path
from maxk.firmware_model.profiles import RampShape, plan_move

RATE = 8192


def _moving_axis(distance: int, peak: float, accel: float) -> tuple[Engine, MotionAxis]:
    engine = Engine(RATE)
    axis = MotionAxis(0, "X")
    axis.begin(plan_move(distance, 0.0, peak, accel, accel, RampShape.LINEAR), engine)
    return engine, axis


def _first_tick(axis: MotionAxis, engine: Engine, position: float, direction: int) -> int | None:
    assert axis.motion_end is not None
    for tick in range(engine.tick + 1, axis.motion_end + 1):
        if direction * (axis.steps_at_tick(tick, engine.period) - position) >= 0:
            return tick
    return None


@settings(max_examples=40, deadline=None)
@given(distance=st.integers(-30_000, 30_000).filter(lambda d: abs(d) > 10),
       peak=st.floats(500, 50_000), accel=st.floats(5_000, 500_000),
       fractions=st.lists(st.floats(-0.2, 1.2), min_size=1, max_size=6))
def test_position_triggers_fire_on_the_tick_a_per_tick_loop_finds(distance, peak, accel,
                                                                   fractions):
    engine, axis = _moving_axis(distance, peak, accel)
    direction = 1 if distance > 0 else -1
    triggers = [PositionTrigger(round(f * distance), d, k)
                for k, f in enumerate(fractions) for d in (1, -1)]
    found = {t.payload * 2 + (t.direction < 0): tick
             for tick, t in trigger_ticks(axis, engine, triggers)}
    for k, trigger in enumerate(triggers):
        ahead = trigger.direction * (trigger.position - axis.steps) > 0
        expected = (_first_tick(axis, engine, trigger.position, trigger.direction)
                    if ahead and trigger.direction == direction else None)
        assert found.get(trigger.payload * 2 + (trigger.direction < 0)) == expected, k


@given(here=st.integers(-100_000, 100_000), offset=st.integers(-5000, 5000),
       period=st.integers(1, 5000), width=st.integers(1, 8))
def test_periodic_marks_are_the_nearest_each_way(here, offset, period, width):
    width = min(width, period)
    up, down = next_periodic_marks(here, offset, period, width)

    def starts_a_mark(p):  # moving up, a mark is met at its first count
        return (p - offset) % period == 0

    def ends_a_mark(p):  # moving down, at its last
        return (p - offset - width + 1) % period == 0

    assert up > here and starts_a_mark(up)
    assert not any(starts_a_mark(p) for p in range(here + 1, up))
    assert down < here and ends_a_mark(down)
    assert not any(ends_a_mark(p) for p in range(down + 1, here))
    assert list(periodic_marks_passed(up, period, up + 3 * period)) == [
        up, up + period, up + 2 * period, up + 3 * period]
    assert list(periodic_marks_passed(down, period, down - period)) == [down, down - period]


def test_path_triggers_fire_on_the_tick_the_path_reaches_their_distance():
    """A straight two-axis path; pulses every 250 counts along it (the MM4005's kind):
    each on the first tick the planned path has reached its distance."""
    defn = SegmentDef("line", (30_000.0, 40_000.0), False, 0.0, None, 5000.0, 20_000.0, None)
    segment = Segment(defn, (0.0, 0.0), 0.0, None)
    plan = plan_path([segment], 0, 0.0, None, 1.0)
    period = 1.0 / RATE
    pulses = EvenlySpaced(0.0, 250.0, 201)  # 0 .. 50,000 along the path (its length)
    ticks = path_trigger_ticks(plan, 100, period, iter(pulses))
    assert len(ticks) == 201
    for tick, k in ticks:
        distance = k * 250.0
        s_at = plan.state((tick - 100) * period)[0]
        s_before = plan.state((tick - 101) * period)[0] if tick > 100 else -1.0
        assert s_at >= distance - 1e-6 and s_before < distance - 1e-6, (k, tick)
    assert list(pulses.from_index(199)) == [(49_750.0, 199), (50_000.0, 200)]


def test_a_computed_output_is_its_function_of_speed_and_position_at_every_tick():
    """The Trio's speed-linked mark: value = f(speed, position), evaluated at any tick
    from the closed-form motion, equal to reading the axis tick by tick."""
    engine, axis = _moving_axis(20_000, 10_000.0, 50_000.0)

    def mark(speed: float, position: float) -> float:
        return min(500.0, speed * 0.1 + 50.0) + 0.0 * position

    output = ComputedOutput(mark, axis_speed(axis, engine), axis_position(axis, engine))
    assert axis.motion_end is not None
    values = output.values(0, axis.motion_end + 5)
    for tick, value in enumerate(values):
        engine.tick = tick
        expected = mark(abs(axis.velocity(engine)), float(axis.steps_now(engine)))
        assert math.isclose(value, expected, abs_tol=1e-9), tick
    assert values[0] == 50.0 and values[-1] == 50.0 and max(values) == 500.0
