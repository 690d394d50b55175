"""A fault in the emulator's own code (a keyword handler that raises an unexpected Python
exception) never stalls an MC405 session: the line is answered with
``%[COMMAND LINE] - Evaluation error``, the traceback goes to the log and never to the
host, the next line runs; a program that meets the fault stops as at a run-time error.

The fault is injected by making MOVE's handler on the machine raise.
"""

from __future__ import annotations

import logging
import socket
import time
from typing import Any

import pytest

from maxk.controllers.registry import build
from maxk.controllers.trio import MC405
from tests.hosting import HostedBoards

TRAILER = b">>\nControl char : 0x10000000A\r\n>>"
FAULT = b"%[COMMAND LINE] - Evaluation error\r\n"


class Boom(RuntimeError):
    """The injected fault (its text must never reach a host)."""


def _break_move(monkeypatch: pytest.MonkeyPatch, controller: Any) -> list[int]:
    """MOVE's handler raises; the list counts its calls."""
    calls: list[int] = []

    def move(self: object, axes: object, distances: object) -> None:
        calls.append(1)
        raise Boom("secret-internal-detail")

    monkeypatch.setattr(type(controller.machine), "move", move)
    return calls


# ---- through the Python API ------------------------------------------------------------------
def test_api_fault_answers_the_line_and_the_next_command_runs_at_once(
        monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture) -> None:
    trio = MC405()
    calls = _break_move(monkeypatch, trio)
    with caplog.at_level(logging.ERROR, logger="maxk.commands"):
        assert trio.send("BASE(0): MOVE(10)") == ["! Evaluation error"]
    assert calls == [1]
    assert any(r.exc_info and r.exc_info[0] is Boom for r in caplog.records)
    tick = trio.machine.tick
    assert trio.send("?1+1") == ["2"]
    assert trio.machine.tick == tick  # no virtual time spent waiting for a dead statement
    assert trio.send("?DPOS AXIS(0), MTYPE AXIS(0)") == ["0\t0"]  # nothing loaded


def test_api_fault_after_earlier_statements_keeps_what_they_did(
        monkeypatch: pytest.MonkeyPatch) -> None:
    trio = MC405()
    _break_move(monkeypatch, trio)
    assert trio.send("VR(5) = 7: MOVE(10): VR(6) = 8") == ["! Evaluation error"]
    assert trio.send("?VR(5), VR(6)") == ["7.0000\t0.0000"]  # before it ran, after it did not


def test_program_fault_stops_the_program_with_a_run_time_error_line(
        monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture) -> None:
    trio = MC405()
    _break_move(monkeypatch, trio)
    trio.load("FLT", "VR(1) = 1\nMOVE(5)\nVR(1) = 2")
    assert trio.send('RUN "FLT",4') == []
    with caplog.at_level(logging.ERROR, logger="maxk.commands"):
        trio.advance(ticks=3)
    out = trio.send("?VR(1), PROC_STATUS PROC(4), RUN_ERROR PROC(4), ERROR_LINE PROC(4)")
    assert out == ["%[Process 4:Program FLT Line 2] - Evaluation error",
                   "1.0000\t0\t62\t2"]  # 62: RUN_ERROR's "Evaluation error"
    assert any(r.exc_info and r.exc_info[0] is Boom for r in caplog.records)
    assert trio.send("?3*3") == ["9"]


# ---- through the telnet door -----------------------------------------------------------------
def _recv_until(sock: socket.socket, end: bytes, count: int = 1) -> bytes:
    """Read until `end` came `count` times, or 30 s (a bound that only ends a failing test)."""
    sock.settimeout(0.2)
    data = b""
    deadline = time.monotonic() + 30.0
    while data.count(end) < count and time.monotonic() < deadline:
        try:
            chunk = sock.recv(1 << 16)
        except TimeoutError:
            continue
        if not chunk:
            break
        data += chunk
    return data


def test_telnet_fault_is_answered_and_the_session_goes_on(
        monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture) -> None:
    boards = HostedBoards(models=("MC405",))
    try:
        controller = boards.services[0].controller
        calls = _break_move(monkeypatch, controller)
        with socket.create_connection(("127.0.0.1", boards.ports[0]), timeout=5) as sock:
            with caplog.at_level(logging.ERROR, logger="maxk.commands"):
                # the faulting line and the next one in one packet: both answered
                sock.sendall(b"MOVE(10)\r\n?1+2\r\n")
                data = _recv_until(sock, TRAILER, 2)
            assert calls == [1]
            first, second = data.split(TRAILER)[:2]
            assert first == b"MOVE(10)\r\n" + FAULT
            assert second == b"?1+2\r\n3\r\n"
            assert b"secret" not in data and b"Traceback" not in data
            sock.sendall(b"?VR(0)+4\r\n")
            assert _recv_until(sock, TRAILER) == b"?VR(0)+4\r\n4.0000\r\n" + TRAILER
        assert any(r.exc_info and r.exc_info[0] is Boom for r in caplog.records)
    finally:
        boards.close()


