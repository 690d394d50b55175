"""The MM4005's waits behind the real doors (`maxk serve`'s server in-process, a manual
clock): over TCP and the pty, ``1PA5;1WS;1TP`` answers ``1TP5.0000`` once the move is
done and not before, the host's next line waits behind it, and AB from a second
connection stops a program that waits."""

from __future__ import annotations

import socket

import serial

from tests.hosting import HostedBoards

MOVE_S = 1 / 5 + 5 / 1  # VA 1, AC 5, 5 units: 0.2 s of ramps' worth + 5 s = 5.2 s


def _connect(hosted: HostedBoards) -> socket.socket:
    sock = socket.create_connection(("127.0.0.1", hosted.ports[0]), timeout=5)
    hosted.on_close(sock.close)
    return sock


def _read_lines(sock: socket.socket, count: int) -> bytes:
    data = b""
    while data.count(b"\r") < count:
        chunk = sock.recv(65536)
        assert chunk, "closed"
        data += chunk
    return data


def _until_in(hosted: HostedBoards, count: int, holding: bool) -> None:
    """Wait (a liveness bound, not a clock) until a host's `count` bytes reached the door
    and, as asked, its session holds a line (a WS) or has run everything."""
    import time

    def reached() -> bool:
        for client in hosted.services[0].clients:
            traffic, session = client.traffic, client.session
            if traffic is not None and traffic.bytes_in == count and session is not None:
                return bool(session.holding) if holding else bool(client.input_run)
        return False

    deadline = time.monotonic() + 10
    while not hosted.call(reached):
        assert time.monotonic() < deadline, "the door never ran what the host sent"
        time.sleep(0.001)


def _sent_to(hosted: HostedBoards, sock: socket.socket) -> int:
    """Bytes the door has sent this host (its traffic record), read on the server loop."""
    name = f"127.0.0.1:{sock.getsockname()[1]}"

    def count() -> int:
        for client in hosted.services[0].clients:
            if client.traffic is not None and client.traffic.peer == name:
                return sum(len(e.data) for e in client.traffic.entries
                           if e.direction == "out")
        return -1

    return int(hosted.call(count))


def test_move_wait_and_read_over_tcp() -> None:
    hosted = HostedBoards(models=("MM4005-2",))
    try:
        host = _connect(hosted)
        other = _connect(hosted)
        line = b"1VA1;1AC5\r1PA5;1WS;1TP\r2TP\r"
        host.sendall(line)
        _until_in(hosted, len(line), holding=True)
        hosted.advance(1.0)
        other.sendall(b"1TP\r")  # another host is answered during the wait
        assert _read_lines(other, 1) == b"1TP0.9000\r"
        hosted.advance(MOVE_S - 1.0 - 0.01)
        assert _sent_to(hosted, host) == 0  # nothing yet: TP and 2TP wait
        hosted.advance(0.01)
        assert _read_lines(host, 2) == b"1TP5.0000\r2TP0.0000\r"
    finally:
        hosted.close()


def test_ab_from_a_second_connection_stops_a_program_that_waits() -> None:
    hosted = HostedBoards(models=("MM4005-2",))
    try:
        runner = _connect(hosted)
        stopper = _connect(hosted)
        lines = b"2VA1;2AC5\r4EP\r2PA10;2WS;2TP\r2PA0;2WS\rQP\r4EX\r"
        runner.sendall(lines)
        _until_in(hosted, len(lines), holding=False)
        hosted.advance(1.0)
        stopper.sendall(b"AB;2TP\r")
        assert _read_lines(stopper, 1) == b"2TP0.9000\r"
        hosted.advance(30.0)
        runner.sendall(b"2TP;TE\r")  # the program's TP never came; its 2PA0 never ran
        assert _read_lines(runner, 2) == b"2TP0.9000\rTE@\r"
    finally:
        hosted.close()


def test_move_wait_and_read_over_the_pty() -> None:
    hosted = HostedBoards(models=("MM4005-2",), pty=True)
    try:
        port = serial.Serial(hosted.ptys[0], 9600, timeout=5)
        hosted.on_close(port.close)
        line = b"1VA1;1AC5;1PA5;1WS;1TP\r"
        port.write(line)
        _until_in(hosted, len(line), holding=True)
        hosted.advance(MOVE_S - 0.01)
        assert port.in_waiting == 0
        hosted.advance(0.01)
        assert port.read_until(b"\r") == b"1TP5.0000\r"
    finally:
        hosted.close()
