"""The vendor's motion-control library API (libOmsMAXkMC) over served boards: a C program
calling every exported function through the PCI map and through the TCP door, a Python
ctypes host written the way the published GUI code is, and the library's own limits.

The boards run on the wall clock here (a separate process cannot be told when virtual
time moves); every limit given to a ...Wait is generous except the one that must expire,
which waits for a move 1000 times longer than its limit."""

from __future__ import annotations

import ctypes
import fcntl
import os
import re
import shutil
import struct
import subprocess
from ctypes import byref, c_long, create_string_buffer
from pathlib import Path

import pytest

from maxk import MAXk
from maxk.host import memory_map as M
from maxk.host import oms_library
from tests.hosting import HostedBoards

ROOT = Path(__file__).parent.parent
pytestmark = pytest.mark.skipif(oms_library.compiler() is None, reason="no C compiler")


@pytest.fixture(scope="module")
def library(tmp_path_factory) -> Path:
    """The library built from the source in this tree (not whatever an install left)."""
    return oms_library.build(tmp_path_factory.mktemp("lib") / oms_library.LIBRARY_NAME)


@pytest.fixture(scope="module")
def check_program(library: Path) -> Path:
    exe = library.parent / "oms_library_check"
    result = subprocess.run(
        [*oms_library.compiler().split(), "-Wall", f"-I{oms_library.INCLUDE_DIR}", "-o", str(exe),
         str(ROOT / "tests" / "oms_library_check.c"), f"-L{library.parent}", "-lOmsMAXkMC",
         f"-Wl,-rpath,{library.parent}", "-lpthread"],
        capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    # the legacy habit `void main(void)` costs one warning, nothing else
    warnings = [line for line in result.stderr.splitlines() if "warning:" in line]
    assert len(warnings) <= 1 and all("main" in w for w in warnings), result.stderr
    return exe


def _prepare_world(board: MAXk) -> None:
    board.set_limits("T", plus=3000, minus=-3000)
    board.set_home("U", 500, 560)
    board.set_home("Z", 200, 400)
    board.set_index("Z", 1000, 4, 300)
    board.set_input(3, True)


def _reference_homes() -> dict[str, int]:
    """The same homing commands on a board run directly: where each home must end."""
    ref = MAXk("MAXk-A000")
    _prepare_world(ref)
    out: dict[str, int] = {}

    def run(text: str, letter: str) -> int:
        ref.send(f"A{letter};CA;{text}")
        assert ref.run_until_done(letter)
        return int(ref.query(f"A{letter} RP"))

    ref.send("AZ;PSE;")
    run("AZ;MR-100;GO;ID;", "Z")
    ref.send("AU;VL20000;AC200000;HL;HH;")
    out["home_fwd_U"] = run("AU;HSHM0;ID;", "U")
    run("AU;MA30;GD;ID;", "U")
    run("AU;MR3000;GD;ID;", "U")
    out["home_rev_U"] = run("AU;HSHR100;ID;", "U")
    run("AU;MR-3000;GD;ID;", "U")
    out["home_fwd2_U"] = run("AU;HSHM7;ID;", "U")
    run("AU;MR3000;GD;ID;", "U")
    out["home_rev2_U"] = run("AU;HSHR-5;ID;", "U")
    ref.send("AZ;VL20000;AC200000;")
    out["home_enc_fwd_Z"] = run("AZ;HEHM0;ID;", "Z")
    run("AZ;MR2000;GD;ID;", "Z")
    out["home_enc_rev_Z"] = run("AZ;HEHR0;ID;", "Z")
    return out


def _served(tmp_path: Path) -> tuple[HostedBoards, list[str]]:
    paths = [str(tmp_path / "maxk"), str(tmp_path / "maxk2")]
    boards = HostedBoards(models=("MAXk-A000", "MAXk-4000"), shm_paths=paths,
                          real_time_speed=1.0)
    boards.call(lambda: _prepare_world(boards.services[0].controller))
    return boards, paths


def _run_check(exe: Path, env: dict[str, str], boards: HostedBoards) -> dict[str, str]:
    """Run the program; at `world slip` make S's stage miss steps, at `io_check` look at
    the world's I/O lines; each time answer so it goes on."""
    board = boards.services[0].controller.board
    proc = subprocess.Popen([str(exe)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env={**os.environ, **env})
    assert proc.stdout is not None and proc.stdin is not None
    printed: dict[str, str] = {}
    try:
        for line in proc.stdout:
            key, _, value = line.rstrip("\n").partition(" ")
            printed[key] = value
            if key == "world" and value == "slip":
                boards.call(lambda: boards.services[0].controller.miss_steps("S", 50))
                proc.stdin.write("\n")
                proc.stdin.flush()
            if key == "io_check":
                # outputs 9 and 12 high, 15 low, input 3 high: in the world, not only in replies
                printed["world_io"] = str(boards.call(lambda: board.io.word(board)))
                proc.stdin.write("\n")
                proc.stdin.flush()
        proc.wait(timeout=300)
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.stdin.close()
        proc.stdout.close()
        stderr = proc.stderr.read() if proc.stderr else ""
        if proc.stderr:
            proc.stderr.close()
    assert proc.returncode == 0, f"{printed}\n{stderr}"
    return printed


def _check_board(boards: HostedBoards, printed: dict[str, str], transport: str) -> None:
    board = boards.services[0].controller
    for key, expected in _reference_homes().items():
        assert int(printed[key]) == expected, key
    assert printed["description"].startswith("MAXk-A000, ver:")
    assert int(printed["home_sensors"]) & 0x10 == 0x10  # U stopped on its switch
    assert int(printed["flags_U"]) & 0x0A == 0x0A  # done and home switch
    assert int(printed["limit_T"]) >= 3000
    x, y, _z, t, u, _v, _r, _s, w, k = (int(v) for v in printed["motor"].split())
    assert (x, y, u, w, k) == (1900, 2400, int(printed["home_rev2_U"]), 1, 12345)
    assert t <= -3000  # stopped on the minus limit it was sent to find
    assert int(printed["world_io"]) & 0xFF08 == 0x1208 == int(printed["io_check"]) & 0xFF08
    # each call reached the board as a host's commands, in its book of hosts (what
    # `maxk serve -vv` logs): the last ones are the 1000-step kill's reply and WY
    hosts = [t for t in boards.services[0].traffic.hosts if t.transport == transport]
    said = b"".join(e.data for t in hosts for e in t.entries if e.direction == "in")
    assert said.endswith(b"AXRP;WY;")
    # ... and the bad command among them in the board's error list (the REPL's :errors)
    assert any(record.command.startswith("QQ") for record in board.board.errors)


def test_every_function_through_the_map(tmp_path, check_program):
    boards, paths = _served(tmp_path)
    try:
        printed = _run_check(check_program, {"MAXK_OMSMAXK1": f"shm:{paths[0]}",
                                             "MAXK_OMSMAXK2": paths[1],
                                             "MAXK_OMS_CONFIG": str(tmp_path / "none.conf")},
                             boards)
        _check_board(boards, printed, "shm")
    finally:
        boards.close()


def test_every_function_over_tcp(tmp_path, check_program):
    boards, _ = _served(tmp_path)
    config = tmp_path / "oms.conf"
    config.write_text("# where the boards are\n"
                      f"OmsMAXk1 = tcp:127.0.0.1:{boards.ports[0]}\n"
                      f"OmsMAXk2 = tcp:127.0.0.1:{boards.ports[1]}\n")
    try:
        printed = _run_check(check_program, {"MAXK_OMS_CONFIG": str(config)}, boards)
        _check_board(boards, printed, "tcp")
    finally:
        boards.close()


# ---- Python hosts through ctypes ------------------------------------------------------
def _serve(tmp_path: Path, *extra: str) -> tuple[subprocess.Popen, dict[int, str]]:
    """`maxk serve` as a user starts it; returns the process and each board's TCP door."""
    proc = subprocess.Popen(
        [os.environ.get("PYTHON", "python3"), "-m", "maxk", "serve", "--no-archive",
         "--seconds", "120", *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert proc.stdout is not None
    doors: dict[int, str] = {}
    for line in proc.stdout:
        number = int(line.split()[1].rstrip(":"))
        doors[number] = line.split(" tcp ")[1].split(",")[0].strip()
        if "--boards" not in extra or len(doors) == int(extra[extra.index("--boards") + 1]):
            break
    return proc, doors


def _stop(proc: subprocess.Popen) -> None:
    proc.terminate()
    proc.wait(timeout=30)
    for stream in (proc.stdout, proc.stderr):
        if stream:
            stream.close()


def test_the_ctypes_example_runs_against_maxk_serve(tmp_path, library):
    """examples/oms_library/ctypes_host.py: the GUI-style host, one line changed."""
    proc, _ = _serve(tmp_path, "--model", "MAXk-8000", "--shm", str(tmp_path / "maxk"))
    try:
        result = subprocess.run(
            [os.environ.get("PYTHON", "python3"),
             str(ROOT / "examples" / "oms_library" / "ctypes_host.py")],
            capture_output=True, text=True, timeout=120,
            env={**os.environ, "OMS_LIBRARY": str(library),
                 "MAXK_OMSMAXK1": str(tmp_path / "maxk")})
    finally:
        _stop(proc)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.splitlines() == [
        "description: Success MAXk-8000, ver:1.33, S/N: 000001, FPGA:20",
        "base velocity: Success", "velocity: Success", "acceleration: Success",
        "too fast: Invalid parameter", "two axes at once: Invalid axis selection",
        "load position: Success", "move: Success", "position: 2500 velocity: 0",
        "bit 12 high: Success", "bit 16: Invalid bit number", "bits: 1000", "AXRP: 2500"]


def _gui_library(path: Path) -> ctypes.CDLL:
    """Loaded as the GUI does: no restype or argtypes declared, handles kept as ints."""
    return ctypes.CDLL(str(path))


def test_gui_style_calls_over_tcp_to_two_boards(tmp_path, library, monkeypatch):
    proc, doors = _serve(tmp_path, "--boards", "2", "--model", "MAXk-4000")
    try:
        monkeypatch.setenv("MAXK_OMSMAXK1", f"tcp:{doors[1]}")
        monkeypatch.setenv("MAXK_OMSMAXK2", f"tcp:{doors[2]}")
        monkeypatch.setenv("MAXK_OMS_CONFIG", str(tmp_path / "none"))
        monkeypatch.setenv("MAXK_OMS_RESPONSE_TIMEOUT_MS", "300")
        lib = _gui_library(library)
        name = [create_string_buffer(b"OmsMAXk1")]
        one = lib.GetOmsHandle((ctypes.c_char_p)(*map(ctypes.addressof, name)))
        two = lib.GetOmsHandle(create_string_buffer(b"OmsMAXk2"))
        assert one != 0 and two != 0 and one != two
        assert lib.GetOmsHandle(create_string_buffer(b"OmsMAXk3")) == 0  # handle 0: no board
        model = create_string_buffer(80)
        assert lib.GetOmsControllerDescription(one, model) == 0
        assert model.value.startswith(b"MAXk-4000, ver:")
        for handle, steps in ((one, 1500), (two, -700)):
            assert lib.SetOmsAxisVelocity(handle, ctypes.c_long(2), ctypes.c_long(30000)) == 0
            assert lib.MoveOmsAxisRelWait(handle, ctypes.c_long(2), ctypes.c_long(steps),
                                          ctypes.c_long(5000)) == 0
        positions = []
        for handle in (one, two):
            position = c_long(0)
            assert lib.GetOmsAxisMotorPosition(handle, c_long(2), byref(position)) == 0
            positions.append(position.value)
        assert positions == [1500, -700]
        codes = [lib.SetOmsAxisVelocity(one, c_long(1), c_long(4000001)),
                 lib.MoveOmsAxisRel(one, c_long(5), c_long(1)),
                 lib.SetOmsIOBit(one, c_long(16), c_long(1)),
                 lib.SetOmsAxisAcceleration(one, c_long(1), c_long(8000001))]
        assert codes == [5, 3, 6, 5]  # INVALID_PARAMETER, _AXIS_SELECTION, _BIT_NUMBER
        # a command that answers nothing times out and owes nothing to the next query
        reply = create_string_buffer(80)
        assert lib.SendAndGetString(one, b"AX;LP5", reply) == 2  # RESPONSE_TIME_OUT
        assert lib.SendAndGetString(one, b"AXRP", reply) == 0 and reply.value == b"5"
        assert lib.ResetOmsController(one) == 0
        reply = create_string_buffer(80)
        assert lib.SendAndGetString(one, b"AYRP", reply) == 0 and reply.value == b"0"
        lib.CloseOmsHandle(one)
        lib.CloseOmsHandle(two)
        assert lib.SendString(one, b"WY") == 1  # COMMAND_TIME_OUT: the handle is closed
    finally:
        _stop(proc)


# ---- the library's own limits --------------------------------------------------------
def _dead_map(path: Path) -> int:
    """A map a server holds (its lock) but never serves: nothing takes or answers text."""
    image = bytearray(M.SIZE)
    image[M.LAYOUT:M.LAYOUT + 4] = M.LAYOUT_MAGIC
    struct.pack_into(">I", image, M.BOARD_NUMBER, 1)
    path.write_bytes(bytes(image))
    fd = os.open(path, os.O_RDWR)
    fcntl.flock(fd, fcntl.LOCK_EX)
    return fd


def test_command_and_response_time_outs(tmp_path, library, monkeypatch):
    fd = _dead_map(tmp_path / "dead")
    monkeypatch.setenv("MAXK_OMSMAXK1", str(tmp_path / "dead"))
    monkeypatch.setenv("MAXK_OMS_COMMAND_TIMEOUT_MS", "50")
    monkeypatch.setenv("MAXK_OMS_RESPONSE_TIMEOUT_MS", "50")
    try:
        lib = ctypes.CDLL(str(library))
        handle = lib.GetOmsHandle(b"OmsMAXk1")
        assert handle != 0
        reply = create_string_buffer(80)
        assert lib.SendAndGetString(handle, b"WY", reply) == 2  # RESPONSE_TIME_OUT
        assert lib.SendString(handle, b"A" * 1100) == 1  # COMMAND_TIME_OUT: the ring is full
        assert lib.MoveOmsAxisRelWait(handle, 1, 10, 1000) in (1, 4)
        lib.CloseOmsHandle(handle)
    finally:
        os.close(fd)


def test_a_map_nobody_serves_gives_no_handle(tmp_path, library, monkeypatch):
    """The file a killed server left behind (no lock on it), a missing file, a file of
    another kind: GetOmsHandle says NULL, as the vendor's does for a board not found."""
    fd = _dead_map(tmp_path / "left")
    os.close(fd)  # the lock goes with its holder
    (tmp_path / "other").write_bytes(b"x" * M.SIZE)
    lib = ctypes.CDLL(str(library))
    for where in (tmp_path / "left", tmp_path / "missing", tmp_path / "other"):
        monkeypatch.setenv("MAXK_OMSMAXK1", str(where))
        assert lib.GetOmsHandle(b"OmsMAXk1") == 0
    monkeypatch.setenv("MAXK_OMS_COMMAND_TIMEOUT_MS", "200")
    monkeypatch.setenv("MAXK_OMS_RESPONSE_TIMEOUT_MS", "200")
    for where in ("tcp:127.0.0.1:1", "tcp:10.255.255.1:5001", "tcp:no-such-host.invalid:1",
                  "tcp:nonsense"):
        monkeypatch.setenv("MAXK_OMSMAXK1", where)
        assert lib.GetOmsHandle(b"OmsMAXk1") == 0  # refused, not a MAX board, no such name


# ---- Windows: the same source builds OmsMAXkMC.dll --------------------------------------
MINGW = "x86_64-w64-mingw32-gcc"


@pytest.mark.skipif(shutil.which(MINGW) is None, reason=f"no {MINGW} (gcc-mingw-w64-x86-64)")
def test_the_same_source_cross_builds_the_windows_dll(tmp_path):
    dll = tmp_path / "OmsMAXkMC.dll"
    built = subprocess.run([MINGW, "-O2", "-Wall", "-Werror", "-shared",
                            f"-I{oms_library.INCLUDE_DIR}", "-o", str(dll),
                            str(oms_library.SOURCE), "-lws2_32"],
                           capture_output=True, text=True, timeout=300)
    assert built.returncode == 0, built.stderr
    objdump = shutil.which("x86_64-w64-mingw32-objdump")
    if objdump:
        table = subprocess.run([objdump, "-p", str(dll)], capture_output=True, text=True).stdout
        exported = set(re.findall(r"^\s*\[\s*\d+\] (\w+)$", table, re.M))
        declared = set(re.findall(r"_stdcall (\w+)\(",
                                  (oms_library.INCLUDE_DIR / "OmsMAXkMC.h").read_text()))
        assert len(declared) == 121 and exported == declared
    # a Windows host program, as the vendor demo is written, links against it
    demo = tmp_path / "demo.c"
    demo.write_text('#include <windows.h>\n#include <stdio.h>\n#include "OmsMAXkMC.H"\n'
                    "int main(void) {\n  char reply[80];\n"
                    '  HANDLE h = GetOmsHandle("OmsMAXk1");\n'
                    "  if (!h) return 1;\n"
                    '  SendAndGetString(h, "AXRP", reply);\n'
                    "  MoveOmsAxisRelWait(h, OMS_X_AXIS, 10000, 5000);\n"
                    "  CloseOmsHandle(h);\n  return 0;\n}\n")
    linked = subprocess.run([MINGW, "-Wall", "-Werror", f"-I{oms_library.INCLUDE_DIR}",
                             "-o", str(tmp_path / "demo.exe"), str(demo), str(dll)],
                            capture_output=True, text=True, timeout=300)
    assert linked.returncode == 0, linked.stderr


@pytest.mark.skipif(shutil.which("g++") is None, reason="no C++ compiler")
def test_cpp_hosts_pass_string_literals_without_a_warning(tmp_path, library):
    """C++ stage code passes literals where the API says LPSTR, as MSVC allows."""
    source = tmp_path / "stage.cpp"
    source.write_text('#include <windows.h>\n#include "OmsMAXkMC.h"\n'
                      "int main() {\n  char reply[80];\n"
                      '  HANDLE h = GetOmsHandle("OmsMAXk1");\n'
                      "  if (h == INVALID_HANDLE_VALUE || h == NULL) return 1;\n"
                      '  SendAndGetString(h, ";WY;", reply);\n'
                      '  SendString(h, ";AX;PSE;LMH;");\n  SendOmsTextCommand(h, "AXRP");\n'
                      '  SendOmsQueryCommand(h, "AXRP", reply);\n'
                      "  AXES_DATA positions;\n  GetEncoderPositions(h, &positions);\n"
                      "  DWORD started = GetTickCount();\n  Sleep(2);\n"
                      "  CloseOmsHandle(h);\n  return GetTickCount() >= started ? 0 : 1;\n}\n")
    built = subprocess.run(["g++", "-Wall", "-Wextra", "-Werror", f"-I{oms_library.INCLUDE_DIR}",
                            "-o", str(tmp_path / "stage"), str(source), f"-L{library.parent}",
                            "-lOmsMAXkMC"], capture_output=True, text=True, timeout=120)
    assert built.returncode == 0, built.stderr


def test_maxk_library_prints_the_library_headers_and_a_compile_line(capsys):
    from maxk.cli import main

    assert main(["library"]) == 0
    out = capsys.readouterr().out.splitlines()
    lib = Path(out[0].split(": ", 1)[1])
    assert lib.name == oms_library.LIBRARY_NAME and lib.exists()
    assert out[1].startswith(f"headers: {oms_library.INCLUDE_DIR}")
    assert out[2].startswith("compile: ") and "-lOmsMAXkMC" in out[2]
    assert main(["library", "--path"]) == 0
    assert capsys.readouterr().out.strip() == str(lib)
