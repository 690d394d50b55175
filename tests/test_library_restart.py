"""Issue 34, the library and the map under hostile use: a host linked to libOmsMAXkMC
lives through its server's kill -9 and restart on the same map path (and a map cut
short under it), a reply line longer than the library's 4 KiB inbox is dropped and
counted instead of stalling the handle (map and TCP), and a configuration line longer
than 1,023 characters is skipped whole.

Separate processes run on the wall clock: every wait here is bounded by a count of
tries or a generous limit, never a sleep that must be long enough."""

from __future__ import annotations

import ctypes
import os
import signal
import socket
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from maxk.host import memory_map as M
from maxk.host import oms_library
from tests.hosting import HostedBoards

ROOT = Path(__file__).parent.parent
pytestmark = pytest.mark.skipif(oms_library.compiler() is None, reason="no C compiler")
SUCCESS, COMMAND_TIME_OUT, RESPONSE_TIME_OUT = 0, 1, 2

# A host as legacy code is written: one handle, a query per line it is told to ask.
HOST_C = r"""
#include <stdio.h>
#include <string.h>
#include "OmsMAXkMC.h"
int main(void)
{
    char line[64], reply[80];
    long position = -1;
    HANDLE h = GetOmsHandle("OmsMAXk1");
    if (!h) {
        printf("nohandle\n");
        return 3;
    }
    printf("ready\n");
    fflush(stdout);
    while (fgets(line, sizeof line, stdin) && line[0] == 'q') {
        long rc = SendAndGetString(h, "AXRP", reply);
        long rc2 = GetOmsAxisMotorPosition(h, OMS_X_AXIS, &position);
        printf("%ld %s %ld %ld\n", rc, rc == SUCCESS ? reply : "-", rc2, position);
        fflush(stdout);
    }
    CloseOmsHandle(h);
    printf("bye\n");
    return 0;
}
"""

# A host that maps the file itself, as examples/c/maxk_shm_move.c does, and reads every
# word of it until told to stop: a map shrunk under it at any moment is SIGBUS.
MAPPER_C = r"""
#include <fcntl.h>
#include <stdio.h>
#include <sys/mman.h>
#include <unistd.h>
int main(int argc, char **argv)
{
    int fd = open(argv[1], O_RDWR);
    volatile unsigned *map;
    unsigned long passes = 0, sum = 0, i;
    if (fd < 0)
        return 4;
    map = (volatile unsigned *)mmap(NULL, 0xE010, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (map == MAP_FAILED)
        return 5;
    printf("mapped\n");
    fflush(stdout);
    while (access(argv[2], F_OK) != 0) {
        for (i = 0; i < 0xE010 / 4; i++)
            sum += map[i];
        passes++;
    }
    printf("passes %lu %lu\n", passes, sum & 1);
    return 0;
}
"""


@pytest.fixture(scope="module")
def library(tmp_path_factory) -> Path:
    return oms_library.build(tmp_path_factory.mktemp("lib") / oms_library.LIBRARY_NAME)


