"""The control door (maxk/host/control.py) in-process: every request through the Python
client (maxk.control.Client) over real HTTP, beside a host on a real TCP door, the
clock the test's (a manual wall clock, or the door's own pause and step)."""

from __future__ import annotations

import asyncio
import json
import urllib.request

import pytest

from maxk.control import Client, ControlError
from maxk.host import control_board
from maxk.host.control import ControlDoor, is_loopback, world_words
from tests.hosting import HostedBoards


class Hosted:
    """Served boards (tests/hosting.py) with a control door on the same loop."""

    def __init__(self, models: tuple[str, ...], host: str = "127.0.0.1") -> None:
        self.boards = HostedBoards(models=models)
        self.door = ControlDoor(self.boards.services)

        async def start() -> tuple[str, int]:
            return await self.door.start(host, 0)

        self.address = asyncio.run_coroutine_threadsafe(start(), self.boards.loop).result(10)
        self.url = f"http://127.0.0.1:{self.address[1]}"
        self.client = Client(self.url, self.door.token)

    def close(self) -> None:
        asyncio.run_coroutine_threadsafe(self.door.close(), self.boards.loop).result(10)
        self.boards.close()


@pytest.fixture
def hosted():
    h = Hosted(("MAXk-8000", "PoKeys57CNC"))
    yield h
    h.close()


def test_index_board_axis_and_world(hosted: Hosted) -> None:
    boards = hosted.client.boards()
    assert [(b["number"], b["model"], b["kind"]) for b in boards] == [
        (1, "MAXk-8000", "MAXk"), (2, "PoKeys57CNC", "PoKeys")]
    assert boards[0]["doors"]["tcp"] == [f"127.0.0.1:{hosted.boards.ports[0]}"]
    assert boards[1]["doors"]["udp"] == [f"127.0.0.1:{hosted.boards.udp_ports[0]}"]
    assert boards[0]["axes"] == ["X", "Y", "Z", "T", "U", "V", "R", "S"]
    board = hosted.client.board(1)
    assert board["axes"][0]["switches"]["plus"]["at"] == 1_000_000_000
    assert board["world"][0].startswith("X: at 0 steps")
    assert hosted.client.reading(1, "x") == {"name": "X", "position": 0, "encoder": 0,
                                             "velocity": 0.0, "done": False,
                                             "moving": False, "flags": []}


def test_world_words_and_the_json_form_are_the_same_words(hosted: Hosted) -> None:
    c = hosted.client
    assert c.world(1, "X limits 5000 -5000") == "X limits 5000 -5000"
    assert c.world(1, axis="Y", set="limits", values=[7000, None]) == "Y limits 7000 none"
    assert c.world(1, input=3, level=True) == "input 3 high"
    assert c.world(1, analog=1, volts=2.5) == "analog 1 2.5 V"
    board = c.board(1)
    assert board["axes"][0]["switches"]["plus"]["at"] == 5000
    assert board["axes"][1]["switches"]["minus"]["at"] is None
    assert board["inputs"]["3"] is True and board["analog"]["1"] == 2.5
    assert c.world(2, "X fault plus active") == "X fault plus active"
    assert c.board(2)["axes"][0]["switches"]["plus"]["fault"] == "active"
    assert world_words({"axis": "X", "set": "fault", "values": ["home", "none"]}) == \
        "X fault home none"


@pytest.mark.parametrize("body, status, reason", [
    ({"words": "X sideways 3"}, 400, "cannot read"),
    ({"words": "Q limits 1 -1"}, 404, "no axis 'Q'"),
    ({"words": "input 99 high"}, 400, "no input 99"),
    ({"words": "X fault plus sideways"}, 400, "active|inactive|none"),
    ({"words": 5}, 400, "the text of one world setting"),
    ({"axis": "X", "set": "limits", "values": ["1 2", 3]}, 400, "not one word"),
    ({"input": 3, "level": "yes"}, 400, "level: true or false"),
    ({"nothing": 1}, 400, "give {"),
])
def test_bad_world_requests_get_a_reason_and_change_nothing(hosted: Hosted, body, status,
                                                            reason) -> None:
    before = hosted.client.board(1)["world"]
    with pytest.raises(ControlError) as error:
        hosted.client.request("POST", "/api/boards/1/world", body)
    assert error.value.status == status and reason in error.value.reason
    assert hosted.client.board(1)["world"] == before


