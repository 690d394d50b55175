"""Regression tests for door defects found in review: bounded memory, no lost output,
no lost doorbell clears, capture overruns in shared memory, thread-safe pyserial."""

import asyncio
import subprocess
import sys
import threading
from pathlib import Path

import pytest
import serial

import maxk  # noqa: F401
from maxk import MAXk
from maxk.host import memory_map as M
from maxk.host.pacing import Pacer
from maxk.host.server import HARD_LIMIT, Service, TcpClient
from maxk.host.shared_memory import SharedMemoryDoor
from maxk.host.shm_client import SharedMemoryHost
from maxk.personalities.maxk.capture import CaptureEntry
from tests.hosting import HostedBoards, ManualClock

ROOT = Path(__file__).parent.parent


def door(tmp_path):
    m = MAXk()
    service = Service(1, m, Pacer(m, 1.0, ManualClock()))
    d = SharedMemoryDoor(service, str(tmp_path / "map"))
    return m, d, SharedMemoryHost(d.path)


def test_capture_overrun_in_shared_memory_keeps_the_newest_entries(tmp_path):
    m, d, host = door(tmp_path)
    ring = m.board.capture_ring
    for i in range(54):
        ring.push(CaptureEntry(i, 0))
    d.update()
    ring.push(CaptureEntry(54, 0))  # overrun: the oldest is lost
    d.update()
    assert len(ring) == 54 and ring.lost == 1
    assert host._get(M.OMR1) == 0x2
    host.mem[M.CAPTURE + 1] = 200  # a nonsense removal index is ignored
    d.update()
    assert len(ring) == 54
    host.mem[M.CAPTURE + 1] = (ring.removal + 10) % 55  # the host takes 10 entries
    d.update()
    assert len(ring) == 44
    d.close()


def test_two_doorbell_clears_are_both_applied(tmp_path):
    m, d, host = door(tmp_path)
    m.send("AX; ID; AY; ID;")
    d.update()
    assert host.doorbell == 0x3

    done = threading.Event()

    def board_passes():  # the board keeps taking clears until the host has written both
        while not done.is_set():
            d.update()

    t = threading.Thread(target=board_passes)
    t.start()
    try:
        host.clear_doorbell(0x1)
        host.clear_doorbell(0x2)  # waits for the board to take the first clear
    finally:
        done.set()
        t.join()
    d.update()
    assert host.doorbell == 0
    d.close()


def test_replies_are_never_dropped_when_the_host_does_not_read(tmp_path):
    m, d, host = door(tmp_path)
    for _ in range(20):  # far more replies than the response ring holds
        host.send("AA RP;" * 30)
        d.update()
    lines = []
    for _ in range(600):
        d.update()
        lines.append(host.read_line(timeout=1))
    assert set(lines) == {"0,0,0,0,0,0,0,0"} and len(lines) == 600
    d.close()


def test_tcp_client_that_never_reads_has_bounded_output():
    from maxk.host.server import TcpClient

    class Transport:
        def __init__(self):
            self.buffered = 0

        def is_closing(self):
            return False

        def get_write_buffer_size(self):
            return self.buffered

        def write(self, data):
            self.buffered += len(data)

        def set_write_buffer_limits(self, high):
            pass

        def pause_reading(self):
            pass

    m = MAXk()
    service = Service(1, m, Pacer(m, 1.0, ManualClock()))
    client = TcpClient(service)

    async def connect_and_notify():
        client.connection_made(Transport())
        for _ in range(200_000):
            client.send(b"%000 01000000\n\r", droppable=True)

    asyncio.run(connect_and_notify())
    assert client.transport.buffered <= HARD_LIMIT + 16


def test_a_slow_pty_reader_loses_no_replies():
    hosted = HostedBoards(pty=True)
    try:
        port = serial.Serial(hosted.ptys[0], timeout=5)
        port.write(b"AA RP;\n" * 900)  # ~15 kB of replies: more than the pty buffer holds
        replies = [port.read_until(b"\n\r") for _ in range(900)]
        assert replies == [b"0,0,0,0,0,0,0,0\n\r"] * 900
    finally:
        hosted.close()


def test_pyserial_port_is_safe_to_read_and_write_from_two_threads():
    port = serial.serial_for_url("maxk://MAXk-4000?speed=1000", timeout=0.01)
    stop = threading.Event()
    errors = []

    def reader():
        try:
            while not stop.is_set():
                port.read(port.in_waiting or 1)
        except Exception as error:  # pragma: no cover - the defect
            errors.append(error)

    t = threading.Thread(target=reader)
    t.start()
    try:
        for _ in range(300):
            port.write(b"AM;MR10,-10,5,1;GO;ID;AM;RI;\n")
    finally:
        stop.set()
        t.join()
    assert not errors
    port.close()
    port.open()  # the board keeps its state across close and open
    port.reset_input_buffer()
    port.write(b"AA RP\n")
    assert port.read_until(b"\n\r").endswith(b"\n\r")


