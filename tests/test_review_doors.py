"""A hostile review of the doors of every controller (MAXk-8000, MM4005, MC405).

Hosts that are careless or hostile: malformed and over-long lines, binary bytes, NUL,
telnet IAC, commands split at every byte, floods, 100 clients at once, clients that never
read, disconnects mid-command, reconnect storms, valid but extreme operands. Each test
either reproduces a defect the review found, now fixed (``test_fixed_...``: its
docstring says what went wrong and what is expected instead), or guards a behaviour that
held under attack (``test_holds_...``).

Door tests use `maxk serve`'s server in-process (tests/hosting.py, a manual clock: virtual
time moves only when the test moves it); session tests drive the door contract directly
(`build(model).open_session()`, `feed`, `read`). The few tests that must show unbounded
work or memory measure it with tracemalloc (allocations, not wall time) or count what one
engine step ran.
"""

from __future__ import annotations

import gc
import os
import random
import re
import socket
import struct
import subprocess
import sys
import threading
import time
import tracemalloc
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from maxk.controllers.registry import build
from maxk.host.server import SLICE
from tests.hosting import HostedBoards

ROOT = Path(__file__).parent.parent
MODELS = ("MAXk-8000", "MM4005", "MC405")
TRIO_TRAILER = b">>\nControl char : 0x10000000A\r\n>>"



# ---- helpers ----------------------------------------------------------------------------
class Fed:
    """One in-process session: send a line, get the bytes it answers; an exception out of
    the session or the engine is a defect and is re-raised with the line that caused it."""

    def __init__(self, model: str) -> None:
        self.controller: Any = build(model)  # the tests reach its engine's own API
        self.session: Any = self.controller.open_session()
        self.eol = b"\r\n" if model == "MC405" else b"\r"

    def __call__(self, line: str | bytes) -> bytes:
        data = line.encode("latin-1") if isinstance(line, str) else line
        self.session.feed(data + self.eol)
        return self.session.read()

    def advance(self, ticks: int) -> None:
        self.controller.engine.advance(ticks)


def mm_reply(fed: Fed, line: str) -> str:
    return fed(line).decode("latin-1")


def trio_output(reply: bytes) -> bytes:
    """The output lines of one Trio command-line exchange (echo and trailer removed)."""
    assert reply.endswith(TRIO_TRAILER), reply
    body = reply[: -len(TRIO_TRAILER)]
    return body.split(b"\r\n", 1)[1] if b"\r\n" in body else b""


def _recv_until(sock: socket.socket, done: Callable[[bytes], bool], timeout: float = 30.0
                ) -> bytes:
    """Read until `done(data)` or the timeout (then return what came: the test decides).
    The timeout only ends a test that failed: a passing one returns when `done`."""
    sock.settimeout(0.2)
    data = b""
    deadline = time.monotonic() + timeout
    while not done(data) and time.monotonic() < deadline:
        try:
            chunk = sock.recv(1 << 20)
        except TimeoutError:
            continue
        if not chunk:
            break
        data += chunk
    return data


def _drain(sock: socket.socket) -> None:
    """Read whatever has arrived, without waiting."""
    sock.setblocking(False)
    try:
        while sock.recv(1 << 20):
            pass
    except BlockingIOError:
        pass
    finally:
        sock.settimeout(5)


def _ends_with(end: bytes) -> Callable[[bytes], bool]:
    return lambda data: data.endswith(end)


def _connect(port: int) -> socket.socket:
    return socket.create_connection(("127.0.0.1", port), timeout=5)


@pytest.fixture
def three():
    """A MAXk-8000, an MM4005 and an MC405 in one server, as `maxk serve --model
    MAXk-8000,MM4005,MC405` runs them."""
    boards = HostedBoards(models=MODELS)
    yield boards
    boards.close()


QUERIES = {  # a query each controller answers, and how its reply ends
    "MAXk-8000": (b"WY;", b"\n\r"),
    "MM4005": (b"VE;\r", b"\r"),
    "MC405": (b"?VERSION\r\n", TRIO_TRAILER),
}


def everyone_answers(boards: HostedBoards) -> dict[str, bytes]:
    """Each controller of the server answers a fresh host's query (or b'' after 5 s)."""
    answers = {}
    for model, port in zip(MODELS, boards.ports, strict=True):
        query, end = QUERIES[model]
        with _connect(port) as sock:
            sock.sendall(query)
            answers[model] = _recv_until(sock, _ends_with(end))
    return answers


def retained_bytes(action: Callable[[], None]) -> int:
    """Bytes still allocated after `action` (tracemalloc, garbage collected)."""
    gc.collect()
    tracemalloc.start()
    before = tracemalloc.take_snapshot()
    action()
    gc.collect()
    after = tracemalloc.take_snapshot()
    tracemalloc.stop()
    return sum(stat.size_diff for stat in after.compare_to(before, "filename"))


def peak_bytes(action: Callable[[], object]) -> int:
    """The highest allocation above the start while `action` runs (tracemalloc)."""
    gc.collect()
    tracemalloc.start()
    tracemalloc.reset_peak()
    start = tracemalloc.get_traced_memory()[0]
    try:
        action()
    finally:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return peak - start


# =========================================================================================
# MM4005
# =========================================================================================

def test_fixed_mm4005_home_search_at_va_1e300_bricks_the_axis_for_good() -> None:
    """CRITICAL. `2VA1e300;2OR0` (a finite VA, accepted) makes axis 2's motion NaN: the
    OR line raises ValueError out of the session, and from then on every command that
    looks at axis 2 raises too: `MS;` and `TP;` (the EPICS model 2 poll), `2ST`, `2MF`,
    `2MO`. The controller never answers its poll again and the axis cannot be stopped."""
    fed = Fed("MM4005")
    failures = []
    for line in ("2VA1e300;2OR0", "MS;", "TP;", "2ST", "2MF", "2MO;2PA1", "MS;"):
        try:
            fed(line)
        except Exception as error:  # noqa: BLE001 - the defect is any exception
            failures.append(f"{line}: {type(error).__name__} {error}")
    assert not failures, failures
    fed.advance(2000)
    assert re.fullmatch(r"1MS.,2MS.,3MS.,4MS.\r", mm_reply(fed, "MS;"))


