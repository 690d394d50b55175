"""Settings the PoKeys used to store only now act on the world, through the requests that
set them: the analog RC filter (0x39), counter options (0xC0 [2]=0 [3]=2), encoder 2x/4x
sampling (0xC4) and the failsafe timeout (0x81). Expected numbers are computed here."""

from __future__ import annotations

import math
import struct

from maxk.controllers.pokeys.controller import PoKeys

ANALOG, COUNTER_INPUT, OUTPUT = 0x08, 0x02 | 0x40, 0x04


def function_frame(dev: PoKeys, pin: int, function: int) -> bytes:
    functions = dev.pin_functions()
    functions[pin - 1] = function
    return bytes(functions)


# ---- the analog RC filter ----------------------------------------------------------------------
def test_the_rc_filter_is_a_first_order_lag_of_its_time_constant_in_ms() -> None:
    dev = PoKeys("PoKeys57CNC")
    assert dev.request(0xC0, 1, payload=function_frame(dev, 41, ANALOG)) is not None
    assert not dev.last_refused
    dev.request(0x39, *struct.pack("<I", 100))  # tau = 100 ms
    assert dev.request(0x38)[2:6] == struct.pack("<I", 100)
    dev.pins.analog(41, 0.0)

    def code() -> int:
        return dev.request(0x3A, 1)[8] << 8 | dev.request(0x3A, 1)[9]

    assert code() == 0
    dev.pins.analog(41, 3.3)  # a step to full scale
    dev.advance(slots=100)  # one time constant: 1 - 1/e of the step
    expected = round((1 - math.exp(-1)) * 4095)  # 2589
    assert abs(code() - expected) <= 1
    dev.advance(slots=400)  # five time constants in all: within 1 % of the input
    assert code() >= round((1 - math.exp(-5)) * 4095) - 1
    dev.request(0x39, 0, 0, 0, 0)  # filter off: the input as it is
    dev.pins.analog(41, 1.0)
    assert code() == round(1.0 / 3.3 * 4095)


# ---- counter options -------------------------------------------------------------------------
def test_counter_options_choose_the_edges_and_the_direction() -> None:
    """Pin 1 of the 57CNC counts. Options 0: rising edges (power-up); 2: falling; 3: both;
    bit 2: down. Four pulses of the world's input on each set-up."""
    dev = PoKeys("PoKeys57CNC")
    dev.request(0xC0, 1, payload=function_frame(dev, 1, COUNTER_INPUT))
    for options, per_pulse in ((0, 1), (1, 1), (2, 1), (3, 2), (0x04, -1), (0x07, -2)):
        options_frame = bytearray(55)
        options_frame[0] = options
        assert dev.request(0xC0, 0, 2, payload=bytes(options_frame))[8] == options
        dev.request(0x1D)  # clear
        for _ in range(4):
            dev.set_input(1, True)
            dev.advance(slots=1)
            dev.set_input(1, False)
            dev.advance(slots=1)
        count = struct.unpack_from("<i", dev.request(0xD8, payload=bytes([0] * 13)), 8)[0]
        assert count == 4 * per_pulse, options


# ---- encoder sampling ------------------------------------------------------------------------
def test_encoder_sampling_counts_each_cycle_once_twice_or_four_times() -> None:
    """Encoder 0 on axis X: a 1000-pulse move counts 1000 at 1x, 2000 with bit 2 (2x),
    4000 with bit 1 (4x)."""
    dev = PoKeys("PoKeys57CNC")
    dev.pins.attach_encoder(0, 0)
    dev.setup(1)
    dev.configure_axis(0, internal=True, max_speed=10, accel=0.05, decel=0.05)
    dev.set_state("running")
    target = 0
    for options, per_cycle in ((0x01, 1), (0x05, 2), (0x03, 4), (0x07, 4)):
        opts = bytearray(25)
        opts[0] = options
        dev.request(0xC4, 1, payload=bytes(opts))
        before = struct.unpack_from("<i", dev.request(0xCD, 0), 8)[0]
        target += 1000
        dev.move({0: target})
        assert dev.run_until_idle(5.0)
        after = struct.unpack_from("<i", dev.request(0xCD, 0), 8)[0]
        assert after - before == 1000 * per_cycle, options