@pytest.mark.parametrize("args,message", [
    (["--speed", "0"], "positive"), (["--speed", "nan"], "positive"),
    (["--port", "65535", "--boards", "2"], "leaves no room")])
def test_serve_argument_errors_are_messages_not_tracebacks(args, message):
    result = subprocess.run([sys.executable, "-m", "maxk", "serve", "--seconds", "0.1", *args],
                            capture_output=True, text=True, timeout=30, cwd=ROOT)
    assert result.returncode == 2 and message in result.stderr
    assert "Traceback" not in result.stderr


def test_pty_link_never_replaces_an_ordinary_file(tmp_path):
    precious = tmp_path / "precious"
    precious.write_text("keep me")
    shm = tmp_path / "map"
    result = subprocess.run([sys.executable, "-m", "maxk", "serve", "--seconds", "0.5",
                             "--shm", str(shm), "--pty-link", str(precious)],
                            capture_output=True, text=True, timeout=30, cwd=ROOT)
    assert result.returncode == 1 and "not a symlink" in result.stderr
    assert precious.read_text() == "keep me"
    assert not shm.exists()  # the failed start cleaned up after itself
    assert not any(p.name.startswith("map") for p in tmp_path.iterdir() if p != precious)


# ---- one host cannot starve another; replies are never dropped ------------------------
class _RecordingTransport:
    """A transport whose host reads everything at once; every write goes in one log
    shared by all hosts, so the order of replies across hosts can be read back."""

    def __init__(self, log, name):
        self.log = log
        self.name = name

    def is_closing(self):
        return False

    def get_write_buffer_size(self):
        return 0

    def write(self, data):
        self.log.append((self.name, bytes(data)))

    def set_write_buffer_limits(self, high):
        pass

    def pause_reading(self):
        pass

    def resume_reading(self):
        pass


