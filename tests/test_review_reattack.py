"""A second hostile review of the MM4005 and MC405 doors, aimed at the fixes of the first
(tests/test_review_doors.py): the MC405 session that holds input while a statement waits
(and the door that stops feeding it), held input run 2 KiB a servo cycle, atrio's
line-by-line download that appends to the program file, and the MM4005's lazily computed
ET pulses (`PulsePoints`).

``test_fixed_...`` reproduces a defect (its docstring: severity, what goes wrong, what is
expected); ``test_holds_...`` guards what held under attack. Door tests use `maxk serve`'s
server in-process with a manual clock (tests/hosting.py); receive timeouts are liveness
bounds only, returning as soon as what is awaited has come.

Every defect it reproduced is fixed; the ``test_fixed_...`` tests guard the fixes.
"""

from __future__ import annotations

import math
import re
import socket
import time
from collections.abc import Sequence
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxk.commands.trio.programs import ProgramStore
from maxk.controllers.registry import build
from maxk.host.server import HARD_LIMIT
from maxk.personalities.mm4005.geometry import Arc, Geometry, Line
from maxk.personalities.mm4005.pulses import PulsePoint, pulse_points
from tests.hosting import HostedBoards
from tests.test_mm4005_doors import MODEL2_INIT, CrHost, _model2_poll, _replay
from tests.test_review_doors import (
    TRIO_TRAILER,
    Fed,
    _connect,
    _drain,
    _ends_with,
    _recv_until,
    _upload,
    mm_reply,
    retained_bytes,
    trio_output,
)
from tests.test_trio_doors import TrioHost

PROMPTED = b">>\nControl char : 0x10000000A\r\n>>"  # the prompt after a command line


@pytest.fixture
def trio():
    boards = HostedBoards(models=("MC405",))
    yield boards
    boards.close()


def _client_of(boards: HostedBoards, before: set) -> object:
    """The server's client for the connection made since `before` was taken."""
    service = boards.services[0]
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        new = boards.call(lambda: set(service.clients) - before)
        if new:
            return new.pop()
    raise AssertionError("the server never saw the connection")


def _hung_up(boards: HostedBoards, client: object) -> None:
    """Wait (a liveness bound) until the server has seen the host hang up."""
    deadline = time.monotonic() + 10
    while boards.call(lambda: client.transport is not None):  # type: ignore[attr-defined]
        assert time.monotonic() < deadline, "the hang-up never reached the server"
        time.sleep(0.01)


def _dpos(boards: HostedBoards, axis: int) -> bytes:
    with _connect(boards.ports[0]) as sock:
        sock.sendall(f"?DPOS AXIS({axis})\r\n".encode())
        got = _recv_until(sock, _ends_with(TRIO_TRAILER), 10)
    return got.split(b"\r\n")[1]


# =========================================================================================
# MC405: a session that holds input
# =========================================================================================

def test_fixed_mc405_ex_held_behind_a_wait_loses_every_reply_before_it(
        trio: HostedBoards) -> None:
    """HIGH (replies dropped, host stalls). A host pipelines `WA(10)`, `?5` and `EX` in
    one write. When the wait ends, the held input runs inside the servo cycle; `EX`
    closes the session, and `resume` notifies only a session that is not closed: the WA's
    prompt, `?5`'s reply `5` and EX's echo stay in the closed session and never reach the
    host (it gets nothing at all after `WA(10)\\r\\n`). Sent as separate writes (the
    door's inbox holds `?5`, EX runs from the door), the same bytes are all answered.
    Expected: what ran before EX is answered in both cases, and EX is echoed."""
    expected = PROMPTED + b"?5\r\n5\r\n" + PROMPTED + b"EX\r\n"
    with _connect(trio.ports[0]) as sock:
        sock.sendall(b"WA(10)\r\n?5\r\nEX\r\n")
        assert _recv_until(sock, _ends_with(b"WA(10)\r\n")) == b"WA(10)\r\n"
        trio.advance(0.05)
        got = _recv_until(sock, _ends_with(b"EX\r\n"), 5)
    assert got == expected


def test_holds_mc405_ex_behind_a_wait_in_separate_writes(trio: HostedBoards) -> None:
    """The same lines in three writes: the prompt, `5` and EX's echo all come."""
    with _connect(trio.ports[0]) as sock:
        sock.sendall(b"WA(10)\r\n")
        _recv_until(sock, _ends_with(b"WA(10)\r\n"))
        sock.sendall(b"?5\r\n")
        sock.sendall(b"EX\r\n")
        client = trio.services[0].clients
        deadline = time.monotonic() + 10
        while not trio.call(lambda: any(c.held_input == 8 for c in client)):
            assert time.monotonic() < deadline
            time.sleep(0.01)
        trio.advance(0.05)
        got = _recv_until(sock, _ends_with(b"EX\r\n"))
    assert got == PROMPTED + b"?5\r\n5\r\n" + PROMPTED + b"EX\r\n"


