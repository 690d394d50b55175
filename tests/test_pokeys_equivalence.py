"""The fast path (whole stretches of slots at once) must be the slot-by-slot engine:
same pulses, positions, states and events, whatever the switches and motions."""

from __future__ import annotations

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from maxk.personalities.pokeys import AxisConfigBits as C
from maxk.personalities.pokeys import BenchWorld, EngineState, PulseEngineV1, PulseEngineV2, Zone
from maxk.personalities.pokeys import SwitchBits as S

zones = st.lists(st.builds(Zone, st.sampled_from([0, 0, 1, 2]),
                           st.sampled_from(["limit_n", "limit_p", "home"]),
                           st.integers(-3000, 3000), st.integers(0, 400)), max_size=4)


def _world(zs: list[Zone], estop: int | None) -> BenchWorld:
    fixed = [Zone(z.axis, z.switch, z.lo, z.lo + z.hi) for z in zs]
    return BenchWorld(zones=fixed, estop_pressed=[] if estop is None else [(estop, estop + 5)])


def _v2(world: BenchWorld, switches: int, accel: float) -> PulseEngineV2:
    e = PulseEngineV2(world)
    e.setup(3, 0, 0, 0, 0, 0)
    configs = (C.ENABLED | C.SOFT_LIMIT_ENABLED, C.ENABLED | C.INTERNAL_PLANNER |
               C.POSITION_MODE, C.ENABLED | C.INTERNAL_PLANNER)
    for a, config in zip(e.axes, configs, strict=False):
        s = a.settings
        s.config, s.switches, s.max_speed = config, switches, 12.5
        s.max_acceleration = s.max_deceleration = accel
        s.soft_limit_min, s.soft_limit_max = -2500, 2500
    return e


def _snapshot(e: PulseEngineV1 | PulseEngineV2) -> tuple:
    return (e.slot, e.positions(), int(e.state), [int(s) for s in e.axis_states()],
            e.buffer.count, [a.direction_out for a in e.axes])


@settings(max_examples=100, deadline=None)
@given(zs=zones, estop=st.one_of(st.none(), st.integers(0, 900)),
       switches=st.sampled_from([0, S.LIMIT_N | S.LIMIT_P, S.LIMIT_P | S.HOME,
                                 S.LIMIT_N | S.INVERT_LIMIT_P]),
       accel=st.sampled_from([0.0, 0.002, 0.05]),
       pulses=st.lists(st.integers(-60, 130), min_size=1, max_size=300),  # drifts up
       target=st.integers(-4000, 4000), speed=st.integers(-12000, 12000),
       checkpoints=st.lists(st.integers(1, 1000), max_size=6))
# a move to where the axis stands ends at once: told before a later move's end (found once)
@example(zs=[], estop=None, switches=0, accel=0.0, pulses=[0], target=0, speed=-1,
         checkpoints=[1])
def test_v2_fast_path_equals_slot_by_slot(zs: list[Zone], estop: int | None, switches: int,
                                          accel: float, pulses: list[int], target: int,
                                          speed: int, checkpoints: list[int]) -> None:
    runs = []
    for traced in (True, False):
        e = _v2(_world(zs, estop), switches, accel)
        events: list[tuple] = []
        e.listeners.append(lambda *ev, events=events: events.append(ev))
        if traced:
            e.trace = lambda record: None
        e.set_state(EngineState.RUNNING, 0, 0)
        rows = np.array([[p, 0, 0] for p in pulses], dtype=np.int32)
        sent = e.fill(rows)
        e.move([0, target, speed] + [0] * 5)
        seen = []
        for i, slot in enumerate(sorted(checkpoints) + [1000]):
            e.run_to(slot)
            sent += e.fill(rows[sent:])
            if i == 0:
                e.move([0, target // 3 - 700, -speed // 2] + [0] * 5)  # re-target on the way
            seen.append(_snapshot(e))
        runs.append((seen, events))
    assert runs[0] == runs[1]


@settings(max_examples=100, deadline=None)
@given(zs=zones, home_axes=st.lists(st.booleans(), min_size=3, max_size=3),
       checkpoints=st.lists(st.integers(1, 3000), max_size=5))
def test_v1_homing_fast_path_equals_slot_by_slot(zs: list[Zone], home_axes: list[bool],
                                                 checkpoints: list[int]) -> None:
    runs = []
    for traced in (True, False):
        e = PulseEngineV1(_world(zs, None))
        for a in e.axes:
            a.settings.max_speed = 25.0
            a.settings.switches = S.HOME | S.LIMIT_N
        if traced:
            e.trace = lambda record: None
        e.homing_start([int(h) for h in home_axes])
        seen = []
        for slot in sorted(checkpoints) + [3000]:
            e.run_to(slot)
            seen.append(_snapshot(e))
        runs.append(seen)
    assert runs[0] == runs[1]


def test_an_internal_move_into_a_limit_stops_alike_both_ways() -> None:
    ends = []
    for traced in (True, False):
        e = _v2(BenchWorld(zones=[Zone(1, "limit_p", 1234, 9999)]), S.LIMIT_P, 0.01)
        if traced:
            e.trace = lambda record: None
        e.set_state(EngineState.RUNNING, 0, 0)
        e.move([0, 4000, 0] + [0] * 5)
        e.run_to(2000)
        ends.append(_snapshot(e))
    assert ends[0] == ends[1] and ends[0][2] == EngineState.STOP_LIMIT
    assert 1234 <= ends[0][1][1] < 1234 + 13


@settings(max_examples=100, deadline=None)
@given(lo=st.integers(-2000, 4000), width=st.integers(0, 300),
       pulses=st.lists(st.integers(-40, 125), min_size=1, max_size=128),
       switch=st.sampled_from(["limit_n", "limit_p"]), cut=st.integers(1, 400))
def test_buffered_axis_meets_a_limit_alike(lo: int, width: int, pulses: list[int],
                                           switch: str, cut: int) -> None:
    runs = []
    for traced in (True, False):
        e = _v2(BenchWorld(zones=[Zone(0, switch, lo, lo + width)]), S.LIMIT_N | S.LIMIT_P,
                0.0)
        if traced:
            e.trace = lambda record: None
        e.set_state(EngineState.RUNNING, 0, 0)
        e.fill(np.array([[p, 0, 0] for p in pulses], dtype=np.int32))
        e.run_to(cut)
        first = _snapshot(e)
        e.run_to(400)
        runs.append((first, _snapshot(e)))
    assert runs[0] == runs[1]
