"""Pulse engine v1 (PoKeys56E) exact to the slot (seed v1, reference 10)."""

from __future__ import annotations

import struct

import numpy as np

from maxk.commands.pokeys import PoKeysSession, make_request
from maxk.personalities.pokeys import (
    AxisState,
    BenchWorld,
    EngineState,
    PoKeysDevice,
    PulseEngineV1,
    SlotRecord,
    Zone,
)
from maxk.personalities.pokeys import SwitchBits as S


def engine(world: BenchWorld | None = None, max_speed: float = 20.0, accel: float = 0.0
           ) -> PulseEngineV1:
    e = PulseEngineV1(world)
    for a in e.axes:
        a.settings.max_speed = max_speed
        a.settings.max_acceleration = a.settings.max_deceleration = accel
    return e


def traced(e: PulseEngineV1, slot: int) -> list[SlotRecord]:
    records: list[SlotRecord] = []
    e.trace = records.append
    e.run_to(slot)
    e.trace = None
    return records


def test_v1_slot_carries_at_most_25_pulses() -> None:
    e = engine()
    e.set_state(EngineState.BUFFER)
    assert e.fill(np.array([[100, -30, 25], [127, 0, -127]])) == 2
    e.run_to(2)
    assert e.positions() == [50, -25, 0]
    assert e.buffer.clipped.tolist() == [177, 5, 102]


def test_v1_buffer_is_128_slots() -> None:
    e = engine()
    e.set_state(EngineState.BUFFER)
    assert e.fill(np.ones((200, 3), dtype=np.int32)) == 128
    assert e.free_slots() == 0
    e.run_to(28)
    assert e.free_slots() == 28 and e.positions() == [28, 28, 28]


def test_v1_homing_at_10_then_1_percent_of_max_speed() -> None:
    world = BenchWorld(zones=[Zone(1, "home", -2000, -101)])
    e = engine(world)
    e.axes[1].settings.switches = S.HOME
    e.homing_start([0, 1, 0])
    assert e.state == EngineState.HOMING and e.axis_states()[1] == AxisState.HOMING_START
    records = traced(e, 80)
    assert {r.pulses[1] for r in records[:51]} == {-2}  # 10 % of 20 pulses/ms
    assert records[50].axis_states[1] == AxisState.HOMING_SEARCH
    assert [r.pulses[1] for r in records[51:61]] == [0, 0, 0, 0, 1, 0, 0, 0, 0, 1]  # 1 %
    assert records[60].axis_states[1] == AxisState.HOMING_BACK
    assert records[61].axis_states[1] == AxisState.HOME
    assert records[61].engine_state == EngineState.HOME
    assert e.positions() == [0, 0, 0]
    assert {r.pulses[0] for r in records} == {0}


def test_v1_homing_parameters_change_the_speeds() -> None:
    world = BenchWorld(zones=[Zone(0, "home", 100, 200)])
    e = engine(world)
    e.homing_speed, e.homing_return_speed = 50, 5
    e.axes[0].settings.switches = S.HOME
    e.axes[0].settings.config |= 0x10  # homing direction change: positive
    e.homing_start([1, 0, 0])
    records = traced(e, 20)
    assert records[0].pulses[0] == 10 and records[10].pulses[0] == -1


def test_v1_axis_without_home_switch_is_an_error() -> None:
    e = engine()
    e.homing_start([1, 0, 0])
    assert e.state == EngineState.STOPPED and e.axis_states()[0] == AxisState.ERROR


def test_v1_jogging_ignores_limits_internal_mode_does_not() -> None:
    world = BenchWorld(zones=[Zone(0, "limit_p", 50, 10**6)])
    e = engine(world)
    e.axes[0].settings.switches = S.LIMIT_P
    e.set_state(EngineState.JOGGING)
    e.move([5000, 0, 0])
    e.run_to(40)
    assert e.positions()[0] == 200 and e.state == EngineState.JOGGING
    e.set_state(EngineState.STOPPED)
    e.clear_buffer()
    # Loading the counter does not move the stage: the axis still stands on the limit,
    # so the internal controller is stopped in its first slot.
    e.set_positions([0, 0, 0])
    e.set_state(EngineState.INTERNAL)
    e.move([1000, 0, 0])
    e.run_to(100)
    assert e.positions()[0] == 0 and e.state == EngineState.STOP_LIMIT
    e = engine(world)
    e.axes[0].settings.switches = S.LIMIT_P
    e.set_state(EngineState.INTERNAL)
    e.move([1000, 0, 0])
    e.run_to(100)
    # 20 pulses/slot: 60 at the end of slot 2, read at slot 3.
    assert e.positions()[0] == 60 and e.state == EngineState.STOP_LIMIT
    assert e.axis_states()[0] == AxisState.LIMIT