def test_fixed_mm4005_door_goes_silent_after_va_1e300_home(three: HostedBoards) -> None:
    """The same over TCP: after `2VA1e300;2OR0`, `MS;` and a VE behind it in the same
    packet get no reply at all (a traceback goes to stderr per request); the MAXk and the
    MC405 in the same server still answer."""
    with _connect(three.ports[1]) as sock:
        sock.sendall(b"2VA1e300;2OR0\r")
        sock.sendall(b"MS;\rVE\r")
        got = _recv_until(sock, lambda d: d.count(b"\r") >= 2)
    answers = everyone_answers(three)
    assert answers["MAXk-8000"].startswith(b"MAXk-8000")
    assert answers["MC405"].endswith(TRIO_TRAILER)
    assert re.fullmatch(rb"1MS.,2MS.,3MS.,4MS.\rVE MM4005 Version 2\.42\r", got), got


INFINITE_SETTINGS = [  # (line, the query reading what it sets)
    ("1SR1e999", "1SR?"), ("1SL-1e999", "1SL?"), ("1SH1e999", "1SH?"),
    ("1VA1e999", "1VA?"), ("1AC1e999", "1AC?"), ("VV1e999", "VV?"), ("VS1e999", "VS?"),
    ("NI1e999", "NI?"), ("CR1e999", "CR?"), ("MX1e999", "MX?"), ("CX1e999", "CX?"),
    ("LX1e999", "XT"),
]


@pytest.mark.parametrize(("line", "query"), INFINITE_SETTINGS)
def test_fixed_mm4005_infinite_operand_is_accepted(line: str, query: str) -> None:
    """HIGH. `1e999` matches the number grammar and becomes float inf; every setting
    checked only for sign accepts it (`1SR1e999` then `1SR?` answers `1SRinf`, `LX1e999`
    adds an element ending at (inf, nan)). Everything below (moves, OR, ET) then
    overflows. Expected: refused (C), the setting unchanged."""
    fed = Fed("MM4005")
    before = mm_reply(fed, query)
    fed(line)
    assert mm_reply(fed, "TE") != "TE@\r", f"{line} accepted"
    assert mm_reply(fed, query) == before


@pytest.mark.parametrize("line", ["FA1e999", "AD1e999", "1PA1e999", "1PR-1e999"])
def test_holds_mm4005_range_checked_operands_refuse_infinity(line: str) -> None:
    fed = Fed("MM4005")
    fed(line)
    assert mm_reply(fed, "TE") == "TEC\r"
    assert mm_reply(fed, "1DP;FA?;AD?") == "1DP0.0000\rFA0\rAD0.001\r"


def test_fixed_mm4005_overflowing_move_drops_the_replies_behind_it(three: HostedBoards
                                                                     ) -> None:
    """HIGH. With infinite limits accepted, `1PA1e999` raises OverflowError inside the
    door's slice: the VE sent behind it in the same packet is never answered (a reply
    dropped), a traceback goes to stderr, and no error is registered (TE@)."""
    with _connect(three.ports[1]) as sock:
        sock.sendall(b"1SL-1e999;1SR1e999\r1PA1e999\rVE\r")
        got = _recv_until(sock, lambda d: d.endswith(b"\r"))
    assert got == b"VE MM4005 Version 2.42\r"


EXTREME_SEQUENCES = [  # minimal sequences found by a grammar fuzzer; all but two finite
    ["2VA1e-300;2OR1"],
    ["1VA1e-320;1OR"],
    ["2VA1e300;OR0"],
    ["3AC1e300;3VA1e-300;3OR1"],
    ["2OR1", "2AC1e-320"],
    ["2AC1e999", "2OR1"],
    ["3SH1e999;3OR"],
    ["VV5e-324", "LX0.0001", "ET"],
]


@pytest.mark.parametrize("lines", EXTREME_SEQUENCES, ids=lambda ls: "|".join(ls))
def test_fixed_mm4005_extreme_speeds_raise_inside_the_engine(lines: list[str]) -> None:
    """HIGH. Valid-looking VA/AC/VV values far from any stage (1e-300, 1e300, a
    denormal) make the profile and switch searches overflow or divide by zero: the
    exception escapes the session or, worse, the engine's event (the pacer reports it on
    stderr and the axis is left half-way: `3SH1e999;3OR` leaves MS with bit 0 and the
    direction bit clear and TP != DP). Expected: refused, or run; never an exception, and
    the poll (MS;TP;TE) answered."""
    fed = Fed("MM4005")
    for line in lines:
        fed(line)
        fed.advance(1)
    fed.advance(20000)
    assert re.fullmatch(r"1MS.,2MS.,3MS.,4MS.\r1TP\S+,2TP\S+,3TP\S+,4TP\S+\rTE.\r",
                        mm_reply(fed, "MS;TP;TE"))


def test_fixed_mm4005_et_builds_every_pulse_before_checking_travel() -> None:
    """CRITICAL (denial of service). ET plans every synchronized pulse as a Python object
    before checking the travel limits: `NT;LX5e8;LX1e9`, `NB1;NE2;NN200000;NS`, `ET`
    allocates about 65 MB and blocks the server's one event loop (NN 2000000: 10.5 s and
    650 MB, measured; NN 50000000 never finishes) and is then refused with R anyway.
    Expected: a refused ET costs nothing and a plan is bounded (the execution already
    generates pulses 256 at a time)."""
    fed = Fed("MM4005")
    fed("NT;LX5e8;LX1e9")
    fed("NB1;NE2;NN200000;NS")
    peak = peak_bytes(lambda: fed("ET"))
    assert mm_reply(fed, "TE") == "TER\r"
    assert peak < 8 * 1024 * 1024, f"a refused ET allocated {peak / 1e6:.0f} MB"


def test_fixed_mm4005_refused_pa_into_a_pressed_limit_still_moves_dp() -> None:
    """MEDIUM (half-applied). `_start_move` stores the target before it finds the limit
    switch pressed: `1PA5` is refused with D but `1DP` then reads 5.0000, and a PR after
    it is relative to that phantom destination."""
    fed = Fed("MM4005")
    fed.controller.engine.world.axes[0].plus_limit.fault = "active"
    fed("1PA5")
    assert mm_reply(fed, "TE") == "TED\r"
    assert mm_reply(fed, "1DP;1TP") == "1DP0.0000\r1TP0.0000\r"


