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
        self.replies: dict[str, str] = {}  # a query's exact text -> the line the card answers
        self._unanswered = ""
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
                    self._unanswered += chr(self.mem[M.CMD_RING + process])
                    process = (process + 1) % M.RING_SIZE
                self.put(M.CMD_PROCESS, process)
                self._answer()
            clear = self.get(M.ODBR_CLEAR)
            if clear:
                self.clears.append(clear)
                self.put(M.ODBR, self.get(M.ODBR) & ~clear)
                self.put(M.ODBR_CLEAR, 0)
            self.put(M.TICK, self.get(M.TICK) + 1)
            time.sleep(0.0002)  # the firmware's pace; nothing depends on it

    def _answer(self) -> None:
        """A registered query that arrived gets its line in the response ring (the MAX
        framing: the reply, then LF CR)."""
        for query, reply in self.replies.items():
            if self._unanswered.endswith(query):
                insert = self.get(M.RESP_INSERT)
                for byte in (reply + "\n\r").encode("latin-1"):
                    self.mem[M.RESP_RING + insert] = byte
                    insert = (insert + 1) % M.RING_SIZE
                self.put(M.RESP_INSERT, insert)
                self._unanswered = ""

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
    monkeypatch.setenv("MAXK_OMS_RESPONSE_TIMEOUT_MS", "5000")  # a query nobody answers
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


def _long(lib, name: str, handle: int, *args: int) -> tuple[int, int]:
    out = ctypes.c_long(-999)
    rc = getattr(lib, name)(ctypes.c_void_p(handle), *(ctypes.c_long(a) for a in args),
                            ctypes.byref(out))
    return int(rc), out.value


# (function, arguments, the query the vendor's template makes, the card's reply, the value)
QUERIES = [
    ("GetOmsAxisVelocity", (Y, ), "AYRV;", "4321", 4321),
    ("GetOmsAxisAcceleration", (T, ), "ATRC;", "250000", 250000),
    ("GetOmsIOBitConfig", (), "AXRB;", "00F0", 0x00F0),
    ("GetAllOmsIOBits", (), "BX;", "0A05", 0x0A05),
    ("GetOmsIOBit", (2, ), "BX;", "0A05", 1),  # 0x0A05 = ...0101: bit 2 set
    ("GetOmsIOBit", (1, ), "BX;", "0A05", 0),
    ("GetOmsIOBit", (11, ), "BX;", "0A05", 1),
    ("GetOmsEncoderFlags", (Y, ), "AM;EA;", "EN---,EESDH,NN---", 0x1F),
    ("GetOmsEncoderFlags", (X, ), "AM;EA;", "EN---,EESDH,NN---", 0x01),
    ("GetOmsEncoderFlags", (Z, ), "AM;EA;", "EN---,EESDH,NN---", 0x00),
]


@pytest.mark.parametrize("name, args, query, reply, value", QUERIES,
                         ids=[f"{q[0]}{q[1]}" for q in QUERIES])
def test_each_query_getter_asks_its_query_and_reads_its_reply(lib, board, name, args, query,
                                                                reply, value) -> None:
    """A getter's value comes from its own query's reply: the card answers only that
    exact text (a getter asking another question would get no reply)."""
    card, handle = board
    card.replies[query] = reply
    assert _long(lib, name, handle, *args) == (SUCCESS, value)
    assert card.take() == query


@pytest.mark.parametrize("name, query", [("GetSelectedOmsVelocities", "AMRV;"),
                                         ("GetSelectedOmsAccelerations", "AMRC;")])
def test_selected_getters_fill_only_the_chosen_axes(lib, board, name, query) -> None:
    card, handle = board
    card.replies[query] = ",".join(str(11 * (i + 1)) for i in range(10))
    data = AxesData(*([-1] * 10))
    assert getattr(lib, name)(ctypes.c_void_p(handle), ctypes.c_long(X | Z | K),
                              ctypes.byref(data)) == SUCCESS
    assert [getattr(data, a) for a in "XYZTUVRSWK"] == [11, -1, 33, -1, -1, -1, -1, -1, -1,
                                                        110]
    assert card.take() == query


def test_the_controller_description_is_the_wy_reply(lib, board) -> None:
    card, handle = board
    card.replies["WY;"] = "MAXk-8000 ver:1.33, s/n:4711"
    text = ctypes.create_string_buffer(80)
    assert lib.GetOmsControllerDescription(ctypes.c_void_p(handle), text) == SUCCESS
    assert text.value == b"MAXk-8000 ver:1.33, s/n:4711"
    assert card.take() == "WY;"


def test_sensor_getters_read_the_switch_words(lib, board) -> None:
    """GetOmsHomeSensors reads the home word, GetOmsLimitSensors the limit word: each its
    own register's bits."""
    card, handle = board
    card.put(M.HOME_WORD, 0b10_0000_0101)  # X, Z, K at home
    # the map's limit word (docs/shared-memory.md, Table 3-2): bit i minus and i+8 plus
    # for X..S, 16/17 W/K minus, 24/25 W/K plus; the API's mask: minus X..K bits 0..9,
    # plus X..K bits 10..19 (reference oms-maxk-dll-api.md)
    card.put(M.LIMIT_WORD, (1 << 1) | (1 << (8 + 3)) | (1 << 17) | (1 << 24))
    rc, home = _long(lib, "GetOmsHomeSensors", handle)
    assert (rc, home) == (SUCCESS, 0b10_0000_0101)
    rc, limits = _long(lib, "GetOmsLimitSensors", handle)
    # Y minus, T plus, K minus, W plus
    assert (rc, limits) == (SUCCESS, (1 << 1) | (1 << (10 + 3)) | (1 << 9) | (1 << (10 + 8)))
    assert card.take() == ""


@pytest.mark.parametrize("name, args, text", SETTERS,
                         ids=[f"{n}{a}" for n, a, _ in SETTERS])
def test_the_board_takes_each_setter_text(name: str, args: tuple[int, ...], text: str) -> None:
    """The other half of a setter: the text it sends is a command the MAXk takes (no
    command error), on a 10-axis board with I/O bits 3 and 14 made outputs first."""
    from maxk import MAXk

    board = MAXk("MAXk-A000")
    board.send("AA;BD4008;")
    board.advance(0.01)
    board.send(text)
    board.advance(0.01)
    assert not board.command_error and board.last_error is None, board.last_error


def test_the_io_bit_setters_move_the_output_lines() -> None:
    """SetOmsIOBit's texts, on the board: the output line goes high, then low."""
    from maxk import MAXk

    board = MAXk("MAXk-A000")
    view = board.world_view()
    board.send("AA;BD4008;")
    board.send("AA;BH3;")
    board.send("AA;BH14;")
    board.advance(0.01)
    assert [n for n in range(16) if view.output_level(n)] == [3, 14]
    board.send("AA;BL14;")
    board.advance(0.01)
    assert [n for n in range(16) if view.output_level(n)] == [3]
