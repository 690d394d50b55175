"""A PoKeysLib-shaped host (tests/pokeys_host.py, written from the reference alone) over
REAL TCP and UDP sockets against `maxk serve`'s server in-process: the controller built
by the registry, its doors opened by its transports, virtual time moved by the test.

The socket sessions are strict hosts: every request must get exactly one 64-byte reply,
in one piece, carrying that request's ID; a bad request gets nothing, proven by the
next good request's reply coming back first (streams and localhost datagrams are
ordered, so a reply owed to the bad one would arrive before it).
"""

from __future__ import annotations

import socket
import struct
import subprocess
import sys
from pathlib import Path

import pytest

from maxk.controllers.pokeys.controller import PoKeys
from maxk.firmware_model.world import axis_position_source
from tests.hosting import HostedBoards
from tests.pokeys_host import Host, axis_config_payload, decode_status, header_sum

ROOT = Path(__file__).parent.parent


class TcpSession:
    """One connection; feed() sends and waits for the reply, so the device has handled
    the request before the test moves the clock."""

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10)
        self.reply = b""

    def send_raw(self, data: bytes) -> None:
        self.sock.sendall(data)

    def feed(self, data: bytes) -> None:
        self.sock.sendall(data)
        self.reply = self._receive(data[-64 + 6])

    def _receive(self, request_id: int) -> bytes:
        reply = self.sock.recv(4096)
        assert len(reply) == 64, f"one 64-byte reply in one write, got {len(reply)} bytes"
        assert reply[0] == 0xAA and reply[7] == header_sum(reply)
        assert reply[6] == request_id, "a reply that is not this request's (an extra one?)"
        return reply

    def read(self) -> bytes:
        reply, self.reply = self.reply, b""
        return reply

    def close(self) -> None:
        self.sock.close()


class UdpSession(TcpSession):
    """The library's UDP socket: never bound or connected, replies from any source."""

    def __init__(self, port: int) -> None:
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.settimeout(10)
        self.port = port
        self.reply = b""

    def send_raw(self, data: bytes) -> None:
        self.sock.sendto(data, ("127.0.0.1", self.port))

    def feed(self, data: bytes) -> None:
        self.send_raw(data)
        self.reply = self._receive(data[-64 + 6])


@pytest.fixture
def hosted():
    boards = HostedBoards(models=("PoKeys57CNC",))
    yield boards
    boards.close()


def host_on(hosted: HostedBoards, session: TcpSession, slots_per_request: int = 0) -> Host:
    host = Host(session)  # type: ignore[arg-type]
    if slots_per_request:
        host.tick = lambda: hosted.advance(slots_per_request * 1e-3)
    return host


def controller(hosted: HostedBoards, board: int = 1) -> PoKeys:
    c = hosted.services[board - 1].controller
    assert isinstance(c, PoKeys)
    return c


def expect_silence(host: Host, bad: bytes) -> None:
    """Send a bad frame, then a good status request: its reply must be the first back."""
    host.session.send_raw(bad)  # type: ignore[attr-defined]
    status = host.pev2_status()
    assert isinstance(status, dict), "the good request after a bad one was not answered"


def status(host: Host) -> dict:
    s = host.pev2_status()
    assert isinstance(s, dict)
    return s


def setup_three_axes(host: Host, internal: int = 0, speed_mode: int = 0,
                     switches: int = 0) -> None:
    assert host.pev2(0x01, payload=bytes([3, 0, 1])) is not None
    for axis in range(3):
        config = 0x01
        if internal >> axis & 1:
            config |= 0x04 | (0 if speed_mode >> axis & 1 else 0x08)
        assert host.pev2(0x11, axis, payload=axis_config_payload(
            config, switches, max_speed=10.0, accel=0.05, decel=0.05)) is not None


# ---- the connect sequence, both transports --------------------------------------------
@pytest.mark.parametrize("transport", ["tcp", "udp"])
def test_connect_sequence_over_real_sockets(hosted: HostedBoards, transport: str) -> None:
    session = (TcpSession(hosted.ports[0]) if transport == "tcp"
               else UdpSession(hosted.udp_ports[0]))
    host = host_on(hosted, session)
    try:
        first = host.device_data_get()
        second = host.device_data_get()  # connect-by-serial runs it twice
        assert first == second
        assert first["serial"] == 32123 and first["hw_type"] == 32
        assert first["fw"] == (0x33, 6) and first["name"] == "PoKeys57CNC"
        assert first["ip"] == (127, 0, 0, 1) and first["options"] == 0xA0
        assert first["options_8f"] & 1  # the pulse engine
        assert [f[1] for f in host.sent] == [0x00, 0x03, 0xE0, 0x06, 0x8F] * 2
        assert status(host)["info"] == (8, 125, 128, 1)
    finally:
        session.close()