def test_holds_mm4005_two_thousand_elements_and_not_one_more() -> None:
    """2,000 elements are accepted (LT lists them all), the 2,001st is refused (L) with
    nothing changed, and ET runs the whole raster with its pulses."""
    fed = Fed("MM4005")
    fed("NT;VV10;VS1000")
    for i in range(2000):
        assert fed(f"LX{(i + 1) * 0.01:.2f}") == b""
    assert mm_reply(fed, "XT;TE") == "XT2000\rTE@\r"
    fed("LX100")
    assert mm_reply(fed, "TE;XT") == "TEL\rXT2000\r"
    assert mm_reply(fed, "LT").count("\r") == 2000
    fed("NB1;NE2000;NN1000;NS")
    fed("ET")
    assert mm_reply(fed, "TE;AT") == "TE@\rAT1\r"
    fed.advance(2000 * 60)
    assert mm_reply(fed, "AT;1TP;2TP") == "AT0\r1TP20.0000\r2TP0.0000\r"
    assert len(fed.controller.engine.pulse_log) == 1000


@pytest.mark.parametrize(("line", "code"), [("ET", "K"), ("NT;ET", "K"), ("EL", "K"),
                                            ("LX-5", "L"), ("LY5", "L"), ("MY1", "L")])
def test_holds_mm4005_empty_or_bad_trajectory_refused_whole(line: str, code: str) -> None:
    fed = Fed("MM4005")
    fed(line)
    assert mm_reply(fed, "TE;XT;AT;MS") == f"TE{code}\rXT0\rAT0\r1MSD,2MSD,3MSD,4MSD\r"


def test_holds_mm4005_over_long_line_and_binary_bytes() -> None:
    """A megabyte without CR, NUL, IAC and 8-bit bytes: each line refused with A, nothing
    of it runs, the next line answers; 110 characters are a line, 111 are not."""
    fed = Fed("MM4005")
    fed.session.feed(b"1PA5;" * 200_000)
    assert fed(b"") == b""
    assert mm_reply(fed, "TE;1DP") == "TEA\r1DP0.0000\r"
    for junk in (b"\x00VE", b"\xff\xfb\x01VE", b"\x80\xfe;1PA5", b"1PA\x005"):
        fed(junk)
        assert mm_reply(fed, "TE;1DP") in ("TEA\r1DP0.0000\r", "TEC\r1DP0.0000\r"), junk
    assert mm_reply(fed, " " * 107 + "VE;") == "VE MM4005 Version 2.42\r"
    fed(" " * 108 + "VE;")
    assert mm_reply(fed, "TE") == "TEA\r"


def test_holds_mm4005_every_split_and_line_ending(three: HostedBoards) -> None:
    """The EPICS model 2 init and poll (reference), one byte per write, with CR and with
    CR LF: replies byte for byte, CR only."""
    exchange = [(b"VE;", b"VE MM4005 Version 2.42\r"), (b"TP;", None),
                (b"1TC", b"1TC0\r"), (b"1TU", b"1TU0.001\r"), (b"1XH", b"1XH0.0000\r"),
                (b"1TL", b"1TL-100.0000\r"), (b"1TR", b"1TR100.0000\r"),
                (b"MS;", b"1MSD,2MSD,3MSD,4MSD\r"), (b"TE;", b"TE@\r")]
    for ending in (b"\r", b"\r\n"):
        with _connect(three.ports[1]) as sock:
            for sent, expected in exchange:
                for byte in sent + ending:
                    sock.sendall(bytes([byte]))
                got = _recv_until(sock, lambda d: d.endswith(b"\r"))
                if expected is None:
                    assert got == b"1TP0.0000,2TP0.0000,3TP0.0000,4TP0.0000\r"
                else:
                    assert got == expected


def test_holds_mm4005_host_that_never_reads_gets_every_reply_later(three: HostedBoards
                                                                    ) -> None:
    """200,000 pipelined `TE;` from a host that does not read (its replies pass the
    256 KiB high water): the server stops reading from it and loses nothing: every reply
    comes once the host reads, exactly once; the other controllers answer meanwhile."""
    count = 200_000
    with _connect(three.ports[1]) as sock:
        sender = threading.Thread(target=sock.sendall, args=(b"TE;\r" * count,))
        sender.start()
        answers = everyone_answers(three)
        assert answers["MAXk-8000"].startswith(b"MAXk-8000")
        assert answers["MM4005"] == b"VE MM4005 Version 2.42\r"
        got = _recv_until(sock, lambda d: len(d) >= 4 * count, timeout=60)
        sender.join(10)
    assert got == b"TE@\r" * count


# =========================================================================================
# MC405
# =========================================================================================

@pytest.mark.parametrize("line", ["WA(1e306)", "WA(1e308)"])
def test_fixed_mc405_wa_beyond_the_float_range_raises(line: str) -> None:
    """HIGH. `WA(1e306)` passes the finiteness check, then `ms x 1000` is inf and
    math.ceil raises OverflowError out of the command line: no `%[COMMAND LINE]` error,
    a traceback on the server's stderr, and the REPL and `maxk run` die."""
    fed = Fed("MC405")
    reply = fed(line)
    assert b"%[COMMAND LINE] - " in reply and reply.endswith(TRIO_TRAILER), reply


def test_fixed_mc405_negative_base_to_a_fraction_raises() -> None:
    """MEDIUM. `?(-2)^0.5` makes a complex number; float() of it raises TypeError, which
    `binary` does not catch: no error line, just a bare prompt later (atrio reads an empty
    result), a traceback on stderr, and the REPL dies."""
    fed = Fed("MC405")
    reply = fed("?(-2)^0.5")
    assert reply.startswith(b"?(-2)^0.5\r\n%[COMMAND LINE] - "), reply
    assert reply.endswith(TRIO_TRAILER)


OVERFLOWING_MOVES = [
    ["SPEED=1e-320", "MOVE(5)"],
    ["SPEED=5e-324", "MOVEABS($7FFFFFFFFFFFFFFF)"],
    ["MOVEABS(0,1e300) AXIS(15)"],
]


@pytest.mark.parametrize("lines", OVERFLOWING_MOVES, ids=lambda ls: ":".join(ls))
def test_fixed_mc405_move_that_overflows_is_half_applied(lines: list[str]) -> None:
    """HIGH. A move whose profile overflows (a denormal SPEED, a distance of 1e300 counts
    on a path) raises out of the machine after the move was recorded: no error line, and
    `SPEED=1e-320: MOVE(5)` leaves DPOS at 5 at once (a teleport) with the axis IDLE.
    Expected: refused whole with an error line, DPOS unchanged (or a real move)."""
    fed = Fed("MC405")
    for line in lines[:-1]:
        fed(line)
    reply = fed(lines[-1])
    assert reply.endswith(TRIO_TRAILER), reply
    assert trio_output(fed("?DPOS AXIS(0)")) == b"0\r\n"


