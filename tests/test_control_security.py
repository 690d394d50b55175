"""The control door against hostile use (issue 34), through its real sockets: who may ask
(Host, Origin, content type, token), what a request may say (bad values are 4xx), how
many may connect and how slowly (caps, header deadline, streams let go), the clock's
words (run during a step wins), and a paused board that still answers its hosts and
acts on their stops. The door's own deadlines are set short here; every wait below is a
liveness bound (a loop with a generous limit), never a measurement."""

from __future__ import annotations

import asyncio
import contextlib
import json
import socket
import struct
import threading
import time
from typing import Any

import pytest

from maxk.control import Client, ControlError
from maxk.host.control import ControlDoor
from tests.hosting import HostedBoards
from tests.pokeys_host import Host as PoKeysHost

LIVENESS = 30.0  # seconds a freed slot or a dropped reader may take to show (loaded CI)


class Door:
    """Served boards with a control door on their loop, the door's limits as asked."""

    def __init__(self, models: tuple[str, ...] = ("MAXk-8000",), host: str = "127.0.0.1",
                 **limits: Any) -> None:
        self.boards = HostedBoards(models=models)
        self.door = ControlDoor(self.boards.services, **limits)

        async def start() -> tuple[str, int]:
            return await self.door.start(host, 0)

        self.port = asyncio.run_coroutine_threadsafe(start(), self.boards.loop).result(10)[1]
        self.address = "127.0.0.1" if host in ("0.0.0.0", "127.0.0.1") else host
        self.client = Client(f"http://{self.address}:{self.port}", self.door.token)

    def raw(self, request: bytes) -> tuple[int, bytes]:
        """One HTTP exchange written byte for byte: the status and the body."""
        with socket.create_connection((self.address, self.port), timeout=10) as sock:
            sock.sendall(request)
            data = b""
            while True:
                chunk = sock.recv(65536)
                if not chunk:
                    break
                data += chunk
        head, _, body = data.partition(b"\r\n\r\n")
        return int(head.split(b" ", 2)[1]), body

    def ask(self, method: str, path: str, body: bytes = b"", **headers: str) -> tuple[int, Any]:
        lines = [f"{method} {path} HTTP/1.1", "Connection: close"]
        headers.setdefault("Host", f"{self.address}:{self.port}")
        lines += [f"{k.replace('_', '-')}: {v}" for k, v in headers.items()]
        if body:
            lines.append(f"Content-Length: {len(body)}")
        status, answer = self.raw(("\r\n".join(lines) + "\r\n\r\n").encode() + body)
        try:
            return status, json.loads(answer)
        except ValueError:
            return status, answer

    def close(self) -> None:
        asyncio.run_coroutine_threadsafe(self.door.close(), self.boards.loop).result(10)
        self.boards.close()


@pytest.fixture
def door():
    d = Door(("MAXk-8000", "PoKeys57CNC"))
    yield d
    d.close()


def _until(predicate, message: str, limit: float = LIVENESS) -> None:
    deadline = time.monotonic() + limit
    while not predicate():
        assert time.monotonic() < deadline, message
        time.sleep(0.02)


# ---- who may ask ---------------------------------------------------------------------------
@pytest.mark.parametrize("path", ["/", "/static/panel.js", "/api", "/api/boards/1/traffic",
                                  "/api/stream", "/api/boards/1/trace.csv"])
def test_a_host_header_naming_another_site_is_refused_on_every_route(door: Door,
                                                                     path: str) -> None:
    """A DNS-rebinding page reaches 127.0.0.1 with its own name in Host: nothing answers
    it, reads included (the hosts' traffic above all)."""
    status, body = door.ask("GET", path, Host=f"attacker.example:{door.port}")
    assert status == 421 and "does not name it" in body["error"]
    for name in ("127.0.0.1", "localhost", "LOCALHOST", "[::1]"):
        if path in ("/api/stream", "/api/boards/1/trace.csv"):
            continue  # (a stream never ends; no trace yet: 404) the names are read above
        assert door.ask("GET", path, Host=f"{name}:{door.port}")[0] == 200, name


