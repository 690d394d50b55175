"""The PoKeys as hosts that speak the protocol themselves see it (home-automation plugins,
Node-RED and OPC UA bridges): a host written here from the protocol's frame rules alone
(not PoKeysLib), over REAL UDP and TCP sockets on 127.0.0.1 against the server in-process.

Discovery in each form (empty datagram, the text "Discovery request", on TCP, unicast
and a loopback broadcast to a server on all interfaces), the older single-pin requests
(0x10, 0x15, 0x35, 0xE6) acting on the pins, and every refusal answered with the error
status in [2]; only a frame the device cannot take (a bad checksum) stays silent.
Expected numbers are worked out here from the protocol, not read from the emulator.
"""

from __future__ import annotations

import socket
import struct

import pytest

from tests.hosting import HostedBoards

DISCOVERY_TEXT = b"Discovery request"  # 17 bytes, as a home-automation plugin sends it
SERIAL_57CNC, SERIAL_57E = 32123, 31877


def frame(cmd: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0, rid: int = 1,
          payload: bytes = b"") -> bytes:
    """A request: 0xBB, command, 4 parameters, ID, sum of bytes 0..6, 56 payload bytes."""
    head = [0xBB, cmd, p1, p2, p3, p4, rid & 0xFF]
    return bytes(head + [sum(head) & 0xFF]) + payload.ljust(56, b"\0")[:56]


def check(reply: bytes, cmd: int, rid: int) -> bytes:
    """A reply to this request: 64 bytes, 0xAA, the command and the ID echoed, a header
    sum over bytes 0..6."""
    assert len(reply) == 64 and reply[0] == 0xAA and reply[1] == cmd and reply[6] == rid
    assert reply[7] == sum(reply[:7]) & 0xFF
    return reply


class UdpHost:
    def __init__(self, port: int) -> None:
        self.port = port
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.settimeout(10)  # a liveness bound: every request here is answered
        self.rid = 0

    def ask(self, cmd: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0,
            payload: bytes = b"") -> bytes:
        self.rid = (self.rid + 1) & 0xFF
        self.sock.sendto(frame(cmd, p1, p2, p3, p4, self.rid, payload), ("127.0.0.1", self.port))
        return check(self.sock.recv(4096), cmd, self.rid)

    def close(self) -> None:
        self.sock.close()


class TcpHost(UdpHost):
    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10)
        self.rid = 0

    def ask(self, cmd: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0,
            payload: bytes = b"") -> bytes:
        self.rid = (self.rid + 1) & 0xFF
        self.sock.sendall(frame(cmd, p1, p2, p3, p4, self.rid, payload))
        return check(self.sock.recv(4096), cmd, self.rid)


@pytest.fixture
def boards():
    hosted = HostedBoards(models=("PoKeys57CNC",))
    yield hosted
    hosted.close()


def host_of(boards: HostedBoards, transport: str) -> UdpHost:
    if transport == "udp":
        return UdpHost(boards.udp_ports[0])
    return TcpHost(boards.ports[0])


def check_discovery_57cnc(answer: bytes) -> None:
    """The 19-byte form: user ID, serial u16 big-endian, firmware 0x33 6, the device's
    address (127.0.0.1), DHCP off, the host's address, serial u32 little-endian, type 32."""
    assert len(answer) == 19
    assert answer[0] == 0 and answer[1] * 256 + answer[2] == SERIAL_57CNC
    assert (answer[3], answer[4]) == (0x33, 6) and tuple(answer[5:9]) == (127, 0, 0, 1)
    assert answer[9] == 0 and tuple(answer[10:14]) == (127, 0, 0, 1)
    assert int.from_bytes(answer[14:18], "little") == SERIAL_57CNC and answer[18] == 32
    # the home-automation plugin's reading: serial = bytes 15, 14 as hex, big first
    assert int(answer[15:16].hex() + answer[14:15].hex(), 16) == SERIAL_57CNC


# ---- discovery ------------------------------------------------------------------------------
@pytest.mark.parametrize("datagram", [b"", DISCOVERY_TEXT, DISCOVERY_TEXT + b"\0"])
def test_discovery_by_datagram_in_each_form(boards: HostedBoards, datagram: bytes) -> None:
    host = UdpHost(boards.udp_ports[0])
    try:
        host.sock.sendto(datagram, ("127.0.0.1", boards.udp_ports[0]))
        check_discovery_57cnc(host.sock.recv(4096))
        reply = host.ask(0x00)  # and the device answers its first request after it
        assert int.from_bytes(reply[12:16], "little") == SERIAL_57CNC
    finally:
        host.close()