def _raw(url: str, method: str = "GET", data: bytes | None = None,
         headers: dict[str, str] | None = None) -> tuple[int, dict]:
    if headers is None and data is not None:
        headers = {"Content-Type": "application/json"}  # as a program sends it
    request = urllib.request.Request(url, data=data, method=method, headers=headers or {})
    try:
        with urllib.request.urlopen(request, timeout=10) as answer:
            return answer.status, json.loads(answer.read())
    except urllib.error.HTTPError as error:
        with error:
            return error.code, json.loads(error.read())


JSON = {"Content-Type": "application/json"}


def test_malformed_requests_are_4xx_and_the_doors_go_on(hosted: Hosted) -> None:
    url = hosted.url
    assert _raw(url + "/api/boards/1/world", "POST", b"{not json", JSON)[0] == 400
    assert _raw(url + "/api/boards/1/world", "POST", b"[1, 2]", JSON)[1]["error"] == \
        "the body must be a JSON object"
    assert _raw(url + "/api/boards/9")[0] == 404
    assert _raw(url + "/api/boards/x/world")[0] == 404
    assert _raw(url + "/api/nothing")[0] == 404
    assert _raw(url + "/api/boards/1/world", "PUT", b"{}", JSON)[0] == 405
    assert _raw(url + "/api/boards/1/world", "POST", b"x" * 100_000, JSON)[0] == 413
    assert _raw(url + "/static/../control.py")[0] == 404
    assert _raw(url + "/api/boards/1/axes/Q")[0] == 404
    host = hosted.boards.connect(1)  # the host's door is untouched
    assert host.query("WY") .startswith("MAXk-8000")


def test_triggers_at_a_tick_and_when_an_axis_passes_a_position(hosted: Hosted) -> None:
    c = hosted.client
    c.pause()
    host = hosted.boards.connect(1)
    host.command("AX; VL10000; AC100000; MA20000; GO;")
    tick = c.clock()[0]["tick"]
    at = c.arm(1, "input 5 high", tick=tick + 100)
    assert at["when"] == {"tick": tick + 100} and at["fired_tick"] is None
    passes = c.arm(1, "X fault plus active", axis="X", passes=12000)
    assert passes["when"] == {"axis": "X", "passes": 12000.0, "direction": "up"}
    c.step(ticks=99)
    assert c.board(1)["inputs"]["5"] is False
    c.step(ticks=1)
    assert c.board(1)["inputs"]["5"] is True
    c.step(3.0)
    fired = {t["id"]: t for t in c.triggers(1)}
    assert fired[at["id"]]["fired_tick"] == tick + 100
    # 12000 steps: the ramp to VL takes 0.1 s and 500 steps, the other 11500 at 10000/s
    # 1.15 s: 1.25 s = 10240 ticks at 8192 Hz (issue 41: the tick, not "not None")
    assert fired[passes["id"]]["fired_tick"] == tick + 10240
    assert fired[passes["id"]]["did"] == "X fault plus active"
    # the host sees the limit its own way: QA's L, and the axis stopped where the limit
    # tripped (the factory style is a hard stop, manual 2.14)
    assert host.query("QA")[2] == "L"
    x = c.reading(1, "X")
    assert x["position"] == 12000 and "overtravel" in x["flags"]
    with pytest.raises(ControlError, match="no trigger 99"):
        c.disarm(1, 99)
    late = c.arm(1, "input 6 high", after=1.0)
    assert c.disarm(1, late["id"])["fired_tick"] is None
    c.step(2.0)
    assert c.board(1)["inputs"]["6"] is False  # disarmed: never fired
    for when, reason in [({"tick": 0}, "not in the future"), ({}, "when:"),
                         ({"axis": "Q", "passes": 1}, "no axis"),
                         ({"axis": "X", "passes": "far"}, "a number"),
                         ({"time": float("nan")}, "a finite number")]:
        status, body = _raw(hosted.url + "/api/boards/1/triggers", "POST",
                            json.dumps({"words": "input 1 high", "when": when}).encode())
        assert status in (400, 404) and reason in body["error"], (when, body)