def test_fixed_mc405_hang_up_drops_the_input_the_session_held(trio: HostedBoards) -> None:
    """MEDIUM (a command lost, depending on packet boundaries). The door promises that
    what a host sent before it hung up still runs. A host sends `WA(100)` and
    `MOVE(10)` in one write and hangs up while the WA waits: the MOVE sits in the
    session's own buffer, the door's inbox is empty, so the hang-up closes the session at
    once and the MOVE never runs (DPOS stays 0). Had the MOVE come in a second write (in
    the door's inbox), it runs (see the test below). Expected: the MOVE runs either way."""
    before = trio.call(lambda: set(trio.services[0].clients))
    sock = _connect(trio.ports[0])
    client = _client_of(trio, before)
    sock.sendall(b"WA(100)\r\nMOVE(10)\r\n")
    _recv_until(sock, _ends_with(b"WA(100)\r\n"))
    sock.close()
    _hung_up(trio, client)
    trio.advance(0.2)
    trio.advance(20.0)  # the move at the default SPEED is long over
    assert _dpos(trio, 0) == b"10"


def test_holds_mc405_hang_up_runs_input_the_door_held(trio: HostedBoards) -> None:
    before = trio.call(lambda: set(trio.services[0].clients))
    sock = _connect(trio.ports[0])
    client = _client_of(trio, before)
    sock.sendall(b"WA(100)\r\n")
    _recv_until(sock, _ends_with(b"WA(100)\r\n"))
    sock.sendall(b"MOVE(10)\r\n")
    deadline = time.monotonic() + 10
    while not trio.call(lambda: bool(client.held_input)):  # type: ignore[attr-defined]
        assert time.monotonic() < deadline
        time.sleep(0.01)
    sock.close()
    _hung_up(trio, client)
    trio.advance(0.2)
    trio.advance(20.0)
    assert _dpos(trio, 0) == b"10"


def test_fixed_mc405_input_after_ex_is_kept_for_ever() -> None:
    """MEDIUM (memory). After EX the session is closed and `restart_requested`; it is no
    longer `holding`, so the door goes on feeding it, and `feed` appends every byte to
    `_input`, which nothing ever runs or drops: a host that keeps sending after EX (atrio
    reconnects, but a careless host does not) grows the server by every byte (4 MB fed,
    4 MB kept). Expected: input to a finished session is dropped (or the door closes)."""
    fed = Fed("MC405")
    assert fed("EX") == b"EX\r\n"

    def flood() -> None:
        for _ in range(64):
            fed.session.feed(b"?1\r\n" * 16384)
            fed.session.read()

    retained = retained_bytes(flood)
    assert retained < 256 * 1024, f"{retained / 1e6:.1f} MB kept by a session after EX"


def test_fixed_mc405_program_print_lands_inside_a_held_command_echo() -> None:
    """LOW (a host cannot parse the echo). Held input runs `RESUME_SLICE` (2048) bytes a
    servo cycle, cut wherever the count falls, so a line is split across two cycles and a
    running program's PRINT is written between its halves: `WA(2)` then 2,000 x `?12`
    beside a `PRINT "P"` loop gives `?1P\\r\\n2\\r\\n12\\r\\n` (atrio's parser, which looks for
    the echo of its command, fails on it). Expected: a cycle's slice ends at a line end,
    so every held command's echo, output and prompt stay together."""
    fed = Fed("MC405")
    for line in ('SELECT "TALK",0', "!TALK,0RWHILE 1", '!TALK,1RPRINT "P"', "!TALK,2RWEND",
                 "COMPILE", 'RUN "TALK"'):
        assert b"%[" not in fed(line)
    fed.advance(3)
    fed.session.read()
    fed.session.feed(b"WA(2)\r\n" + b"?12\r\n" * 2000)
    fed.advance(2000)
    out = fed.session.read()
    split = [m.start() for m in re.finditer(rb"\?(?!12\r\n)", out)]
    assert not split, out[split[0] - 10: split[0] + 30]
    assert out.count(b"?12\r\n12\r\n" + PROMPTED) == 2000