def test_discovery_text_on_a_tcp_stream_then_requests(boards: HostedBoards) -> None:
    host = TcpHost(boards.ports[0])
    try:
        host.sock.sendall(DISCOVERY_TEXT)
        check_discovery_57cnc(host.sock.recv(4096))
        assert host.ask(0x00)[18] == 32  # the stream stays aligned on 64-byte frames
    finally:
        host.close()


def test_a_pokeys56e_answers_discovery_in_the_14_byte_form() -> None:
    hosted = HostedBoards(models=("PoKeys56E",))
    host = UdpHost(hosted.udp_ports[0])
    try:
        host.sock.sendto(DISCOVERY_TEXT, ("127.0.0.1", hosted.udp_ports[0]))
        answer = host.sock.recv(4096)
        assert len(answer) == 14 and answer[1] * 256 + answer[2] == 27431
        assert (answer[3], answer[4]) == (32, 61)
    finally:
        host.close()
        hosted.close()


def _answers(sock: socket.socket, count: int) -> dict[int, tuple[int, bytes]]:
    """`count` discovery answers (bounded: each within the socket's timeout), by serial
    u32 (19-byte form): the source port and the answer."""
    found: dict[int, tuple[int, bytes]] = {}
    for _ in range(count):
        answer, (_, port) = sock.recvfrom(4096)
        found[int.from_bytes(answer[14:18], "little")] = (port, answer)
    return found


@pytest.mark.parametrize("how", ["unicast", "broadcast"])
def test_on_all_interfaces_discovery_finds_every_served_pokeys(how: str) -> None:
    """Two PoKeys and a MAXk served on 0.0.0.0: a discovery sent from 127.0.0.2 to the
    first PoKeys's port (unicast to 127.0.0.1, or the loopback broadcast 127.255.255.255)
    is answered by both PoKeys, each from its own door naming the asking host, and by
    nothing else."""
    hosted = HostedBoards(models=("PoKeys57CNC", "MAXk-8000", "PoKeys57E"), host="0.0.0.0")
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_BROADCAST, 1)
    sock.settimeout(10)
    sock.bind(("127.0.0.2", 0))  # a host at another loopback address: the answers name it
    try:
        target = "127.0.0.1" if how == "unicast" else "127.255.255.255"
        sock.sendto(DISCOVERY_TEXT, (target, hosted.udp_ports[0]))
        found = _answers(sock, 2)
        assert set(found) == {SERIAL_57CNC, SERIAL_57E}
        assert found[SERIAL_57CNC][0] == hosted.udp_ports[0]
        assert found[SERIAL_57E][0] == hosted.udp_ports[1]  # the 57E's own door
        assert found[SERIAL_57E][1][18] == 31 and len(found[SERIAL_57E][1]) == 19
        for _, answer in found.values():
            assert tuple(answer[10:14]) == (127, 0, 0, 2)  # the host that asked
        # nothing more: the next datagram back is the answer to a request sent now
        sock.sendto(frame(0x00, rid=77), ("127.0.0.1", hosted.udp_ports[0]))
        assert check(sock.recv(4096), 0x00, 77)[18] == 32
    finally:
        sock.close()
        hosted.close()


# ---- the older single-pin requests ----------------------------------------------------------
@pytest.mark.parametrize("transport", ["udp", "tcp"])
def test_set_pin_function_then_the_pin_is_an_output(boards: HostedBoards,
                                                    transport: str) -> None:
    """Pin 8 (index 7; a digital I/O pin of the 57CNC): 0x15 reads 0 (inactive), 0x10
    makes it an output (4), 0x15 reads 4, 0x40 then drives it (status 0, not 'not an
    output') and 0xCC shows bit 7 of byte 8 set."""
    host = host_of(boards, transport)
    try:
        assert host.ask(0x15, 7)[2:4] == bytes([0, 0])
        assert host.ask(0x10, 7, 4)[2:4] == bytes([0, 4])
        assert host.ask(0x15, 7)[2:4] == bytes([0, 4])
        assert host.ask(0x40, 7, 1)[2] == 0
        assert host.ask(0xCC)[8] == 0x80
        assert host.ask(0x10, 7, 2)[2:4] == bytes([0, 2])  # back to an input
        assert host.ask(0x40, 7, 1)[2] == 1  # not an output now: refused
    finally:
        host.close()


