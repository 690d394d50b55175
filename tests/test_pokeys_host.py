"""A PoKeysLib-shaped host (tests/pokeys_host.py, written from the reference alone)
driving a PoKeysSession with real request bytes."""

from __future__ import annotations

import struct

import pytest

from maxk.commands.pokeys import PoKeysSession
from maxk.personalities.pokeys import BenchWorld, PoKeysDevice, Zone
from tests.pokeys_host import (
    PK_ERR_GENERIC,
    Host,
    axis_config_payload,
    decode_status,
    encode_entries,
    header_sum,
)


def connect(model: str = "PoKeys57CNC", world: BenchWorld | None = None,
            slots_per_request: int = 1) -> tuple[PoKeysDevice, Host]:
    device = PoKeysDevice.create(model, world)
    host = Host(PoKeysSession(device))
    host.tick = lambda: device.run_to(device.slot + slots_per_request)
    return device, host


def h(text: str) -> bytes:
    return bytes.fromhex(text)


def test_connect_sequence_57cnc_matches_the_reference_bytes() -> None:
    device, host = connect()
    data = host.device_data_get()
    assert [f[:8] for f in host.sent] == [
        h("bb 00 00 00 00 00 01 bc"), h("bb 03 00 00 00 00 02 c0"),
        h("bb e0 00 00 00 00 03 9e"), h("bb 06 00 00 00 00 04 c5"),
        h("bb 8f 00 00 00 00 05 4f")]
    assert data == {
        "fw": (0x33, 6), "serial": 32123, "hw_type": 32, "build_date": "Jan 10 2018",
        "name_0x00": "PoKeys57CN", "user_id": 0, "lock": 0, "dhcp": 0,
        "ip": (127, 0, 0, 1), "tcp_timeout": 1000, "options": 0xA0, "name": "PoKeys57CNC",
        "options_8f": 1}


def test_connect_replies_byte_for_byte() -> None:
    _, host = connect()
    r0 = host.send(host.create(0x00))
    assert r0 is not None and r0[:44] == h(
        "aa 00 7d 7b 33 06 01 dc 50 4b 45 78 7b 7d 00 00 00 00 20 00 4a 61 6e 20 31 30 20 32"
        " 30 31 38 50 6f 4b 65 79 73 35 37 43 4e 00 33 06")
    host.send(host.create(0x03))
    re0 = host.send(host.create(0xE0))
    assert re0 is not None and re0[:28] == h(
        "aa e0 00 00 00 00 03 8d 00 7f 00 00 01 7f 00 00 01 e8 03 7f 00 00 01 ff 00 00 00 a0")
    r6 = host.send(host.create(0x06))
    assert r6 is not None and r6[:8] == h("aa 06 00 00 00 00 04 b4")
    assert r6[8:18] == b"PoKeys57CN" and r6[35:55] == b"PoKeys57CNC".ljust(20, b"\0")


def test_connect_sequence_56e_old_id_with_build_date_requests() -> None:
    _, host = connect("PoKeys56E")
    data = host.device_data_get()
    assert [f[1] for f in host.sent] == [0x00, 0x03, 0xE0, 0x06, 0x04, 0x04, 0x04, 0x8F]
    assert [f[2] for f in host.sent if f[1] == 0x04] == [0, 1, 2]
    assert data["serial"] == 27431 and data["fw"] == (32, 61)
    assert data["build_date"] == "Mar 14 2014" and data["name"] == "PoKeys56E"
    assert data["options_8f"] & 1


def test_connect_twice_as_the_serial_path_does() -> None:
    _, host = connect()
    first = host.device_data_get()
    second = host.device_data_get()
    assert first == second and host.request_id == 10


def test_ids_wrap_and_every_reply_echoes_its_request() -> None:
    _, host = connect()
    host.request_id = 250
    for _ in range(10):
        status = host.pev2_status()
        assert isinstance(status, dict) and status["info"] == (8, 125, 128, 1)
    assert host.request_id == 4


