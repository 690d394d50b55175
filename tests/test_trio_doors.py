"""The MC405 behind the real doors: a host written from shared/reference/
trio-command-line.md alone, over a real TCP socket, against `maxk serve`'s server
in-process (virtual time moves only when the test moves the clock).
"""

from __future__ import annotations

import random
import re
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.hosting import HostedBoards
from tests.trio_helpers import EXAMPLE_2

ROOT = Path(__file__).parent.parent


class HostError(Exception):
    """What atrio raises: a reply it cannot parse, or a %[COMMAND error line."""


def crc16(data: bytes, crc: int = 0) -> int:
    """Reference section 5: CRC-16, poly 0x8005, init 0, not reflected."""
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


class TrioHost:
    """A telnet host as the reference describes atrio: one write of cmd CR LF per
    command, then wait for echo, CR LF, output, `>>`, the LF's control-char line, `>>`."""

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=5)
        self.buffer = b""
        self.extra: list[bytes] = []  # what came before a command's echo

    def _receive(self, timeout: float = 5.0) -> bool:
        self.sock.settimeout(timeout)
        try:
            chunk = self.sock.recv(65536)
        except TimeoutError:
            return False
        if not chunk:
            raise EOFError("connection closed")
        self.buffer += chunk.replace(b"\x00", b"").replace(b"\x11", b"")
        return True

    def raw(self, cmd: bytes, timeout: float = 5.0) -> bytes:
        """Send a command, return the output (group 2) of the reply; errors raise."""
        self.sock.sendall(cmd + b"\r\n")
        pattern = re.compile(b"(.*?)" + re.escape(cmd) +
                             b"\r\n(.*)>>\nControl char : ((?-s:.*))\r\n>>",
                             re.MULTILINE | re.DOTALL)
        deadline = time.monotonic() + timeout
        while (match := pattern.search(self.buffer)) is None:
            if time.monotonic() > deadline or not self._receive(deadline - time.monotonic()):
                got, self.buffer = self.buffer, b""
                raise HostError(f"Cannot parse answer to {cmd!r}: {got!r}")
        self.buffer = self.buffer[match.end():]
        if match.group(1):
            self.extra.append(match.group(1))
        output = match.group(2)
        error = re.match(rb".*%(\[COMMAND[^\n]+)\r", output, re.MULTILINE | re.DOTALL)
        if error:
            raise HostError(f"Command Error {error.group(1)!r}")
        if match.group(3) != b"0x10000000A":
            raise HostError(f"bad return code {match.group(3)!r}")
        return output[:-2] if output.endswith(b"\r\n") else output

    def cmd(self, text: str, timeout: float = 5.0) -> str:
        out = self.raw(text.encode("ascii"), timeout)
        return out.replace(b"\r\n", b"\n").replace(b"\r", b"\n").decode()

    def cmd_int(self, text: str) -> int:
        return int(float(self.raw(text.encode("ascii"))))  # a VR prints as a FLOAT

    def cmd_float(self, text: str) -> float:
        return float(self.raw(text.encode("ascii")))

    def connect(self) -> None:
        """Reference section 3: ?<random> must come back exactly, ?MPE must be int 0."""
        for _ in range(4):
            x = str(int(1000000 * random.random()))
            try:
                if self.cmd("?" + x) == x:
                    break
            except HostError:
                continue
        else:
            raise HostError("Could not connect: Motion Perfect probably open?")
        if self.cmd_int("?MPE") != 0:
            raise HostError("Motion Perfect probably open")

    def unasked(self, timeout: float = 10.0) -> bytes:
        """Whatever the controller sends without being asked: up to a line end, waiting
        at most `timeout` seconds of wall time for the server thread (a loaded machine
        can take seconds to deliver)."""
        deadline = time.monotonic() + timeout
        while not self.buffer.endswith(b"\r\n") and time.monotonic() < deadline:
            self._receive(max(0.01, deadline - time.monotonic()))
        got, self.buffer = self.buffer, b""
        return got

    def close(self) -> None:
        self.sock.close()


@pytest.fixture
def hosted():
    boards = HostedBoards(models=("MC405",))
    yield boards
    boards.close()


@pytest.fixture
def host(hosted):
    client = TrioHost(hosted.ports[0])
    client.connect()
    yield client
    client.close()