# ---- the failsafe timeout --------------------------------------------------------------------
def test_the_failsafe_acts_when_the_host_is_silent_for_its_timeout() -> None:
    """Timeout 3 x 100 ms, on digital I/O, PoExtBus, PWM and the pulse engine: silent for
    299 ms nothing happens; at 300 ms outputs, PoExtBus and PWM take their safe values and
    the engine stops with its buffer cleared; a request arms it again."""
    dev = PoKeys("PoKeys57CNC")
    dev.request(0xC0, 1, payload=function_frame(dev, 8, OUTPUT))
    dev.set_output(8, True)
    dev.request(0xDA, 1, payload=bytes([0xFF] * 10))  # PoExtBus all on
    dev.set_pwm(0b000001, [500, 0, 0, 0, 0, 0], 1000)  # channel 0 at 50 %
    dev.setup(1)
    dev.configure_axis(0, max_speed=10)
    dev.set_state("running")
    assert dev.fill([[1]] * 100) == 100
    safe = bytearray(23)
    safe[0] = 0x00  # pins 1..8 low in the failsafe state
    safe[7:17] = bytes([0x0F] * 10)  # PoExtBus safe bytes
    safe[17] = 10  # PWM channel 0: 10 %
    dev.request(0x81, 1, 3, 0x0F, payload=bytes(safe))
    watch = dev.device.failsafe
    set_at = dev.slot
    assert watch.last_contact == set_at
    dev.advance(slots=299)  # no request meanwhile
    assert watch.trips == 0 and dev.device.io.outputs[7] is True
    dev.advance(slots=1)  # 300 slots of silence: 3 x 100 ms
    assert watch.trips == 1 and dev.slot == set_at + 300
    assert dev.device.io.outputs[7] is False
    assert dev.device.io.poextbus == bytes([0x0F] * 10)
    assert dev.device.io.pwm_duty[0] == 100  # 10 % of 1000
    status = dev.status()  # (a request: it arms the failsafe again)
    assert status.state_name == "STOPPED" and dev.free_slots() == 128  # buffer cleared
    assert dev.digital_inputs()[7] is False  # what a host reads: the safe level
    dev.advance(slots=299)
    assert watch.trips == 1
    dev.request(0x00)  # a host speaks before the timeout: it starts again
    dev.advance(slots=299)
    assert watch.trips == 1
    dev.advance(slots=1)
    assert watch.trips == 2


# ---- synced fast outputs ---------------------------------------------------------------------
def test_synced_fast_outputs_follow_the_buffer_slot_by_slot() -> None:
    """Axis Y (1) carries output bits: bit 0 -> pin 8, bit 1 -> pin 12, bit 7 -> pin 13
    (all digital outputs of the 57CNC). Each slot of an 8-bit fill sets them, as sent
    (0x80 and 0xFF included, which as pulses would mean -0 and a clipped -127); X moves
    its 5 pulses a slot and Y does not move."""
    dev = PoKeys("PoKeys57CNC")
    functions = dev.pin_functions()
    for pin in (8, 12, 13):
        functions[pin - 1] = OUTPUT
    dev.request(0xC0, 1, payload=bytes(functions))
    dev.setup(2)
    dev.configure_axis(0, max_speed=10)
    dev.configure_axis(1, max_speed=10)
    mapping = bytes([8, 12, 0, 0, 0, 0, 0, 13])
    assert dev.request(0x85, 0x0B, 1, 1, payload=mapping)[2] == 0x0B
    dev.set_state("running")
    slots = [0x01, 0x03, 0x02, 0x80, 0xFF, 0x00]
    payload = b"".join(bytes([5, v]) for v in slots)
    assert dev.request(0x85, 0xFF, len(slots), 2, payload=payload)[2] == len(slots)

    def pins() -> tuple[int, int, int]:
        bits = int.from_bytes(dev.request(0xCC)[8:15], "little")
        return bits >> 7 & 1, bits >> 11 & 1, bits >> 12 & 1

    seen = []
    for _ in slots:
        dev.advance(slots=1)
        seen.append(pins())
    assert seen == [(1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1), (0, 0, 0)]
    assert dev.status().positions[:2] == (5 * len(slots), 0)
    dev.request(0x85, 0x0B, 0, 0)  # off: Y's entries are pulses again
    dev.fill([[0, 3]] * 4)
    dev.advance(slots=4)
    assert dev.status().positions[:2] == (5 * len(slots), 12) and pins() == (0, 0, 0)