def test_fixed_mc405_input_behind_a_waiting_command_is_not_back_pressured(
        three: HostedBoards) -> None:
    """HIGH (memory). While a command-line statement waits (WA, WAIT IDLE, a full move
    buffer) the session takes every byte the door feeds it into a private buffer, so the
    door never stops reading: a host sends `WA(100000)` and then as much as it likes
    (60 MB measured against `maxk serve`: accepted in 0.4 s, VmRSS +55 MB). Expected: the
    door's 64 KiB inbox limit holds, the host is back-pressured."""
    total = 48 * 1024 * 1024
    with _connect(three.ports[2]) as sock:
        sock.sendall(b"WA(100000)\r\n")
        _recv_until(sock, lambda d: d.endswith(b"WA(100000)\r\n"))
        sock.settimeout(3)
        block = b"?1\r\n" * 16384
        sent = 0
        try:
            while sent < total:
                sent += sock.send(block)
        except TimeoutError:
            pass
    assert sent < 16 * 1024 * 1024, f"{sent / 1e6:.0f} MB taken while WA waits"


def test_fixed_mc405_wait_end_runs_all_held_input_in_one_turn() -> None:
    """HIGH (denial of service). When the wait ends, the session runs everything held
    inside one engine event, not in the door's 2 KiB turns: against `maxk serve`, WA(1000)
    followed by 800 KB of `?1` froze the MAXk and the MM4005 of the same process for 7.8 s
    (51 ms without the WA). Expected: one engine step runs at most one slice of it."""
    fed = Fed("MC405")
    lines = 8000
    fed.session.feed(b"WA(100)\r\n" + b"?1\r\n" * lines)
    fed.session.read()
    fed.advance(100)  # the servo cycle the wait ends in
    answered = fed.session.read().count(b"\r\n1\r\n")
    assert answered <= SLICE // 4, f"{answered} lines ({answered * 4} bytes) in one step"
    fed.advance(lines)  # the rest, a slice a cycle, every line answered in order
    out = fed.session.read()
    assert answered + out.count(b"?1\r\n1\r\n>>") == lines
    assert out.endswith(b"?1\r\n1\r\n>>\nControl char : 0x10000000A\r\n>>")


def test_fixed_mc405_line_without_cr_grows_without_bound() -> None:
    """MEDIUM (memory). The 1024-character line limit is checked only at CR: a host that
    never sends CR makes the line buffer grow by every byte (150 MB sent to `maxk serve`:
    VmRSS +140 MB). Expected: bounded, the line refused when it ends (as the MAXk's lexer
    cuts at 256 and the MM4005 at 111)."""
    fed = Fed("MC405")

    def flood() -> None:
        for _ in range(64):
            fed.session.feed(b"A" * 65536)
            fed.session.read()  # the host reads its echo

    retained = retained_bytes(flood)
    reply = fed(b"")
    assert b"%[COMMAND LINE] - Line too long" in reply
    assert retained < 256 * 1024, f"{retained / 1e6:.1f} MB held for one line"


def test_holds_mc405_over_long_line_is_an_error_and_nothing_runs() -> None:
    fed = Fed("MC405")
    reply = fed("VR(1)=5:" * 200)
    assert b"%[COMMAND LINE] - Line too long\r\n" in reply and reply.endswith(TRIO_TRAILER)
    assert trio_output(fed("?VR(1)")) == b"0.0000\r\n"  # a VR is FLOAT


def test_holds_mc405_telnet_nul_and_every_split(three: HostedBoards) -> None:
    """The reference's `?1+1` exchange, with IAC DO/WILL/WONT, an IAC SB ... IAC SE
    subnegotiation and NUL bytes mixed in, one byte per write: the reply is exactly the
    reference's bytes."""
    noise = b"\xff\xfd\x01\xff\xfb\x03\x00\xff\xfa\x18\x00xterm\xff\xf0\xff\xfc\x22"
    sent = noise[:6] + b"?1" + noise[6:] + b"+1\r\x00\n"
    with _connect(three.ports[2]) as sock:
        for byte in sent:
            sock.sendall(bytes([byte]))
        got = _recv_until(sock, lambda d: d.endswith(TRIO_TRAILER))
    assert got == b"?1+1\r\n2\r\n" + TRIO_TRAILER


@pytest.mark.parametrize(("line", "output"), [
    ("?1e308*10", b"%[COMMAND LINE] - Arithmetic error\r\n"),
    ("?1/0", b"%[COMMAND LINE] - Divide by zero\r\n"),
    ("?SQR(-1)", b"%[COMMAND LINE] - Parameter out of range\r\n"),
    ("?LN(0)", b"%[COMMAND LINE] - Parameter out of range\r\n"),
    ("?1e999", b"%[COMMAND LINE] - Arithmetic error\r\n"),
    ("?$FFFFFFFFFFFFFFFFF", b"%[COMMAND LINE] - Arithmetic error\r\n"),
    ("TABLE(1e9,1)", b"%[COMMAND LINE] - TABLE index out of range\r\n"),
    ("VR(-1)=1", b"%[COMMAND LINE] - Parameter out of range\r\n"),
    ("MOVE(1) AXIS(16)", b"%[COMMAND LINE] - Invalid axis number\r\n"),
    ("WHILE 1", b"%[COMMAND LINE] - Structure error\r\n"),
    ('RUN "NOPE"', b"%[COMMAND LINE] - Program not found\r\n"),
    ("!P,99999999999R?1", b"%[COMMAND LINE] - Program not found\r\n"),
])
def test_holds_mc405_extreme_expressions_are_error_lines(line: str, output: bytes) -> None:
    fed = Fed("MC405")
    assert trio_output(fed(line)) == output
    assert trio_output(fed("?DPOS:?IDLE:?VR(1)")) == b"0\r\n-1\r\n0.0000\r\n"


