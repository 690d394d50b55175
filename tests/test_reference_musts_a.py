"""The "must" sentences of shared/reference/pokeys-protocol.md, trio-command-line.md and
mm4005-epics-client.md that no other test pinned down on its own: each test here fails
if the emulator stops doing what that sentence asks. (Where another test already fails
on a broken must, it is not repeated here.)"""

from __future__ import annotations

import re
import socket
import subprocess
import sys
from pathlib import Path

from tests.hosting import HostedBoards
from tests.pokeys_host import axis_config_payload, header_sum
from tests.test_pokeys_doors import TcpSession, UdpSession, host_on, status
from tests.test_trio_doors import TrioHost

ROOT = Path(__file__).parent.parent


def _status_request(request_id: int, test: int) -> bytes:
    frame = bytearray(64)
    frame[0:7] = bytes([0xBB, 0x85, 0x00, test, 0, 0, request_id])
    frame[7] = header_sum(frame)
    return bytes(frame)


def _nothing_waiting(sock: socket.socket) -> bool:
    """True if no byte is waiting on the socket (everything the server wrote before the
    caller's last synchronised step has reached it: loopback delivers at write time)."""
    sock.setblocking(False)
    try:
        return not sock.recv(4096)
    except BlockingIOError:
        return True
    finally:
        sock.setblocking(True)
        sock.settimeout(10)


# ---- PoKeys (pokeys-protocol.md) -----------------------------------------------------------
def test_pokeys_udp_answers_each_senders_own_address_and_port() -> None:
    """S1: "The device must answer to the sender's address/port." Two unbound host sockets
    (two ephemeral ports) take turns: each gets exactly its own reply, by its own ID."""
    hosted = HostedBoards(models=("PoKeys57CNC",))
    first, second = UdpSession(hosted.udp_ports[0]), UdpSession(hosted.udp_ports[0])
    try:
        for n in range(3):
            first.send_raw(_status_request(0x10 + n, 0x20 + n))
            second.send_raw(_status_request(0x60 + n, 0x30 + n))
            a, b = first.sock.recv(4096), second.sock.recv(4096)
            assert len(a) == len(b) == 64
            assert (a[6], a[63]) == (0x10 + n, 0x20 + n + 0x5A)
            assert (b[6], b[63]) == (0x60 + n, 0x30 + n + 0x5A)
        assert _nothing_waiting(first.sock) and _nothing_waiting(second.sock)
    finally:
        first.close()
        second.close()
        hosted.close()


def test_pokeys_each_reply_is_one_64_byte_write_once() -> None:
    """S3: "answer every valid request exactly once ... as one 64-byte write". The door's
    own socket writes are recorded: a request arriving in pieces, and a multi-part 0xB0
    fill of 8 frames in one send, each get one write of 64 bytes (the last frame's ID)."""
    hosted = HostedBoards(models=("PoKeys57CNC",))
    session = TcpSession(hosted.ports[0])
    host = host_on(hosted, session)
    service = hosted.services[0]
    writes: list[bytes] = []
    try:
        assert status(host)["state"] == 0  # connected: the door's client exists

        def spy() -> None:
            (client,) = service.clients
            transport = client.transport
            real = transport.write

            def write(data: bytes) -> None:
                writes.append(bytes(data))
                real(data)

            transport.write = write

        hosted.call(spy)
        frame = _status_request(0x42, 0x21)
        for piece in (frame[:8], frame[8:40], frame[40:]):
            session.send_raw(piece)
        assert session._receive(0x42)[63] == 0x21 + 0x5A
        assert writes == [writes[0]] and len(writes[0]) == 64

        writes.clear()
        assert host.pev2(0x01, payload=bytes([3, 0, 1])) is not None  # 3 axes
        writes.clear()
        reply = host.buffer_fill_large([[1, 2, -3]] * 10, 3)
        assert reply is not None and reply[0] == 10  # accepted, to the last frame's ID
        assert len(writes) == 1 and len(writes[0]) == 64
    finally:
        session.close()
        hosted.close()