# ---- backlash compensation -------------------------------------------------------------------
def backlash_payload(width: int, accel: int = 0) -> bytes:
    """Axis 0's u16 width at [8] and acceleration at [10]; other axes 0."""
    return struct.pack("<HBB", width, accel, 0) + bytes(28)


def encoder_0(dev: PoKeys) -> int:
    return struct.unpack_from("<i", dev.request(0xCD, 0), 8)[0]


def test_backlash_compensation_takes_up_the_play_on_a_reversal_in_buffered_slots() -> None:
    """Width 3 (half the play), 2 pulses a slot. Four slots of +5 then four of -5: the
    register goes 0 -> 2 -> 3 -> 3 -> 3, then on the reversal 3 -> 1 -> -1 -> -3 -> -3.
    The counter ends at 0, the motor (the stage an encoder reads) at -3."""
    dev = PoKeys("PoKeys57CNC")
    dev.pins.attach_encoder(0, 0)
    opts = bytearray(25)
    opts[0] = 0x01
    dev.request(0xC4, 1, payload=bytes(opts))
    dev.setup(1)
    dev.configure_axis(0, max_speed=10)
    dev.request(0x85, 0x41, 1, 2, payload=backlash_payload(3))
    dev.set_state("running")
    assert dev.fill([[5]] * 4 + [[-5]] * 4) == 8
    registers, stages = [], []
    for _ in range(8):
        dev.advance(slots=1)
        registers.append(struct.unpack_from("<h", dev.request(0x85, 0x40), 40)[0])
        stages.append(encoder_0(dev))
    assert registers == [2, 3, 3, 3, 1, -1, -3, -3]
    counters = [5, 10, 15, 20, 15, 10, 5, 0]
    assert stages == [c + r for c, r in zip(counters, registers, strict=True)]
    assert dev.status().positions[0] == 0


def test_backlash_compensation_on_internal_moves_and_switched_off() -> None:
    """Width 10 at once (speed 0): a move to +1000 leaves the motor at 1010, back to 0
    at -10; switched off, the motor stays where it is and moves with the counter."""
    dev = PoKeys("PoKeys57CNC")
    dev.pins.attach_encoder(0, 0)
    opts = bytearray(25)
    opts[0] = 0x01
    dev.request(0xC4, 1, payload=bytes(opts))
    dev.setup(1)
    dev.configure_axis(0, internal=True, max_speed=10, accel=0.05, decel=0.05)
    dev.request(0x85, 0x41, 1, 0, payload=backlash_payload(10))
    dev.set_state("running")
    dev.move({0: 1000})
    assert dev.run_until_idle(5.0)
    assert (dev.status().positions[0], encoder_0(dev)) == (1000, 1010)
    dev.move({0: 0})
    assert dev.run_until_idle(5.0)
    assert (dev.status().positions[0], encoder_0(dev)) == (0, -10)
    dev.request(0x85, 0x41, 0, 0, payload=backlash_payload(10))  # off
    assert struct.unpack_from("<h", dev.request(0x85, 0x40), 40)[0] == 0
    assert encoder_0(dev) == -10
    dev.move({0: 500})
    assert dev.run_until_idle(5.0)
    assert (dev.status().positions[0], encoder_0(dev)) == (500, 490)