def test_handshake_and_random_integers_print_exactly(host: TrioHost) -> None:
    rng = random.Random(405)
    for _ in range(40):
        x = rng.randrange(0, 1000000)
        assert host.cmd(f"?{x}") == str(x)
    assert host.cmd("?-123456") == "-123456"
    assert host.cmd("?1/3") == "0.3333"
    assert host.cmd("?version") == "2.0299"  # lower case, echoed as sent


def test_errors_are_command_lines_and_change_nothing(host: TrioHost) -> None:
    for bad in ("?1+", "FOO BAR", "PWM_CYCLE AXIS(0)=70000", "SPEED AXIS(99)=1",
                "PWM_CONTROL(7) AXIS(4)", "?1/0"):
        with pytest.raises(HostError, match=r"Command Error b'\[COMMAND"):
            host.cmd(bad)
    assert host.cmd("?PWM_CYCLE AXIS(0)") == "1000"
    assert host.cmd("?SPEED AXIS(0)") == "1000"
    assert host.cmd("?2*21") == "42"  # the session goes on after errors


def test_telnet_negotiation_is_ignored(hosted) -> None:
    client = TrioHost(hosted.ports[0])
    client.sock.sendall(b"\xff\xfd\x18\xff\xfb\x01\xff\xfa\x18\x00ANSI\xff\xf0")
    client.connect()
    assert client.cmd("?7") == "7"
    client.close()


def test_upload_run_and_poll_the_mark_while_the_program_moves(hosted, host) -> None:
    name = "LASER"
    lines = EXAMPLE_2.splitlines()
    directory = host.cmd("DIR")
    assert re.match(r".*---------\n(.*)OK", directory, re.DOTALL)
    assert host.cmd_int(f'?IS_PROG "{name}"') == 0
    assert host.cmd("&M") == ""
    assert host.cmd(f'SELECT "{name}",0') == ""
    for n, line in enumerate(lines):
        assert host.cmd(f"!{name},{n}R{line}") == ""
    assert host.cmd(f"!{name},M") == "" and host.cmd(f"!{name},Z") == ""
    assert host.cmd_int("?FLASH_STATUS") == 0
    assert host.cmd("COMPILE") == ""
    assert host.cmd_int(f'?PROG_TYPE "{name}"') == 0
    assert host.cmd(f'LIST "{name}"').split("\n") == lines
    expected = 0
    for line in lines:
        expected = crc16(line.encode() + b"\xaa", expected)
    assert host.cmd_int(f'EDPROG"{name}",10') == expected
    assert host.cmd(f'RUNTYPE"{name}",0,-1') == ""
    entries = re.match(r".*---------\n(.*)OK", host.cmd("DIR"), re.DOTALL).group(1)
    assert re.search(rf"^{name}\s+\d+\s+\d+\s+Manual\s+Normal", entries, re.MULTILINE)
    assert host.cmd(f'RUN "{name}"') == ""  # tick 0: the program's first cycle is tick 1
    # the program reaches its loop after WA(10): the path runs from tick 11 at 10000/s
    # (ramps of 0.2 s); the host polls the mark while it moves
    polled = []
    for _ in range(30):
        hosted.advance(0.1)
        polled.append((host.cmd_float("?DPOS AXIS(8)"), host.cmd_int("?PWM_MARK AXIS(4)"),
                       host.cmd_float("?VP_SPEED AXIS(0)")))
    for k, (path, mark, speed) in enumerate(polled, start=1):
        tick = 100 * k
        t = (tick - 11) / 1000
        assert speed == pytest.approx(50000 * t if t < 0.2 else 10000, abs=1e-3), tick
        assert path == pytest.approx(25000 * t * t if t < 0.2 else 10000 * t - 1000, abs=1e-3)
        amplitude = min(max(path - 15000, 0) / 5, 1000)  # TABLE 1000..1008 rising 15000-20000
        assert abs(mark - min(500, speed * amplitude / 10000 + 50)) < 1.0001, tick
    assert {m for _p, m, _s in polled} == {50, 227, 428, 500}
    assert "Program LASER - Running" in host.cmd("PROCESS")
    assert host.cmd("HALT") == ""
    assert host.cmd("PROCESS") == ""