def test_udp_discovery_names_the_device_and_the_next_request_is_answered(
        hosted: HostedBoards) -> None:
    session = UdpSession(hosted.udp_ports[0])
    try:
        session.send_raw(b"")
        reply = session.sock.recv(4096)
        assert len(reply) == 19
        assert reply[1] << 8 | reply[2] == 32123  # serial u16 big-endian
        assert (reply[3], reply[4]) == (0x33, 6)
        assert tuple(reply[5:9]) == (127, 0, 0, 1)  # the address to connect to
        assert struct.unpack_from("<I", reply, 14)[0] == 32123 and reply[18] == 32
        host = host_on(hosted, session)
        assert status(host)["state"] == 0
    finally:
        session.close()


# ---- silence and framing ----------------------------------------------------------------
@pytest.mark.parametrize("transport", ["tcp", "udp"])
def test_bad_requests_get_silence_and_the_next_is_answered(hosted: HostedBoards,
                                                           transport: str) -> None:
    session = (TcpSession(hosted.ports[0]) if transport == "tcp"
               else UdpSession(hosted.udp_ports[0]))
    host = host_on(hosted, session)
    try:
        bad_sum = bytearray(64)
        bad_sum[0:7] = bytes([0xBB, 0x85, 0, 0, 0, 0, 0x70])
        bad_sum[7] = header_sum(bad_sum) ^ 0x55
        expect_silence(host, bytes(bad_sum))
        wrong_header = bytearray(bad_sum)
        wrong_header[0], wrong_header[6] = 0xBC, 0x71
        wrong_header[7] = header_sum(wrong_header)
        expect_silence(host, bytes(wrong_header))
        for cmd, p1, p2, code in ((0xF7, 0, 0, 0xFF), (0x85, 0x10, 8, 1),
                                  (0x85, 0x02, 21, 1)):
            # unknown command, axis 8, HOMING by StateSet: refused, answered at once
            reply = host.send(host.create(cmd, p1, p2))
            assert reply is not None and reply[1] == cmd and reply[2] == code
            assert reply[6] == host.request_id and reply[8:] == bytes(56)
        assert status(host)["state"] == 0
    finally:
        session.close()


def test_a_request_split_over_several_sends_gets_one_reply(hosted: HostedBoards) -> None:
    session = TcpSession(hosted.ports[0])
    try:
        frame = bytearray(64)
        frame[0:7] = bytes([0xBB, 0x85, 0x00, 0x21, 0, 0, 0x42])
        frame[7] = header_sum(frame)
        for piece in (frame[:5], frame[5:40], frame[40:]):
            session.send_raw(bytes(piece))
        assert session._receive(0x42)[63] == 0x21 + 0x5A
    finally:
        session.close()


# ---- setup, RUNNING, internal moves -----------------------------------------------------
def test_position_and_speed_moves_in_virtual_time(hosted: HostedBoards) -> None:
    session = TcpSession(hosted.ports[0])
    host = host_on(hosted, session)
    try:
        setup_three_axes(host, internal=0b011, speed_mode=0b010)
        got = host.pev2(0x10, 0)
        assert got is not None and got[8] == 0x0D and struct.unpack_from("<f", got, 16)[0] == 10
        assert host.pev2(0x02, 3) is not None
        assert host.pev2(0x20, payload=struct.pack("<2i", 1000, 5000)) is not None
        s = status(host)
        assert s["state"] == 3 and s["axis_states"][:3] == [2, 2, 1]
        hosted.advance(0.200)
        s = status(host)
        assert s["axis_states"][0] == 2 and 0 < s["positions"][0] < 1000
        # 10 pulses/ms peak, 0.05 pulses/ms^2: 1000 pulses are a triangle of 283 slots.
        hosted.advance(0.083)
        s = status(host)
        assert s["positions"][0] == 1000 and s["axis_states"][0] == 1
        hosted.advance(0.717)
        # Y at 5000 pulses/s after a 100 ms ramp: 250 + 900 x 5 at 1 s.
        assert status(host)["positions"][1] == 4750
        assert host.pev2(0x20, payload=struct.pack("<2i", 1000, 0)) is not None
        hosted.advance(0.100)  # ramps down in 100 ms: 250 more
        s = status(host)
        assert s["positions"][1] == 5000 and s["axis_states"][1] == 1
        assert controller(hosted).engine.tick == 1100
    finally:
        session.close()