def test_fixed_mc405_host_that_never_reads_grows_the_server_by_every_print(
        trio: HostedBoards) -> None:
    """HIGH (memory). Since the first review's fix, what a session says unasked is no
    longer dropped for a host that has not read its last megabyte: it stays in the
    session "until the host reads". On the MC405 that includes every PRINT of every
    running program (each session hears them all), so one telnet host that connects and
    never reads (a stuck or sleeping client, not even hostile) makes its session keep all
    program output for ever: a `PRINT` loop of 900 characters a cycle grows it by 0.9 MB
    per second of controller time, 1.5 MB after 6 s and on without limit. (The door's
    own docstring still says notifications are lost past HARD_LIMIT.) Expected: what a
    deaf host is kept is bounded (program output beyond the limit dropped; replies to
    what it asked may stay, they are bounded by its held input)."""
    service = trio.services[0]
    deaf = socket.socket()
    deaf.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    deaf.connect(("127.0.0.1", trio.ports[0]))
    loader = _connect(trio.ports[0])
    _upload(loader, "TALK", ["WHILE 1", 'PRINT "' + "x" * 900 + '"', "WEND"])

    def kept() -> int:
        return trio.call(lambda: max(len(c.session._out) + c._unsent()
                                     for c in service.clients if c.session is not None))

    for _ in range(120):  # 12 s of controller time: 11 MB printed
        trio.advance(0.1)
        _drain(loader)  # the loader reads what it hears
    held = kept()
    loader.sendall(b"HALT\r\n")
    for sock in (loader, deaf):
        sock.close()
    assert held < 3 * HARD_LIMIT, f"{held / 1e6:.1f} MB kept for a host that never reads"


@pytest.mark.parametrize(("line", "output"), [
    (b"WA(10):?1/0", b"%[COMMAND LINE] - Divide by zero\r\n"),
    (b"WA(10):MOVE(1e300)", b"%[COMMAND LINE] - Parameter out of range\r\n"),
    (b"WA(10):?3", b"3\r\n"),
])
def test_holds_mc405_error_inside_a_waiting_statement_frees_the_door(
        trio: HostedBoards, line: bytes, output: bytes) -> None:
    """A statement that fails after its wait: the error line, the prompt, then the line
    held behind it, all over TCP (the session notifies once it stops holding)."""
    with _connect(trio.ports[0]) as sock:
        sock.sendall(line + b"\r\n?9\r\n")
        _recv_until(sock, _ends_with(line + b"\r\n"))
        trio.advance(0.05)
        got = _recv_until(sock, _ends_with(b"?9\r\n9\r\n" + TRIO_TRAILER))
    assert got == output + PROMPTED + b"?9\r\n9\r\n" + TRIO_TRAILER


def test_holds_mc405_ex_from_another_host_while_one_waits(trio: HostedBoards) -> None:
    """Host B restarts the controller while host A's WA waits with `?5` held: A's wait
    ends, A gets its prompt and `5`, and A's next query is answered."""
    with _connect(trio.ports[0]) as a, _connect(trio.ports[0]) as b:
        a.sendall(b"WA(100)\r\n?5\r\n")
        _recv_until(a, _ends_with(b"WA(100)\r\n"))
        b.sendall(b"EX\r\n")
        assert _recv_until(b, _ends_with(b"EX\r\n")) == b"EX\r\n"
        trio.advance(0.5)
        assert _recv_until(a, _ends_with(b"?5\r\n5\r\n" + TRIO_TRAILER)) == (
            PROMPTED + b"?5\r\n5\r\n" + TRIO_TRAILER)
        a.sendall(b"?6\r\n")
        assert _recv_until(a, _ends_with(TRIO_TRAILER)) == b"?6\r\n6\r\n" + TRIO_TRAILER


def test_holds_mc405_fifty_hosts_each_waiting_with_input_held(trio: HostedBoards) -> None:
    """50 hosts each send `WA(10 i)` and `?i` (held): every host gets its own prompt and
    answer, in order, as its own wait ends, and a host without a wait is answered
    meanwhile."""
    socks = [_connect(trio.ports[0]) for _ in range(50)]
    try:
        for i, sock in enumerate(socks):
            sock.sendall(f"WA({10 * i + 10})\r\n?{i}\r\n".encode())
        for i, sock in enumerate(socks):
            assert _recv_until(sock, _ends_with(f"WA({10 * i + 10})\r\n".encode())
                               ) == f"WA({10 * i + 10})\r\n".encode()
        with _connect(trio.ports[0]) as other:
            other.sendall(b"?77\r\n")
            assert _recv_until(other, _ends_with(TRIO_TRAILER)) == (
                b"?77\r\n77\r\n" + TRIO_TRAILER)
        for _ in range(60):
            trio.advance(0.01)
        for i, sock in enumerate(socks):
            want = PROMPTED + f"?{i}\r\n{i}\r\n".encode() + TRIO_TRAILER
            assert _recv_until(sock, _ends_with(want)) == want, i
    finally:
        for sock in socks:
            sock.close()