def test_a_program_prints_to_the_host_unasked(hosted, host) -> None:
    host.cmd('SELECT "HELLO",0')
    for n, line in enumerate(["WA(250)", 'PRINT "laser ready";', "PRINT 6*7"]):
        host.cmd(f"!HELLO,{n}R{line}")
    host.cmd('RUN "HELLO"')
    hosted.advance(0.2)
    assert host.unasked(0.2) == b""
    hosted.advance(0.1)
    assert host.unasked() == b"laser ready42\r\n"


def test_a_waiting_command_holds_only_its_prompt(hosted, host) -> None:
    other = TrioHost(hosted.ports[0])
    other.connect()
    host.sock.sendall(b"WA(500)\r\n")
    assert host.unasked() == b"WA(500)\r\n"  # echoed; its prompt waits, so does the LF
    assert other.cmd("?3") == "3"  # the other host is served meanwhile
    hosted.advance(0.499)
    assert host.unasked(0.2) == b""
    hosted.advance(0.001)
    assert host.unasked(2.0) == b">>\nControl char : 0x10000000A\r\n>>"
    other.close()


def test_ex_restarts_and_the_host_reconnects_with_autorun(hosted, host) -> None:
    host.cmd('SELECT "BOOT",0')
    host.cmd("!BOOT,0RVR(7)=77")
    host.cmd('RUNTYPE"BOOT",1,5')
    host.sock.sendall(b"EX\r\n")
    assert host.unasked(1.0).startswith(b"EX\r\n")
    with pytest.raises(HostError, match="Cannot parse"):
        host.cmd("?1", timeout=0.3)  # the old session is finished
    again = TrioHost(hosted.ports[0])
    again.connect()
    hosted.advance(0.01)
    assert again.cmd("?VR(7)") == "77.0000"  # the autorun program ran at the restart
    assert "Program BOOT] - Running" in again.cmd("AUTORUN")
    again.close()


# ---- maxk serve ------------------------------------------------------------------------------
def _serve(*args: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, "-m", "maxk", "serve", *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)


def _finish(proc: subprocess.Popen[str]) -> None:
    proc.terminate()
    _out, err = proc.communicate(timeout=20)
    assert proc.returncode == 0, err


def test_serve_mc405_alone_and_beside_a_maxk(tmp_path) -> None:
    proc = _serve("--model", "MAXk-8000,MC405", "--archive-dir", str(tmp_path))
    try:
        first, second = proc.stdout.readline(), proc.stdout.readline()
        assert re.match(r"board 1: MAXk-8000 tcp 127\.0\.0\.1:\d+", first)
        match = re.match(r"board 2: MC405 tcp 127\.0\.0\.1:(\d+)$", second.strip())
        assert match, second
        host = TrioHost(int(match[1]))
        host.connect()
        host.cmd('SELECT "KEEP",0')
        host.cmd('!KEEP,0R?"kept"')
        host.close()
    finally:
        _finish(proc)
    assert (tmp_path / "MC405-board2.programs" / "KEEP.BAS").read_text() == '?"kept"\n'
    proc = _serve("--model", "MC405", "--archive-dir", str(tmp_path))
    try:
        match = re.match(r"board 1: MC405 tcp 127\.0\.0\.1:(\d+)$", proc.stdout.readline().strip())
        assert match
        host = TrioHost(int(match[1]))
        host.connect()
        assert host.cmd_int('?IS_PROG "KEEP"') == 0  # board 1 has its own store
        host.close()
    finally:
        _finish(proc)


def _port_23_free() -> bool:
    try:
        with socket.socket() as probe:
            probe.bind(("127.0.0.1", 23))
    except OSError:
        return False
    return True


@pytest.mark.skipif(not _port_23_free(), reason="port 23 needs privileges (or is taken)")
def test_serve_on_port_23_as_atrio_needs() -> None:
    proc = _serve("--model", "MC405", "--port", "23", "--no-archive")
    try:
        line = proc.stdout.readline().strip()
        if not line:  # taken since the check (another server, another test run)
            proc.communicate(timeout=20)
            pytest.skip("port 23 was taken meanwhile")
        assert line == "board 1: MC405 tcp 127.0.0.1:23"
        host = TrioHost(23)
        host.connect()
        assert host.cmd("?1+1") == "2"
        host.close()
    finally:
        _finish(proc)