@pytest.mark.parametrize("transport", ["udp", "tcp"])
def test_read_one_analog_input(boards: HostedBoards, transport: str) -> None:
    """Pin 41 (index 40) at 1.0 V: 12 bits of 3.3 V full scale, 1.0 / 3.3 * 4095 = 1240.9
    -> 1241 = 0x4D9 once the pin is an analog input (0x10 function 8); 0 before."""
    host = host_of(boards, transport)
    try:
        controller = boards.services[0].controller
        boards.call(lambda: controller.device.pins.analog(41, 1.0))  # type: ignore[attr-defined]
        assert host.ask(0x35, 40)[2:5] == bytes([0, 0, 0])
        assert host.ask(0x10, 40, 8)[2] == 0
        assert host.ask(0x35, 40)[2:5] == bytes([0, 0x04, 0xD9])
        block = host.ask(0x3A)  # a zeroed header, as an OPC UA bridge sends it
        assert block[8:10] == bytes([0x04, 0xD9])
    finally:
        host.close()


def test_poled_channel_set_and_read_back(boards: HostedBoards) -> None:
    host = UdpHost(boards.udp_ports[0])
    try:
        assert host.ask(0xE6, 0x20, 3, 1)[2] == 0x20
        assert host.ask(0xE6, 0x10, 3)[3:5] == bytes([3, 1])
        assert host.ask(0xE6, 0x10, 4)[3:5] == bytes([4, 0])
    finally:
        host.close()


def test_easy_sensors_in_the_frames_a_bridge_asks(boards: HostedBoards) -> None:
    """0x76 with 4 sensors a frame (48 bytes) and 0x77 with 14 values (56 bytes)."""
    host = UdpHost(boards.udp_ports[0])
    try:
        setup = bytes(range(1, 13)) + bytes(range(21, 33))
        host.ask(0x76, 10, 2, 1, payload=setup)  # set sensors 10 and 11
        got = host.ask(0x76, 9, 4, 0)
        assert got[8:20] == bytes(12) and got[20:44] == setup and got[44:56] == bytes(12)
        values = host.ask(0x77, 0, 14)
        assert values[2] == 0 and values[4:6] == bytes(2) and values[8:64] == bytes(56)
    finally:
        host.close()


# ---- refusals are answers ---------------------------------------------------------------------
@pytest.mark.parametrize("transport", ["udp", "tcp"])
@pytest.mark.parametrize("request_, status", [
    ((0xF7,), 0xFF),  # no such command
    ((0x85, 0x77), 0xFF),  # no such pulse-engine sub-command
    ((0x80, 0x30), 0xFF),  # pulse engine v1's request, on a v2 device
    ((0x10, 6, 4), 1),  # pin 7 is the 57CNC's own: no output there
    ((0x10, 60, 2), 1),  # no pin 61
    ((0x15, 55), 1),  # no pin 56
    ((0x35, 10), 1),  # pin 11 has no analog input
    ((0x76, 0, 5), 1),  # 5 sensors' set-ups do not fit a frame
    ((0x77, 0, 15), 1),  # 15 values do not fit a frame
    ((0x85, 0x10, 8), 1),  # no axis 8
    ((0x83, 0x10), 1),  # a clock set to month 0, day 0
])
def test_a_refusal_is_answered_with_its_status(boards: HostedBoards, transport: str,
                                               request_: tuple[int, ...], status: int) -> None:
    host = host_of(boards, transport)
    try:
        reply = host.ask(*request_)
        assert reply[2] == status and reply[8:] == bytes(56)
        assert host.ask(0x15, 6)[3] == 0  # and nothing changed
    finally:
        host.close()


@pytest.mark.parametrize("transport", ["udp", "tcp"])
def test_only_a_frame_the_device_cannot_take_is_silent(boards: HostedBoards,
                                                       transport: str) -> None:
    """A bad header sum gets nothing: the next good request's reply is the first back
    (streams and loopback datagrams keep their order)."""
    host = host_of(boards, transport)
    try:
        bad = bytearray(frame(0x00, rid=200))
        bad[7] ^= 0xFF
        if transport == "udp":
            host.sock.sendto(bytes(bad), ("127.0.0.1", boards.udp_ports[0]))
        else:
            host.sock.sendall(bytes(bad))
        assert host.ask(0x00)[6] == 1
    finally:
        host.close()


def test_a_fill_that_does_not_fit_is_refused_as_nothing_accepted(boards: HostedBoards) -> None:
    host = UdpHost(boards.udp_ports[0])
    try:
        host.ask(0x85, 0x01, payload=bytes([3]))  # 3 axes
        reply = host.ask(0x85, 0xFF, 19, 3)  # 19 x 3 = 57 bytes > 56
        assert reply[2] == 0 and struct.unpack_from("<3i", reply, 24) == (0, 0, 0)
    finally:
        host.close()
