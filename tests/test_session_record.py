"""A session typed at the REPL becomes a regression script that passes as it is.

Driven through the REPL's own loop (`ReplSession.handle`, what the terminal calls for each
line typed), on each kind of controller: the commands, the virtual time between them,
the world changes and the replies are written by `:record FILE`, and `maxk run` passes the
file unchanged on a fresh controller.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from maxk import session_record
from maxk.cli import main
from maxk.repl import ReplSession
from maxk.script import load_script, run_script


def type_lines(session: ReplSession, lines: list[str]) -> list[str]:
    out: list[str] = []
    for line in lines:
        out += session.handle(line)
    return out


def test_a_maxk_session_recorded_is_the_script_it_was(tmp_path: Path) -> None:
    path = tmp_path / "session.maxk"
    session = ReplSession("MAXk-2000", manual_time=True, archive=False)
    type_lines(session, [
        "AX; VL5000; AC50000; MR1000; GO; ID;",
        ":advance 100 ticks",
        "AX RP",                         # partway: the tick matters
        ":world X limits 3000 -3000",
        "help VL",                       # the REPL's own words are not the controller's
        "AX; MR5000; GO;",
        ":run 5 s",
        "AX RP",
        "MR",                            # refused: expected in the script
        f":record {path}",
        "AX QA",                         # after :record, still written
    ])
    # 100 ticks at 8192 Hz into a 5000 steps/s, 50000 steps/s2 ramp: 1/2 a t^2 = 3.05
    assert path.read_text() == (
        "// Recorded in the maxk REPL on the MAXk-2000.\n"
        "@board MAXk-2000\n"
        "AX; VL5000; AC50000; MR1000; GO; ID;\n"
        "@wait 100 ticks\n"
        "AX RP\n"
        "< 3\n"
        "@world X limits 3000 -3000\n"
        "AX; MR5000; GO;\n"
        f"@wait {session.controller.engine.tick - 100} ticks\n"
        "AX RP\n"
        "< 3000\n"
        "MR\n"
        "@expect error 'MR': MR needs an operand\n"
        "AX QA\n"
        "< PDLN\n")
    assert main(["run", str(path)]) == 0
    assert not run_script(load_script(path)).failures


@pytest.mark.parametrize("model,lines", [
    ("MM4005", ["1PA5", ":advance 0.25 s", "1TP", "2PA-3", ":run 10 s", "2TP", "1PA99999999",
                "TE", "1TP"]),
    ("MC405", ["SPEED AXIS(0) = 100", "ACCEL AXIS(0) = 1000", "DECEL AXIS(0) = 1000",
               "MOVE(50) AXIS(0)", ":advance 0.3 s", "?MPOS AXIS(0)", "MOVEE(1)",
               ":run 5 s", "?DPOS AXIS(0)", ":world 0 plus-limit 20", "?IN(0)"]),
    ("PoKeys57CNC", ["setup 3", "axis X internal position max 10 accel 0.05 decel 0.05",
                     "state running", "move X 1000", ":advance 100 ms", "status", "frob",
                     ":world X limits 800 -800", ":run 5 s", "pos"]),
])
def test_every_kind_records_a_session_that_passes(tmp_path: Path, model: str,
                                                  lines: list[str]) -> None:
    path = tmp_path / "s.maxk"
    session = ReplSession(model, manual_time=True, archive=False)
    type_lines(session, [f":record {path}", *lines])
    text = path.read_text()
    assert f"@board {model}\n" in text
    assert text.count("< ") >= 2, text
    result = run_script(load_script(path))
    assert not result.failures, (text, [str(f) for f in result.failures])


def test_a_realtime_session_keeps_the_ticks_the_wall_clock_gave() -> None:
    """At the wall clock's pace, the waits recorded are the ticks that passed between
    the lines: 0.5 s at 8192 Hz is 4096 ticks."""
    now = [100.0]
    session = ReplSession("MAXk-1000", clock=lambda: now[0], archive=False)
    type_lines(session, ["AX; VL1000; AC10000; MR800; GO;"])
    now[0] += 0.5
    type_lines(session, ["AX RP"])
    # 0.1 s of ramp (50 steps), then 0.4 s at 1000 steps/s: 450
    assert session.record.script().splitlines()[2:] == [
        "AX; VL1000; AC10000; MR800; GO;", "@wait 4096 ticks", "AX RP", "< 450"]


def test_a_reset_starts_the_record_again(tmp_path: Path) -> None:
    session = ReplSession("MAXk-1000", manual_time=True, archive=False)
    type_lines(session, ["AX; MR100; GO;", ":advance 1 s", ":reset", "AX RP"])
    assert session.record.script().splitlines()[2:] == ["AX RP", "< 0"]


def test_the_record_is_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(session_record, "MAX_ENTRIES", 10)
    session = ReplSession("MAXk-1000", manual_time=True, archive=False)
    type_lines(session, ["AX RP"] * 25)
    assert len(session.record.entries) == 10
    assert session.record.dropped == 15
    assert "Its first 15 lines were let go" in session.record.script()


def test_record_words(tmp_path: Path) -> None:
    session = ReplSession("MAXk-1000", manual_time=True, archive=False)
    assert session.handle(":record") == ["not recording (:record FILE); 0 lines since "
                                         "power-up"]
    blocked = tmp_path / "no such dir" / "s.maxk"
    assert session.handle(f":record {blocked}")[0].startswith("record: ")
    assert session.record_path is None
    path = tmp_path / "s.maxk"
    session.handle(f":record {path}")
    session.handle("AX RP")
    assert session.handle(":record off") == [f"recording stopped; {path} kept"]
    session.handle("AX RP")
    assert path.read_text().count("AX RP") == 1
