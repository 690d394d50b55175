"""The PoKeys on the shared machine: the SlotEngine (firmware_model Engine at 1 ms slots)
driven by the pulse engine as its event source, axis motions as MotionPlans, switches,
e-stop and probe from the shared World."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from maxk.firmware_model.axis import MotionAxis
from maxk.firmware_model.world import Switch, World, time_source
from maxk.personalities.pokeys import (
    AxisConfigBits,
    EngineState,
    PoKeysDevice,
    PulseEngineV2,
    PulsePlan,
    SegmentPlan,
    SharedWorld,
    pokeys_world,
)
from maxk.personalities.pokeys import SwitchBits as S
from maxk.personalities.pokeys.constants import SLOT_SECONDS
from maxk.personalities.pokeys.motion import whole_pulses


def running(world: World | None = None, axes: int = 3, internal: int = 0,
            switches: int = 0) -> PoKeysDevice:
    device = PoKeysDevice.create("PoKeys57CNC", None if world is None else SharedWorld(world))
    e = device.engine
    assert isinstance(e, PulseEngineV2)
    e.setup(axes, 0, 0, 0, 0, 0)
    for a in e.axes[:axes]:
        a.settings.config = AxisConfigBits.ENABLED | (
            AxisConfigBits.INTERNAL_PLANNER | AxisConfigBits.POSITION_MODE
            if internal >> a.index & 1 else 0)
        a.settings.switches = switches
        a.settings.max_speed, a.settings.max_acceleration = 10.0, 0.05
        a.settings.max_deceleration = 0.05
    e.set_state(EngineState.RUNNING, 0, 0)
    return device


def test_events_are_the_slots_where_something_changes() -> None:
    world = pokeys_world(8)
    world.axes[0].set_plus_limit(300)
    device = running(world, internal=0b010, switches=S.LIMIT_P)
    e, machine = device.engine, device.machine
    e.fill(np.array([[7, 0, 0]] * 100))
    # 7 pulses a slot cross the switch at 300 in slot 42 (301 at its end): the event.
    assert machine.next_event() == 43
    machine.advance_to(43)
    assert e.positions()[0] == 301 and e.state == EngineState.RUNNING
    machine.advance(1)  # slot 43 reads the switch: a hard stop, no pulse in it
    assert e.state == EngineState.STOP_LIMIT and e.positions()[0] == 301
    assert machine.next_event() is None  # stopped: nothing will change by itself


def test_buffer_dry_and_move_end_events_and_run_until() -> None:
    device = running(internal=0b010)
    e, machine = device.engine, device.machine
    e.fill(np.array([[5, 0, 0]] * 100))
    e.move([0, 1000, 0])
    ends = []
    while (event := machine.next_event()) is not None:
        machine.advance_to(event)
        ends.append(event)
    # the buffer runs dry at 100; the 1000-pulse triangle (0.05 pulses/ms^2) ends at 283
    assert 100 in ends and ends[-1] == 283
    assert e.positions()[:2] == [500, 1000] and e.idle()
    device2 = running()
    device2.engine.fill(np.array([[3, 0, 0]] * 50))
    assert device2.machine.run_until(lambda _m: device2.engine.buffer.count == 0, 1000)
    assert device2.machine.tick == 50


def test_an_observer_sees_the_slots_up_to_its_tick() -> None:
    device = running()
    device.engine.fill(np.array([[2, -1, 0]] * 128))
    seen: list[tuple[int, int]] = []
    device.machine.add_observer(lambda m: seen.append((m.tick, device.engine.positions()[0])),
                                every_ticks=10)
    device.machine.advance_to(45)
    assert seen == [(10, 20), (20, 40), (30, 60), (40, 80)]
    assert device.slot == 45 and device.engine.slot == 45


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(-125, 125), st.integers(-125, 125)), min_size=1,
                max_size=128),
       st.lists(st.integers(1, 40), min_size=1, max_size=10),
       st.integers(-3000, 3000))
def test_the_shared_engine_equals_the_bare_slot_loop(rows, chunks, limit) -> None:
    """Driving the pulse engine through the shared Engine (events, integrate) gives the
    slot loop's result exactly, switches included."""
    def make() -> PoKeysDevice:
        world = pokeys_world(8)
        world.axes[0].set_plus_limit(abs(limit) + 1)
        world.axes[1].set_minus_limit(-abs(limit) - 1)
        d = running(world, axes=2, switches=S.LIMIT_P | S.LIMIT_N)
        d.engine.fill(np.array(rows))
        return d

    shared, bare = make(), make()
    slot = 0
    for n in chunks:
        slot += n
        shared.run_to(slot)
        bare.engine.run_to(slot)
        assert shared.engine.positions() == bare.engine.positions()
        assert shared.engine.state == bare.engine.state and shared.machine.tick == slot


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(-125, 125), min_size=1, max_size=128))
def test_buffered_pulses_as_a_plan_are_exact_at_every_slot(pulses) -> None:
    device = running(axes=1)
    device.engine.fill(np.array(pulses)[:, None])
    found = device.machine.motion_plan(0)
    assert found is not None and isinstance(found.plan, PulsePlan)
    plan = found.plan
    assert plan.final_offset == sum(pulses) and plan.end_time == len(pulses) * SLOT_SECONDS
    for k in range(len(pulses) + 1):
        device.run_to(k)
        assert found.origin + int(plan.offset(k * SLOT_SECONDS)) == device.engine.positions()[0]
    for phase in plan.phases:  # each phase is monotonic
        first = round(phase.t0 / SLOT_SECONDS)
        last = first + round(phase.duration / SLOT_SECONDS)
        assert all(p * phase.direction >= 0 for p in pulses[first:last])