def test_holds_mc405_move_beyond_what_a_double_counts_is_refused() -> None:
    """A move of 1e300 counts (or to beyond 2^53 counts) is out of range, as a path of
    such moves overflowed; a move just inside runs and cancels."""
    fed = Fed("MC405")
    assert trio_output(fed("SPEED=1000:MOVE(1e300)")) == (
        b"%[COMMAND LINE] - Parameter out of range\r\n")
    assert trio_output(fed("?IDLE:?DPOS")) == b"-1\r\n0\r\n"
    assert trio_output(fed("MOVE(2^53-1)")) == b""
    fed.advance(1000)
    assert trio_output(fed("?IDLE:?VP_SPEED")) == b"0\r\n1000\r\n"
    fed("RAPIDSTOP")
    fed.advance(2000)
    assert trio_output(fed("?IDLE")) == b"-1\r\n"


def test_fixed_mc405_gate_edge_log_grows_for_ever() -> None:
    """LOW (memory over time). Every gate toggle is appended to `gate_edges` (the `:gates`
    REPL word) and never dropped: the seed's own example 3 (an endless REPEAT of gated
    moves) grows the server by about 650 bytes per second of running, 56 MB a day, with
    no host doing anything. Expected: a bounded log (the newest N edges)."""
    from maxk.controllers.trio.controller import MC405
    from maxk.personalities.trio.pwm_link import GATE_LOG
    from tests.trio_helpers import EXAMPLE_3

    trio = MC405()
    assert trio.load("EX3", EXAMPLE_3) == []
    assert trio.send('RUN "EX3"') == []
    trio.advance(400)  # the log is full (about 3.7 edges a second)
    assert len(trio.machine.gate_edges) == GATE_LOG
    newest = trio.machine.gate_edges[-1].tick
    tracemalloc.start()  # traced from here: the edges that replace the old ones, then
    trio.advance(300)  # the edges that replace those: they cost nothing more
    gc.collect()
    before = tracemalloc.take_snapshot()
    trio.advance(300)
    gc.collect()
    after = tracemalloc.take_snapshot()
    tracemalloc.stop()
    retained = sum(stat.size_diff for stat in after.compare_to(before, "filename"))
    assert retained < 16 * 1024, f"{retained / 1e3:.0f} KB more after 300 s of example 3"
    assert len(trio.machine.gate_edges) == GATE_LOG
    assert trio.machine.gate_edges[0].tick > newest  # the log holds the newest edges


def _bytes_written() -> int:
    """Bytes this process has written through write() so far (Linux /proc/self/io)."""
    for line in Path("/proc/self/io").read_text().splitlines():
        if line.startswith("wchar:"):
            return int(line.split()[1])
    raise AssertionError("no wchar in /proc/self/io")


def test_fixed_mc405_program_upload_rewrites_the_whole_program_per_line(tmp_path) -> None:
    """LOW (I/O, event loop). With a program store on disk (what `maxk serve` gives
    every MC405 unless --no-archive), each `!NAME,nR` line atrio sends rewrites the whole
    program file and the index: uploading n lines writes O(n^2) bytes, synchronously on
    the server's one event loop (1,000 lines of 100 characters: 1.8 s; 4,000: 11.4 s).
    A 150 KB program here writes about 100 MB. Expected: about the program's size."""
    from maxk.controllers.trio.controller import MC405

    trio = MC405(archive=tmp_path / "MC405-board1.params.json")
    session = trio.open_session()
    session.feed(b'SELECT "BIG",0\r\n')
    text = "a=a+1 '" + "x" * 93
    before = _bytes_written()
    for n in range(1500):
        session.feed(f"!BIG,{n}R{text}\r\n".encode())
        session.read()
    written = _bytes_written() - before
    assert trio.programs.source_size("BIG") == 1500 * 101
    assert written < 16 * 1024 * 1024, f"{written / 1e6:.0f} MB written for 150 KB"
    session.feed(b"!BIG,3R' changed\r\n!BIG,0D\r\n")  # edits inside rewrite the file
    again = MC405(archive=tmp_path / "MC405-board1.params.json")  # the store, read back
    assert again.programs.source_size("BIG") == 1498 * 101 + len("' changed\n")
    assert again.programs.checksum("BIG") == trio.programs.checksum("BIG")


def _upload(host: socket.socket, name: str, lines: list[str]) -> None:
    for command in [f'SELECT "{name}",0', *(f"!{name},{n}R{t}" for n, t in enumerate(lines)),
                    "COMPILE", f'RUN "{name}"']:
        host.sendall(command.encode() + b"\r\n")
        got = _recv_until(host, lambda d: d.endswith(TRIO_TRAILER))
        assert b"%[" not in got, got


def test_fixed_mc405_reply_after_a_wait_is_dropped_for_a_slow_reader(three: HostedBoards
                                                                       ) -> None:
    """MEDIUM (a reply dropped). What a session says through `notify` is sent as a
    droppable notification, lost once 1 MiB waits unsent; on the MC405 that is not only a
    program's PRINT but the prompt after a WA/WAIT IDLE and the replies of every line held
    behind it. A host that reads slowly while a program prints (here: `WA(8000)` then
    `?7`, and a PRINT loop of 900 characters a cycle) never gets `?7`'s reply; a host that
    reads gets it, and so does a slow one when the program prints little."""
    loader = _connect(three.ports[2])
    slow = socket.socket()
    slow.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    slow.connect(("127.0.0.1", three.ports[2]))
    slow.sendall(b"WA(8000)\r\n?7\r\n")
    _recv_until(slow, _ends_with(b"WA(8000)\r\n"))
    _upload(loader, "TALK", ["WHILE 1", 'PRINT "' + "x" * 900 + '"', "WEND"])
    for _ in range(100):
        three.advance(0.1)
        _drain(loader)  # the loader reads what it hears
    loader.sendall(b"HALT\r\n")
    _recv_until(loader, _ends_with(TRIO_TRAILER))
    three.advance(0.1)
    got = _recv_until(slow, lambda d: b"?7\r\n7\r\n" in d)
    for sock in (loader, slow):
        sock.close()
    assert b"?7\r\n7\r\n" in got, f"{len(got)} bytes, no reply to ?7"