def test_holds_mc405_held_backlog_in_order_over_tcp(trio: HostedBoards) -> None:
    """20,000 numbered queries behind a WA, in one stream: every one answered, in order,
    the door's inbox limit respected while the session holds."""
    lines = 20000
    with _connect(trio.ports[0]) as sock:
        sock.sendall(b"WA(50)\r\n")
        _recv_until(sock, _ends_with(b"WA(50)\r\n"))
        sock.sendall(b"".join(f"?{n}\r\n".encode() for n in range(lines)))
        trio.advance(0.1)
        last = f"?{lines - 1}\r\n{lines - 1}\r\n".encode() + TRIO_TRAILER
        got = b""
        for _ in range(200):
            trio.advance(0.01)
            got += _recv_until(sock, lambda d: d.endswith(last) or d.endswith(TRIO_TRAILER),
                               5)
            if got.endswith(last):
                break
    answered = re.findall(rb"\?(\d+)\r\n(\d+)\r\n>>", got)
    assert all(asked == said for asked, said in answered)
    assert [int(asked) for asked, _ in answered] == list(range(lines))


def test_holds_epics_and_atrio_beside_a_holding_session() -> None:
    """The EPICS model 2 exchange (reference mm4005-epics-client.md) byte for byte on the
    MM4005 and atrio's handshake and queries (trio-command-line.md) on the MC405 of the
    same server, while another MC405 host holds a WA with 8 KiB queued behind it."""
    boards = HostedBoards(models=("MM4005-2", "MC405"))
    try:
        holder = _connect(boards.ports[1])
        holder.sendall(b"WA(100000)\r\n" + b"?1\r\n" * 2048)
        _recv_until(holder, _ends_with(b"WA(100000)\r\n"))
        epics = CrHost(boards.ports[0])
        _replay(epics, MODEL2_INIT + _model2_poll(b"1MSD,2MSD\r", b"1TP0.0000,2TP0.0000\r"))
        epics.exchange(b"1AC5.00000;1VA1.00000;1PA2.50000;\r", b"")
        _replay(epics, _model2_poll(b"1MSE,2MSD\r", b"1TP0.0000,2TP0.0000\r"))
        boards.advance(1.0)
        _replay(epics, _model2_poll(b"1MSE,2MSD\r", b"1TP0.9000,2TP0.0000\r"))
        boards.advance(1.7)
        _replay(epics, _model2_poll(b"1MSD,2MSD\r", b"1TP2.5000,2TP0.0000\r"))
        assert b"\n" not in epics.received
        epics.close()
        atrio = TrioHost(boards.ports[1])
        atrio.connect()
        assert atrio.cmd("?1+1") == "2"
        assert atrio.cmd_int("?MPE") == 0
        assert atrio.raw(b"?VERSION") == b"2.0299"
        atrio.close()
        holder.close()
    finally:
        boards.close()


# =========================================================================================
# MC405: program store
# =========================================================================================

def test_fixed_mc405_torn_last_line_glues_onto_the_next_download(tmp_path: Path) -> None:
    """MEDIUM (a program corrupted after a crash). atrio's download now appends each line
    to the program file; a crash in the middle of that write leaves a torn last line
    (`PRI`, no LF). The next start drops it (each line must end in LF), but the next
    appended line is written straight after the torn bytes: the controller lists
    `PRINT 3` while the file, and so the program after the following restart, holds
    `PRIPRINT 3`. (The module still says a crash never leaves a half-written program.)
    Expected: what a restart loads is what the controller had."""
    store = ProgramStore(tmp_path)
    store.create("P", 0)
    for n in range(3):
        store.edit("P", n, "R", f"PRINT {n}")
    with (tmp_path / "P.BAS").open("a", encoding="latin-1") as f:
        f.write("PRI")  # the crash: line 3's write cut short
    after_crash = ProgramStore(tmp_path)
    assert after_crash.lines["P"] == ["PRINT 0", "PRINT 1", "PRINT 2"]
    after_crash.edit("P", 3, "R", "PRINT 3")
    assert ProgramStore(tmp_path).lines["P"] == after_crash.lines["P"]


@pytest.mark.parametrize("edits", [
    [(1, "I", "A"), (0, "D", ""), (2, "R", "B"), (3, "R", "C"), (0, "I", "D")],
    [(3, "D", ""), (3, "R", "E"), (3, "I", "F"), (5, "R", "G")],
])
def test_holds_mc405_edits_in_the_middle_survive_a_reload(tmp_path: Path,
                                                          edits: list) -> None:
    """Inserts, deletes and replacements in the middle mixed with appends: a reload holds
    what the controller had, line for line."""
    store = ProgramStore(tmp_path)
    store.create("P", 0)
    for n in range(4):
        store.edit("P", n, "R", f"L{n}")
    store.set_compiled("P", 10)
    for number, action, text in edits:
        store.edit("P", number, action, text)
        assert ProgramStore(tmp_path).lines["P"] == store.lines["P"]
        assert ProgramStore(tmp_path).info["P"].code_size == 0


