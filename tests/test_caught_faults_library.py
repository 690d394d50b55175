"""Faults the suite once let through (issue 41), caught in the vendor's library API
(libOmsMAXkMC, built here from this tree's source): the exact text each setter writes
into the board's command ring, the command ring's free room, the absolute encoder
registers, and the clear of the controller's command-error flag.

The board here is a stand-in card: a map file laid out as docs/shared-memory.md and
maxk/host/memory_map.py say (the layout tag, the rings, the registers), locked as a
serving board's is, with a thread that plays the firmware's part (takes the ring's text,
zeroes the doorbell clear word after applying it, counts update ticks). So the text a
function sends, and the register a getter reads, are seen as written, with nothing of the
emulator's board in between: the expected values are the vendor's templates (reference
oms-maxk-dll-api.md, docs/oms-library.md's table) and numbers the test placed.

The card runs on the wall clock (the library is a separate world that polls the map);
its loop is a liveness bound only: no expected value depends on speed.
"""

from __future__ import annotations

import ctypes
import fcntl
import mmap
import os
import struct
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from maxk.host import memory_map as M
from maxk.host import oms_library

pytestmark = pytest.mark.skipif(oms_library.compiler() is None, reason="no C compiler")

X, Y, Z, T, U, V, R, S, W, K = (1 << i for i in range(10))
ALL = 0x3FF
SUCCESS = 0
COMMAND_ERROR = 0x01
ODBR_COMMAND_ERROR = 1 << 24  # the doorbell's command-error bit (docs/shared-memory.md)
MODE_OFF, MODE_ON, LOW, HIGH, POSITIVE, NEGATIVE = 0, 1, 0, 1, 0, 1


class AxesData(ctypes.Structure):
    _fields_ = [(name, ctypes.c_long) for name in "XYZTUVRSWK"]


class Card:
    """A map file with a firmware stand-in: what the library writes, the test reads."""

    def __init__(self, path: Path) -> None:
        self.path = path
        with open(path, "wb") as f:
            f.truncate(M.SIZE)
        self.fd = os.open(path, os.O_RDWR)
        fcntl.flock(self.fd, fcntl.LOCK_EX)  # served: the library checks the lock
        self.mem = mmap.mmap(self.fd, M.SIZE)
        self.mem[M.LAYOUT:M.LAYOUT + 4] = M.LAYOUT_MAGIC
        self.put(M.BOARD_NUMBER, 1)
        self.put(M.FIRMWARE_FLAGS, 0)  # power-up initialization done
        self.text = bytearray()
        self.clears: list[int] = []
        self.consuming = threading.Event()
        self.consuming.set()
        self.stopped = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    # the map's words are big-endian, as the PCI board's registers (docs/shared-memory.md)
    def get(self, offset: int) -> int:
        return int(struct.unpack_from(">I", self.mem, offset)[0])

    def put(self, offset: int, value: int) -> None:
        struct.pack_into(">I", self.mem, offset, value & 0xFFFF_FFFF)

    def put_signed(self, offset: int, value: int) -> None:
        struct.pack_into(">i", self.mem, offset, value)

    def _run(self) -> None:
        while not self.stopped.is_set():
            if self.consuming.is_set():
                insert, process = self.get(M.CMD_INSERT), self.get(M.CMD_PROCESS)
                while process != insert:
                    self.text.append(self.mem[M.CMD_RING + process])
                    process = (process + 1) % M.RING_SIZE
                self.put(M.CMD_PROCESS, process)
            clear = self.get(M.ODBR_CLEAR)
            if clear:
                self.clears.append(clear)
                self.put(M.ODBR, self.get(M.ODBR) & ~clear)
                self.put(M.ODBR_CLEAR, 0)
            self.put(M.TICK, self.get(M.TICK) + 1)
            time.sleep(0.0002)  # the firmware's pace; nothing depends on it

    def take(self) -> str:
        """The text the library has sent since the last take (once the ring is empty)."""
        for _ in range(100_000):  # a liveness bound
            if self.get(M.CMD_PROCESS) == self.get(M.CMD_INSERT):
                break
            time.sleep(0.0002)
        text = self.text.decode("latin-1")
        self.text.clear()
        return text

    def close(self) -> None:
        self.stopped.set()
        self.thread.join(10)
        self.mem.close()
        os.close(self.fd)


@pytest.fixture(scope="module")
def lib(tmp_path_factory) -> ctypes.CDLL:
    path = oms_library.build(tmp_path_factory.mktemp("lib") / oms_library.LIBRARY_NAME)
    library = ctypes.CDLL(str(path))
    library.GetOmsHandle.restype = ctypes.c_void_p
    library.GetOmsHandle.argtypes = [ctypes.c_char_p]
    return library