def test_no_host_header_is_no_door(door: Door) -> None:
    status, _ = door.raw(b"GET /api HTTP/1.0\r\n\r\n")
    assert status == 421
    for host in (f"attacker.example@127.0.0.1:{door.port}", "127.0.0.1/x", "127.0.0.2",
                 "localhost.attacker.example", "127.0.0.1.nip.io"):
        assert door.ask("GET", "/api", Host=host)[0] == 421, host


@pytest.mark.parametrize("kind", ["text/plain", "application/x-www-form-urlencoded",
                                  "multipart/form-data; boundary=x", None])
def test_a_request_that_acts_needs_a_json_content_type(door: Door, kind: str | None) -> None:
    """A page may send text/plain or a form anywhere without asking first: such a body
    never acts, whatever it holds."""
    headers = {} if kind is None else {"Content_Type": kind}
    for path, body in (("/api/clock", b'{"pause": true}'),
                       ("/api/boards/1/world", b'{"words": "X fault plus active"}'),
                       ("/api/boards/1/reset", b"{}")):
        status, answer = door.ask("POST", path, body, **headers)
        assert status == 415 and "application/json" in answer["error"], (path, answer)
    assert door.client.clock()[0]["paused"] is False
    assert door.client.board(1)["axes"][0]["switches"]["plus"]["fault"] is None


def test_a_page_of_another_origin_can_neither_act_nor_read(door: Door) -> None:
    """What a browser sends from a page on another local port: its Origin (or only
    Sec-Fetch-Site on a read) names it, and the door refuses it, reads included."""
    other = "http://127.0.0.1:1"  # another port of the same machine: another origin
    body = b'{"pause": true}'
    status, answer = door.ask("POST", "/api/clock", body, Content_Type="application/json",
                              Origin=other)
    assert status == 403 and other in answer["error"]
    assert door.ask("GET", "/api/boards/1/traffic", Origin=other)[0] == 403
    assert door.ask("GET", "/api/panel", Sec_Fetch_Site="same-site")[0] == 403
    assert door.ask("GET", "/api", Sec_Fetch_Site="cross-site",
                    Sec_Fetch_Mode="cors")[0] == 403
    assert door.ask("DELETE", "/api/boards/1/trace", Origin="null")[0] == 403
    assert door.client.clock()[0]["paused"] is False
    # the door's own page, and a program (no Origin), may
    own = f"http://127.0.0.1:{door.port}"
    assert door.ask("POST", "/api/clock", body, Content_Type="application/json",
                    Origin=own, Sec_Fetch_Site="same-origin")[0] == 200
    assert door.client.clock()[0]["paused"] is True
    assert door.ask("GET", "/", Sec_Fetch_Site="cross-site", Sec_Fetch_Mode="navigate")[0] \
        == 200  # a link to the panel from another page opens it (a read of nothing)


def test_off_loopback_the_token_guards_every_route_and_the_page_carries_it() -> None:
    """Listening on every address (as `--host 0.0.0.0`), reached here through
    127.0.0.1: a token is made, nothing answers without it, and the page links its
    script and style with it (the script carries it on its requests and its stream)."""
    d = Door(host="0.0.0.0")
    try:
        token = d.door.token
        assert token
        for path in ("/", "/static/panel.js", "/static/panel.css", "/api", "/api/stream",
                     "/api/boards/1/trace.csv"):
            status, answer = d.ask("GET", path)
            assert status == 401 and "token" in answer["error"], path
            assert d.ask("GET", path, Authorization="Bearer wrong")[0] == 401
        status, page = d.ask("GET", f"/?token={token}")
        assert status == 200
        text = page.decode()
        assert f'"static/panel.js?token={token}"' in text
        assert f'"static/panel.css?token={token}"' in text
        assert d.ask("GET", f"/static/panel.js?token={token}")[0] == 200
        assert d.ask("GET", f"/static/panel.css?token={token}")[0] == 200
        assert d.client.boards()[0]["model"] == "MAXk-8000"  # the client's Bearer token
        # a name of this machine that is an address literal names a door on every address
        assert d.ask("GET", "/api", Host=f"192.0.2.77:{d.port}",
                     Authorization=f"Bearer {token}")[0] == 200
        assert d.ask("GET", "/api", Host="rebound.example",
                     Authorization=f"Bearer {token}")[0] == 421
    finally:
        d.close()


