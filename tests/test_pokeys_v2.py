"""Pulse engine v2 behaviour, exact to the slot (seed v2, reference 6-9)."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from maxk.personalities.pokeys import (
    AxisConfigBits as C,
)
from maxk.personalities.pokeys import (
    AxisState,
    BenchWorld,
    EngineState,
    PulseEngineV2,
    SlotRecord,
    Zone,
)
from maxk.personalities.pokeys import (
    SwitchBits as S,
)

ENABLED = C.ENABLED
INTERNAL_POS = C.ENABLED | C.INTERNAL_PLANNER | C.POSITION_MODE
INTERNAL_SPEED = C.ENABLED | C.INTERNAL_PLANNER


def engine(axes: int = 3, world: BenchWorld | None = None, config: int = ENABLED,
           max_speed: float = 10.0, accel: float = 0.0) -> PulseEngineV2:
    e = PulseEngineV2(world)
    e.setup(axes, 0, 0, 0, 0, 0)
    for a in e.axes[:axes]:
        st = a.settings
        st.config, st.max_speed = config, max_speed
        st.max_acceleration = st.max_deceleration = accel
    return e


def run(e: PulseEngineV2, slot: int, traced: bool = False) -> list[SlotRecord]:
    records: list[SlotRecord] = []
    if traced:
        e.trace = records.append
    e.run_to(slot)
    e.trace = None
    return records


def stream(e: PulseEngineV2, rows: list[list[int]]) -> int:
    return e.fill(np.array(rows, dtype=np.int32))


def test_fill_accepts_what_fits_in_128_slots() -> None:
    e = engine()
    assert stream(e, [[1, 0, 0]] * 100) == 100
    assert stream(e, [[1, 0, 0]] * 100) == 28
    assert stream(e, [[1, 0, 0]] * 5) == 0
    e.run_to(50)  # stopped: nothing is consumed
    assert e.buffer.count == 128 and e.positions()[0] == 0
    e.set_state(EngineState.RUNNING, 0, 0)
    e.run_to(60)
    assert e.positions()[0] == 10 and e.buffer.free == 10
    assert stream(e, [[1, 0, 0]] * 50) == 10


def test_one_entry_per_slot_and_positions_count_pulses() -> None:
    e = engine()
    stream(e, [[5, -3, 1], [0, 2, -1], [7, 0, 0]])
    e.set_state(EngineState.RUNNING, 0, 0)
    records = run(e, 5, traced=True)
    assert [r.pulses[:3] for r in records] == [(5, -3, 1), (0, 2, -1), (7, 0, 0), (0, 0, 0),
                                               (0, 0, 0)]
    assert [r.directions[:3] for r in records][:3] == [
        (False, True, False), (False, False, True), (False, False, True)]
    assert e.positions()[:3] == [12, -1, 0]


def test_pulses_above_125_per_slot_are_clipped_and_counted() -> None:
    e = engine(axes=2)
    stream(e, [[200, -130], [125, -125]])
    e.set_state(EngineState.RUNNING, 0, 0)
    e.run_to(2)
    assert e.positions()[:2] == [250, -250]
    assert e.buffer.clipped[:2].tolist() == [75, 5]


def test_only_enabled_axes_move() -> None:
    e = engine(axes=2)
    e.axes[1].settings.config = 0
    stream(e, [[4, 4, 4]])
    e.set_state(EngineState.RUNNING, 0, 0)
    e.run_to(1)
    assert e.positions()[:3] == [4, 0, 0]


def _limit_case(traced: bool) -> tuple[PulseEngineV2, list[SlotRecord], list[tuple]]:
    world = BenchWorld(zones=[Zone(0, "limit_p", 1005, 10**6)])
    e = engine(axes=1, world=world)
    e.axes[0].settings.switches = S.LIMIT_P
    events: list[tuple] = []
    e.listeners.append(lambda slot, kind, axis: events.append((slot, kind, axis)))
    stream(e, [[10]] * 128)
    e.set_state(EngineState.RUNNING, 0, 0)
    return e, run(e, 120, traced), events


def test_limit_stops_hard_in_the_slot_it_is_read() -> None:
    e, records, events = _limit_case(traced=True)
    # Position 1010 is reached at the end of slot 100; slot 101 reads the switch.
    assert records[100].pulses[0] == 10 and records[100].engine_state == EngineState.RUNNING
    assert records[101].pulses[0] == 0
    assert records[101].engine_state == EngineState.STOP_LIMIT
    assert records[101].axis_states[0] == AxisState.LIMIT
    assert e.positions()[0] == 1010 and e.buffer.count == 0
    assert (101, "limit", 0) in events


def test_limit_stop_is_the_same_without_the_trace() -> None:
    e, _, events = _limit_case(traced=False)
    assert e.positions()[0] == 1010 and e.state == EngineState.STOP_LIMIT
    assert (101, "limit", 0) in events


def test_limit_override_disabled_switch_and_inverted_switch() -> None:
    for switches, override, moves in ((S.LIMIT_P, 1, True), (0, 0, True),
                                      (S.LIMIT_P | S.INVERT_LIMIT_P, 0, False)):
        world = BenchWorld(zones=[Zone(0, "limit_p", 5, 10**6)])
        e = engine(axes=1, world=world)
        e.axes[0].settings.switches = switches
        stream(e, [[1]] * 20)
        e.set_state(EngineState.RUNNING, override, 0)
        e.run_to(20)
        # Inverted: the closed (low) switch reads tripped before the first pulse.
        assert e.positions()[0] == (20 if moves else 0)


def test_estop_stops_in_the_slot_it_is_pressed_and_stays_stopped() -> None:
    world = BenchWorld(estop_pressed=[(250, 400)])
    e = engine(axes=1, world=world, config=INTERNAL_SPEED)
    e.set_state(EngineState.RUNNING, 0, 0)
    e.move([4000] + [0] * 7)  # 4 pulses per slot, no ramp (acceleration 0 = instant)
    e.run_to(1000)
    assert e.positions()[0] == 250 * 4
    assert e.state == EngineState.STOP_EMERGENCY and e.axis_states()[0] == AxisState.ERROR
    e.set_state(EngineState.RUNNING, 0, 0)
    e.move([4000] + [0] * 7)
    e.run_to(1010)
    assert e.positions()[0] == 1040


def test_estop_polarity_inverts_the_input() -> None:
    e = engine(axes=1)
    e.setup(1, 0, 0, 0, 1, 0)  # polarity 1: the closed (low) e-stop reads tripped
    stream(e, [[1]] * 10)
    e.set_state(EngineState.RUNNING, 0, 0)
    e.run_to(10)
    assert e.positions()[0] == 0 and e.state == EngineState.STOP_EMERGENCY


def test_internal_position_move_is_the_closed_form_profile() -> None:
    e = engine(axes=2, config=INTERNAL_POS, max_speed=10.0, accel=0.05)
    e.axes[1].settings.config = ENABLED  # buffered beside it
    e.set_state(EngineState.RUNNING, 0, 0)
    e.run_to(7)
    e.move([3000, 0] + [0] * 6)
    stream(e, [[0, 2]] * 100)
    records = run(e, 800, traced=True)
    # the trapezoid written out (issue 41: not the engine's plan_move): 10 pulses/ms =
    # 10000/s, 0.05 pulses/ms^2 = 50000/s^2: 0.2 s (1000 pulses) up, 1000 at speed in
    # 0.1 s, 0.2 s down; 3000 pulses in 0.5 s
    def offset(ms: int) -> Fraction:
        t = Fraction(ms, 1000)
        if t <= Fraction(1, 5):
            return 25000 * t * t
        if t <= Fraction(3, 10):
            return 1000 + 10000 * (t - Fraction(1, 5))
        return 3000 - 25000 * (Fraction(1, 2) - min(t, Fraction(1, 2))) ** 2

    expected = [math.floor(offset(k)) for k in range(794)]
    got = [0]
    for r in records:
        got.append(got[-1] + r.pulses[0])
    assert got == expected
    assert max(r.pulses[0] for r in records) == 10
    end = 7 + 500
    # records[i] is slot 7 + i, states as at its end: the last pulses go out in slot end-1.
    assert records[end - 9].axis_states[0] == AxisState.RUNNING
    assert records[end - 8].axis_states[0] == AxisState.READY and records[end - 8].pulses[0]
    assert e.positions()[:2] == [3000, 200]


def test_buffer_clear_leaves_internal_axes_moving() -> None:
    e = engine(axes=2, config=INTERNAL_SPEED)
    e.axes[1].settings.config = ENABLED
    e.set_state(EngineState.RUNNING, 0, 0)
    e.move([3000, 0] + [0] * 6)
    stream(e, [[0, 1]] * 100)
    e.run_to(10)
    e.clear_buffer()
    e.run_to(20)
    assert e.positions()[:2] == [60, 10]


def test_speed_mode_ramps_and_stops() -> None:
    e = engine(axes=1, config=INTERNAL_SPEED, max_speed=10.0, accel=0.01)
    e.set_state(EngineState.RUNNING, 0, 0)
    e.move([-5000] + [0] * 7)
    records = run(e, 1000, traced=True)
    assert [r.pulses[0] for r in records[600:603]] == [-5, -5, -5]  # ramp took 500 slots
    assert e.positions()[0] == -(1250 + 5 * 500)
    e.move([0] * 8)
    e.run_to(2000)
    assert e.positions()[0] == -(1250 + 2500 + 1250) and e.axis_states()[0] == AxisState.READY


def test_moves_are_ignored_outside_running_and_on_buffered_axes() -> None:
    e = engine(axes=2)
    e.axes[0].settings.config = INTERNAL_POS
    e.move([500, 500] + [0] * 6)
    e.run_to(100)
    e.set_state(EngineState.RUNNING, 0, 0)
    e.move([500, 500] + [0] * 6)
    e.run_to(200)
    assert e.positions()[:2] == [500, 0]


def _homing(switches: int = S.HOME, config: int = ENABLED, zone: str = "home",
            lo: int = -2000, hi: int = -903) -> tuple[PulseEngineV2, list[SlotRecord]]:
    e = engine(axes=1, world=BenchWorld(zones=[Zone(0, zone, lo, hi)]), config=config)
    st = e.axes[0].settings
    st.switches, st.homing_speed, st.homing_return_speed = switches, 50, 20
    e.homing_start(1, [0] * 8)
    return e, run(e, 400, traced=True)


def test_homing_speeds_and_phases() -> None:
    e, records = _homing()
    # 50 % of 10 pulses/ms toward negative until the home switch reads tripped...
    assert records[0].pulses[0] == -5 and records[0].axis_states[0] == AxisState.HOMING_SEARCH
    assert sum(r.pulses[0] for r in records[:181]) == -905  # -905 is reached in slot 180
    # ...then back at 20 % of that (1 pulse/slot) until it releases: counter reset.
    assert records[181].pulses[0] == 1 and records[181].axis_states[0] == AxisState.HOMING_BACK
    assert [r.pulses[0] for r in records[182:184]] == [1, 1]  # -902 leaves the switch
    assert records[184].pulses[0] == 0 and records[184].axis_states[0] == AxisState.HOME
    assert records[184].engine_state == EngineState.HOME
    assert e.positions()[0] == 0


def test_homing_defaults_offset_direction_and_shared_limit() -> None:
    e = engine(axes=1, world=BenchWorld(zones=[Zone(0, "home", 1000, 1099)]))
    st = e.axes[0].settings
    st.switches, st.config = S.HOME, ENABLED | C.INVERTED_HOME  # defaults: 10 %, then half
    e.homing_start(1, [777] + [0] * 7)
    e.run_to(1002)  # 1 pulse/slot up to 1000 (slot 999), back at 0.5: 999 after slot 1001
    assert e.state == EngineState.HOMING and e.positions()[0] == 999
    e.run_to(1003)
    assert e.state == EngineState.HOME and e.positions()[0] == 777
    # Home on the limit- input: the limit does not stop the homing axis.
    e2, _ = _homing(switches=S.HOME_ON_LIMIT_N | S.LIMIT_N, zone="limit_n")
    assert e2.state == EngineState.HOME and e2.positions()[0] == 0


def test_homing_without_a_home_input_does_nothing() -> None:
    e = engine(axes=1)
    e.homing_start(1, [0] * 8)
    assert e.state == EngineState.STOPPED


def test_probing_saves_positions_when_the_probe_trips() -> None:
    world = BenchWorld(probe_axis=0, probe_at=-1234, probe_direction=-1)
    e = engine(axes=2, world=world)
    e.set_state(EngineState.RUNNING, 0, 0)
    e.probing_start(0b01, [-5000, 0] + [0] * 6, 0.5, 1, 1)
    records = run(e, 400, traced=True)
    # 5 pulses/slot: -1235 at the end of slot 246, read at slot 247.
    assert records[246].axis_states[0] == AxisState.PROBE_SEARCH
    assert records[247].engine_state == EngineState.PROBE_COMPLETE
    assert records[247].pulses[0] == 0 and records[247].axis_states[0] == AxisState.PROBED
    assert e.probing_finish() == ([-1235] + [0] * 7, 1)
    assert e.state == EngineState.RUNNING


def test_probing_error_at_the_max_position() -> None:
    world = BenchWorld(probe_axis=0, probe_at=-99999, probe_direction=-1)
    e = engine(axes=1, world=world)
    e.probing_start(1, [-1003] + [0] * 7, 0.5, 1, 1)
    e.run_to(400)
    assert e.positions()[0] == -1003 and e.state == EngineState.PROBE_ERROR
    assert e.probing_finish()[1] == 2 and e.state == EngineState.STOPPED


def test_soft_limits_clip_buffered_pulses_and_internal_targets() -> None:
    e = engine(axes=2)
    for a in e.axes[:2]:
        a.settings.config |= C.SOFT_LIMIT_ENABLED
        a.settings.soft_limit_min, a.settings.soft_limit_max = -50, 1000
    e.axes[1].settings.config |= C.INTERNAL_PLANNER | C.POSITION_MODE
    stream(e, [[7, 0]] * 128)
    e.set_state(EngineState.RUNNING, 0, 0)
    e.move([0, -500] + [0] * 6)
    e.run_to(400)
    assert e.positions()[:2] == [896, -50]
    stream(e, [[7, 0]] * 128)
    e.run_to(600)
    assert e.positions()[0] == 1000 and e.soft_limit_bits() == 0b11


def test_mpg_jog_follows_the_encoder_times_the_multiplier() -> None:
    world = BenchWorld(mpg={1: [(10, 5), (30, 3)]})
    e = engine(axes=1, world=world, max_speed=4.0)
    e.axes[0].settings.mpg_encoder, e.axes[0].settings.mpg_multiplier = 1, 3
    e.set_state(EngineState.JOGGING, 0, 0)
    records = run(e, 40, traced=True)
    assert [r.pulses[0] for r in records[9:15]] == [0, 4, 4, 4, 3, 0]
    assert [r.pulses[0] for r in records[30:33]] == [-4, -2, 0]
    assert e.positions()[0] == 9


def test_next_event_reports_buffer_dry_move_end_and_switches() -> None:
    # A limit switch enabled (overridden, so it does not stop the axis) makes its edges
    # events; a home switch outside homing changes nothing, so its edges are not.
    e = engine(axes=2, world=BenchWorld(zones=[Zone(1, "limit_p", 30, 40),
                                               Zone(0, "home", 10, 20)]))
    e.axes[1].settings.switches = S.LIMIT_P
    assert e.next_event() is None
    stream(e, [[1, 0]] * 50)
    e.set_state(EngineState.RUNNING, 0b10, 0)
    assert e.next_event() == 50
    e.run_to(50)
    e.axes[1].settings.config = INTERNAL_POS
    e.move([0, 100] + [0] * 6)
    assert e.next_event() == 53  # position 30 (a switch edge) at the end of slot 52
    e.run_to(53)
    assert e.next_event() == 55  # 41 at the end of slot 54
    e.run_to(55)
    assert e.next_event() == 60  # the move ends


def test_leaving_a_limit_needs_the_override() -> None:
    e, _, _ = _limit_case(traced=False)
    e.set_state(EngineState.RUNNING, 0, 0)
    stream(e, [[-10]] * 5)
    e.run_to(121)
    assert e.state == EngineState.STOP_LIMIT and e.positions()[0] == 1010
    e.set_state(EngineState.RUNNING, 0b1, 0)
    stream(e, [[-10]] * 5)
    e.run_to(130)
    assert e.state == EngineState.RUNNING and e.positions()[0] == 960
    assert e.switch_bits() == (0, 0, 0)


def _retarget(first: int, second: int, at: int) -> tuple[PulseEngineV2, list[int]]:
    e = engine(axes=1, config=INTERNAL_POS, max_speed=10.0, accel=0.05)
    e.set_state(EngineState.RUNNING, 0, 0)
    e.move([first] + [0] * 7)
    records = run(e, at, traced=True)
    e.move([second] + [0] * 7)
    records += run(e, 2000, traced=True)
    return e, [r.pulses[0] for r in records]


def test_a_new_target_ahead_carries_on_without_stopping() -> None:
    e, pulses = _retarget(1000, 5000, 100)
    last = max(i for i, p in enumerate(pulses) if p)
    assert min(pulses[100:last - 100]) >= 5  # 5 pulses/slot at slot 100; 200 slots down
    assert max(pulses) == 10 and e.positions()[0] == 5000
    # Stop (100 slots) and a fresh 4750-pulse move (675 slots) would end at slot 875.
    assert last < 800


def test_a_new_target_behind_stops_then_comes_back() -> None:
    e, pulses = _retarget(5000, 1000, 300)
    position = np.cumsum(pulses)
    turn = int(np.argmax(position))
    # At 10 pulses/ms, 0.05 pulses/ms^2 down: 1000 more pulses to stop, then back.
    assert position[turn] == position[299] + 1000
    assert min(pulses[turn + 1:]) >= -10 and e.positions()[0] == 1000