# ---- the shared line session (the MM4005 uses it too) -----------------------------------------
def test_mm4005_fault_is_logged_answered_as_a_refused_line_and_the_next_line_runs(
        monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture) -> None:
    """One packet, three lines: the first faults; TE then reads A (unknown message, as a
    line it refuses) and VE still answers, where the fault used to take the packet's
    remaining lines with it."""
    controller: Any = build("MM4005")
    session: Any = controller.open_session()
    real_start = type(session.interpreter).start
    faults: list[str] = []

    def start(self: object, text: str, owner: object) -> object:
        if text.startswith("1PA"):
            faults.append(text)
            raise Boom("secret-internal-detail")
        return real_start(self, text, owner)

    monkeypatch.setattr(type(session.interpreter), "start", start)
    with caplog.at_level(logging.ERROR, logger="maxk.commands"):
        session.feed(b"1PA5\rTE\rTE\r")
    assert faults == ["1PA5"]
    assert session.read() == b"TEA\rTE@\r"
    assert any(r.exc_info and r.exc_info[0] is Boom for r in caplog.records)


# ---- the MAX stream (its own splitter, the same guard) ----------------------------------------
def test_max_fault_is_a_refused_command_and_the_commands_after_it_run(
        caplog: pytest.LogCaptureFixture) -> None:
    """WY's handler faults once: that WY is refused as a bad command is (the command-error
    flag and its notification, the fault logged), and the WY after it in the same write
    answers."""
    from maxk.commands.max.table import COMMANDS

    spec = COMMANDS["WY"]
    real: Any = spec.handler
    faults: list[int] = []

    def identify(ctx: Any) -> str | None:
        if not faults:
            faults.append(1)
            raise Boom("secret-internal-detail")
        return real(ctx)

    controller: Any = build("MAXk-8000")
    session: Any = controller.open_session()
    expected: Any = build("MAXk-8000").open_session()
    expected.feed(b"QQQ;WY;")  # a command it refuses, then WY
    object.__setattr__(spec, "handler", identify)  # (the table's entries are frozen)
    try:
        with caplog.at_level(logging.ERROR, logger="maxk.commands"):
            session.feed(b"WY;WY;")
    finally:
        object.__setattr__(spec, "handler", real)
    assert faults == [1]
    assert session.read() == expected.read()  # as a refused command and one WY
    assert controller.board.command_error is True
    assert any(r.exc_info and r.exc_info[0] is Boom for r in caplog.records)


def test_mm4005_fault_after_a_wait_ends_the_line_and_the_session_is_free(
        caplog: pytest.LogCaptureFixture) -> None:
    """A line that waited (WS) meets the fault when it resumes: the line ends as a refused
    one (TE reads A) and the session takes the next line at once, where the waiting line
    used to hold the session for good."""
    from maxk.commands.mm4005.table import COMMANDS

    spec = COMMANDS["TP"]
    real: Any = spec.handler

    def report(*args: Any) -> Any:
        raise Boom("secret-internal-detail")

    controller: Any = build("MM4005")
    assert controller.send("MO") == []
    object.__setattr__(spec, "handler", report)
    try:
        with caplog.at_level(logging.ERROR, logger="maxk.commands"):
            assert controller.send("1PA5;1WS;1TP") == []
    finally:
        object.__setattr__(spec, "handler", real)
    assert controller._own.waiting is False
    assert controller.send("TE") == ["TEA"]
    assert controller.send("1TP") == ["1TP5.0000"]  # the move before it stays done
    assert any(r.exc_info and r.exc_info[0] is Boom for r in caplog.records)


# ---- PoKeys: a request whose handler faults is refused, never left unanswered -----------------
def _pokeys_frame(cmd: int, p1: int = 0, rid: int = 1) -> bytes:
    """A 64-byte request: 0xBB, command, 4 parameters, ID, the sum of bytes 0..6."""
    head = [0xBB, cmd, p1, 0, 0, 0, rid]
    return bytes(head + [sum(head) & 0xFF]) + bytes(56)


def test_pokeys_fault_is_a_refusal_and_the_next_request_is_answered(
        caplog: pytest.LogCaptureFixture) -> None:
    """The pin-function read (0x15) faults once: its reply is the refusal (status 1 in
    byte 2, the payload zero, its ID), and a second request in the same write still
    gets its own answer."""
    from maxk.commands.pokeys import table

    entry = table.lookup(0x15, 6)
    assert entry is not None
    real: Any = entry.handler
    faults: list[int] = []

    def handler(device: Any, request: Any) -> Any:
        if not faults:
            faults.append(1)
            raise Boom("secret-internal-detail")
        return real(device, request)

    controller: Any = build("PoKeys57E")
    session: Any = controller.open_session()
    fresh: Any = build("PoKeys57E").open_session()
    fresh.feed(_pokeys_frame(0x15, 6, rid=2))
    object.__setattr__(entry, "handler", handler)
    try:
        with caplog.at_level(logging.ERROR, logger="maxk.commands"):
            session.feed(_pokeys_frame(0x15, 6, rid=1) + _pokeys_frame(0x15, 6, rid=2))
    finally:
        object.__setattr__(entry, "handler", real)
    out = session.read()
    assert faults == [1] and len(out) == 128
    refusal, second = out[:64], out[64:]
    head = [0xAA, 0x15, 0x01, 0, 0, 0, 1]
    assert refusal == bytes(head + [sum(head) & 0xFF]) + bytes(56)
    assert second == fresh.read()  # as a device that never faulted answers it
    assert any(r.exc_info and r.exc_info[0] is Boom for r in caplog.records)
