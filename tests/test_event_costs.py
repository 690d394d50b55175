"""The axes' one-scan-an-event shortcut (`next_event` notes the axes due at the earliest
tick, `on_event` looks only at them) changes nothing a host can see: the same random
scenarios run with the note ignored (every axis looked at, as before) give the same
positions and flags at every event tick."""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from maxk import MAXk
from maxk.personalities.maxk import board as board_module

LETTERS = "XYZTUVRSWK"

_moves = st.lists(st.integers(-4000, 4000), min_size=1, max_size=3)
_axis_script = st.tuples(st.integers(1000, 60000), st.integers(10000, 600000), _moves,
                         st.integers(0, 40))


def _script(per_axis: list[tuple[int, int, list[int], int]], together: list[int]) -> str:
    parts = []
    for letter, (velocity, accel, moves, wait_ms) in zip(LETTERS, per_axis, strict=False):
        body = " ".join(f"MR{m}; GO;" + (f" WT{wait_ms};" if wait_ms else "") for m in moves)
        parts.append(f"A{letter} VL{velocity}; AC{accel}; LS3; {body} LE;")
    if together:
        parts.append("AA MR" + ",".join(str(m) for m in together) + "; GO;")
    return " ".join(parts)


def _trace(script: str, stop_after: int) -> list[tuple[int, tuple[int, ...], int]]:
    board = MAXk("MAXk-A000")
    seen: list[tuple[int, tuple[int, ...], int]] = []

    def note(engine: object) -> None:
        b = board.board
        seen.append((b.tick, tuple(a.motor_position(b) for a in b.axes),
                     sum(a.flags << (4 * a.index) for a in b.axes)))

    board.board.add_observer(note)
    board.send(script)
    board.advance(ticks=stop_after)
    board.send("AY ST;")  # a stop from the host between events
    board.advance(3.0)
    return seen


def _ignoring_the_note(monkeypatch: pytest.MonkeyPatch) -> None:
    source = board_module._AxesSource
    original: Callable[[board_module._AxesSource, int], None] = source.on_event

    def on_event(self: board_module._AxesSource, now: int) -> None:
        self._noted = False
        original(self, now)

    monkeypatch.setattr(source, "on_event", on_event)


@settings(max_examples=25, deadline=None)
@given(st.lists(_axis_script, min_size=1, max_size=10),
       st.lists(st.integers(-3000, 3000), min_size=0, max_size=10),
       st.integers(1, 20000))
def test_noted_scan_matches_the_full_scan(per_axis: list[tuple[int, int, list[int], int]],
                                          together: list[int], stop_after: int) -> None:
    script = _script(per_axis, together)
    fast = _trace(script, stop_after)
    with pytest.MonkeyPatch.context() as patch:
        _ignoring_the_note(patch)
        full = _trace(script, stop_after)
    assert fast == full
    assert fast  # events happened


def test_axes_ending_on_one_tick_are_all_done() -> None:
    """Two axes with the same move end on the same tick; both are due and both report
    done from that tick (the note keeps every axis sharing the earliest tick)."""
    board = MAXk("MAXk-A000")
    board.send("AX VL10000; AC100000; AY VL10000; AC100000; AX MR5000 GO ID; AY MR-5000 GO ID;")
    b = board.board
    end = b.axes[0].motion_end
    assert end is not None and end == b.axes[1].motion_end
    board.advance(ticks=end - 1 - b.tick)
    assert board.send("AM; RI;") == ["PNNN,MNNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN"]
    board.advance(ticks=1)
    assert board.send("AX RP; AY RP;") == ["5000", "-5000"]
    assert board.send("AM; RI;") == ["PDNN,MDNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN"]
    assert b.axes[0].rest_since == b.axes[1].rest_since == end


def test_a_config_change_drops_the_memoised_plans() -> None:
    """AxisConfig.plan_move memoises per parameter set: any parameter set afterwards
    (VL, AC, the ramp, ...) plans afresh, and a plan is the one profiles would make."""
    from maxk.firmware_model.profiles import RampShape, plan_move
    from maxk.personalities.maxk.config import AxisConfig

    c = AxisConfig()
    first = c.plan_move(7001)
    assert c.plan_move(7001) is first
    c.velocity = 50_000
    slower = c.plan_move(7001)
    assert slower is not first and slower.end_time > first.end_time
    assert slower == plan_move(7001, 0, 50_000, 2_000_000, 2_000_000, RampShape.LINEAR)
    c.ramp, c.scurve_factor = RampShape.SCURVE, 40
    assert c.plan_move(7001) == plan_move(7001, 0, 50_000, 2_000_000, 2_000_000,
                                          RampShape.SCURVE, 0.4, 0.4)
    board = MAXk("MAXk-A000")
    board.send("AX VL1000; AC100000; MR1000; GO; ID;")
    board.advance(2.0)
    board.send("AX VL20000; MR1000; GO; ID;")  # the same distance, a new VL
    start, b = board.board.tick, board.board
    board.advance(2.0)
    plan = plan_move(1000, 0, 20_000, 100_000, 100_000, RampShape.LINEAR)
    assert b.axes[0].rest_since - start == math.ceil(plan.end_time / b.period - 1e-9)
    assert board.send("AX RP;") == ["2000"]