def test_fixed_mc405_defpos_walks_around_the_two_to_the_53_limit() -> None:
    """MEDIUM (a position the host cannot read back; a small move refused). The fix
    refuses a move that goes or ends beyond 2^53 counts "so that DPOS can read back where
    the axis is", but it checks the machine's internal counts, while DEFPOS moves the
    frame the host sees. `DEFPOS(9007199254740992)` (or `DEFPOS(1e300)`) is accepted, and
    `MOVE(1)` after it is accepted too, yet DPOS still reads 9007199254740992: the count
    is lost, as the fix meant to prevent. The other way round, after a move to 2^53 and
    `DEFPOS(0)`, DPOS reads 0 and `MOVE(2)` is refused "Parameter out of range".
    Expected: the limit is about positions the host sees: DEFPOS beyond it refused (or
    the moves after it), a two-count move from DPOS 0 accepted."""
    fed = Fed("MC405")
    accepted = [trio_output(fed(line)) == b"" for line in ("DEFPOS(9007199254740992)",
                                                          "MOVE(1)")]
    fed.advance(10_000)
    dpos = trio_output(fed("?DPOS"))
    assert not all(accepted) or dpos == b"9007199254740993\r\n", (accepted, dpos)
    fed = Fed("MC405")
    fed("SPEED=1e15:ACCEL=1e15:DECEL=1e15:MOVEABS(9007199254740992)")
    fed.advance(100_000)
    assert trio_output(fed("DEFPOS(0):?DPOS")) == b"0\r\n"
    assert trio_output(fed("MOVE(2)")) == b""


def test_holds_mc405_download_with_edits_reloads_with_the_same_crc(tmp_path: Path) -> None:
    """atrio's download of 200 lines, then an insert in the middle, a delete of the first,
    a replace of the last and an insert at the end, COMPILE: a new controller on the same
    program directory gives the same EDPROG CRC, LIST and DIR."""
    from maxk.controllers.trio.controller import MC405

    def run(session, line: str) -> bytes:
        session.feed(line.encode() + b"\r\n")
        return trio_output(session.read())

    first = MC405(archive=tmp_path).open_session()
    assert run(first, 'SELECT "DL",0') == b""
    for n in range(200):
        assert run(first, f"!DL,{n}RVR({n})={n}") == b""
    for line in ("!DL,100IPRINT 1", "!DL,0D", "!DL,199RVR(0)=7", "!DL,200IVR(1)=1", "COMPILE"):
        assert run(first, line) == b"", line
    seen = [run(first, line) for line in ('EDPROG"DL",10', 'LIST "DL"', "DIR")]
    again = MC405(archive=tmp_path).open_session()
    assert [run(again, line) for line in ('EDPROG"DL",10', 'LIST "DL"', "DIR")] == seen


@settings(max_examples=100, deadline=None, derandomize=True)
@given(st.lists(st.tuples(st.integers(-1, 8), st.sampled_from("RRID"), st.text("AB1 ",
                                                                              max_size=5)),
                max_size=25))
def test_holds_mc405_any_edits_reload_line_for_line(edits: list) -> None:
    """Any sequence of R/I/D edits (refused ones too): a reload from the directory holds
    exactly the controller's lines after each."""
    import contextlib
    import tempfile

    from maxk.commands.trio.lexer import TrioError

    with tempfile.TemporaryDirectory() as directory:
        store = ProgramStore(directory)
        store.create("P", 0)
        for number, action, text in edits:
            with contextlib.suppress(TrioError):
                store.edit("P", number, action, text)
            assert ProgramStore(directory).lines["P"] == store.lines["P"]


def test_holds_mc405_table_and_vr_extremes() -> None:
    """TABLE and VR at and beyond their ends, with extreme values: an error line or the
    value, never an exception, and the session answers after."""
    fed = Fed("MC405")
    for line in ("TABLE(0,1e308)", "?TABLE(0)", "TABLE(-1,1)", "?TABLE(-1)",
                 "TABLE(1e9,1)", "?TABLE(1e9)", "TABLE(1e300)", "VR(-1)=1", "?VR(1e300)",
                 "VR(0)=1e308*10", "?VR(0)", "VR(1023)=-5e-324", "?VR(1023)", "?VR(1024)",
                 "TABLE(63999,1,2,3)", "?TABLE(64001)", "?VR(NaN)"):
        reply = fed(line)
        assert reply.startswith(line.encode() + b"\r\n"), (line, reply)
        assert reply.endswith(TRIO_TRAILER), (line, reply)
    assert fed("?1") == b"?1\r\n1\r\n" + TRIO_TRAILER