# ---- what a request may say ----------------------------------------------------------------
@pytest.mark.parametrize("path, body, status, reason", [
    ("/api/clock", {"board": True, "pause": True}, 404, "no board True"),
    ("/api/clock", {"board": 1.0, "pause": True}, 404, "no board 1.0"),
    ("/api/clock", {"speed": 1e-300}, 400, "speed: from 0.001"),
    ("/api/clock", {"speed": 1e300}, 400, "speed: from 0.001"),
    ("/api/clock", {"pause": "yes"}, 400, "pause: true"),
    ("/api/clock", {"ticks": 1.5}, 400, "a whole number"),
    ("/api/boards/1/triggers", {"words": "input 1 high", "when": {"after": "1e308"}}, 400,
     "at most 1e+07 virtual seconds"),
    ("/api/boards/1/triggers", {"words": "input 1 high", "when": {"time": 1e308}}, 400,
     "out of range"),
    ("/api/boards/1/triggers", {"words": "input 1 high", "when": {"tick": 10 ** 400}}, 400,
     "out of range"),
    ("/api/boards/1/triggers", {"words": "input 1 high", "when": {"after": 1e7 + 1}}, 400,
     "at most 1e+07"),
    ("/api/boards/1/triggers", {"words": "input 1 high", "when": {"after": True}}, 400,
     "a number"),
])
def test_bad_values_are_4xx_with_a_reason_and_change_nothing(door: Door, path: str,
                                                            body: dict, status: int,
                                                            reason: str) -> None:
    before = door.client.clock()
    got, answer = door.ask("POST", path, json.dumps(body).encode(),
                           Content_Type="application/json")
    assert got == status and reason in answer["error"], answer
    assert door.client.clock() == before
    assert door.client.triggers(1) == []


@pytest.mark.parametrize("raw, reason", [
    (b"[" * 30_000, "nested too deeply"),
    (b'{"speed": NaN}', "a finite number only"),
    (b'{"speed": Infinity}', "a finite number only"),
    (b'{"speed": 1e999}', "speed: a finite number"),
    (b'{"step": "inf"}', "a finite number"),
])
def test_deep_or_unnumbered_json_is_a_400(door: Door, raw: bytes, reason: str) -> None:
    status, answer = door.ask("POST", "/api/clock", raw, Content_Type="application/json")
    assert status == 400 and reason in answer["error"], answer
    assert door.client.clock()[0]["speed"] == 1.0
    assert door.client.errors() == []  # nothing went wrong inside: no 500, no traceback


# ---- the clock: the latest word wins -------------------------------------------------------
def test_run_said_during_a_long_step_wins(door: Door) -> None:
    """A step of an hour that ticks every tick (an armed position trigger far away) is
    under way when `run` comes: the step ends at its next slice and the board runs."""
    c = door.client
    c.pause()
    c.arm(1, "input 1 high", axis="X", passes=1e9)  # an engine call every tick
    start = c.clock()[0]["tick"]
    stepped: list[Any] = []
    thread = threading.Thread(target=lambda: stepped.append(
        Client(c.url, c.token, timeout=LIVENESS).step(3600.0, board=1)))
    thread.start()
    _until(lambda: c.clock()[0]["tick"] > start, "the step never began")
    c.run(board=1)
    thread.join(LIVENESS)
    assert not thread.is_alive() and stepped, "the step did not end when run came"
    board = c.clock()[0]
    assert board["paused"] is False and board["speed"] == 1.0
    assert board["tick"] < start + 3600 * 8192  # the hour was not stepped whole
    assert c.clock()[1]["paused"] is True  # the other board was not told to run


def test_pause_during_a_step_leaves_the_board_paused(door: Door) -> None:
    c = door.client
    c.speed(2.0, board=1)
    c.step(0.5, board=1)
    board = c.clock()[0]
    assert board["paused"] is True
    c.run(board=1)
    assert c.clock()[0]["speed"] == 2.0  # the speed it had


# ---- how many, how slowly -------------------------------------------------------------------
def _connect(port: int) -> socket.socket:
    sock = socket.create_connection(("127.0.0.1", port), timeout=10)
    return sock