_shapes = st.sampled_from(["LINEAR", "PARABOLIC", "SCURVE", "COSINE"])


@pytest.mark.parametrize(("name", "value", "ramp_args"), [
    ("velocity", 50_000, (0, 50_000, 2_000_000, 2_000_000, "linear")),
    ("base_velocity", 1_000, (1_000, 200_000, 2_000_000, 2_000_000, "linear")),
    ("acceleration", 500_000, (0, 200_000, 500_000, 2_000_000, "linear")),
    ("deceleration", 700_000, (0, 200_000, 2_000_000, 700_000, "linear")),
    ("ramp", "s-curve", (0, 200_000, 2_000_000, 2_000_000, "s-curve")),
])
def test_each_plan_parameter_makes_a_fresh_plan(name: str, value: object,
                                                 ramp_args: tuple) -> None:
    """The memo is keyed on VB, VL, AC, DC and the ramp with its factors: a change of
    any one plans afresh (the plan profiles makes from scratch); a change of anything
    else (SE, BC, the slip tolerance) keeps the plan made."""
    from maxk.firmware_model.profiles import RampShape, plan_move
    from maxk.personalities.maxk.config import AxisConfig

    c = AxisConfig()
    first = c.plan_move(-3001)
    c.settle_ms, c.backlash, c.slip_tolerance = 5, 3, 7
    assert c.plan_move(-3001) is first
    setattr(c, name, RampShape(value) if name == "ramp" else value)
    fresh = c.plan_move(-3001)
    base, peak, accel, decel, shape = ramp_args
    assert fresh is not first
    assert fresh == plan_move(-3001, base, peak, accel, decel, RampShape(shape))
    assert fresh != first


@pytest.mark.parametrize("name", ["ramp_factor", "scurve_factor", "ramp_parameter"])
def test_each_ramp_factor_makes_a_fresh_plan(name: str) -> None:
    """PN, SS and PR shape the ramps: a change of any one replans (PN on a parabolic
    ramp, SS and PR on an S-curve)."""
    from maxk.firmware_model.profiles import RampShape, plan_move
    from maxk.personalities.maxk.config import AxisConfig

    c = AxisConfig()
    c.ramp = RampShape.PARABOLIC if name == "ramp_factor" else RampShape.SCURVE
    first = c.plan_move(5000)
    setattr(c, name, 3 if name == "ramp_factor" else 30)
    fresh = c.plan_move(5000)
    up, down = {"ramp_factor": (3.0, 3.0), "scurve_factor": (0.3, 0.3),
                "ramp_parameter": (None, 0.3)}[name]
    assert fresh == plan_move(5000, 0, 200_000, 2_000_000, 2_000_000, c.ramp, up, down)
    assert fresh != first


@settings(max_examples=200, deadline=None)
@given(st.integers(-200_000, 200_000).filter(bool), st.integers(0, 5_000),
       st.integers(1, 400_000), st.integers(1_000, 4_000_000), st.integers(1_000, 4_000_000),
       _shapes, st.sampled_from([None, 0.25, 0.5, 3.0]), st.floats(0.0, 1.0),
       st.floats(-300_000, 300_000), st.integers(0, 20_000))
# a stop from a denormal speed: a ramp of no duration (was a division by zero)
@example(distance=1, base=0, peak=1, accel=1000, decel=1000, shape_name="LINEAR", param=None,
         where=0.0, jog=5e-324, base_jog=0)
def test_a_one_way_motion_never_reads_the_other_way(
        distance: int, base: int, peak: int, accel: int, decel: int, shape_name: str,
        param: float | None, where: float, jog: float, base_jog: int) -> None:
    """A status poll takes a one-way motion's direction without its velocity
    (MotionAxis.travel_direction): exact, as no one-way move, stop or jog ever has a
    velocity of the other sign, nor a step back from one update cycle to the next."""
    from maxk.firmware_model.profiles import RampShape, plan_jog, plan_move, plan_stop

    shape = RampShape[shape_name]
    if param is not None and shape is RampShape.SCURVE and param > 1.0:
        param = None
    if param is not None and shape is RampShape.PARABOLIC and param < 1.0:
        param = None
    period = 1 / 8192
    plans = [plan_move(distance, base, peak, accel, decel, shape, param, param),
             plan_stop(0.3, jog, base_jog, decel, shape, param),
             plan_jog(0.0, 0.0, jog, base_jog, accel, decel, shape, param, param)]
    for plan in plans:
        if not plan.monotonic:
            continue
        span = plan.end_time if plan.end_time is not None else 2.0
        ticks = int(span / period) + 2
        for tick in {0, 1, ticks - 2, ticks - 1, ticks, int(where * ticks)}:
            t = tick * period
            v = plan.velocity(t)
            assert v * plan.direction >= 0, (plan, t, v)
            step = int(plan.offset(t)) - int(plan.offset(max(0.0, t - period)))
            assert step * plan.direction >= 0, (plan, t, step)