def test_holds_mc405_infinite_loops_while_others_poll(three: HostedBoards) -> None:
    """A busy loop and a PRINT loop run on the MC405 while a third host never reads: a
    poller on the MC405 gets every answer, the loop counts one pass per servo cycle, and
    the MAXk and MM4005 answer."""
    loader = _connect(three.ports[2])
    deaf = _connect(three.ports[2])  # never reads: the PRINT loop's output piles up there
    _upload(loader, "SPIN", ["WHILE 1", "VR(1)=VR(1)+1", "WEND"])
    _upload(loader, "TALK", ["WHILE 1", 'PRINT "' + "x" * 100 + '"', "WEND"])
    poller = _connect(three.ports[2])
    seen = []
    for _ in range(20):
        three.advance(0.05)
        poller.sendall(b"?VR(1)\r\n")
        got = _recv_until(poller, lambda d: b"?VR(1)\r\n" in d
                          and d.split(b"?VR(1)\r\n")[-1].endswith(TRIO_TRAILER))
        value = got.split(b"?VR(1)\r\n")[-1].split(b"\r\n")[0]
        seen.append(int(float(value)))
    assert seen == sorted(seen) and abs(seen[-1] - seen[0] - 19 * 50) <= 1, seen
    answers = everyone_answers(three)
    assert answers["MAXk-8000"].startswith(b"MAXk-8000")
    assert answers["MM4005"] == b"VE MM4005 Version 2.42\r"
    loader.sendall(b"HALT\r\n")
    for sock in (loader, deaf, poller):
        sock.close()


# =========================================================================================
# every controller of one server
# =========================================================================================