# =========================================================================================
# MM4005: lazily computed pulses, trajectory extremes
# =========================================================================================

def _eager(elements: Sequence[Geometry], start_element: int, end_element: int,
           count: int) -> tuple[PulsePoint, ...]:
    """The pulses as ET computed them before they became lazy (every one at once)."""
    lengths = [g.length for g in elements]
    before = sum(lengths[: start_element - 1])
    cptl = sum(lengths[start_element - 1 : end_element])
    points: list[PulsePoint] = []
    element = start_element
    element_start = before
    for k in range(count):
        s = cptl * k / (count - 1)
        path = before + s
        while element < end_element and path > element_start + lengths[element - 1]:
            element_start += lengths[element - 1]
            element += 1
        geometry = elements[element - 1]
        at = (geometry.end if k == count - 1
              else geometry.point_at(path - element_start))
        points.append(PulsePoint(k, path, s, element, at))
    return tuple(points)


@st.composite
def _paths(draw: st.DrawFn) -> list[Geometry]:
    """Chained lines (zero-length ones too) and arcs (tiny to huge radii and sweeps)."""
    x = y = 0.0
    out: list[Geometry] = []
    for _ in range(draw(st.integers(2, 12))):
        if draw(st.booleans()):
            dx = draw(st.sampled_from([0.0, 1e-9, 1e-3, 0.1, 1.0, 3.0, 1e6]))
            dy = draw(st.sampled_from([0.0, 1e-9, 0.3, 1.0]))
            out.append(Line((x, y), (x + dx, y + dy)))
            x, y = x + dx, y + dy
        else:
            r = draw(st.sampled_from([1e-6, 1e-3, 1.0, 10.0, 1e5]))
            sweep = draw(st.sampled_from([1e-6, 0.5, 90.0, -45.0, 360.0, -270.0]))
            a0 = draw(st.sampled_from([0.0, 30.0, -90.0]))
            c = (x - r * math.cos(math.radians(a0)), y - r * math.sin(math.radians(a0)))
            end = (c[0] + r * math.cos(math.radians(a0 + sweep)),
                   c[1] + r * math.sin(math.radians(a0 + sweep)))
            out.append(Arc(c, r, a0, sweep, (x, y), end))
            x, y = end
    return out


@settings(max_examples=400, deadline=None)
@given(_paths(), st.data())
def test_holds_pulse_points_are_the_eager_points(path: list[Geometry],
                                                 data: st.DataObject) -> None:
    """PulsePoints gives exactly (==, floats bit for bit) the points the eager computation
    gave, for every index, negative indices, any slice, and IndexError just outside."""
    nb = data.draw(st.integers(1, len(path) - 1))
    ne = data.draw(st.integers(nb + 1, len(path)))
    count = data.draw(st.integers(3, 300))
    lazy, eager = pulse_points(path, nb, ne, count), _eager(path, nb, ne, count)
    assert len(lazy) == len(eager) and list(lazy) == list(eager)
    i = data.draw(st.integers(-count, count - 1))
    assert lazy[i] == eager[i]
    bound = st.none() | st.integers(-400, 400)
    cut = slice(data.draw(bound), data.draw(bound),
                data.draw(st.none() | st.integers(-5, 5).filter(bool)))
    assert list(lazy[cut]) == list(eager[cut])
    for outside in (count, -count - 1):
        with pytest.raises(IndexError):
            lazy[outside]


def test_holds_mm4005_two_thousand_tiny_arcs_nn_beyond_mpn_and_st_mid_run() -> None:
    """2,000 arcs of radius 0.001 alternating 90/-90 degrees, NN far beyond the MPN: ET
    substitutes the MPN (P), runs, fires pulses in order, ST stops it mid-run without a
    further pulse after the stop completes, and the controller answers throughout."""
    fed = Fed("MM4005")
    assert mm_reply(fed, "NT;VV10;VS1000;TE") == "TE@\r"
    for i in range(2000):
        assert fed("CR0.001;CA" + ("90" if i % 2 == 0 else "-90")) == b""
    assert mm_reply(fed, "XT;TE") == "XT2000\rTE@\r"
    assert mm_reply(fed, "NB1;NE2000;NN100000000;NS;ET;TE;NN?") == "TEP\rNN628\r"
    engine = fed.controller.engine
    fed.advance(50)
    assert mm_reply(fed, "TE") == "TE@\r"
    fired = len(engine.pulse_log)
    assert 0 < fired < 628
    mm_reply(fed, "ST")
    fed.advance(5000)
    assert mm_reply(fed, "AT;TE;MS") == "AT0\rTE@\r1MSD,2MSD,3MSD,4MSD\r"
    log = engine.pulse_log
    assert [p.index for p in log] == list(range(len(log))) and len(log) < 628
    assert all(math.isfinite(p.x) and math.isfinite(p.y) for p in log)