def test_a_time_trigger_is_exact_to_the_tick(hosted: Hosted) -> None:
    c = hosted.client
    c.pause()
    t = c.arm(2, "input 7 high", time=c.clock()[1]["time"] + 0.25)
    c.step(1.0)
    fired = c.triggers(2)[0]
    assert fired["fired_tick"] == t["when"]["tick"]


def test_clock_pause_step_speed_run(hosted: Hosted) -> None:
    c = hosted.client
    paused = c.pause()
    assert all(b["paused"] and b["speed"] == 0 for b in paused)
    hosted.boards.advance(5.0)  # the wall clock moves; a paused board does not
    assert c.clock()[0]["tick"] == paused[0]["tick"]
    stepped = c.step(0.5, board=1)
    assert stepped[0]["tick"] == paused[0]["tick"] + 4096  # 0.5 s of 8192 Hz
    assert stepped[1]["tick"] == paused[1]["tick"]
    c.speed(4.0)  # while paused: the speed to run at
    running = c.run()
    assert [b["speed"] for b in running] == [4.0, 4.0]
    hosted.boards.advance(0.25)
    assert c.clock()[0]["tick"] == stepped[0]["tick"] + 8192  # 1 s of virtual time
    for body in ({"speed": 0}, {"speed": -1}, {"speed": 1e9}, {"step": -1}, {"step": 1e7},
                 {}, {"pause": True, "run": True}, {"board": 7, "pause": True}):
        with pytest.raises(ControlError) as error:
            c.request("POST", "/api/clock", body)
        assert error.value.status in (400, 404)


def test_reset_one_controller(hosted: Hosted) -> None:
    c = hosted.client
    c.pause()
    host = hosted.boards.connect(1)
    host.command("AX; LP5000;")
    assert c.reading(1, "X")["position"] == 5000
    c.world(1, "X limits 9000 -9000")
    c.reset(1)
    assert host.query("AX RP") == "0"  # counters read 0 where the stage stands
    assert c.board(1)["axes"][0]["switches"]["plus"]["at"] == 9000  # the world stays


def test_trace_start_stop_fetch_and_its_bound(hosted: Hosted, monkeypatch) -> None:
    monkeypatch.setattr(control_board, "TRACE_LIMIT", 20_000)
    c = hosted.client
    c.pause()
    with pytest.raises(ControlError, match="no trace"):
        c.trace_csv(1)
    assert c.start_trace(1, every_ticks=8192)["running"] is True
    c.step(3.0)
    state = c.stop_trace(1)
    assert state["running"] is False and state["rows"] == 4  # start + one a second
    engine = hosted.boards.services[0].controller.engine
    assert hosted.boards.call(lambda: list(engine._observers)) == []  # the trace let go
    lines = c.trace_csv(1).splitlines()
    assert lines[0].startswith("tick,time_s,X_position") and len(lines) == 5
    assert [int(line.split(",")[0]) - int(lines[1].split(",")[0]) for line in lines[1:]] == \
        [0, 8192, 16384, 24576]
    with pytest.raises(ControlError, match="every_ticks"):
        c.start_trace(1, every_ticks=0)
    c.start_trace(2, every_ticks=1)  # a row a slot: the bound stops it
    c.step(60.0)
    state = c.request("GET", "/api/boards/2/trace")
    assert state["full"] and not state["running"] and state["chars"] <= 20_000
    assert state["limit"] == 20_000 and c.trace_csv(2).count("\n") == state["rows"] + 1