def test_status_test_byte_rule() -> None:
    _, host = connect()
    for test in (0, 0x15, 0xA5, 0xC6):
        r = host.send(host.create(0x85, 0x00, test))
        assert r is not None and r[63] == (test + 0x5A) & 0xFF
        assert r[:8] == bytes([0xAA, 0x85, 0, 0, 0, 0, host.request_id, r[7]])


def test_stopped_status_matches_the_reference_example() -> None:
    _, host = connect()
    host.request_id = 5
    r = host.send(host.create(0x85, 0x00, (0x10 + 5) % 199))
    assert r is not None
    assert r[:11] == h("aa 85 00 00 00 00 06 35 00 01 00")
    assert r[56:] == h("08 7d 80 01 00 00 00 6f")
    assert set(r[11:56]) == {0}


def test_bad_requests_get_silence_and_the_stream_stays_aligned() -> None:
    device, host = connect()
    session = host.session
    bad_sum = bytearray(64)
    bad_sum[0:7] = h("bb 85 00 00 00 00 07")
    bad_sum[7] = 0x00
    session.feed(bytes(bad_sum))
    wrong_header = bytearray(64)
    wrong_header[0:7] = h("bc 85 00 00 00 00 08")
    wrong_header[7] = header_sum(wrong_header)
    session.feed(bytes(wrong_header))
    assert session.read() == b""
    refusal = host.send(host.create(0xF7))  # unknown command: refused at the first send
    assert host.request_id == 1 and refusal is not None
    assert refusal[:8] == bytes([0xAA, 0xF7, 0xFF, 0, 0, 0, 1, (0xAA + 0xF7 + 0xFF + 1) & 0xFF])
    for sub, p2, p3, status in ((0x10, 8, 0, 1),  # axis 8 does not exist
                                (0xFF, 19, 3, 0),  # 57 bytes do not fit: 0 accepted
                                (0x02, 21, 0, 1)):  # HOMING cannot be set by StateSet
        r = host.pev2(sub, p2, p3, payload=bytes(56))
        assert r is not None and r[2] == status, hex(sub)
    status = host.pev2_status()
    assert isinstance(status, dict) and status["state"] == 0
    assert device.engine.buffer.count == 0


def test_a_request_split_anywhere_gets_one_reply() -> None:
    _, host = connect()
    frame = bytearray(host.create(0x85, 0x00, 0x33))
    frame[0], frame[6] = 0xBB, 0x41
    frame[7] = header_sum(frame)
    for piece in (frame[:5], frame[5:40], frame[40:63]):
        host.session.feed(bytes(piece))
        assert host.session.read() == b""
    host.session.feed(bytes(frame[63:]))
    reply = host.session.read()
    assert len(reply) == 64 and reply[6] == 0x41 and reply[63] == 0x33 + 0x5A


def test_setup_and_axis_configuration_round_trip() -> None:
    device, host = connect()
    host.request_id = 6
    setup = host.pev2(0x01, payload=h("03 00 01"))
    assert host.sent[-1][:11] == h("bb 85 01 00 00 00 07 48 03 00 01")
    assert setup is not None
    example = h("0d 04 00 00 00 32 32 00 00 00 20 41 cd cc 4c 3d cd cc 4c 3d 60 79 fe ff"
                " a0 86 01 00")
    host.request_id = 9
    assert host.pev2(0x11, 0, payload=example) is not None
    assert host.sent[-1][:36] == h("bb 85 11 00 00 00 0a 5b") + example
    got = host.pev2(0x10, 0)
    assert got is not None and got[8:53] == example.ljust(45, b"\0")
    axis = device.engine.axes[0].settings
    assert (axis.max_speed, axis.soft_limit_min, axis.soft_limit_max) == (10.0, -100000, 100000)
    assert axis.max_acceleration == pytest.approx(0.05)
    status = host.pev2_status()
    assert isinstance(status, dict) and status["enabled"] == 3 and status["generator"] == 1