def test_the_shared_switch_search_finds_the_slot_on_a_buffered_plan() -> None:
    """MotionAxis.tick_reaching (the MAXk's limit and trigger search) on a PoKeys plan
    gives the slot the pulse engine crosses the position in."""
    pulses = [1, 2, 3, 5, 8, 13, 21, 0, -4, 34, 55, 89]
    device = running(axes=1)
    device.engine.fill(np.array(pulses)[:, None])
    found = device.machine.motion_plan(0)
    assert found is not None
    axis = MotionAxis(0, "X", steps=found.origin, motion=found.plan, motion_start=found.start,
                      motion_end=found.start + len(pulses))
    for target in (10, 50, 100, 200):
        tick = axis.tick_reaching(target, 1, device.machine)
        cum = np.cumsum(pulses)
        expected = int(np.argmax(cum >= target)) + 1
        assert tick == expected, target
    assert axis.tick_reaching(10_000, 1, device.machine) is None


def test_an_internal_move_as_a_plan_counts_the_engines_pulses() -> None:
    device = running(internal=0b001)
    e = device.engine
    e.move([1000, 0, 0])
    device.run_to(90)
    e.move([400, 0, 0])  # behind: stop within the deceleration, then come back
    found = device.machine.motion_plan(0)
    assert found is not None and isinstance(found.plan, SegmentPlan)
    plan = found.plan
    assert not plan.monotonic and plan.final_offset == 400 - found.origin
    assert [p.direction for p in plan.phases][0] == 1 and plan.phases[-1].direction == -1
    axis = MotionAxis(0, "X", steps=found.origin, motion=plan, motion_start=found.start)
    for k in range(90, 600, 7):
        device.run_to(k)
        t = (k - found.start) * SLOT_SECONDS
        assert found.origin + whole_pulses(plan.offset(t)) == e.positions()[0]
        assert axis.steps_at_tick(k, SLOT_SECONDS) == e.positions()[0]


def test_counters_move_switches_do_not() -> None:
    world = pokeys_world(8)
    world.axes[0].set_plus_limit(300)
    device = running(world, switches=S.LIMIT_P)
    e = device.engine
    assert isinstance(e, PulseEngineV2)
    e.set_positions(0b1, [1000] + [0] * 7)  # the counter reads 1000, the stage is at 0
    e.fill(np.array([[7, 0, 0]] * 100))
    device.run_to(100)
    assert e.state == EngineState.STOP_LIMIT
    assert e.positions()[0] == 1301 and e.axes[0].stage == 301


@settings(max_examples=80, deadline=None)
@given(st.integers(-50, 50), st.integers(0, 30), st.integers(0, 4), st.integers(-80, 80),
       st.sampled_from([1, -1]))
def test_the_worlds_switch_edges_agree_with_its_levels(low, width, bounce, position,
                                                       direction) -> None:
    world = pokeys_world(1)
    world.axes[0].home = Switch(low, low + width, bounce=bounce)
    shared = SharedWorld(world)
    d = shared.next_switch_edge(0, position, direction)
    here = shared.switch_levels(0, position)
    horizon = 200 if d is None else min(d, 200)  # the limits are 1e9 away
    for k in range(1, horizon):
        assert shared.switch_levels(0, position + direction * k) == here
    if d is not None:
        assert shared.switch_levels(0, position + direction * d) != shared.switch_levels(
            0, position + direction * (d - 1))


def test_estop_and_a_stuck_switch_come_from_the_world() -> None:
    world = pokeys_world(8)
    device = running(world)
    device.engine.fill(np.array([[1, 1, 1]] * 100))
    device.run_to(10)
    world.digital[0] = True  # the e-stop input (0) pressed: open
    device.run_to(11)
    assert device.engine.state == EngineState.STOP_EMERGENCY
    assert device.engine.positions() == [10, 10, 10] + [0] * 5
    world2 = pokeys_world(8)
    world2.axes[1].minus_limit.fault = "active"
    device2 = running(world2, switches=S.LIMIT_N)
    device2.engine.fill(np.array([[1, 1, 1]] * 10))
    device2.run_to(5)
    assert device2.engine.state == EngineState.STOP_LIMIT
    assert device2.engine.positions()[:3] == [0, 0, 0]


def test_an_estop_timed_by_a_source_of_time_stops_in_its_slot() -> None:
    world = pokeys_world(8)
    world.digital[0] = time_source(lambda t: t >= 0.0375)  # pressed from 37.5 ms on
    device = running(world)
    device.engine.fill(np.array([[2, 0, 0]] * 128))
    device.run_to(100)
    # the start of slot 38 is the first to read it pressed: 38 slots of 2 pulses ran
    assert device.engine.state == EngineState.STOP_EMERGENCY
    assert device.engine.positions()[0] == 76


def test_a_reset_keeps_the_stage_and_the_time() -> None:
    world = pokeys_world(8)
    world.axes[0].set_plus_limit(100)
    device = running(world, switches=S.LIMIT_P)
    device.engine.fill(np.array([[5, 0, 0]] * 10))
    device.run_to(30)
    device.power_up()
    assert device.slot == 30 and device.engine.slot == 30
    assert device.engine.positions()[0] == 0 and device.engine.axes[0].stage == 50
    assert device.engine.state == EngineState.STOPPED
    device.run_to(40)
    assert device.machine.tick == 40