def test_holds_a_hundred_clients_each_split_anywhere(three: HostedBoards) -> None:
    """100 hosts per controller (300 at once), 100 pipelined queries each, written in
    random pieces (every fourth host one byte per write): every host gets exactly its 100
    replies, nothing dropped, nothing duplicated, nothing from another host."""
    per_client = 100
    results: dict[tuple[str, int], bytes] = {}

    def host(model: str, port: int, index: int) -> None:
        query, end = QUERIES[model]
        rnd = random.Random(index)
        data = query * per_client
        with _connect(port) as sock:
            at = 0
            while at < len(data):
                step = 1 if index % 4 == 0 else rnd.randint(1, 300)
                sock.sendall(data[at:at + step])
                at += step
            results[(model, index)] = _recv_until(
                sock, lambda d: d.count(end) >= per_client, timeout=60)

    threads = [threading.Thread(target=host, args=(model, port, i))
               for model, port in zip(MODELS, three.ports, strict=True) for i in range(100)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(90)
    expected = {
        "MAXk-8000": b"MAXk-8000, ver:1.33, S/N: 000001, FPGA:20\n\r",
        "MM4005": b"VE MM4005 Version 2.42\r",
        "MC405": b"?VERSION\r\n2.0299\r\n" + TRIO_TRAILER,
    }
    wrong = [key for key, got in results.items() if got != expected[key[0]] * per_client]
    assert len(results) == 300 and not wrong, wrong[:5]


def test_holds_reconnect_storm_and_disconnects_mid_command(three: HostedBoards) -> None:
    """300 connections per controller, each leaving half a command (a Trio one leaves a
    waiting WA and lines behind it), half of them closed with a reset: every controller
    still answers, and a half command never leaks into another host's line."""
    halves = {"MAXk-8000": [b"AX;MA10", b"AX;VL500", b"#W"],
              "MM4005": [b"1PA0.", b"VE", b"1TP;2T"],
              "MC405": [b"?1+", b"MOVE(1", b"\xff\xfa\x18", b"WA(100000)\r\n?1\r\n"]}
    rnd = random.Random(7)
    for i in range(300):
        for model, port in zip(MODELS, three.ports, strict=True):
            sock = _connect(port)
            sock.sendall(rnd.choice(halves[model]))
            if i % 2:
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
            sock.close()
    answers = everyone_answers(three)
    assert answers == {"MAXk-8000": b"MAXk-8000, ver:1.33, S/N: 000001, FPGA:20\n\r",
                       "MM4005": b"VE MM4005 Version 2.42\r",
                       "MC405": b"?VERSION\r\n2.0299\r\n" + TRIO_TRAILER}
    with _connect(three.ports[1]) as sock:
        sock.sendall(b"1TP;1DP\r")
        assert _recv_until(sock, lambda d: d.count(b"\r") >= 2) == b"1TP0.0000\r1DP0.0000\r"


def _session_storm(model: str, half: bytes) -> int:
    """Bytes a controller still holds after 5,000 hosts came, sent half a command, left."""
    controller = build(model)

    def storm() -> None:
        for _ in range(5000):
            session = controller.open_session(notify=lambda: None)
            session.feed(half)
            session.close()
        controller.engine.advance(10)

    storm()  # warm caches first
    return retained_bytes(storm)


def test_fixed_maxk_keeps_every_closed_session() -> None:
    """LOW-MEDIUM (memory). `MAXk.open_session` appends every session to `_sessions`,
    pruned only by reset(): each connection ever made keeps its session, interpreter and
    lexer (about 200 bytes: 1.9 MB per 10,000 connections); a host reconnecting in a loop
    grows the server without bound."""
    retained = _session_storm("MAXk-8000", b"AX;MA10")
    assert retained < 100 * 1024, f"{retained / 1e6:.1f} MB kept for 5,000 closed sessions"


@pytest.mark.parametrize(("model", "half"), [("MM4005", b"1PA0."), ("MC405", b"?1+"),
                                             ("MC405", b"WA(100000)\r\n?1\r\n")])
def test_holds_closed_sessions_are_forgotten(model: str, half: bytes) -> None:
    assert _session_storm(model, half) < 100 * 1024


# ---- hypothesis: the sessions in-process ----------------------------------------------
MM_MNEMONICS = ["TP", "TH", "DP", "MS", "TE", "TB", "VE", "TU", "TC", "XH", "TL", "TR",
                "VA", "AC", "PA", "PR", "ST", "OR", "SH", "DH", "SL", "SR", "MO", "MF", "NT",
                "FA", "AD", "AX", "AY", "LX", "LY", "MX", "MY", "CR", "CA", "CX", "CY", "EL",
                "AT", "LT", "XA", "XE", "XT", "XU", "XV", "VV", "VS", "ET", "NB", "NE", "NI",
                "NN", "NS"]
MODERATE = ["", "?", "0", "1", "-1", "2.5", "10", "-10", "90", "-90", "360", "0.001",
            "100", "-100", "3", "0.5", "1e-3", "99"]
EXTREME = ["1e300", "-1e300", "1e-300", "5e-324", "1e999", "-1e999", "1e20"]


def _mm_lines(values: list[str]) -> st.SearchStrategy[list[str]]:
    command = st.builds(lambda a, m, v: a + m + v, st.sampled_from(["", "1", "2", "3", "4"]),
                        st.sampled_from(MM_MNEMONICS), st.sampled_from(values))
    return st.lists(st.lists(command, min_size=1, max_size=3).map(";".join),
                    min_size=1, max_size=25)


def _run_mm(lines: list[str], ticks: list[int]) -> None:
    fed = Fed("MM4005")
    for line, advance in zip(lines, ticks, strict=False):
        fed.advance(advance)
        fed(line)
    fed.advance(200_000)
    reply = mm_reply(fed, "MS;TP;TE")
    assert re.fullmatch(r"1MS.,2MS.,3MS.,4MS.\r1TP\S+,2TP\S+,3TP\S+,4TP\S+\rTE.\r", reply)


_TICKS = st.lists(st.sampled_from([0, 1, 10, 1000, 100_000]), min_size=25, max_size=25)
_FUZZ = settings(max_examples=300, deadline=None, derandomize=True,
                 suppress_health_check=[HealthCheck.too_slow])


@_FUZZ
@given(_mm_lines(MODERATE), _TICKS)
def test_holds_mm4005_session_fuzz_with_moderate_operands(lines, ticks) -> None:
    _run_mm(lines, ticks)


def _mm_extreme_lines() -> st.SearchStrategy[list[str]]:
    """A setting to an extreme value, or an action that uses the settings."""
    axis = st.sampled_from(["", "1", "2"])
    setting = st.builds(lambda a, m, v: a + m + v, axis,
                        st.sampled_from(["VA", "AC", "SH", "SL", "SR", "VV", "VS", "NI",
                                         "CR", "LX", "LY", "CA"]),
                        st.sampled_from(["1", "10", *EXTREME]))
    action = st.builds(lambda a, m: a + m, axis,
                       st.sampled_from(["OR", "OR1", "ET", "ST", "DH", "PA1", "PR-1", "NS",
                                        "NB1;NE2;NN5"]))
    return st.lists(st.one_of(setting, action), min_size=1, max_size=25)


@_FUZZ
@given(_mm_extreme_lines(), _TICKS)
def test_fixed_mm4005_session_fuzz_with_extreme_operands(lines, ticks) -> None:
    """Fails with an exception out of the session or the engine (see the tests above)."""
    _run_mm(lines, ticks)


_TRIO_NUMBERS = ["0", "1", "-1", "2", "0.5", "16", "1000", "-5", "3", "512"]
_TRIO_OPERATORS = ["+", "-", "*", "/", " MOD ", " AND "]  # "^": see the complex power test
_TRIO_EXTREME = ["1e306", "1e300", "1e-320", "5e-324", "$7FFFFFFFFFFFFFFF", "-1e308"]


def _trio_lines(numbers: list[str], operators: list[str]) -> st.SearchStrategy[list[str]]:
    n = st.sampled_from(numbers)
    expr = st.recursive(n, lambda inner: st.one_of(
        st.tuples(inner, st.sampled_from(operators), inner)
        .map(lambda t: f"({t[0]}{t[1]}{t[2]})"),
        st.tuples(st.sampled_from(["ABS", "INT", "SQR", "SIN", "EXP", "LN"]), inner)
        .map(lambda t: f"{t[0]}({t[1]})")), max_leaves=4)
    axis = st.sampled_from(["", " AXIS(0)", " AXIS(1)", " AXIS(4)", " AXIS(15)"])
    stmt = st.one_of(
        expr.map(lambda e: "?" + e),
        st.tuples(st.sampled_from(["SPEED", "ACCEL", "DECEL", "UNITS", "MERGE", "PWM_CYCLE",
                                   "PWM_MARK"]), axis, expr).map(lambda t: f"{t[0]}{t[1]}={t[2]}"),
        st.tuples(st.sampled_from(["MOVE", "MOVEABS", "DEFPOS"]),
                  st.lists(expr, min_size=1, max_size=3), axis)
        .map(lambda t: f"{t[0]}({','.join(t[1])}){t[2]}"),
        st.tuples(st.sampled_from(["CONNPATH", "CAMBOX", "PWM_CONTROL", "TABLE"]),
                  st.lists(expr, min_size=1, max_size=5), axis)
        .map(lambda t: f"{t[0]}({','.join(t[1])}){t[2]}"),
        expr.map(lambda e: f"WA({e})"),
        expr.map(lambda e: f"VR(3)={e}"),
        st.sampled_from(["CANCEL", "RAPIDSTOP", "BASE(0,1)", "BASE(1,0)", "WDOG=ON"]))
    return st.lists(st.lists(stmt, min_size=1, max_size=3).map(":".join),
                    min_size=1, max_size=20)


def _run_trio(lines: list[str], ticks: list[int]) -> None:
    fed = Fed("MC405")
    for line, advance in zip(lines, ticks, strict=False):
        fed.advance(advance)
        fed.session.feed(line.encode() + b"\r\n")
        fed.session.read()
    fed.advance(200_000)
    for _ in range(len(lines) * 3):  # a console's break for each statement still waiting
        fed.session.abandon()  # (a move behind a CONNPATH link waits for ever, by design)
    fed.session.read()
    assert trio_output(fed("RAPIDSTOP:?1+1")) == b"2\r\n"


@_FUZZ
@given(_trio_lines(_TRIO_NUMBERS, _TRIO_OPERATORS), _TICKS)
def test_holds_mc405_session_fuzz_with_moderate_operands(lines, ticks) -> None:
    _run_trio(lines, ticks)


@_FUZZ
@given(_trio_lines(_TRIO_NUMBERS + _TRIO_EXTREME, [*_TRIO_OPERATORS, "^"]), _TICKS)
def test_fixed_mc405_session_fuzz_with_extreme_operands(lines, ticks) -> None:
    """Fails with an exception out of the command line (see the tests above)."""
    _run_trio(lines, ticks)


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.sampled_from(MODELS), st.lists(st.binary(max_size=64), min_size=1, max_size=40))
def test_holds_random_bytes_never_raise(model: str, chunks: list[bytes]) -> None:
    """Raw random bytes (NUL, IAC, 8-bit, CR/LF anywhere) into each session."""
    fed = Fed(model)
    for chunk in chunks:
        fed.session.feed(chunk)
        fed.session.read()
        fed.advance(7)


# ---- the REPL, scripts and `maxk serve` as processes -------------------------------------
def _maxk(*args: str, stdin: str = "", timeout: float = 60) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "maxk", *args], input=stdin, text=True,
                          capture_output=True, timeout=timeout, cwd=ROOT,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})