def _running_three_axes(host: Host, internal: int = 0) -> None:
    """Setup 3 axes; axes in `internal` use the internal planner in position mode."""
    assert host.pev2(0x01, payload=h("03 00 01")) is not None
    for axis in range(3):
        config = 0x01 | (0x0C if internal >> axis & 1 else 0)
        assert host.pev2(0x11, axis, payload=axis_config_payload(config, 0)) is not None
    assert host.pev2(0x02, 3) is not None


def test_running_and_internal_moves() -> None:
    device, host = connect()
    _running_three_axes(host, internal=0b011)
    assert host.pev2(0x20, payload=struct.pack("<2i", 1000, -500)) is not None
    status = host.pev2_status()
    assert isinstance(status, dict) and status["state"] == 3
    assert status["axis_states"][:3] == [2, 2, 1]
    # 10 pulses/ms peak, 0.05 pulses/ms^2: 200 ms up, 200 ms down; 1000 is a triangle.
    device.run_to(device.slot + 400)
    status = host.pev2_status()
    assert isinstance(status, dict)
    assert status["positions"][:3] == [1000, -500, 0]
    assert status["axis_states"][:3] == [1, 1, 1]


def test_8bit_fill_back_pressure_and_resend() -> None:
    device, host = connect()
    assert host.pev2(0x01, payload=h("03 00 01")) is not None
    for axis in range(3):
        assert host.pev2(0x11, axis, payload=axis_config_payload(1, 0)) is not None
    stream = [[5, -3, 1]] * 300
    accepted: list[int] = []
    sent = 0
    while sent < len(stream) and len(accepted) < 12:
        result = host.buffer_fill(stream[sent:], 3)
        assert result is not None
        accepted.append(result[0])
        sent += result[0]
    assert accepted[:9] == [18] * 7 + [2, 0]  # engine stopped: the buffer fills to 128
    assert host.pev2(0x02, 3) is not None
    while sent < len(stream):
        device.run_to(device.slot + 20)
        result = host.buffer_fill(stream[sent:], 3)
        assert result is not None
        sent += result[0]
    device.run_to(device.slot + 200)
    status = host.pev2_status()
    assert isinstance(status, dict) and status["positions"][:3] == [1500, -900, 300]


def test_the_reference_8bit_and_16bit_frames() -> None:
    device, host = connect()
    host.pev2(0x01, payload=h("03 00 01"))
    host.request_id = 0x40
    r = host.buffer_fill([[5, -3, 1]] * 18, 3)
    assert host.sent[-1][:14] == h("bb 85 ff 12 03 00 41 95 05 83 01 05 83 01")
    assert r is not None and r[0] == 18
    host.request_id = 0x78
    r = host.buffer_fill([[120, -100, 0]] * 9, 3, wide=True)
    assert host.sent[-1][:14] == h("bb 85 fe 09 03 00 79 c3 78 00 64 80 00 00")
    assert r is not None and r[0] == 9
    assert device.engine.buffer.peek(27)[18].tolist()[:3] == [120, -100, 0]


def test_multipart_fill_one_reply_to_the_last_id() -> None:
    device, host = connect()
    host.pev2(0x01, payload=h("03 00 01"))
    before = host.request_id
    result = host.buffer_fill_large([[1, 2, -3]] * 200, 3)
    assert result is not None and result[0] == 128
    parts = host.sent[-8:]
    assert [p[2] for p in parts] == [0x08, 1, 2, 3, 4, 5, 6, 0x17]
    assert [p[6] for p in parts] == list(range(before + 1, before + 9))
    assert {p[1] for p in parts} == {0xB0} and {p[3:6] for p in parts} == {h("ff 95 03")}
    assert device.engine.buffer.count == 128
    result = host.buffer_fill_large([[1, 2, -3]] * 200, 3)
    assert result is not None and result[0] == 0
    device.engine.clear_buffer()
    result = host.buffer_fill_large([[300, -300, 7]] * 90, 3, wide=True)
    assert result is not None and result[0] == 74  # 448 // 6 bytes per entry
    assert device.engine.buffer.peek(1)[0].tolist()[:3] == [125, -125, 7]  # clipped