# ---- the buffer ---------------------------------------------------------------------------
@pytest.mark.parametrize("transport", ["tcp", "udp"])
def test_8bit_fills_with_back_pressure_as_the_buffer_drains(hosted: HostedBoards,
                                                            transport: str) -> None:
    session = (TcpSession(hosted.ports[0]) if transport == "tcp"
               else UdpSession(hosted.udp_ports[0]))
    host = host_on(hosted, session)
    try:
        setup_three_axes(host)
        stream = [[5, -3, 1]] * 400
        sent, accepted = 0, []
        while True:
            result = host.buffer_fill(stream[sent:], 3)
            assert result is not None
            accepted.append(result[0])
            sent += result[0]
            if result[0] < 18:
                break
        assert accepted == [18] * 7 + [2] and sent == 128  # stopped: nothing drains
        assert host.pev2(0x02, 3) is not None
        for _ in range(5):
            hosted.advance(0.020)  # 20 slots drain in 20 ms of virtual time
            taken = 0
            while True:
                result = host.buffer_fill(stream[sent:], 3)
                assert result is not None
                taken += result[0]
                sent += result[0]
                if result[0] < 18:
                    break
            assert taken == 20
            assert result[1]["axis_states"][:3] == [2, 2, 2]
        s = status(host)
        assert s["positions"][:3] == [100 * 5, -100 * 3, 100]
        hosted.advance(0.128)
        s = status(host)
        assert s["positions"][:3] == [228 * 5, -228 * 3, 228]
        assert s["axis_states"][:3] == [1, 1, 1]  # the buffer ran dry: ready
    finally:
        session.close()


def test_16bit_and_multipart_fills(hosted: HostedBoards) -> None:
    session = TcpSession(hosted.ports[0])
    host = host_on(hosted, session)
    try:
        setup_three_axes(host)
        result = host.buffer_fill([[120, -100, 0]] * 20, 3, wide=True)
        assert result is not None and result[0] == 9  # 9 entries of 6 bytes per frame
        result = host.buffer_fill_large([[1, 2, -3]] * 200, 3)
        assert result is not None and result[0] == 119  # 128 - 9 free of the 149 sent
        assert [p[2] for p in host.sent[-8:]] == [0x08, 1, 2, 3, 4, 5, 6, 0x17]
        result = host.buffer_fill_large([[1, 2, -3]] * 200, 3)
        assert result is not None and result[0] == 0  # full: back-pressure
        assert host.pev2(0x02, 3) is not None
        hosted.advance(0.074)
        result = host.buffer_fill_large([[300, -300, 7]] * 90, 3, wide=True)
        assert result is not None and result[0] == 74  # 448 // 6 entries, 74 slots free
        hosted.advance(0.128)
        s = status(host)
        # 9 x (120, -100, 0) + 119 x (1, 2, -3) + 74 x (125, -125, 7): 300 clipped to 125
        assert s["positions"][:3] == [9 * 120 + 119 + 74 * 125, -900 + 238 - 74 * 125,
                                      -357 + 74 * 7]
    finally:
        session.close()


# ---- homing and probing on the shared world ---------------------------------------------
def test_homing_on_the_worlds_home_switch(hosted: HostedBoards) -> None:
    session = TcpSession(hosted.ports[0])
    host = host_on(hosted, session, slots_per_request=1)
    dev = controller(hosted)
    hosted.call(lambda: dev.set_home(0, -2000, -1503))
    try:
        assert host.pev2(0x01, payload=bytes([1, 0, 1])) is not None
        assert host.pev2(0x11, 0, payload=axis_config_payload(0x01, 0x04)) is not None
        assert host.pev2(0x21, 0x01, payload=bytes(32)) is not None
        seen = []
        for _ in range(700):
            s = status(host)
            if not seen or seen[-1] != (s["state"], s["axis_states"][0]):
                seen.append((s["state"], s["axis_states"][0]))
            if s["state"] == 20:
                break
        assert seen == [(21, 12), (21, 13), (20, 10)], seen  # axis search, back, home
        assert s["positions"][0] == 0
        # The counter is reset; the stage stays just off the switch it backed away from.
        # Search at 5 pulses/slot to -1505 (inside -2000..-1503), back at 2.5 (2, 3, ...):
        # -1503, then -1500 is read released at the next slot's start.
        assert hosted.call(lambda: dev.pulse_engine.axes[0].stage) == -1500
        assert host.pev2(0x22, 0, 1) is not None
        assert status(host)["state"] == 0
    finally:
        session.close()