@pytest.fixture
def board(lib: ctypes.CDLL, tmp_path: Path, monkeypatch) -> Iterator[tuple[Card, int]]:
    card = Card(tmp_path / "card")
    monkeypatch.setenv("MAXK_OMSMAXK1", f"shm:{card.path}")
    monkeypatch.setenv("MAXK_OMS_COMMAND_TIMEOUT_MS", "20000")
    monkeypatch.setenv("MAXK_OMS_RESPONSE_TIMEOUT_MS", "20000")
    handle = lib.GetOmsHandle(b"OmsMAXk1")
    assert handle, "the library did not take the stand-in card"
    card.take()  # whatever opening sent (nothing, on the map)
    yield card, handle
    lib.CloseOmsHandle(ctypes.c_void_p(handle))
    card.close()


def call(lib: ctypes.CDLL, name: str, handle: int, *args: int) -> int:
    return int(getattr(lib, name)(ctypes.c_void_p(handle), *(ctypes.c_long(a) for a in args)))


# (function, arguments, the text the vendor's template makes of them)
SETTERS = [
    ("SetOmsAxisVelocity", (Y, 12345), "AYVL12345;"),
    ("SetOmsAxisBaseVelocity", (Y, 200), "AYVB200;"),
    ("SetOmsAxisAcceleration", (Y, 50000), "AYAC50000;"),
    ("SelectOmsCosineRamp", (Z, ), "AZCN;"),
    ("SelectOmsLinearRamp", (Z, ), "AZLA;"),
    ("SelectOmsParabolicRamp", (T, 3), "ATPN3;"),
    ("SelectOmsSCurveRamp", (U, 40), "AUSC;SS40;PR40;"),
    ("SelectOmsSCurveRamp", (K, 0), "AKSC;SS0;PR0;"),
    ("SetOmsAxisPosition", (Z, -77), "AZLP-77;"),
    ("DefineOmsHomeAsSwitchClosed", (X, ), "AXHH;"),
    ("DefineOmsHomeAsSwitchOpen", (X, ), "AXHL;"),
    ("EnableOmsSlipDetection", (V, ), "AVIS;"),
    ("SetOmsAxisPidEnable", (X, MODE_ON), "AXHN;"),
    ("SetOmsAxisPidEnable", (X, MODE_OFF), "AXHF;"),
    ("SetOmsEncoderHoldMode", (R, MODE_ON), "ARHN;"),
    ("SetOmsEncoderHoldMode", (R, MODE_OFF), "ARHF;"),
    ("SetOmsEncoderRatio", (S, 4000, 1000), "ASER4000,1000;"),
    ("SetOmsHoldDeadBand", (X, 5), "AXHD5;"),
    ("SetOmsEncoderSlipTolerance", (X, 7), "AXES7;"),
    ("SetOmsHoldGain", (X, 9), "AXHG9;"),
    ("SetOmsHoldVelocity", (X, 300), "AXHV300;"),
    ("SetOmsAxisOvertravelDetect", (W, MODE_ON), "AWLN;"),
    ("SetOmsAxisOvertravelDetect", (W, MODE_OFF), "AWLF;"),
    ("ConfigureOmsAxisLimitInput", (X, HIGH), "AXLH;"),
    ("ConfigureOmsAxisLimitInput", (X, LOW), "AXLL;"),
    ("SetOmsSoftLimitsMode", (Y, MODE_ON), "AYSL;"),
    ("SetOmsSoftLimitsMode", (Y, MODE_OFF), "AYSF;"),
    ("ConfigureAllOmsIOBits", (0x00F0, ), "AA;BD00F0;"),
    ("SetAllOmsIOBits", (0x1234, ), "AA;BS1234;"),
    ("SetOmsIOBit", (3, 1), "AA;BH3;"),
    ("SetOmsIOBit", (14, 0), "AA;BL14;"),
    ("EnableOmsAxisAuxOutAutoMode", (X, MODE_ON), "AXPA1;"),
    ("EnableOmsAxisAuxOutAutoMode", (X, MODE_OFF), "AXPA0;"),
    ("SetOmsAxisAuxOutSettleTime", (Z, 25), "AZSE25;"),
    ("SetOmsAxisAuxOutBit", (T, 1), "ATAN;"),
    ("SetOmsAxisAuxOutBit", (T, 0), "ATAF;"),
    ("SetSelectedOmsAuxOutBits", (X | Z, 1), "AXAN;AZAN;"),
    ("MoveOmsAxisIndefinite", (X, -500), "AXJG-500;"),
    ("MoveOmsAxisOneStep", (X, POSITIVE), "AXMPMO;"),
    ("MoveOmsAxisOneStep", (X, NEGATIVE), "AXMMMO;"),
    ("StopOmsAxis", (Y, ), "AYST;"),
]


@pytest.mark.parametrize("name, args, text", SETTERS,
                         ids=[f"{n}{a}" for n, a, _ in SETTERS])
def test_each_setter_sends_its_template(lib, board, name: str, args: tuple[int, ...],
                                        text: str) -> None:
    """Fault 8 (`SelectOmsSCurveRamp` sending only `SC;`), and every other setter: the
    exact text in the command ring, nothing more."""
    card, handle = board
    assert call(lib, name, handle, *args) == SUCCESS
    assert card.take() == text