@pytest.mark.parametrize(("model", "stdin", "expected"), [
    ("MM4005", "1SL-1e999\n1SR1e999\n1PA1e999\nVE\n", "VE MM4005 Version 2.42"),
    ("MM4005", "2VA1e300\n2OR0\nMS\nVE\n", "VE MM4005 Version 2.42"),
    ("MC405", "?(-2)^0.5\n?1+1\n", "2"),
    ("MC405", "WA(1e306)\n?1+1\n", "2"),
])
def test_fixed_repl_dies_on_a_bad_line(model: str, stdin: str, expected: str) -> None:
    """HIGH (REPL). The exceptions above end the piped REPL with a traceback; the lines
    after the bad one never run."""
    result = _maxk("--model", model, "--manual-time", "--no-archive", stdin=stdin)
    assert "Traceback" not in result.stderr, result.stderr[-600:]
    assert expected in result.stdout.splitlines()


@pytest.mark.parametrize(("board", "lines"), [
    ("MM4005", ["3SH1e999;3OR", "@wait 10 s", "VE", "< VE MM4005 Version 2.42"]),
    ("MC405", ["SPEED=1e-320", "MOVE(5)", "?1+1", "< 2"]),
])
def test_fixed_maxk_run_dies_on_a_bad_line(tmp_path, board: str, lines: list[str]) -> None:
    """HIGH (scripts). The same exceptions end `maxk run` with a traceback."""
    script = tmp_path / "bad.maxk"
    script.write_text("\n".join([f"@board {board}", *lines]) + "\n")
    result = _maxk("run", str(script))
    assert "Traceback" not in result.stderr, result.stderr[-600:]
    assert result.returncode in (0, 1)


@pytest.mark.parametrize(("model", "stdin"), [
    ("MM4005", ":pulses-csv /nonexistent/dir/p.csv\nVE\n"),
    ("MC405", ":trace\n:trace /nonexistent/dir/t.csv\n?1+1\n"),
])
def test_fixed_repl_dies_when_a_file_word_cannot_write(model: str, stdin: str) -> None:
    """LOW (REPL). `:pulses-csv FILE` (MM4005) and `:trace FILE` (MC405) let an OSError
    out: a typo in a path ends the REPL with a traceback. `:advance`, `:run` and `help`
    answer bad input with a message (see the guard below)."""
    result = _maxk("--model", model, "--manual-time", "--no-archive", stdin=stdin)
    assert "Traceback" not in result.stderr, result.stderr[-400:]
    assert result.stdout.splitlines()[-1] in ("VE MM4005 Version 2.42", "2")


@pytest.mark.parametrize("model", MODELS)
def test_holds_repl_words_refuse_bad_durations(model: str) -> None:
    stdin = ":advance nan\n:advance inf s\n:advance -1 s\n:run 1e400\nhelp \x00\n:time\n"
    result = _maxk("--model", model, "--manual-time", "--no-archive", stdin=stdin)
    assert result.returncode == 0 and "Traceback" not in result.stderr
    assert result.stdout.count("not a duration") == 4
    assert result.stdout.splitlines()[-1].startswith("tick 0, 0.000000 s virtual")


@pytest.mark.parametrize("board", ["MM4005", "MC405"])
@pytest.mark.parametrize(("body", "code"), [("@expect X position 5", 2),  # no axis X there
                                            ("@world X limits 5 -5", 2),  # (refused read)
                                            ("@wait 1e400 s", 2), ("< stray", 2),
                                            ("@wait until idle", 0)])
def test_holds_maxk_run_refuses_bad_directives(tmp_path, board: str, body: str,
                                               code: int) -> None:
    script = tmp_path / "s.maxk"
    script.write_text(f"@board {board}\n{body}\n")
    result = _maxk("run", str(script))
    assert result.returncode == code and "Traceback" not in result.stderr


def test_fixed_repl_prints_the_echo_of_a_line_with_nul() -> None:
    """LOW (REPL, MC405). The console strips the echo by searching for the typed line; the
    session drops NUL (telnet), so the echo differs and is printed as output: `?1<NUL>+1`
    prints `?1+1` and then `2`."""
    result = _maxk("--model", "MC405", "--manual-time", "--no-archive", stdin="?1\x00+1\n")
    assert result.stdout.splitlines()[-1:] == ["2"]
    assert "?1+1" not in result.stdout


def test_fixed_serve_hostile_catalogue_leaves_tracebacks_and_silence() -> None:
    """End to end against `maxk serve --model MAXk-8000,MM4005,MC405 --no-archive`: the
    catalogue of hostile lines above, then a poll of each controller. Expected: no
    traceback on stderr, every controller answers."""
    proc = subprocess.Popen([sys.executable, "-m", "maxk", "serve", "--model",
                             "MAXk-8000,MM4005,MC405", "--no-archive", "--seconds", "60"],
                            cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)},
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None
        ports = [int(proc.stdout.readline().rsplit(":", 1)[1]) for _ in MODELS]
        hostile = {1: [b"1SL-1e999;1SR1e999\r1PA1e999\r", b"4SH1e999;4OR\r",
                       b"2VA1e300;2OR0\r"],
                   2: [b"WA(1e306)\r\n", b"?(-2)^0.5\r\n", b"SPEED=1e-320:MOVE(5)\r\n"]}
        for index, packets in hostile.items():
            with _connect(ports[index]) as sock:
                for packet in packets:
                    sock.sendall(packet)
                    _recv_until(sock, _ends_with(b"\x00never"), timeout=0.5)
        answers = {}
        for model, port in zip(MODELS, ports, strict=True):
            query, end = QUERIES[model]
            query = b"MS;\r" if model == "MM4005" else query
            end = b"\r" if model == "MM4005" else end
            with _connect(port) as sock:
                sock.sendall(query)
                answers[model] = _recv_until(sock, _ends_with(end))
    finally:
        proc.terminate()
        _, stderr = proc.communicate(timeout=20)
    assert answers["MAXk-8000"].startswith(b"MAXk-8000")
    assert answers["MC405"].endswith(TRIO_TRAILER)
    assert re.fullmatch(rb"1MS.,2MS.,3MS.,4MS.\r", answers["MM4005"]), answers["MM4005"]
    assert "Traceback" not in stderr and "still serving" not in stderr, stderr[-800:]