def test_v1_internal_moves_hold_10_slots_of_the_buffer() -> None:
    e = engine()
    e.set_state(EngineState.INTERNAL)
    e.move([10000, 0, -45])
    assert e.free_slots() == 118
    assert e.fill(np.ones((5, 3), dtype=np.int32)) == 0  # the controller owns the buffer
    e.run_to(100)
    assert e.positions() == [2000, 0, -45]
    # Switching straight to buffer mode: 10 ms of the move are still in the buffer.
    e.set_state(EngineState.BUFFER)
    assert e.buffer.count == 10 and e.free_slots() == 118
    e.run_to(200)
    assert e.positions() == [2200, 0, -45]


def test_v1_clearing_the_buffer_after_internal_mode_stops_at_once() -> None:
    e = engine()
    e.set_state(EngineState.INTERNAL)
    e.move([10000, 0, 0])
    e.run_to(100)
    e.set_state(EngineState.BUFFER)
    e.clear_buffer()
    e.run_to(200)
    assert e.positions()[0] == 2000
    # Near the end of a move the look-ahead is what is left of it.
    e.set_state(EngineState.INTERNAL)
    e.move([2100, 0, 0])  # 5 slots of 20 pulses, from slot 200
    assert e.free_slots() == 123
    e.run_to(202)
    assert e.free_slots() == 125
    e.run_to(300)
    assert e.free_slots() == 128 and e.axis_states()[0] == AxisState.READY


def test_v1_estop() -> None:
    world = BenchWorld(estop_pressed=[(30, 31)])
    e = engine(world)
    e.set_state(EngineState.JOGGING)  # jogging ignores limits, never the e-stop
    e.move([-3000, 0, 0])
    e.run_to(100)
    assert e.positions()[0] == -90 and e.state == EngineState.STOP_EMERGENCY


# ---- over the wire ------------------------------------------------------------------------
def _v1_session() -> tuple[PoKeysDevice, PoKeysSession]:
    device = PoKeysDevice.create("PoKeys56E")
    return device, PoKeysSession(device)


def ask(session: PoKeysSession, sub: int, p2: int = 0, payload: bytes = b"",
        request_id: int = 1) -> bytes:
    session.feed(make_request(0x80, sub, p2, request_id=request_id, payload=payload))
    return session.read()


def test_v1_parameters_and_axis_config_round_trip() -> None:
    device, session = _v1_session()
    params = struct.pack("<9f", 20, 15, 10, 0.5, 0.5, 0.5, 0.25, 0.25, 0.25) + bytes([30, 3, 1])
    assert len(ask(session, 0x11, payload=params)) == 64
    assert ask(session, 0x10)[8:47] == params
    e = device.engine
    assert isinstance(e, PulseEngineV1)
    assert (e.axes[1].settings.max_speed, e.homing_speed, e.estop_polarity) == (15.0, 30, 1)
    config = bytes([0b101, 0b011, 0b111, 0b010, 0b001])
    ask(session, 0x13, payload=config)
    assert ask(session, 0x12)[8:13] == config
    assert e.axes[2].settings.switches == S.LIMIT_P | S.HOME


def test_v1_fill_over_the_wire() -> None:
    device, session = _v1_session()
    ask(session, 0x02, payload=bytes([EngineState.BUFFER]))
    slots = bytes([5, 0x83, 1]) * 18
    reply = ask(session, 0x35, 18, slots)
    assert reply[8] == 18 and reply[24] == EngineState.BUFFER
    assert list(reply[25:28]) == [AxisState.RUNNING] * 3
    refusal = ask(session, 0x35, 19, bytes(55))  # 19 slots do not fit in 55 bytes
    assert refusal[2] == 1 and refusal[8:] == bytes(56)  # refused, nothing taken
    assert ask(session, 0x37)[8] == 110
    device.run_to(18)
    status = ask(session, 0x00)
    assert struct.unpack_from("<3i", status, 8) == (90, -54, 18)
    assert status[23] == EngineState.BUFFER and status[27] == 1
    reply = ask(session, 0x35, 1, bytes([1, 1, 1]))
    assert struct.unpack_from("<3i", reply, 9) == (90, -54, 18)
    ask(session, 0x36)
    assert ask(session, 0x37)[8] == 128
    assert list(ask(session, 0x30)[8:12]) == [3, 25, 128, 1]


def test_v1_bad_state_is_refused() -> None:
    device, session = _v1_session()
    assert ask(session, 0x02, payload=bytes([3]))[2] == 1  # RUNNING is a v2 state
    assert device.engine.state == EngineState.STOPPED