def test_holds_mm4005_nn_at_mpn_on_a_tiny_arc_path_fires_every_pulse() -> None:
    """NN exactly the MPN over 2,000 tiny arcs: every pulse fires, numbered in order, and
    the last at the end of the path."""
    fed = Fed("MM4005")
    fed("NT;VV10;VS1000")
    for i in range(2000):
        fed("CR0.001;CA" + ("90" if i % 2 == 0 else "-90"))
    assert mm_reply(fed, "NB1;NE2000;NN628;NS;ET;TE") == "TE@\r"
    fed.advance(20000)
    assert mm_reply(fed, "AT;TE") == "AT0\rTE@\r"
    log = fed.controller.engine.pulse_log
    assert [p.index for p in log] == list(range(628))
    assert [p.element for p in log][-1] == 2000


@pytest.mark.parametrize("path", ["LX100", "CR50;CA360", "CR1e-6;CA1e-6;LX1", "LX1e-9;LY50"])
def test_holds_mm4005_trajectory_at_vv_vs_and_ad_extremes(path: str) -> None:
    """VV and VS from the 1e-6 floor to 1e9, AD from 0 to 1e9, on a plain, a full-circle,
    a tiny-arc and a near-zero-line path: ET with pulses runs or is refused with a code,
    ST ends it, and the controller reports no error after."""
    for vv in ("1e-6", "1", "1e6", "1e9"):
        for vs in ("1e-6", "1", "1e9"):
            for ad in ("AD0", "AD1e-6", "AD0.001", "AD180", "AD1e9"):
                fed = Fed("MM4005")
                assert mm_reply(fed, f"NT;VV{vv};VS{vs};TE") == "TE@\r", (vv, vs)
                fed(ad)  # 0.001..10 degrees: the others are refused (C)
                assert mm_reply(fed, "TE") in ("TE@\r", "TEC\r"), ad
                fed(path)  # a corner beyond AD is refused (L)
                assert re.fullmatch(r"TE[@L]\r", mm_reply(fed, "TE")), (vv, vs, ad)
                nb_ne = "NB1;NE2;NN100;NS;" if ";" in path else ""
                fed(nb_ne + "ET")
                reply = mm_reply(fed, "TE")
                assert re.fullmatch(r"TE[@A-Z]\r", reply), (vv, vs, ad, reply)
                fed.advance(1000)
                assert re.fullmatch(r"AT\d+\r1TP-?\d+\.\d{4},2TP-?\d+\.\d{4},3TP0.0000,"
                                    r"4TP0.0000\r", mm_reply(fed, "AT;TP")), (vv, vs, ad)
                fed("ST")
                fed.advance(100_000)
                assert mm_reply(fed, "AT;MS;TE") == "AT0\r1MSD,2MSD,3MSD,4MSD\rTE@\r", (
                    vv, vs, ad)


@pytest.mark.parametrize("rate", ["1e-6", "0.000001", "1.0000001e-6", "1e9"])
def test_holds_mm4005_moves_and_homes_at_the_rate_floor_and_ceiling(rate: str) -> None:
    """VA and AC at the 1e-6 floor (and 1e9): moves, home searches and presets start,
    ST stops them, positions stay numbers and the controller answers."""
    for ac in ("1e-6", "1", "1e9"):
        for op in ("1PA99", "1PR1e-6", "1OR0", "1OR2", "1PA1e9", "1SH5;1DH", "1PA50;2PA-50"):
            fed = Fed("MM4005")
            mm_reply(fed, f"1VA{rate};1AC{ac};2VA{rate};2AC{ac};{op}")
            fed.advance(3000)
            polled = mm_reply(fed, "MS;TP;TE")
            assert "nan" not in polled.lower() and "inf" not in polled.lower(), polled
            fed("1ST;2ST")
            fed.advance(3_000_000)
            assert re.fullmatch(r"1MS[D-d@-z],2MS.,3MSD,4MSD\r.*TE@\r",
                                mm_reply(fed, "MS;TP;TE"), re.DOTALL), (rate, ac, op)


