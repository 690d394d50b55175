"""The PoKeys as an I/O device over REAL TCP and UDP sockets: a host written from the
library's source (tests/pokeys_lib_host.py) calls each function and checks its effect
on the shared world (a pin set as output is high there; a world input is read by
DigitalIOGet; an encoder on a moving axis counts its pulses exactly). Time moves only
when the test moves it."""

from __future__ import annotations

import struct

import pytest

from maxk.controllers.pokeys.controller import PoKeys
from tests.hosting import HostedBoards
from tests.pokeys_host import PK_ERR_GENERIC, PK_OK, Host, axis_config_payload
from tests.pokeys_lib_host import LibHost
from tests.test_pokeys_doors import TcpSession, UdpSession

DI, DO, AI, COUNTER, INVERT = 0x02, 0x04, 0x08, 0x40, 0x80


@pytest.fixture(params=["tcp", "udp"])
def lib(request):
    boards = HostedBoards(models=("PoKeys57CNC",))
    session = (TcpSession(boards.ports[0]) if request.param == "tcp"
               else UdpSession(boards.udp_ports[0]))
    host = LibHost(Host(session))  # type: ignore[arg-type]
    host.boards = boards  # type: ignore[attr-defined]
    yield host
    session.close()
    boards.close()


def dev(lib: LibHost) -> PoKeys:
    c = lib.boards.services[0].controller  # type: ignore[attr-defined]
    assert isinstance(c, PoKeys)
    return c


def world(lib: LibHost, fn):
    """Act on the device's world on the server's own loop (it is not thread-safe)."""
    return lib.boards.call(fn)  # type: ignore[attr-defined]


def advance(lib: LibHost, seconds: float) -> None:
    lib.boards.advance(seconds)  # type: ignore[attr-defined]


def refused(lib: LibHost, cmd: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0,
            payload: bytes = b"", status: int = 1) -> bool:
    """The device refuses this frame the way it answers a refusal: one reply, at once,
    with this request's ID, the error status in [2] (1: a parameter or a capability
    refused) and a zero payload. What it leaves unchanged the caller checks."""
    h = lib.host
    sent = h.request_id
    reply = h.send(h.create(cmd, p1, p2, p3, p4, payload))
    return (reply is not None and h.request_id == (sent + 1) & 0xFF and reply[1] == cmd
            and reply[2] == status and reply[8:] == bytes(56))


# ---- pins ----------------------------------------------------------------
def test_pin_configuration_round_trip_and_a_refused_set_up_changes_nothing(lib):
    assert lib.PK_PinConfigurationGet() == PK_OK
    assert lib.pin_function == [0] * 55
    lib.pin_function[0] = DO          # pin 1
    lib.pin_function[2] = DI | COUNTER  # pin 3
    lib.pin_function[40] = AI         # pin 41
    lib.pin_function[18] = DI | INVERT  # pin 19, the probe input
    lib.counter_options[2] = 0x10
    assert lib.PK_PinConfigurationSet() == PK_OK
    got = LibHost(lib.host)
    assert got.PK_PinConfigurationGet() == PK_OK
    assert got.pin_function == lib.pin_function and got.counter_options[2] == 0x10
    # pin 7 is restricted on the 57CNC; pin 19 cannot drive; pin 45 cannot count
    for pin, function in ((7, DO), (19, DO), (45, DI | COUNTER), (41, AI | INVERT),
                          (1, DI | DO)):
        bad = list(lib.pin_function)
        bad[pin - 1] = function
        assert refused(lib, 0xC0, 1, payload=bytes(bad))
        assert got.PK_PinConfigurationGet() == PK_OK and got.pin_function == lib.pin_function


def test_a_pin_set_as_output_is_high_in_the_world(lib):
    lib.pin_function[0] = DO
    lib.pin_function[17] = DO | INVERT  # pin 18, inverted
    assert lib.PK_PinConfigurationSet() == PK_OK
    view = world(lib, lambda: dev(lib).world_view())
    assert world(lib, lambda: view.output_level(1)) is False
    lib.digital_set[0] = 1
    assert lib.PK_DigitalIOSetGet() == PK_OK
    assert world(lib, lambda: view.output_level(1)) is True
    assert world(lib, lambda: view.output_level(18)) is True  # 0 written, inverted: high
    assert lib.digital_get[0] == 1
    assert world(lib, lambda: view.output_level(2)) is None  # not an output
    assert lib.PK_DigitalIOSetSingle(0, 0) == PK_OK
    assert world(lib, lambda: dev(lib).pins.output_levels()) == {1: False, 18: True}
    assert lib.PK_DigitalIOSetSingle(2, 1) == PK_ERR_GENERIC  # pin 3 is no output