def test_a_flooding_client_gets_one_turn_before_a_fresh_clients_query():
    """1 MB of queries from one host, then one WY from another: the WY is answered after
    at most a slice or two of the flood (it used to wait for every byte read before it)."""
    m = MAXk()
    service = Service(1, m, Pacer(m, 1.0, ManualClock()))
    flooder, fresh = TcpClient(service), TcpClient(service)
    log = []
    flood = b"AX RP;" * (1_000_000 // 6)

    async def scenario():
        flooder.connection_made(_RecordingTransport(log, "flooder"))
        fresh.connection_made(_RecordingTransport(log, "fresh"))
        flooder.data_received(flood)
        fresh.data_received(b"WY\r")
        while not any(name == "fresh" for name, _ in log):
            await asyncio.sleep(0)

    asyncio.run(scenario())
    first_fresh = next(k for k, (name, _) in enumerate(log) if name == "fresh")
    assert log[first_fresh][1].startswith(b"MAXk-8000, ver:")
    replies_before = sum(data.count(b"\n\r") for _, data in log[:first_fresh])
    assert replies_before <= 2 * 2048 // 6  # at most two slices of the flood's queries


class _SlowHostTransport(_RecordingTransport):
    """A host that reads only when told: unread bytes pile up, and past the high-water
    mark the transport tells its protocol to pause writing, as asyncio's does."""

    def __init__(self, protocol, high):
        super().__init__([], "host")
        self.protocol = protocol
        self.high = high
        self.unread = 0
        self.paused = False

    def get_write_buffer_size(self):
        return self.unread

    def write(self, data):
        super().write(data)
        self.unread += len(data)
        if self.unread > self.high and not self.paused:
            self.paused = True
            self.protocol.pause_writing()

    def host_reads(self):
        self.unread = 0
        if self.paused:
            self.paused = False
            self.protocol.resume_writing()


def test_replies_are_never_dropped_for_a_client_that_reads_late():
    """200,000 WY arrive in one read (9 MB of replies, far past HARD_LIMIT) from a host
    that reads late: while it does not read, its input waits unrun; once it reads, every
    reply comes, in order. (They used to be discarded past HARD_LIMIT.)"""
    from maxk.host.server import HARD_LIMIT, HIGH_WATER

    n = 200_000
    m = MAXk()
    service = Service(1, m, Pacer(m, 1.0, ManualClock()))
    client = TcpClient(service)
    expected = b"MAXk-8000, ver:1.33, S/N: 000001, FPGA:20\n\r"
    assert n * len(expected) > 8 * HARD_LIMIT

    async def scenario():
        transport = _SlowHostTransport(client, HIGH_WATER)
        client.connection_made(transport)
        client.data_received(b"WY\r" * n)
        for _ in range(100):  # the host is busy elsewhere: the server gets turns
            await asyncio.sleep(0)
        assert transport.unread <= HIGH_WATER + 64 * 1024  # at most a slice's replies past
        while True:  # now the host reads whenever there is something
            transport.host_reads()
            await asyncio.sleep(0)
            if not transport.unread and not client.held_input:
                return transport

    transport = asyncio.run(scenario())
    data = b"".join(chunk for _name, chunk in transport.log)
    assert data == expected * n


def _line(fd: int, timeout: float = 5.0) -> bytes:
    """One reply line from a raw file descriptor (bounded wait)."""
    import os
    import select

    data = b""
    while not data.endswith(b"\n\r"):
        ready, _, _ = select.select([fd], [], [], timeout)
        assert ready, f"no line within {timeout} s (got {data!r})"
        data += os.read(fd, 1)
    return data


def test_a_freshly_opened_pty_starts_clean():
    """Notifications raised while nobody has the port open never reach the next host
    that opens it (a real line loses them): its first bytes are its own reply. The port
    is opened raw, as C code does (pyserial would flush its input on open anyway)."""
    import os


    hosted = HostedBoards(pty=True)
    try:
        tcp = hosted.connect()
        for _ in range(300):  # 300 done notifications, nobody on the serial port
            tcp.command("AX ID;")
        fd = os.open(hosted.ptys[0], os.O_RDWR | os.O_NOCTTY)

        os.write(fd, b"WY\r")
        assert _line(fd) == b"MAXk-8000, ver:1.33, S/N: 000001, FPGA:20\n\r"
        tcp.command("AY ID;")  # while the port is open, notifications do arrive
        assert _line(fd) == b"%000 00000002\n\r"
        os.close(fd)
        tcp.command("AZ ID;")  # closed again: lost
        fd = os.open(hosted.ptys[0], os.O_RDWR | os.O_NOCTTY)

        os.write(fd, b"AX RP\r")
        assert _line(fd) == b"0\n\r"
        os.close(fd)
    finally:
        hosted.close()


def test_commands_sent_just_before_a_hang_up_all_run():
    """A host writes 1,000 commands (8.9 KB, more than a turn) and closes at once: every
    one of them runs, as on the board (the sliced door once dropped what was left)."""
    m = MAXk("MAXk-4000")
    service = Service(1, m, Pacer(m, 1.0, ManualClock()))
    client = TcpClient(service)
    log = []

    async def scenario():
        client.connection_made(_RecordingTransport(log, "host"))
        client.data_received(b"".join(f"AX LP{i};".encode() for i in range(1, 1001)))
        client.connection_lost(None)
        while client.session is not None:  # it runs out in turns, then the session goes
            await asyncio.sleep(0)

    asyncio.run(scenario())
    assert m.query("AX RP") == "1000"


def test_a_fault_inside_a_controller_does_not_stop_the_door(caplog):
    """A session that raises on some bytes: reported on stderr, that input lost, and the
    same host's next bytes and every other host are still served."""
    m = MAXk()
    service = Service(1, m, Pacer(m, 1.0, ManualClock()))
    victim, other = TcpClient(service), TcpClient(service)
    log = []

    async def scenario():
        victim.connection_made(_RecordingTransport(log, "victim"))
        other.connection_made(_RecordingTransport(log, "other"))
        real_feed = victim.session.feed

        def feed(data):
            if b"BOOM" in data:
                raise RuntimeError("a fault inside the controller")
            real_feed(data)

        victim.session.feed = feed
        victim.data_received(b"BOOM\r")
        victim.data_received(b"WY\r")
        other.data_received(b"AX RP\r")
        for _ in range(10):
            await asyncio.sleep(0)

    asyncio.run(scenario())
    said = {name: b"".join(d for n, d in log if n == name) for name in ("victim", "other")}
    assert said["victim"] == b"MAXk-8000, ver:1.33, S/N: 000001, FPGA:20\n\r"
    assert said["other"] == b"0\n\r"
    # logged on maxk.door at ERROR (`maxk serve` shows it on stderr, one line)
    assert any(r.name == "maxk.door" and r.levelname == "ERROR"
               and "RuntimeError: a fault inside the controller" in r.getMessage()
               for r in caplog.records)