def test_multipart_with_a_bad_frame_is_refused_at_its_last_frame() -> None:
    device, host = connect()
    host.pev2(0x01, payload=h("03 00 01"))
    frames = bytearray()
    for i in range(8):
        part = bytearray(64)
        part[0:6] = bytes([0xBB, 0xB0, i | (0x08 if i == 0 else 0x10 if i == 7 else 0),
                           0xFF, 10, 3])
        part[6] = 100 + i
        part[7] = header_sum(part) ^ (0xFF if i == 3 else 0)
        frames += part
    host.session.feed(bytes(frames))
    reply = host.session.read()  # one reply, to the last frame: refused, 0 accepted
    assert len(reply) == 64 and reply[6] == 107 and reply[2] == 0
    assert device.engine.buffer.count == 0


def test_homing_as_the_example_drives_it() -> None:
    world = BenchWorld(zones=[Zone(0, "home", -2000, -1503)])
    device, host = connect(world=world, slots_per_request=1)
    assert host.pev2(0x01, payload=h("01 00 01")) is not None
    assert host.pev2(0x11, 0, payload=axis_config_payload(0x01, 0x04)) is not None
    assert host.pev2(0x21, 0x01, payload=bytes(32)) is not None
    seen_axis, seen_engine = [], []
    for _ in range(700):
        status = host.pev2_status()
        assert isinstance(status, dict)
        for seen, value in ((seen_axis, status["axis_states"][0]),
                            (seen_engine, status["state"])):
            if not seen or seen[-1] != value:
                seen.append(value)
        if status["state"] == 20:
            break
    assert seen_engine == [21, 20] and seen_axis in ([11, 12, 13, 10], [12, 13, 10])
    assert status["positions"][0] == 0
    host.request_id = 0xFA
    assert host.pev2(0x22, 0, 1) is not None
    assert host.sent[-1][:8] == h("bb 85 22 00 01 00 fb 5e")
    status = host.pev2_status()
    assert isinstance(status, dict) and status["state"] == 0


def test_probing_start_and_finish() -> None:
    world = BenchWorld(probe_axis=2, probe_at=-1234, probe_direction=-1)
    device, host = connect(world=world, slots_per_request=3)
    _running_three_axes(host)
    payload = struct.pack("<8i", 0, 0, -5000, 0, 0, 0, 0, 0) + struct.pack("<f", 0.5)
    payload += bytes([1, 1])
    assert host.pev2(0x23, 0b100, payload=payload) is not None
    for _ in range(400):
        status = host.pev2_status()
        assert isinstance(status, dict)
        if status["state"] != 31:
            break
    assert status["state"] == 30 and status["axis_states"][2] == 14
    r = host.pev2(0x24)
    assert r is not None
    assert struct.unpack_from("<8i", r, 8)[2] == -1235 and r[40] == 1
    status = host.pev2_status()
    assert isinstance(status, dict) and status["state"] == 3


def test_a_v1_device_refuses_pev2_requests_and_answers_its_own() -> None:
    device, host = connect("PoKeys56E")
    # 0x85 is no command of a v1 device: refused (status 0xFF), so [63] is not the test
    # byte + 0x5A and the library's rule fails the call at once (PK_ERR_GENERIC)
    assert host.pev2_status() == PK_ERR_GENERIC
    assert host.sent[-1][1] == 0x85 and len(host.sent) == 1
    r = host.send(host.create(0x80, 0x30))
    assert r is not None and tuple(r[8:12]) == (3, 25, 128, 1)


def test_status_fails_generically_if_byte_63_were_wrong() -> None:
    # The host's own rule, checked against a forged reply: guards the helper itself.
    forged = bytearray(64)
    forged[0:7] = bytes([0xAA, 0x85, 0, 0, 0, 0, 1])
    forged[7] = header_sum(forged)

    class Forger:
        def feed(self, data: bytes) -> None:
            pass

        def read(self) -> bytes:
            return bytes(forged)

    assert Host(Forger()).pev2_status() == PK_ERR_GENERIC
    assert decode_status(bytes(forged))["state"] == 0
    assert encode_entries([[-1]], wide=True) == b"\x01\x80"