def test_a_world_input_is_read_by_digital_io_get(lib):
    lib.pin_function[2] = DI
    lib.pin_function[18] = DI | INVERT
    assert lib.PK_PinConfigurationSet() == PK_OK
    world(lib, lambda: dev(lib).world_view().set_input(3, True))  # the world contract
    assert lib.PK_DigitalIOGet() == PK_OK
    assert lib.digital_get[2] == 1 and lib.digital_get[18] == 1  # 19 low, inverted
    assert lib.PK_DigitalIOGetSingle(2) == (PK_OK, 1)
    world(lib, lambda: dev(lib).pins.set_input(19, True))
    assert lib.PK_DigitalIOGetSingle(18) == (PK_OK, 0)
    assert lib.PK_DigitalIOGetSingle(60)[0] == PK_ERR_GENERIC


def test_analog_inputs_are_12_bit_codes_of_the_world_volts(lib):
    lib.pin_function[40] = AI
    lib.pin_function[43] = AI
    assert lib.PK_PinConfigurationSet() == PK_OK
    world(lib, lambda: dev(lib).pins.analog(41, 1.0))
    world(lib, lambda: dev(lib).world_view().set_analog(44, 3.3))
    world(lib, lambda: dev(lib).pins.analog(42, 2.0))  # pin 42 not configured: 0
    assert lib.PK_AnalogIOGet() == PK_OK
    assert lib.analog == [round(1.0 / 3.3 * 4095), 0, 0, 4095, 0, 0, 0]
    with pytest.raises(ValueError):
        world(lib, lambda: dev(lib).pins.analog(41, float("nan")))


def test_digital_counters_count_the_worlds_rising_edges(lib):
    lib.pin_function[2] = DI | COUNTER  # pin 3
    lib.pin_function[0] = DI  # pin 1 can count, but is not set to
    assert lib.PK_PinConfigurationSet() == PK_OK

    def toggle():
        pins = dev(lib).pins
        for level in (True, False) * 5:
            pins.set_input(3, level)
            pins.set_input(1, level)

    world(lib, toggle)
    assert lib.PK_DigitalCounterGet([2, 0, 6]) == {2: 5, 0: 0, 6: 0}
    assert lib.PK_DigitalCounterClear() == PK_OK
    assert lib.PK_DigitalCounterGet([2]) == {2: 0}


# ---- PWM ----------------------------------------------------------------
def test_pwm_configuration_update_and_a_channel_that_cannot_drive(lib):
    lib.pwm_enabled = [1, 1, 0, 0, 0, 0]
    lib.pwm_period, lib.pwm_duty = 25000, [12500, 2500, 0, 0, 0, 0]
    assert lib.PK_PWMConfigurationSet() == PK_OK
    got = LibHost(lib.host)
    assert got.PK_PWMConfigurationGet() == PK_OK
    assert (got.pwm_enabled, got.pwm_duty, got.pwm_period) == (
        lib.pwm_enabled, lib.pwm_duty, 25000)
    lib.pwm_duty = [5000, 25000, 0, 0, 0, 0]
    assert lib.PK_PWMUpdate() == PK_OK
    assert world(lib, lambda: dev(lib).device.pwm_output(0)) == 0.2
    assert world(lib, lambda: dev(lib).device.pwm_output(1)) == 1.0
    lib.pwm_enabled[3] = 1  # channel 3 = pin 19, an input on the 57CNC
    assert refused(lib, 0xCB, 1, payload=lib._pwm_payload())
    assert got.PK_PWMConfigurationGet() == PK_OK and got.pwm_enabled[3] == 0


def test_synced_pwm_follows_its_axis_speed(lib):
    h = lib.host
    assert h.pev2(0x01, payload=bytes([1, 0, 1])) is not None
    assert h.pev2(0x11, 0, payload=axis_config_payload(0x01 | 0x04 | 0x08, 0, max_speed=10.0,
                                                       accel=0.0, decel=0.0)) is not None
    lib.pwm_enabled = [1, 0, 0, 0, 0, 0]
    lib.pwm_period, lib.pwm_duty = 1000, [0] * 6
    assert lib.PK_PWMConfigurationSet() == PK_OK
    assert h.pev2(0x0A, 1, 0, 0) is not None  # enabled, axis 0, channel 0
    assert refused(lib, 0x85, 0x0A, 1, 8, 0)  # no axis 8
    assert h.pev2(0x02, 3) is not None  # RUNNING
    assert h.pev2(0x20, payload=struct.pack("<i", 100000)) is not None
    advance(lib, 0.5)
    assert world(lib, lambda: dev(lib).device.pwm_output(0)) == pytest.approx(1.0)