def test_probing_with_a_probe_input_in_the_world(hosted: HostedBoards) -> None:
    session = UdpSession(hosted.udp_ports[0])
    host = host_on(hosted, session, slots_per_request=3)
    dev = controller(hosted)
    hosted.call(lambda: dev.set_input(1, axis_position_source("Z", lambda p: p <= -1234)))
    try:
        setup_three_axes(host)
        assert host.pev2(0x02, 3) is not None
        payload = struct.pack("<8if", 0, 0, -5000, 0, 0, 0, 0, 0, 0.5) + bytes([1, 1])
        assert host.pev2(0x23, 0b100, payload=payload) is not None
        for _ in range(400):
            s = status(host)
            if s["state"] != 31:
                break
        assert s["state"] == 30 and s["axis_states"][2] == 14
        r = host.pev2(0x24, 1)
        assert r is not None and struct.unpack_from("<8i", r, 8)[2] == -1235 and r[40] == 1
        assert status(host)["state"] == 3
    finally:
        session.close()


def test_a_limit_in_the_world_hard_stops_a_buffered_axis(hosted: HostedBoards) -> None:
    session = TcpSession(hosted.ports[0])
    host = host_on(hosted, session)
    dev = controller(hosted)
    hosted.call(lambda: dev.set_limits(0, plus=300))
    try:
        setup_three_axes(host, switches=0x02)  # limit+ enabled
        assert host.pev2(0x02, 3) is not None
        for _ in range(4):  # 56 slots of 7 pulses: 392 would pass the switch at 300
            result = host.buffer_fill([[7, 0, 0]] * 14, 3)
            assert result is not None and result[0] == 14
        hosted.advance(0.050)
        s = status(host)
        # 7 per slot: 301 after slot 42, read at the start of slot 43: no pulse there.
        assert s["state"] == 100 and s["positions"][0] == 301
        assert s["axis_states"][0] == 30 and s["lim_p"] & 1
    finally:
        session.close()


# ---- two kinds side by side, and the command line -----------------------------------------
def test_a_maxk_and_a_pokeys56e_served_together() -> None:
    boards = HostedBoards(models=("MAXk-8000", "PoKeys56E"))
    try:
        assert len(boards.ports) == 2 and len(boards.udp_ports) == 1
        session = TcpSession(boards.ports[1])
        host = host_on(boards, session)
        data = host.device_data_get()
        assert data["serial"] == 27431 and data["build_date"] == "Mar 14 2014"
        info = host.send(host.create(0x80, 0x30))
        assert info is not None and tuple(info[8:12]) == (3, 25, 128, 1)
        session.close()
    finally:
        boards.close()


def test_serve_command_line_opens_tcp_and_udp_for_a_pokeys() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "maxk", "serve", "--model", "MAXk-8000,PoKeys56E",
         "--seconds", "0.3", "--no-archive"],
        capture_output=True, text=True, timeout=60, cwd=ROOT)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].startswith("board 1: MAXk-8000 tcp 127.0.0.1:")
    assert lines[1].startswith("board 2: PoKeys56E tcp 127.0.0.1:") and ", udp 127.0.0.1:" in \
        lines[1]


def test_decode_status_agrees_with_the_api(hosted: HostedBoards) -> None:
    session = TcpSession(hosted.ports[0])
    host = host_on(hosted, session)
    try:
        setup_three_axes(host)
        r = host.pev2(0x00, 0x10)
        assert r is not None
        mine = decode_status(r)
        theirs = hosted.call(lambda: controller(hosted).status())
        assert mine["positions"] == list(theirs.positions)
        assert mine["state"] == theirs.state and mine["enabled"] == theirs.enabled_axes
    finally:
        session.close()


def test_a_stray_udp_datagram_of_another_size_is_ignored_whole(hosted: HostedBoards) -> None:
    """A datagram that is not a whole request (10 bytes, 100 bytes) gets silence and
    leaves nothing behind: the next request is read from its own first byte."""
    session = UdpSession(hosted.udp_ports[0])
    host = host_on(hosted, session)
    try:
        expect_silence(host, bytes([0xBB]) + bytes(9))
        expect_silence(host, bytes([0xBB]) + bytes(99))
        assert status(host)["state"] == 0
    finally:
        session.close()