def test_traffic_and_the_error_log(hosted: Hosted) -> None:
    c = hosted.client
    host = hosted.boards.connect(1)
    assert host.query("WY").startswith("MAXk-8000")
    hosts = c.traffic(1)
    assert len(hosts) == 1 and hosts[0]["transport"] == "tcp"
    entries = hosts[0]["entries"]
    assert entries[0]["direction"] == "in" and entries[0]["text"] == "WY\n"
    assert entries[1]["direction"] == "out" and "MAXk-8000" in entries[1]["text"]
    assert c.traffic(2) == []
    import logging

    logging.getLogger("maxk.door.serve").error("a fault for the log")
    assert c.errors()[-1]["message"] == "a fault for the log"


def test_panel_state_and_stream(hosted: Hosted) -> None:
    c = hosted.client
    c.world(1, "X fault home active")
    panel = c.panel()
    x = panel["boards"][0]["axes"][0]
    assert x["lamps"]["home"] == {"on": True, "fault": "active"}
    assert x["lamps"]["plus"] == {"on": False, "fault": None}
    pokeys = panel["boards"][1]
    assert pokeys["extras"]["buffer"] == {"count": 0, "depth": 128}
    with urllib.request.urlopen(hosted.url + "/api/stream", timeout=10) as stream:
        assert stream.headers["Content-Type"] == "text/event-stream"
        line = stream.readline()
        assert line.startswith(b"data: ")
        assert json.loads(line[6:])["boards"][0]["model"] == "MAXk-8000"
    with urllib.request.urlopen(hosted.url + "/", timeout=10) as page:
        assert b"static/panel.js" in page.read()
    with urllib.request.urlopen(hosted.url + "/static/panel.js", timeout=10) as script:
        assert b"EventSource" in script.read()


def test_beyond_loopback_every_request_needs_the_token() -> None:
    assert is_loopback("127.0.0.1") and is_loopback("::1") and is_loopback("localhost")
    assert not is_loopback("0.0.0.0") and not is_loopback("192.168.1.2")
    h = Hosted(("MAXk-8000",), host="0.0.0.0")
    try:
        assert h.door.token
        assert _raw(h.url + "/api")[0] == 401
        assert _raw(h.url + "/api?token=wrong")[0] == 401
        assert _raw(h.url + "/api", headers={"Authorization": "Bearer " + h.door.token})[0] \
            == 200
        assert _raw(h.url + "/api?token=" + h.door.token)[0] == 200
        assert Client(h.url, h.door.token).boards()[0]["model"] == "MAXk-8000"
    finally:
        h.close()


ODD_BODIES = [b"", b"null", b"0", b'"x"', b"[]", b"{}", b'{"words": null}',
              b'{"words": ""}', b'{"words": "X"}', b'{"words": "X limits 1e999 -1"}',
              b'{"words": "input -1 high"}', b'{"words": "analog 0 nan"}',
              b'{"words": "X index -4 4 0"}', b'{"words": "X motor inertia=-1"}',
              b'{"words": "X home 10 5"}', b'{"axis": {}, "set": "limits"}',
              b'{"when": {"tick": 1e400}, "words": "input 1 high"}',
              b'{"when": {"axis": "X", "passes": null}, "words": "input 1 high"}',
              b'{"when": [], "words": "input 1 high"}', b'{"every_ticks": "many"}',
              b'{"every_ticks": true}', b'{"speed": "fast"}', b'{"step": [1]}',
              b'{"ticks": 1e300}', b'{"board": "1", "pause": true}', "\u00ff".encode(),
              b"\xff\xfe", b'{"words": "X limits 1 -1"' + b" " * 10, b"{" * 5000]


@pytest.mark.parametrize("path", ["/api/boards/1/world", "/api/boards/1/triggers",
                                  "/api/boards/2/trace", "/api/clock",
                                  "/api/boards/2/reset"])
def test_no_odd_body_is_a_server_fault(hosted: Hosted, path: str) -> None:
    for body in ODD_BODIES:
        status, answer = _raw(hosted.url + path, "POST", body,
                              {"Content-Type": "application/json"})
        assert status < 500 and ("error" in answer or status < 300), (path, body, answer)
    assert hosted.client.errors() == []  # nothing reached the fault log
    host = hosted.boards.connect(1)
    assert host.query("WY").startswith("MAXk-8000")