# ---- encoders ----------------------------------------------------------------
def test_an_encoder_on_a_moving_axis_counts_its_pulses_exactly(lib):
    h = lib.host
    world(lib, lambda: dev(lib).pins.attach_encoder(0, 0))
    world(lib, lambda: dev(lib).pins.attach_encoder(25, 1, direction=-1))
    lib.encoder_options[0] = 1
    lib.ultra_fast = (1, 0, 7)
    assert lib.PK_EncoderConfigurationSet() == PK_OK
    assert h.pev2(0x01, payload=bytes([2, 0, 1])) is not None
    for axis in (0, 1):
        assert h.pev2(0x11, axis, payload=axis_config_payload(0x01, 0)) is not None
    assert h.pev2(0x02, 3) is not None
    entries = [[5, -3]] * 20
    accepted, _ = h.buffer_fill(entries, axes=2)
    assert accepted == 20
    advance(lib, 0.05)
    assert lib.PK_EncoderValuesGet() == PK_OK
    assert lib.encoder_values[0] == 5 * 20 and lib.encoder_values[25] == 3 * 20
    assert lib.encoder_values[1] == 0
    got = LibHost(lib.host)
    assert got.PK_EncoderConfigurationGet() == PK_OK
    assert got.encoder_options[0] == 1 and got.ultra_fast == (1, 0, 7)
    lib.encoder_values[0] = -7
    assert lib.PK_EncoderValuesSet() == PK_OK
    accepted, _ = h.buffer_fill([[2, 0]] * 10, axes=2)
    advance(lib, 0.05)
    assert lib.PK_EncoderValuesGet() == PK_OK and lib.encoder_values[0] == -7 + 20
    r = h.pev2(0x37)
    assert r is not None and r[12:24] == bytes(12)


# ---- the rest of the device ----------------------------------------------------------------
def test_rtc_runs_on_virtual_time_and_refuses_a_date_that_does_not_exist(lib):
    assert lib.PK_RTCSet(58, 59, 23, 31, 12, 2025) == PK_OK
    assert lib.PK_RTCGet() == {"sec": 58, "min": 59, "hour": 23, "dow": 3, "dom": 31,
                               "month": 12, "doy": 365, "year": 2025}
    advance(lib, 3.0)
    now = lib.PK_RTCGet()
    assert isinstance(now, dict) and (now["year"], now["month"], now["dom"], now["sec"]) == (
        2026, 1, 1, 1)
    for bad in ([0, 0, 0, 0, 30, 2], [60, 0, 0, 0, 1, 1], [0, 0, 24, 0, 1, 1]):
        assert refused(lib, 0x83, 0x10, payload=bytes(bad) + struct.pack("<HH", 0, 2026))
    now = lib.PK_RTCGet()
    assert isinstance(now, dict) and now["year"] == 2026