def test_a_setter_refused_sends_nothing(lib, board) -> None:
    card, handle = board
    assert call(lib, "SelectOmsSCurveRamp", handle, X, 101) == 5  # INVALID_PARAMETER
    assert call(lib, "SetOmsAxisVelocity", handle, X | Y, 100) == 3  # INVALID_AXIS_SELECTION
    assert call(lib, "SetOmsIOBit", handle, 16, 1) == 6  # INVALID_BIT_NUMBER
    assert card.take() == ""


def test_cmd_buffer_free_is_the_room_left_in_the_ring(lib, board) -> None:
    """Fault 7 (`GetCmdBufferFree` always 512): a 1024-byte ring holds 1023 bytes; with
    the firmware not taking text, each byte sent is one byte less."""
    card, handle = board
    assert lib.GetCmdBufferFree(ctypes.c_void_p(handle)) == 1023
    card.consuming.clear()
    assert lib.SendOmsTextCommand(ctypes.c_void_p(handle), b"AXVL100;") == SUCCESS
    assert lib.GetCmdBufferFree(ctypes.c_void_p(handle)) == 1023 - 8
    assert lib.SendString(ctypes.c_void_p(handle), b"AYST;" * 100) == SUCCESS
    assert lib.GetCmdBufferFree(ctypes.c_void_p(handle)) == 1023 - 8 - 500
    card.consuming.set()
    assert card.take() == "AXVL100;" + "AYST;" * 100
    assert lib.GetCmdBufferFree(ctypes.c_void_p(handle)) == 1023


def _place_positions(card: Card) -> None:
    """Motor, encoder and absolute-encoder registers, each with its own numbers."""
    for i in range(8):  # X..S
        card.put_signed(M.MOTOR_XS + 4 * i, 1000 * i + 1)
        card.put_signed(M.ENCODER_XS + 4 * i, -(1000 * i + 2))
    for i in range(2):  # W, K
        card.put_signed(M.MOTOR_WK + 4 * i, 1000 * (8 + i) + 1)
        card.put_signed(M.ENCODER_WK + 4 * i, -(1000 * (8 + i) + 2))
    for i in range(10):
        card.put_signed(M.ABSOLUTE_ENCODERS + 4 * i, 70000 + 1000 * i + 3)


def test_absolute_encoder_positions_come_from_the_absolute_registers(lib, board) -> None:
    """Fault 9 (`GetAbsoluteEncoderPositions` reading the motor counter): each getter
    returns its own register's numbers, never another's."""
    card, handle = board
    _place_positions(card)
    data = AxesData()
    h = ctypes.c_void_p(handle)
    assert lib.GetAbsoluteEncoderPositions(h, ctypes.byref(data)) == SUCCESS
    assert [getattr(data, a) for a in "XYZTUVRSWK"] == [70000 + 1000 * i + 3 for i in range(10)]
    assert lib.GetMotorPositions(h, ctypes.byref(data)) == SUCCESS
    assert [getattr(data, a) for a in "XYZTUVRSWK"] == [1000 * i + 1 for i in range(10)]
    assert lib.GetEncoderPositions(h, ctypes.byref(data)) == SUCCESS
    assert [getattr(data, a) for a in "XYZTUVRSWK"] == [-(1000 * i + 2) for i in range(10)]
    one = ctypes.c_long()
    assert lib.GetOmsAxisAbsoluteEncoderPosition(h, ctypes.c_long(Z), ctypes.byref(one)) == 0
    assert one.value == 72003
    assert lib.GetOmsAxisMotorPosition(h, ctypes.c_long(K), ctypes.byref(one)) == 0
    assert one.value == 9001
    assert lib.GetOmsAxisEncoderPosition(h, ctypes.c_long(W), ctypes.byref(one)) == 0
    assert one.value == -8002
    assert card.take() == ""  # read from the registers: no text


@pytest.mark.parametrize("clear", ["ClrOmsControllerFlags", "ClrStatusFlags"])
def test_clearing_the_controller_flags_writes_the_doorbell_clear(lib, board, clear) -> None:
    """Fault 10 (`ClrOmsControllerFlags` doing nothing): the command-error bit goes into
    the doorbell clear word, and the flag reads clear afterwards; a mask without the bit
    clears nothing."""
    card, handle = board
    h = ctypes.c_void_p(handle)
    card.put(M.ODBR, ODBR_COMMAND_ERROR)
    flags = ctypes.c_long(-1)
    assert lib.GetOmsControllerFlags(h, ctypes.byref(flags)) == SUCCESS
    assert flags.value == COMMAND_ERROR
    assert getattr(lib, clear)(h, ctypes.c_long(0)) == SUCCESS
    assert card.clears == []
    assert lib.GetStatusFlags(h, ctypes.byref(flags)) == SUCCESS and flags.value == COMMAND_ERROR
    assert getattr(lib, clear)(h, ctypes.c_long(COMMAND_ERROR)) == SUCCESS
    assert card.clears == [ODBR_COMMAND_ERROR]
    assert card.get(M.ODBR) == 0
    assert lib.GetOmsControllerFlags(h, ctypes.byref(flags)) == SUCCESS and flags.value == 0
    assert card.take() == ""