def test_pokeys_keeps_tcp_open_and_sends_nothing_unasked_through_motion_and_idle() -> None:
    """S3: "never send unsolicited data; keep TCP open". A move runs to its end and the
    engine state changes, then an hour of virtual idle passes (the 0xE0 TCP timeout is
    1000): the socket holds no byte nobody asked for, and the same connection answers."""
    hosted = HostedBoards(models=("PoKeys57CNC",))
    session = TcpSession(hosted.ports[0])
    host = host_on(hosted, session)
    try:
        assert host.pev2(0x01, payload=bytes([1, 0, 1])) is not None
        assert host.pev2(0x11, 0, payload=axis_config_payload(
            0x01 | 0x04 | 0x08, 0, max_speed=10.0, accel=0.05, decel=0.05)) is not None
        assert host.pev2(0x02, 3) is not None  # RUNNING
        move = bytearray(32)
        move[0:4] = (2000).to_bytes(4, "little", signed=True)
        assert host.pev2(0x20, payload=bytes(move)) is not None
        assert status(host)["axis_states"][0] == 2  # running
        for _ in range(10):
            hosted.advance(0.1)
            assert _nothing_waiting(session.sock)
        hosted.advance(3600.0)
        assert _nothing_waiting(session.sock)
        s = status(host)  # the same connection, still answered
        assert s["positions"][0] == 2000 and s["axis_states"][0] != 2
        assert _nothing_waiting(session.sock)
    finally:
        session.close()
        hosted.close()


# ---- Trio (trio-command-line.md) ---------------------------------------------------------
def test_trio_door_keeps_the_connection_open_through_errors_noise_and_idle() -> None:
    """Section 6.6: "Keep the connection open". After error lines, telnet replies, a stray
    control character and an hour of virtual idle, the same connection still answers."""
    hosted = HostedBoards(models=("MC405",))
    host = TrioHost(hosted.ports[0])
    try:
        host.connect()
        host.sock.sendall(b"\xff\xfc\x01\xff\xfe\x03\x03")  # WONT ECHO, DONT SGA, ^C
        hosted.advance(3600.0)
        assert host.cmd("?1+1") == "2"
        assert host.cmd("?2*21") == "42"
        assert b"Control char : 0x100000003" in b"".join(host.extra)
    finally:
        host.close()
        hosted.close()


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _serve(*args: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, "-m", "maxk", "serve", *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)


def _finish(proc: subprocess.Popen[str]) -> None:
    proc.terminate()
    _out, err = proc.communicate(timeout=20)
    assert proc.returncode == 0, err


def test_trio_door_listens_on_any_port_given() -> None:
    """Section 6.6: "listen on 23 where allowed, and on any port given" (atrio's port is
    read at call time, so a host can be pointed elsewhere)."""
    port = _free_port()
    proc = _serve("--model", "MC405", "--port", str(port), "--no-archive")
    try:
        assert proc.stdout is not None
        assert proc.stdout.readline().strip() == f"board 1: MC405 tcp 127.0.0.1:{port}"
        host = TrioHost(port)
        host.connect()
        assert host.cmd("?1+1") == "2"
        host.close()
    finally:
        _finish(proc)


# ---- MM4005 (mm4005-epics-client.md) -----------------------------------------------------
def test_mm4005_is_listening_when_serve_says_where() -> None:
    """Crash 1: "The emulator must be listening before the IOC starts." An IOC started as
    soon as `maxk serve` names the port connects on its first try (no retry: the model 2
    driver's VE; fails 3 times at once on a refused port, then segfaults) and gets VE."""
    proc = _serve("--model", "MM4005-2", "--no-archive")
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline().strip()
        match = re.fullmatch(r"board 1: MM4005-2 tcp 127\.0\.0\.1:(\d+)", line)
        assert match, line
        with socket.create_connection(("127.0.0.1", int(match[1])), timeout=10) as sock:
            sock.sendall(b"VE;\r")
            reply = b""
            while not reply.endswith(b"\r"):
                chunk = sock.recv(4096)
                assert chunk, "closed"
                reply += chunk
            assert reply == b"VE MM4005 Version 2.42\r"
    finally:
        _finish(proc)