def test_holds_mc405_hosts_gone_behind_a_wait_idle_leave_when_it_ends(
        trio: HostedBoards) -> None:
    """30 hosts each wait on `WAIT IDLE` behind a long move, queue `VR(i)=i+1` in a second
    write and hang up: they stay (what they sent must run) until a CANCEL ends the move;
    then every VR is set and every one of them is gone."""
    service = trio.services[0]
    with _connect(trio.ports[0]) as mover:
        mover.sendall(b"SPEED=1:MOVE(1000000)\r\n")
        _recv_until(mover, _ends_with(TRIO_TRAILER))
        before = trio.call(lambda: set(service.clients))
        gone = []
        for i in range(30):
            sock = _connect(trio.ports[0])
            sock.sendall(b"WAIT IDLE\r\n")
            _recv_until(sock, _ends_with(b"WAIT IDLE\r\n"))
            sock.sendall(f"VR({i})={i + 1}\r\n".encode())
            client = _client_of(trio, before | set(gone))
            deadline = time.monotonic() + 10
            while not trio.call(lambda c=client: bool(c.held_input)):  # type: ignore[attr-defined]
                assert time.monotonic() < deadline
                time.sleep(0.01)
            sock.close()
            gone.append(client)
        for client in gone:
            _hung_up(trio, client)
        trio.advance(1.0)
        assert trio.call(lambda: len(service.clients)) == 31
        mover.sendall(b"CANCEL\r\n")
        _recv_until(mover, _ends_with(b"CANCEL\r\n" + TRIO_TRAILER))
        trio.advance(2.0)
        deadline = time.monotonic() + 10
        while trio.call(lambda: len(service.clients)) != 1:
            assert time.monotonic() < deadline, trio.call(lambda: len(service.clients))
            trio.advance(0.01)
        mover.sendall(b"?VR(0)+VR(29)\r\n")
        assert _recv_until(mover, _ends_with(TRIO_TRAILER)) == (
            b"?VR(0)+VR(29)\r\n31.0000\r\n" + TRIO_TRAILER)


_HELD_LINES = st.one_of(
    st.integers(0, 30).map(lambda n: f"WA({n})"), st.integers(-9, 99999).map(lambda n: f"?{n}"),
    st.just("VR(1)=VR(1)+1"), st.just("?VR(1)"), st.just("WAIT IDLE"), st.just("?1/0"),
    st.just("MOVE(1):WAIT IDLE:?DPOS"), st.integers(0, 3000).map(lambda n: "?VR(2)" + " " * n))


@settings(max_examples=150, deadline=None, derandomize=True)
@given(st.lists(_HELD_LINES, min_size=1, max_size=40), st.data())
def test_holds_mc405_held_input_answers_as_one_line_at_a_time(lines: list[str],
                                                             data: st.DataObject) -> None:
    """Lines sent at once, in any chunks, fed as the door feeds (nothing while the session
    holds) with servo cycles in between, give exactly the bytes the same lines give when
    each is sent after the previous one finished: in order, nothing dropped or doubled."""
    reference = Fed("MC405")
    expected = b""
    for line in lines:
        reference.session.feed(line.encode() + b"\r\n")
        while reference.session.holding:
            reference.advance(1)
        expected += reference.session.read()
    fed = Fed("MC405")
    inbox = bytearray(b"".join(line.encode() + b"\r\n" for line in lines))
    got = b""
    while inbox or fed.session.holding:
        if inbox and not fed.session.holding:
            k = data.draw(st.integers(1, 300))
            fed.session.feed(bytes(inbox[:k]))
            del inbox[:k]
        got += fed.session.read()
        fed.advance(data.draw(st.integers(0, 5)))
    assert got + fed.session.read() == expected


def test_holds_mc405_console_abandons_a_wait_and_goes_on() -> None:
    """The REPL's console gives up a statement that waits past its limit (`WA`, a
    `WAIT IDLE` behind a long move, a WA between two assignments) and answers the next
    line; a host's waiting session beside it does not hold the console up."""
    controller = build("MC405")
    host = controller.open_session(notify=lambda: None)
    host.feed(b"WA(100000000)\r\n?7\r\n")
    assert host.read() == b"WA(100000000)\r\n"
    assert controller.send("WA(100000000)") == ["! still waiting after 600 s: abandoned"]
    assert controller.send("?1") == ["1"]
    assert controller.send("SPEED=1:MOVE(1000000)") == []
    assert controller.send("WAIT IDLE") == ["! still waiting after 600 s: abandoned"]
    assert controller.send("CANCEL:WAIT IDLE:?3") == ["3"]
    assert controller.send("VR(1)=1:WA(100000000):VR(1)=2") == [
        "! still waiting after 600 s: abandoned"]
    assert controller.send("?VR(1)") == ["1.0000"]
