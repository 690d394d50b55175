"""The front panel's console over the control door's HTTP (the page's own requests):
each board's console answers as the REPL does, completes words with their summaries,
shows in the board's traffic, obeys the door's guard, and its session saved as a script
passes `maxk run` on a fresh controller. The clock is the door's: paused, then stepped.
"""

from __future__ import annotations

import json
import urllib.error
import urllib.request
from collections.abc import Iterator

import pytest

from maxk.control import ControlError
from maxk.repl import ReplSession
from maxk.script import parse_script, run_script
from tests.test_control import Hosted


@pytest.fixture
def hosted() -> Iterator[Hosted]:
    h = Hosted(("MAXk-2000", "MM4005", "MC405", "PoKeys57CNC"))
    h.client.pause()
    yield h
    h.close()


def test_a_maxk_console_moves_the_axis_and_answers_as_the_repl_does(hosted: Hosted) -> None:
    c = hosted.client
    assert c.console(1, "AX; VL5000; AC50000; MR1000; GO;")["lines"] == []
    c.step(ticks=100)
    answer = c.console(1, "AX RP")
    # 100 ticks at 8192 Hz of a 50,000 steps/s2 ramp: 1/2 a t^2 = 3.05 steps
    assert answer["lines"] == ["3"]
    assert answer["errors"] == []
    assert answer["prompt"] == "MAXk-2000 AX> "
    assert answer["tick"] == c.clock()[0]["tick"]
    c.step(1.0)
    assert c.console(1, "AX RP")["lines"] == ["1000"]
    assert c.reading(1, "X")["position"] == 1000
    refused = c.console(1, "MR")
    assert refused["lines"] == [] and refused["errors"] == [
        "! command error: 'MR': MR needs an operand"]
    repl = ReplSession("MAXk-2000", manual_time=True, archive=False)
    assert c.console(1, "help VL")["lines"] == repl.handle("help VL")


@pytest.mark.parametrize("board,line,reply,bad,error", [
    (2, "1PA5", [], "1PA99999999", "! C Parameter out of limits"),
    (3, "?1+1", ["2"], "MOVEE(10)", "! Variable not defined"),
])
def test_other_kinds_answer_in_their_own_language(hosted: Hosted, board: int, line: str,
                                                  reply: list[str], bad: str,
                                                  error: str) -> None:
    c = hosted.client
    assert c.console(board, line)["lines"] == reply
    assert c.console(board, bad)["errors"] == [error]


def test_an_mm4005_move_typed_is_read_back_when_done(hosted: Hosted) -> None:
    c = hosted.client
    c.console(2, "1PA5")
    c.step(30.0)
    assert c.console(2, "1TP")["lines"] == ["1TP5.0000"]


def test_a_pokeys_console_uses_its_own_words(hosted: Hosted) -> None:
    c = hosted.client
    assert c.console(4, "status")["lines"] == ["state STOPPED, buffer 0/128",
                                               "no axes enabled (setup N)"]
    assert c.console(4, "frob")["lines"] == ["! unknown word 'frob'; try help"]


def test_tab_completion_gives_the_words_and_their_summaries(hosted: Hosted) -> None:
    c = hosted.client
    words = {w["word"]: w["summary"] for w in c.console_words(1, "VL")}
    repl = ReplSession("MAXk-2000", manual_time=True, archive=False)
    assert "VL" in words
    assert words["VL"] == repl.console.summary("VL") != ""
    assert all(w.upper().startswith("VL") for w in words)
    trio = [w["word"] for w in c.console_words(3, "movec")]
    assert "MOVECIRC" in trio
    assert len(c.console_words(1, "")) == 64  # every word matches: the answer is capped


def test_the_console_shows_in_the_board_traffic(hosted: Hosted) -> None:
    c = hosted.client
    c.console(1, "AX RP")
    hosts = c.traffic(1)
    console = [h for h in hosts if h["transport"] == "console"]
    assert len(console) == 1 and console[0]["peer"] == "front panel"
    assert [(e["direction"], e["text"]) for e in console[0]["entries"]] == [
        ("in", "AX RP\r"), ("out", "0\n")]


def test_the_session_saved_is_a_script_that_passes(hosted: Hosted) -> None:
    c = hosted.client
    c.console(1, "AX; VL5000; AC50000; MR1000; GO;")
    c.step(ticks=100)
    c.console(1, "AX RP")
    c.world(1, "X limits 600 -600")  # a click on the page: part of the session
    c.step(1.0)
    c.console(1, "AX RP")
    c.console(1, "AX QA")
    c.console(1, "MR")
    c.console(1, "help VL")  # the console's own words are not written
    script = c.console_script(1)
    assert script.splitlines() == [
        "// Recorded in the front panel's console on the MAXk-2000.",
        "@board MAXk-2000",
        "AX; VL5000; AC50000; MR1000; GO;",
        "@wait 100 ticks",
        "AX RP",
        "< 3",
        "@world X limits 600 -600",
        "@wait 8192 ticks",
        "AX RP",
        f"< {c.reading(1, 'X')['position']}",
        "AX QA",
        "< PNLN",
        "MR",
        "@expect error 'MR': MR needs an operand",
    ]
    assert not run_script(parse_script(script, "panel.maxk")).failures


def test_a_reset_starts_the_record_again(hosted: Hosted) -> None:
    c = hosted.client
    c.console(3, "VR(1) = 5")
    c.reset(3)
    c.console(3, "?VR(1)")
    # the record starts again; VR(1) outlives the reset (EX's page: VRs stay in memory)
    assert c.console_script(3).splitlines()[2:] == ["?VR(1)", "< 5.0000"]


@pytest.mark.parametrize("body,status", [
    ({"line": 5}, 400), ({"line": None}, 400), ({}, 400), ({"line": "AX\rRP"}, 400),
    ({"line": "A" * 1025}, 400), ({"line": "x\x00"}, 400),
])
def test_bad_lines_are_refused_whole(hosted: Hosted, body: dict, status: int) -> None:
    with pytest.raises(ControlError) as info:
        hosted.client.request("POST", "/api/boards/1/console", body)
    assert info.value.status == status
    assert [h["entries"] for h in hosted.client.traffic(1)
            if h["transport"] == "console"] in ([], [[]])  # nothing ran


def test_a_console_line_is_an_action_the_guard_checks(hosted: Hosted) -> None:
    """From another origin, or not as JSON, a line is refused and nothing runs."""
    url = hosted.url + "/api/boards/1/console"
    data = json.dumps({"line": "AX; MR500; GO;"}).encode()
    for headers in ({"Content-Type": "text/plain"},
                    {"Content-Type": "application/json", "Origin": "http://evil.example"},
                    {"Content-Type": "application/json", "Host": "evil.example"}):
        request = urllib.request.Request(url, data=data, method="POST", headers=headers)
        with pytest.raises(urllib.error.HTTPError) as info:
            urllib.request.urlopen(request, timeout=10)
        info.value.close()
        assert info.value.code in (403, 415, 421)
    hosted.client.step(1.0)
    assert hosted.client.reading(1, "X")["position"] == 0