def test_poextbus_matrix_keyboard_lcd_and_failsafe(lib):
    h = lib.host
    data = bytes(range(1, 11))
    r = h.send(h.create(0xDA, 1, payload=data))
    assert r is not None and r[8:18] == data  # the library compares the echo
    assert h.send(h.create(0xDA, 2))[8:18] == data  # type: ignore[index]
    # matrix keyboard 4 rows x 4 columns, on
    config = bytearray(42)
    config[0], config[1] = 1, (4 - 1) | (4 - 1) << 4
    assert h.send(h.create(0xCA, 1, payload=bytes(config))) is not None
    assert h.send(h.create(0xCA, 10))[8:10] == bytes(config[:2])  # type: ignore[index]
    world(lib, lambda: dev(lib).pins.press_key(1 * 8 + 2))
    world(lib, lambda: dev(lib).pins.press_key(5 * 8 + 0))  # outside 4 x 4: not seen
    r = h.send(h.create(0xCA, 20))
    assert r is not None and r[8 + 10 // 8] == 1 << (10 % 8) and sum(r[8:24]) == 1 << 2
    # LCD: 2 x 16, print at row 1 column 3, then an update of row 2
    assert h.send(h.create(0xD0, 0, 1, 2, 16)) is not None
    assert h.send(h.create(0xD0, 1))[3:6] == bytes([1, 2, 16])  # type: ignore[index]
    assert h.send(h.create(0xD1, 0x20, 3, 0)) is not None
    assert h.send(h.create(0xD1, 0x30, payload=b"X=12.5\0")) is not None
    assert h.send(h.create(0xD1, 0x85, 2, payload=b"hello".ljust(20))) is not None
    assert world(lib, lambda: dev(lib).lcd_lines()) == ["   X=12.5       ", "hello           "]
    assert refused(lib, 0xD0, 0, 1, 5, 20)  # 5 rows
    fs = bytes(range(23))
    assert h.send(h.create(0x81, 1, 1, 0x0F, payload=fs)) is not None
    r = h.send(h.create(0x81, 0))
    assert r is not None and (r[3], r[4]) == (1, 0x0F) and r[8:31] == fs


def test_ponet_kbd48cnc_keys_the_world_presses(lib):
    h = lib.host
    assert h.send(h.create(0xDD, 0x00))[8] == 1  # type: ignore[index]
    r = h.send(h.create(0xDD, 0x10, 0))
    assert r is not None and r[9] != 0  # a module is there
    assert h.send(h.create(0xDD, 0x10, 3))[9] == 0  # type: ignore[index]
    world(lib, lambda: dev(lib).pins.press_kbd48(47))
    assert h.send(h.create(0xDD, 0x50, 0x10, 0)) is not None
    r = h.send(h.create(0xDD, 0x50, 0x30))
    assert r is not None and (r[3], r[8]) == (1, 0) and r[9 + 5] == 0x80
    leds = bytes(range(16))
    assert h.send(h.create(0xDD, 0x55, 0, payload=leds)) is not None
    assert world(lib, lambda: dev(lib).device.io.kbd48.leds) == leds


def test_save_configuration_survives_a_reset(lib):
    lib.pin_function[0] = DO
    assert lib.PK_PinConfigurationSet() == PK_OK
    world(lib, lambda: dev(lib).reset())
    assert lib.PK_PinConfigurationGet() == PK_OK and lib.pin_function[0] == 0
    lib.pin_function[0] = DO
    assert lib.PK_PinConfigurationSet() == PK_OK
    assert lib.host.send(lib.host.create(0x50, 0xAA, 0x55)) is not None
    assert refused(lib, 0x50, 0xAA, 0x00)  # the wrong key
    world(lib, lambda: dev(lib).reset())
    assert lib.PK_PinConfigurationGet() == PK_OK and lib.pin_function[0] == DO


def test_backlash_postep_and_buses_with_nothing_attached(lib):
    h = lib.host
    payload = b"".join(struct.pack("<HBx", 10 * i, i) for i in range(8))
    assert h.pev2(0x41, 1, 50, payload=payload) is not None
    r = h.pev2(0x40)
    assert r is not None and (r[3], r[4]) == (1, 50) and r[8:40] == payload
    assert r[40:56] == bytes(16)
    assert h.pev2(0x50, 0x10, 1, payload=bytes([1, 0x20, 0] * 8)) is not None
    r = h.pev2(0x50)
    assert r is not None and r[4] == 1 and r[8:11] == bytes([1, 0x20, 0])
    assert h.pev2(0x51)[8:56] == bytes(48)  # type: ignore[index]
    # I2C: a scan finds nothing, a read ends in error
    assert h.send(h.create(0xDB, 0x30)) is not None
    r = h.send(h.create(0xDB, 0x31))
    assert r is not None and r[3] == 1 and r[9:25] == bytes(16)
    assert h.send(h.create(0xDB, 0x20, 0x50, 4)) is not None
    assert h.send(h.create(0xDB, 0x21))[3] == 0  # type: ignore[index]
    r = h.send(h.create(0xE5, 0x20, 4))
    assert r is not None and r[3] == 1 and r[8:12] == b"\xff" * 4
    assert h.send(h.create(0xDC, 0x21))[8:10] == bytes([1, 0])  # type: ignore[index]
    assert h.send(h.create(0x86, 0x31))[3] == 0  # type: ignore[index]


def test_every_library_request_is_answered_over_the_socket(lib):
    """Each request of PoKeysLib's functions, over this transport: one 64-byte reply."""
    from tests.test_pokeys_io_robustness import LIBRARY_REQUESTS

    h = lib.host
    first_of = {0x85: 0x00, 0xD6: 0x01, 0x4B: 0x00, 0x07: 0x0A, 0x1C: 0xFF, 0xC0: 0,
                0xCA: 10, 0xCE: 2, 0x30: 0, 0x40: 0, 0xDB: 0x02, 0xDC: 0x11, 0x76: 0,
                0x77: 0}
    for command, sub in LIBRARY_REQUESTS:
        if command == 0xB0:
            continue
        first = first_of.get(command, 0) if sub is None else sub
        p2 = {0x76: 1, 0x50: 0x55, 0x52: 0x55, 0xD1: 1, 0xDD: 0x10}.get(command, 0)
        p3 = 1 if command == 0x85 and first in (0xFE, 0xFF) else 0
        payload = bytes([0, 0, 0, 0, 1, 1, 1, 0, 0xEA, 0x07]) if command == 0x83 else b""
        reply = h.send(h.create(command, first, p2, p3, payload=payload))
        assert reply is not None and reply[1] == command, (hex(command), hex(first))