def _compile(source: str, name: str, library: Path) -> Path:
    src = library.parent / f"{name}.c"
    src.write_text(source)
    exe = library.parent / name
    result = subprocess.run(
        [*oms_library.compiler().split(), "-Wall", f"-I{oms_library.INCLUDE_DIR}", "-o",
         str(exe), str(src), f"-L{library.parent}", "-lOmsMAXkMC",
         f"-Wl,-rpath,{library.parent}", "-lpthread"],
        capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    return exe


def _serve(shm: Path) -> subprocess.Popen:
    proc = subprocess.Popen([sys.executable, "-m", "maxk", "serve", "--no-tcp", "--shm",
                             str(shm), "--seconds", "300"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert proc.stdout is not None
    line = proc.stdout.readline()
    assert f"shared memory {shm}" in line, (line, proc.stderr.read() if proc.poll() else "")
    return proc


def _ask(host: subprocess.Popen) -> tuple[int, str, int, int]:
    assert host.stdin is not None and host.stdout is not None
    host.stdin.write("q\n")
    host.stdin.flush()
    rc, reply, rc2, position = host.stdout.readline().split()
    return int(rc), reply, int(rc2), int(position)


def _answered(host: subprocess.Popen) -> tuple[int, str, int, int]:
    """Ask until a new server answers (it does within a few tries of 3 s at most)."""
    for _ in range(20):
        answer = _ask(host)
        if answer[0] == SUCCESS:
            break
    return answer


def _stop(proc: subprocess.Popen, how: int = signal.SIGTERM) -> None:
    if proc.poll() is None:
        proc.send_signal(how)
    proc.wait(timeout=30)
    for pipe in (proc.stdin, proc.stdout, proc.stderr):
        if pipe is not None:
            pipe.close()


def test_a_c_host_lives_through_kill_9_and_a_restart_on_the_same_map(tmp_path, library):
    host_exe = _compile(HOST_C, "restart_host", library)
    mapper_exe = _compile(MAPPER_C, "mapper", library)
    shm, stop = tmp_path / "maxk", tmp_path / "stop"
    env = {**os.environ, "MAXK_OMSMAXK1": f"shm:{shm}",
           "MAXK_OMS_COMMAND_TIMEOUT_MS": "3000", "MAXK_OMS_RESPONSE_TIMEOUT_MS": "3000"}
    first = _serve(shm)
    second = None
    host = subprocess.Popen([str(host_exe)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)
    mapper = subprocess.Popen([str(mapper_exe), str(shm), str(stop)], stdout=subprocess.PIPE,
                              text=True)
    try:
        assert host.stdout.readline() == "ready\n"
        assert mapper.stdout.readline() == "mapped\n"
        assert _ask(host) == (SUCCESS, "0", SUCCESS, 0)

        os.kill(first.pid, signal.SIGKILL)  # the server dies; its map file stays
        first.wait(timeout=30)
        assert shm.stat().st_size == M.SIZE
        # nobody serves the map: the call says so at once, no text goes into a dead ring
        assert _ask(host)[::2] == (COMMAND_TIME_OUT, COMMAND_TIME_OUT)

        second = _serve(shm)  # takes over the map a killed server left: cleared in place
        assert shm.stat().st_size == M.SIZE
        assert _answered(host) == (SUCCESS, "0", SUCCESS, 0)
        assert _ask(host) == (SUCCESS, "0", SUCCESS, 0)
        stop.touch()  # the mapper read the whole map without pause all along
        mapper_rc = mapper.wait(timeout=30)

        # a clean stop removes the map; a new server makes a new file at the path, and
        # the host finds it there
        _stop(second)
        assert not shm.exists()
        assert _ask(host)[::2] == (COMMAND_TIME_OUT, COMMAND_TIME_OUT)
        second = _serve(shm)
        assert _answered(host) == (SUCCESS, "0", SUCCESS, 0)

        # another process cuts the map short under the host: the library host gets a
        # return code, never a signal
        os.truncate(shm, 0x1000)
        assert _ask(host)[::2] == (COMMAND_TIME_OUT, COMMAND_TIME_OUT)
    finally:
        stop.touch()
        if host.poll() is None:
            host.stdin.write("x\n")
            host.stdin.flush()
        host_rc = host.wait(timeout=30)
        mapper.wait(timeout=30)
        _stop(host)
        _stop(mapper)
        for server in (first, second):
            if server is not None:
                _stop(server)
    assert host_rc == 0  # not -SIGBUS
    assert mapper_rc == 0


def test_a_mapping_host_survives_a_restart_on_its_map(tmp_path, library):
    """A raw mapping host (no library) reading the map without pause while its server
    is killed and restarted: the new server never shrinks the file."""
    mapper_exe = _compile(MAPPER_C, "mapper2", library)
    shm, stop = tmp_path / "maxk", tmp_path / "stop"
    first = _serve(shm)
    mapper = subprocess.Popen([str(mapper_exe), str(shm), str(stop)], stdout=subprocess.PIPE,
                              text=True)
    second = None
    try:
        assert mapper.stdout.readline() == "mapped\n"
        for _ in range(3):  # several restarts, each a chance for a shrink to be caught
            os.kill(first.pid, signal.SIGKILL)
            first.wait(timeout=30)
            _stop(first)
            first = _serve(shm)
    finally:
        stop.touch()
        mapper_rc = mapper.wait(timeout=30)
        out = mapper.stdout.read()
        _stop(mapper)
        _stop(first)
        if second is not None:
            _stop(second)
    assert mapper_rc == 0, out
    assert out.startswith("passes ")


def test_a_reused_map_is_cleared_in_place_never_truncated(tmp_path, monkeypatch):
    """What the restart above relies on, exactly: taking over a map a killed server left
    never makes the file shorter, and clears what the old run left in it."""
    from maxk.host.shared_memory import SharedMemoryDoor

    shm = str(tmp_path / "maxk")
    boards = HostedBoards(models=("MAXk-4000",))
    try:
        service = boards.services[0]
        door = SharedMemoryDoor(service, shm)
        os.pwrite(door.fd, b"\x12\x34\x56\x78", M.CMD_RING)  # text an old host left
        os.pwrite(door.fd, (5).to_bytes(4, "big"), M.CMD_INSERT)
        os.close(door.fd)  # as kill -9 leaves it: the file, no lock, not removed
        door.fd = -1
        sizes: list[tuple[int, int]] = []
        real = os.ftruncate

        def watch(fd: int, length: int) -> None:
            sizes.append((os.fstat(fd).st_size, length))
            real(fd, length)

        monkeypatch.setattr(os, "ftruncate", watch)
        again = SharedMemoryDoor(service, shm)
        try:
            assert all(length >= before for before, length in sizes), sizes
            assert os.stat(shm).st_size == M.SIZE
            assert os.pread(again.fd, 4, M.CMD_RING) == bytes(4)
            assert os.pread(again.fd, 4, M.CMD_INSERT) == bytes(4)
            assert os.pread(again.fd, 4, M.LAYOUT) == M.LAYOUT_MAGIC
            assert os.stat(shm).st_mode & 0o777 == 0o600
        finally:
            again.close()
    finally:
        boards.close()


# ---- a reply line longer than the inbox ----------------------------------------------------
def _library(library: Path) -> ctypes.CDLL:
    lib = ctypes.CDLL(str(library))
    lib.SendAndGetString.restype = ctypes.c_long
    lib.MaxkOmsDroppedLines.restype = ctypes.c_ulong
    return lib


def _query(lib: ctypes.CDLL, handle: int, text: bytes) -> tuple[int, str]:
    reply = ctypes.create_string_buffer(80)
    rc = lib.SendAndGetString(ctypes.c_void_p(handle), text, reply)
    return rc, reply.value.decode()


def test_a_5_kib_reply_line_through_the_map_is_dropped_and_counted(tmp_path, library,
                                                                     monkeypatch):
    shm = str(tmp_path / "maxk")
    boards = HostedBoards(models=("MAXk-4000",), shm_paths=[shm], real_time_speed=1.0)
    monkeypatch.setenv("MAXK_OMSMAXK1", f"shm:{shm}")
    lib = _library(library)
    handle = lib.GetOmsHandle(b"OmsMAXk1")
    try:
        assert handle
        door = boards.memories[0]
        boards.call(lambda: boards.services[0].controller.send("AX LP1234;"))
        assert _query(lib, handle, b"AXRP") == (SUCCESS, "1234")
        for round_ in range(1, 4):
            # a line of 5 KiB reaches the response ring as any reply does (in passes of
            # at most 1023 bytes): the library drops it, whole, and takes the reply after
            boards.call(lambda: door._pending.extend(b"A" * 5120 + b"\n"))
            assert _query(lib, handle, b"AXRP") == (SUCCESS, "1234")
            assert lib.MaxkOmsDroppedLines(ctypes.c_void_p(handle)) == round_
            assert _query(lib, handle, b"AYRP") == (SUCCESS, "0")
        # a long line that is still arriving while a query waits for its reply
        boards.call(lambda: door._pending.extend(b"C" * 9000 + b"\n"))
        assert _query(lib, handle, b"AXRP") == (SUCCESS, "1234")
        assert lib.MaxkOmsDroppedLines(ctypes.c_void_p(handle)) == 4
        assert _query(lib, handle, b"AYRP") == (SUCCESS, "0")
    finally:
        if handle:
            lib.CloseOmsHandle(ctypes.c_void_p(handle))
        boards.close()


class _Peer:
    """A TCP peer that answers as a MAX board does (WY, then RP), except that it sends
    a 5 KiB line before the answer to each RP it is told to spoil."""

    def __init__(self) -> None:
        self.server = socket.create_server(("127.0.0.1", 0))
        self.port = self.server.getsockname()[1]
        self.spoil = 0
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        conn, _ = self.server.accept()
        with conn:
            text = b""
            while True:
                data = conn.recv(4096)
                if not data:
                    return
                text += data
                while b";" in text:
                    command, _, text = text.partition(b";")
                    if command == b"WY":
                        conn.sendall(b"\n\rMAXk-4000 ver:1.0, s/n:1\n\r")
                    elif command.endswith(b"RP"):
                        if self.spoil:
                            self.spoil -= 1
                            conn.sendall(b"\n\r" + b"Z" * 5120 + b"\n\r")
                        conn.sendall(b"\n\r777\n\r")

    def close(self) -> None:
        self.server.close()


def test_a_5_kib_reply_line_over_tcp_is_dropped_and_counted(library, monkeypatch):
    peer = _Peer()
    monkeypatch.setenv("MAXK_OMSMAXK1", f"tcp:127.0.0.1:{peer.port}")
    lib = _library(library)
    handle = lib.GetOmsHandle(b"OmsMAXk1")
    try:
        assert handle
        assert _query(lib, handle, b"AXRP") == (SUCCESS, "777")
        for round_ in range(1, 4):
            peer.spoil = 1
            assert _query(lib, handle, b"AXRP") == (SUCCESS, "777")
            assert lib.MaxkOmsDroppedLines(ctypes.c_void_p(handle)) == round_
            assert _query(lib, handle, b"AXRP") == (SUCCESS, "777")
    finally:
        if handle:
            lib.CloseOmsHandle(ctypes.c_void_p(handle))
        peer.close()


# ---- the configuration file ----------------------------------------------------------------
def test_a_configuration_line_over_1023_characters_is_skipped_whole(tmp_path, library,
                                                                    monkeypatch):
    boards = HostedBoards(models=("MAXk-4000",), real_time_speed=1.0)
    port = boards.ports[0]
    lib = _library(library)
    config = tmp_path / "oms.conf"
    monkeypatch.delenv("MAXK_OMSMAXK1", raising=False)
    monkeypatch.setenv("MAXK_OMS_CONFIG", str(config))
    setting = f"OmsMAXk1 = tcp:127.0.0.1:{port}"
    try:
        # a commented-out line whose tail, past character 1,023, reads as a setting
        config.write_text("# " + "x" * 1021 + setting + "\n")
        assert lib.GetOmsHandle(b"OmsMAXk1") == 0
        config.write_text("# " + "x" * 3000 + setting + "\n" + "# the end\n")
        assert lib.GetOmsHandle(b"OmsMAXk1") == 0
        # the line after a long one is read as usual
        config.write_text("# " + "x" * 3000 + "\n" + setting + "\n")
        handle = lib.GetOmsHandle(b"OmsMAXk1")
        assert handle and _query(lib, handle, b"AXRP") == (SUCCESS, "0")
        lib.CloseOmsHandle(ctypes.c_void_p(handle))
        # a setting of exactly 1,023 characters (padded) is whole: taken, with or
        # without a line end after it
        padded = setting + " " * (1023 - len(setting))
        for text in (padded + "\n", padded):
            config.write_text(text)
            handle = lib.GetOmsHandle(b"OmsMAXk1")
            assert handle, text[-3:]
            lib.CloseOmsHandle(ctypes.c_void_p(handle))
        # one character more is over-long: skipped, no handle
        config.write_text(padded + " \n")
        assert lib.GetOmsHandle(b"OmsMAXk1") == 0
    finally:
        boards.close()