def _closed(sock: socket.socket) -> bool:
    """The door hung up on this socket (what it sent first, e.g. a 503, is read)."""
    sock.setblocking(False)
    try:
        while True:
            data = sock.recv(65536)
            if not data:
                return True
    except BlockingIOError:
        return False
    except OSError:
        return True
    finally:
        sock.setblocking(True)


def test_slow_headers_are_cut_and_the_cap_refuses_the_rest() -> None:
    """8 connections that send half a request hold the door's 8 places; the 9th gets a
    503 at once; the header deadline lets the 8 go and a request is served again."""
    d = Door(connections=8, header_seconds=0.5)
    socks: list[socket.socket] = []
    try:
        for _ in range(8):
            sock = _connect(d.port)
            sock.sendall(b"GET /api HTTP/1.1\r\nHost: 127.0.0.1\r\n")  # and no more
            socks.append(sock)
        _until(lambda: d.boards.call(lambda: d.door.open_connections) == 8,
               "the 8 never connected")
        status, answer = d.raw(b"GET /api HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
        assert status == 503 and "too many connections" in answer.decode()
        assert d.door.refused >= 1
        _until(lambda: all(_closed(s) for s in socks), "slow headers were never cut")
        status, _ = d.ask("GET", "/api")
        assert status == 200
        host = d.boards.connect(1)  # the host's door was never in it
        assert host.query("WY").startswith("MAXk-8000")
    finally:
        for sock in socks:
            sock.close()
        d.close()


def test_a_kept_alive_connection_sending_its_next_request_slowly_is_cut() -> None:
    d = Door(header_seconds=0.5)
    try:
        with _connect(d.port) as sock:
            sock.sendall(b"GET /api HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
            data = b""
            while b'"token_required"' not in data:
                data += sock.recv(65536)
            sock.sendall(b"GET /api HTTP/1.1\r\n")  # the second, never finished
            _until(lambda: _closed(sock), "a slow second request was never cut")
    finally:
        d.close()


def _never_reading(port: int, path: str) -> socket.socket:
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    sock.settimeout(10)
    sock.connect(("127.0.0.1", port))
    sock.sendall(f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n".encode())
    return sock


def test_streams_that_are_never_read_are_let_go_and_the_17th_panel_gets_in() -> None:
    """16 event streams whose readers never read hold every panel place for a moment
    (the 17th: 429); the write deadline lets them go, and a panel gets its place."""
    d = Door(("MAXk-8000", "PoKeys57CNC", "MM4005", "MC405"), stream_hz=500.0,
             write_seconds=0.3)
    socks: list[socket.socket] = []
    try:
        for _ in range(16):
            socks.append(_never_reading(d.port, "/api/stream"))
        _until(lambda: d.boards.call(lambda: d.door._streams) == 16, "16 never streamed")
        with pytest.raises(ControlError, match="at most 16 panels"):
            d.client.request("GET", "/api/stream")
        _until(lambda: d.boards.call(lambda: d.door._streams) == 0,
               "streams never read were kept")
        _until(lambda: d.boards.call(lambda: d.door.open_connections) == 0,
               "their connections were kept")
        with _connect(d.port) as panel:
            panel.sendall(b"GET /api/stream HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
            data = b""
            while b"\ndata: {" not in data:
                chunk = panel.recv(65536)
                assert chunk, "the 17th panel was refused"
                data += chunk
            assert data.startswith(b"HTTP/1.1 200")
    finally:
        for sock in socks:
            sock.close()
        d.close()


def test_trace_csv_streams_whole_in_chunks_and_a_reader_that_stops_is_let_go() -> None:
    d = Door(write_seconds=0.3)
    try:
        c = d.client
        c.pause()
        host = d.boards.connect(1)
        host.command("AX; VL20000; AC200000; MR40000; GO;")
        c.start_trace(1, every_ticks=1)
        c.step(3.0)
        state = c.stop_trace(1)
        assert state["chars"] > 4 * 65536  # more than a few chunks
        text = c.trace_csv(1)
        assert len(text) == state["chars"] and text.count("\n") == state["rows"] + 1
        rows = text.splitlines()
        assert rows[0].startswith("tick,time_s,X_position") and len(rows) == state["rows"] + 1
        # readers that never read: each is dropped; the door stays whole for the next
        socks = [_never_reading(d.port, "/api/boards/1/trace.csv") for _ in range(6)]
        try:
            _until(lambda: d.boards.call(lambda: d.door.open_connections) == 6,
                   "the readers never came")
            _until(lambda: d.boards.call(lambda: d.door.open_connections) == 0,
                   "a CSV reader that never reads was kept")
        finally:
            for sock in socks:
                sock.close()
        assert c.trace_csv(1) == text
    finally:
        d.close()


def test_a_tcp_door_caps_its_hosts_and_frees_a_place_when_one_leaves() -> None:
    boards = HostedBoards(models=("MAXk-8000",))
    try:
        boards.server.hosts_per_door = 4
        for listener in boards.server.listeners:
            listener.cap = 4
        hosts = [boards.connect(1) for _ in range(4)]
        for host in hosts:
            assert host.query("WY").startswith("MAXk-8000")
        extra = _connect(boards.ports[0])
        _until(lambda: _closed(extra), "a fifth host was kept")
        extra.close()
        hosts[0].close()
        _until(lambda: boards.server.listeners[0].open == 3, "the place was never freed")
        fresh = boards.connect(1)
        assert fresh.query("WY").startswith("MAXk-8000")
        assert hosts[1].query("WY").startswith("MAXk-8000")
    finally:
        boards.close()


# ---- time stands, the hosts are answered -----------------------------------------------------
def _pokeys_stream(port: int) -> Any:
    from tests.test_pokeys_doors import TcpSession

    return TcpSession(port)


def test_a_paused_board_answers_every_host_and_acts_on_every_stop() -> None:
    """Paused mid-move, each kind answers its hosts at the same tick and stops at once
    on its host's stop (MAXk KL and AB, MM4005 AB, PoKeys engine stopped, MC405 HALT of
    a program waiting in WA): only the motion clock stands."""
    d = Door(("MAXk-8000", "MM4005", "MC405", "PoKeys57CNC"))
    try:
        c = d.client
        b = d.boards
        maxk = b.connect(1)
        maxk.command("AX; VL1000; AC100000; MR100000; GO; AY; VL1000; AC100000; MR100000; GO;")
        mm = socket.create_connection(("127.0.0.1", b.ports[1]), timeout=10)
        b.on_close(mm.close)
        mm.sendall(b"MO\r1VA10\r1PA100\r")
        trio = socket.create_connection(("127.0.0.1", b.ports[2]), timeout=10)
        b.on_close(trio.close)
        pk = _pokeys_stream(b.ports[3])
        b.on_close(pk.close)
        pokeys = PoKeysHost(pk)
        from tests.test_pokeys_doors import setup_three_axes
        setup_three_axes(pokeys, internal=0b001)
        assert pokeys.pev2(0x02, 3) is not None  # running
        assert pokeys.pev2(0x20, payload=struct.pack("<i", 100000)) is not None
        mc405 = b.services[2].controller
        assert b.call(lambda: mc405.load("WAITER", 'WA(2000)\nPRINT "WOKE"\n')) == []
        _trio(trio, b'RUN "WAITER"\r', expect=b">>")
        b.advance(0.5)  # everything is moving now
        c.pause()
        tick = [board["tick"] for board in c.clock()]
        # the MAXk: answers, and KL stops X and Y where they stand
        x = int(maxk.query("AX; RP"))
        assert 0 < x < 100000 and maxk.query("AX; RV") != "0"
        maxk.command("KL;")
        assert c.reading(1, "X")["velocity"] == 0.0 and c.reading(1, "Y")["velocity"] == 0.0
        # the MM4005: answers, and AB stops axis 1 at once
        mm.sendall(b"1TP\r")
        at = float(_line(mm, b"1TP"))
        assert 0 < at < 100
        mm.sendall(b"AB\r1MS\r")
        assert c.reading(2, "1")["velocity"] == 0.0
        # the PoKeys: answers, and its engine stopped stops the axis
        status = pokeys.pev2_status()
        assert isinstance(status, dict) and 0 < status["positions"][0] < 100000
        assert pokeys.pev2(0x02, 0) is not None
        assert pokeys.pev2_status()["state"] == 0
        assert c.reading(4, "X")["velocity"] == 0.0
        # the MC405: a program in WA(2000) stays waiting; a host's HALT ends it at once
        _trio(trio, b"?1+1\r", expect=b"2\r\n>>")
        assert b"WAITER" in _trio(trio, b"PROCESS\r", expect=b">>")
        _trio(trio, b"HALT\r", expect=b">>")
        assert b"WAITER" not in _trio(trio, b"PROCESS\r", expect=b">>")
        assert [board["tick"] for board in c.clock()] == tick  # time stood throughout
        c.step(0.5)  # after the stops, the clock moves nothing
        assert int(maxk.query("AX; RP")) == x
        mm.sendall(b"1TP\r")
        assert float(_line(mm, b"1TP")) == at
    finally:
        d.close()


def _trio(sock: socket.socket, data: bytes, expect: bytes) -> bytes:
    sock.sendall(data)
    got = b""
    while expect not in got:
        chunk = sock.recv(65536)
        assert chunk, "the MC405 door hung up"
        got += chunk
    return got


def _line(sock: socket.socket, prefix: bytes) -> str:
    got = b""
    while True:
        while b"\r" not in got:
            chunk = sock.recv(65536)
            assert chunk
            got += chunk
        line, got = got.split(b"\r", 1)
        if line.startswith(prefix):
            return line[len(prefix):].decode()


# ---- triggers: 64 a board, watched by two observers, each exact to its tick ----------------
def test_sixty_four_triggers_each_fire_at_their_own_tick(door: Door) -> None:
    """32 timed triggers armed out of order and 32 position triggers (X up past 16
    positions, Y down past 16) on one board: each fires at its tick, the position ones at
    the first tick the trace's reading is at or beyond the position; the 65th is a 409.
    (The trace, written by maxk.trace, is the independent record of every tick.)"""
    c = door.client
    c.pause()
    host = door.boards.connect(1)
    host.command("AX; VL20000; AC100000; MR30000; GO; AY; VL20000; AC100000; MR-30000; GO;")
    now = c.clock()[0]["tick"]
    offsets = [(k * 37) % 320 + 5 for k in range(32)]  # distinct, not in order
    assert len(set(offsets)) == 32
    timed = {c.arm(1, f"input {k % 8} high", tick=now + o)["id"]: now + o
             for k, o in enumerate(offsets)}
    up = {c.arm(1, "input 9 high", axis="X", passes=p)["id"]: p
          for p in range(1500, 25501, 1600)}
    down = {c.arm(1, "input 10 high", axis="Y", passes=-p)["id"]: -p
            for p in range(1500, 25501, 1600)}
    assert len(up) == len(down) == 16
    with pytest.raises(ControlError, match="at most 64 triggers"):
        c.arm(1, "input 1 high", after=1.0)
    c.start_trace(1, every_ticks=1)
    c.step(2.0)
    c.stop_trace(1)
    rows = c.trace_csv(1).splitlines()
    names = rows[0].split(",")
    tick_at, x_at, y_at = (names.index(n) for n in ("tick", "X_position", "Y_position"))
    table = [(int(r.split(",")[tick_at]), float(r.split(",")[x_at]),
              float(r.split(",")[y_at])) for r in rows[1:]]
    fired = {t["id"]: t["fired_tick"] for t in c.triggers(1)}
    for ident, tick in timed.items():
        assert fired[ident] == tick
    for ident, position in up.items():
        assert fired[ident] == next(t for t, x, _y in table if x >= position), position
    for ident, position in down.items():
        assert fired[ident] == next(t for t, _x, y in table if y <= position), position
    assert c.arm(1, "input 1 high", after=1.0)["fired_tick"] is None  # room again


# ---- the whole server: descriptors and signals ---------------------------------------------
def _serve_limited(files: int, *models: str, options: tuple[str, ...] = ()) -> Any:
    """`maxk serve --control` in a process allowed `files` descriptors (ulimit -n)."""
    import resource

    from maxk import testing

    real = testing.subprocess.Popen

    def limited(*args: Any, **kwargs: Any) -> Any:
        kwargs["preexec_fn"] = lambda: resource.setrlimit(resource.RLIMIT_NOFILE,
                                                          (files, files))
        return real(*args, **kwargs)

    testing.subprocess.Popen = limited  # type: ignore[assignment]
    try:
        return testing.serve(*models, options=options)
    finally:
        testing.subprocess.Popen = real  # type: ignore[assignment]


def test_a_flood_of_connections_never_takes_the_server_to_emfile() -> None:
    """`ulimit -n 256`, every address: 300 connections to the control door that never
    send a request, and 300 to the MAXk's door. The doors' caps fit the descriptors:
    the flood is refused, a host still connects to the MC405 and is answered, nothing
    says EMFILE, and after SIGTERM the server ends cleanly."""
    import signal

    served = _serve_limited(256, "MAXk-8000", "MC405", options=("--host", "0.0.0.0"))
    socks: list[socket.socket] = []
    try:
        port = int(served.url.rsplit(":", 1)[1])
        maxk = served.doors[0].tcp[1]
        for target in [("127.0.0.1", port)] * 300 + [("127.0.0.1", maxk)] * 300:
            # (a full backlog may refuse one: what matters is the server, below)
            with contextlib.suppress(OSError):
                socks.append(socket.create_connection(target, timeout=10))
        with socket.create_connection(("127.0.0.1", served.doors[1].tcp[1]), timeout=10) as host:
            assert b"2" in _trio(host, b"?1+1\r", expect=b">>")
        for sock in socks:
            sock.close()
        socks.clear()
        served.process.send_signal(signal.SIGTERM)
        assert served.process.wait(LIVENESS) == 0
        assert served.process.stdout is not None
        said = served.process.stdout.read()
        assert "Too many open files" not in said and "EMFILE" not in said, said
        assert "Traceback" not in said, said
    finally:
        for sock in socks:
            sock.close()
        served.stop()


def test_sigterm_ends_a_loaded_server() -> None:
    """SIGTERM while a long step ticks every tick, panels never read their streams and
    hosts poll: the server ends (code 0) at once; figures in docs/control.md."""
    import signal

    from maxk import testing

    served = testing.serve("MAXk-8000", "MC405")
    socks: list[socket.socket] = []
    try:
        port = int(served.url.rsplit(":", 1)[1])
        c = served.client
        c.pause()
        c.arm(1, "input 1 high", axis="X", passes=1e9)
        stepping = threading.Thread(target=_step_an_hour, args=(c,), daemon=True)
        stepping.start()
        _until(lambda: c.clock()[0]["tick"] > 0, "the step never began")
        for _ in range(8):
            socks.append(_never_reading(port, "/api/stream"))
        host = socket.create_connection(served.doors[0].tcp, timeout=10)
        socks.append(host)
        host.sendall(b"WY\n" * 100)
        served.process.send_signal(signal.SIGTERM)
        assert served.process.wait(LIVENESS) == 0
        stepping.join(LIVENESS)
    finally:
        for sock in socks:
            sock.close()
        served.stop()


def _step_an_hour(c: Client) -> None:
    with contextlib.suppress(Exception):  # (the server goes away under it: the test)
        Client(c.url, timeout=LIVENESS).step(3600.0)


def test_a_paused_mc405_frees_a_waiting_prompt_on_another_hosts_halt() -> None:
    """While the clock stands, a `WA(2000)` typed at one host's MC405 prompt waits (no
    prompt yet, the time cannot pass); another host's HALT gives it up at once: its
    prompt comes, it answers again, and the clock has not moved."""
    d = Door(("MC405",))
    try:
        c = d.client
        b = d.boards
        waiter = socket.create_connection(("127.0.0.1", b.ports[0]), timeout=10)
        b.on_close(waiter.close)
        other = socket.create_connection(("127.0.0.1", b.ports[0]), timeout=10)
        b.on_close(other.close)
        _trio(waiter, b"?1\r", expect=b">>")
        _trio(other, b"?2\r", expect=b">>")
        c.pause()
        tick = c.clock()[0]["tick"]
        waiter.sendall(b"WA(2000)\r")
        waiter.settimeout(0.5)
        with pytest.raises(TimeoutError):  # a liveness probe: no prompt while time stands
            while b">>" not in waiter.recv(4096):
                pass
        waiter.settimeout(10)
        _trio(other, b"HALT\r", expect=b">>")
        _trio(waiter, b"", expect=b">>")  # the given-up statement's prompt
        _trio(waiter, b"?3+4\r", expect=b"7\r\n>>")
        assert c.clock()[0]["tick"] == tick
    finally:
        d.close()
