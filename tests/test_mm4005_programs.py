"""The MM4005's program machinery: WS holding a line (or a program) to the tick its
motion ends, a host's later lines held behind it while other hosts are answered, stored
programs (EP ... QP, EX, XX) with their errors, AB ending a program, and the program
archive across a power cycle (damaged: reported, never a traceback).

Times are worked by hand from the trapezoid: VA v, AC a, distance d >= v^2/a takes
v/a + d/v seconds; at 2000 Hz a motion of T seconds ends on tick start + T * 2000."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import pytest

from maxk.commands.mm4005 import MM4005Session
from maxk.controllers.mm4005.controller import MM4005Controller
from maxk.personalities.mm4005.programs import MEMORY, ProgramStore

RATE = 2000  # ticks a second


def _mm(model: str = "MM4005-2", archive: Path | None = None) -> MM4005Controller:
    mm = MM4005Controller(model, archive=archive)
    assert mm.send("1VA1;1AC5;2VA2;2AC10") == []
    return mm


def _host(mm: MM4005Controller) -> tuple[MM4005Session, list[int]]:
    """A host's session and the ticks at which it was told output waits (notify)."""
    told: list[int] = []
    session = mm.open_session(lambda: told.append(mm.machine.tick))
    return session, told


# ---- WS on the command line ------------------------------------------------------------------
def test_ws_holds_the_line_until_the_tick_the_move_ends() -> None:
    mm = _mm()
    host, told = _host(mm)
    host.feed(b"1PA5;1WS;1TP\r")
    assert host.read() == b"" and host.holding  # PA ran, TP waits behind WS
    end = round((1 / 5 + 5 / 1) * RATE)  # 0.2 + 5.0 s = 10400 ticks
    mm.machine.advance_to(end - 1)
    assert host.read() == b"" and told == []
    mm.machine.advance_to(end)
    assert told == [end]
    assert host.read() == b"1TP5.0000\r" and not host.holding


def test_lines_sent_during_the_wait_run_after_it_in_order() -> None:
    mm = _mm()
    host, _ = _host(mm)
    host.feed(b"1PA1;1WS;1TP\r1TP;2PA1\r2TP\r")
    assert host.read() == b""
    end = round((0.2 + 1.0) * RATE)
    mm.machine.advance_to(end)
    assert host.read() == b"1TP1.0000\r1TP1.0000\r2TP0.0000\r"
    assert mm.machine.status(2).moving  # the held 2PA1 ran on the tick the wait ended


def test_another_host_is_answered_during_the_wait_and_its_stop_ends_it() -> None:
    mm = _mm()
    waiting, told = _host(mm)
    other, _ = _host(mm)
    waiting.feed(b"1PA5;1WS;1TP\r")
    mm.machine.advance_to(RATE)  # 1 s: 0.1 accelerating + 0.8 at speed
    other.feed(b"1TP\r")
    assert other.read() == b"1TP0.9000\r" and waiting.read() == b""
    other.feed(b"AB\r")  # a stop from the second connection acts at once
    assert told == [RATE] and waiting.read() == b"1TP0.9000\r"
    assert not waiting.holding


def test_st_ending_the_move_ends_the_wait_when_the_axis_has_stopped() -> None:
    mm = _mm()
    waiting, told = _host(mm)
    other, _ = _host(mm)
    waiting.feed(b"1PA5;1WS;1TP\r")
    mm.machine.advance_to(RATE)
    other.feed(b"1ST\r")  # decelerates at AC 5 from 1 unit/s: 0.2 s, 0.1 unit
    mm.machine.advance_to(RATE + round(0.2 * RATE) - 1)
    assert waiting.read() == b""
    mm.machine.advance_to(RATE + round(0.2 * RATE))
    assert told == [RATE + 400] and waiting.read() == b"1TP1.0000\r"


def test_ws_delay_after_the_stop_and_every_axis_without_a_number() -> None:
    mm = _mm()
    host, told = _host(mm)
    host.feed(b"1PA1;2PA2;WS250;1TP;2TP\r")  # WS without a number: both axes
    end1 = round((1 / 5 + 1 / 1) * RATE)  # 1.2 s
    end2 = round((2 / 10 + 2 / 2) * RATE)  # 1.2 s
    later = max(end1, end2) + round(0.250 * RATE)
    mm.machine.advance_to(later - 1)
    assert host.read() == b""
    mm.machine.advance_to(later)
    assert told == [later] and host.read() == b"1TP1.0000\r2TP2.0000\r"


def test_ws_on_an_axis_at_rest_goes_straight_on_and_its_errors() -> None:
    mm = _mm("MM4005-4")
    assert mm.send("1WS;2WS0;1TP") == ["1TP0.0000"] and mm.machine.tick == 0
    for bad, code in (("5WS", "B"), ("1WS-1", "C"), ("1WS1.5", "C"), ("1WS3600001", "C"),
                      ("1WS?", "C")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad


def test_send_from_python_runs_virtual_time_through_the_wait() -> None:
    mm = _mm()
    assert mm.send("1PA2.5;1WS;1TP") == ["1TP2.5000"]
    assert mm.machine.tick == round((0.2 + 2.5) * RATE)


# ---- stored programs ----------------------------------------------------------------------
def _enter(mm: MM4005Controller, number: int, lines: list[str]) -> None:
    assert mm.send(f"{number}EP") == []
    for line in lines:
        assert mm.send(line) == []  # stored, not run: nothing moves, nothing replies
    assert mm.send("QP") == [] and mm.send("TE") == ["TE@"]


def test_program_lines_are_stored_as_entered_not_run() -> None:
    mm = _mm()
    _enter(mm, 7, ["1PA 1", "1WS", "BOGUS", "2TP"])
    assert mm.machine.programs.get(7) == ["1PA 1", "1WS", "BOGUS", "2TP"]
    assert not mm.machine.status(1).moving and mm.send("TE") == ["TE@"]
    # the rest of the EP line is its first line; what follows QP on a line runs
    assert mm.send("8EP;1PA3") == [] and mm.send("1WS;QP;2TP") == ["2TP0.0000"]
    assert mm.machine.programs.get(8) == ["1PA3", "1WS"]


def test_a_program_with_waits_runs_beside_the_command_line_to_the_tick() -> None:
    mm = _mm()
    _enter(mm, 3, ["1PA1", "1WS;2PA2", "2WS", "1PA0;1WS;1TP;2TP"])
    host, told = _host(mm)
    host.feed(b"3EX\r")
    assert host.read() == b"" and not host.holding  # the host is free at once
    # 5 + 9 + 4 + 17 bytes (each line and its terminator); held at line 2's 1WS
    assert mm.console().status_lines()[-1] == (
        "programs stored: 3 (35 of 30720 bytes), program 3 running at line 2")
    one = round((0.2 + 1.0) * RATE)  # axis 1 to 1: 1.2 s
    two = one + round((0.2 + 1.0) * RATE)  # then axis 2 to 2 at VA 2, AC 10: 1.2 s
    back = two + round((0.2 + 1.0) * RATE)  # then axis 1 back to 0: 1.2 s
    mm.machine.advance_to(one + RATE // 2)  # axis 2 started on tick `one`: 0.5 s later
    host.feed(b"2TP;1TP;TX\r")  # 0.5 s into axis 2's move: 0.2 ramp (0.2) + 0.3 at 2 (0.6)
    assert host.read() == b"2TP0.8000\r1TP1.0000\rTXK\r"  # TX bit 0: a program runs
    mm.machine.advance_to(back - 1)
    assert host.read() == b"" and mm.machine.status(1).moving
    mm.machine.advance_to(back)
    assert host.read() == b"1TP0.0000\r2TP2.0000\r" and set(told) == {back}
    assert mm.machine.tasks.program is None and mm.machine.is_idle()
    assert mm.send("TX") == ["TXJ"]


def test_ab_from_a_second_host_ends_a_program_that_waits() -> None:
    mm = _mm()
    _enter(mm, 1, ["2PA10;2WS", "2PA0;2WS"])
    runner, _ = _host(mm)
    stopper, _ = _host(mm)
    runner.feed(b"1EX\r")
    mm.machine.advance_to(RATE)  # 1 s: 0.1 ramp (0.2) + 0.8 at 2 (1.6)
    stopper.feed(b"AB;2TP\r")
    assert stopper.read() == b"2TP1.8000\r" and mm.machine.tasks.program is None
    mm.machine.advance(60 * RATE)
    assert mm.send("2TP;2MS") == ["2TP1.8000", "2MSD"]  # the 2PA0 never ran


def test_program_errors() -> None:
    mm = _mm()
    _enter(mm, 2, ["1PA1;1WS"])
    # program numbers 1..127, else F (manual 3.175 XM's range and error)
    for bad, code in (("EP", "F"), ("0EP", "F"), ("128EP", "F"), ("2EP", "D"), ("QP", "D"),
                      ("9EX", "C"), ("128EX", "F"), ("0XX", "F"), ("2EX4", "C"),
                      ("EP?", "C")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad
    assert mm.send("2EX;2EX") == [] and mm.send("TE") == ["TED"]  # one program at a time
    assert mm.send("2XX") == [] and mm.send("TE") == ["TED"]  # it is running
    mm.run_until_idle()
    assert mm.send("2XX;2XX;TE") == ["TE@"] and mm.machine.programs.get(2) is None


def test_a_program_ends_at_a_refused_command_or_a_malformed_line() -> None:
    mm = _mm()
    _enter(mm, 4, ["1PA0.5", "9PA1", "1PA2"])  # line 2: no axis 9 (B)
    _enter(mm, 5, ["1PA0.5", "1P@", "1PA2"])  # line 2: malformed (A)
    _enter(mm, 6, ["6EP"])  # EP inside a program: refused D
    for number, code in ((4, "B"), (5, "A"), (6, "D")):
        mm.send("1PA0;1WS")
        assert mm.send(f"{number}EX") == []
        mm.run_until_idle()
        assert mm.send("TE") == [f"TE{code}"], number
        assert mm.send("1TP") == ["1TP0.5000" if number != 6 else "1TP0.0000"], number


def test_program_replies_go_to_the_host_that_started_it() -> None:
    mm = _mm()
    _enter(mm, 9, ["1PA1;1WS;1TP"])
    starter, told = _host(mm)
    other, _ = _host(mm)
    starter.feed(b"9EX\r")
    end = round(1.2 * RATE)
    mm.machine.advance_to(end)
    assert starter.read() == b"1TP1.0000\r" and told == [end] and other.read() == b""


def test_program_memory_is_30720_bytes_as_xm_reads_it() -> None:
    mm = _mm()
    line = "1PA1;" * 21 + "1WS"  # 108 characters, 109 with the terminator
    assert mm.send("1EP") == []
    for _ in range(MEMORY // 109):
        mm.send(line)
    assert mm.errors.peek().char == "@"  # (a TE now would be a program line)
    assert mm.send(line) == [] and mm.errors.peek().char == "D"  # memory full: refused
    assert mm.send("QP") == [] and len(mm.machine.programs.get(1) or []) == MEMORY // 109
    left = 30720 - (30720 // 109) * 109
    assert mm.send("XM;0XM;1XM;127XM") == [f"XM{left}", f"XM{left}", f"1XM{30720 - left}",
                                            "127XM0"]


def test_xm_reads_the_memory_and_a_programs_length_as_its_page_says() -> None:
    mm = _mm()
    assert mm.send("XM;1XM;100XM") == ["XM30720", "1XM0", "100XM0"]  # none stored yet
    _enter(mm, 1, ["1PA2", "1WS;1TP"])  # 4 + 1 and 7 + 1 bytes (each line's terminator)
    assert mm.send("XM;1XM") == [f"XM{30720 - 13}", "1XM13"]
    assert mm.send("128XM") == [] and mm.send("TE") == ["TEF"]


def test_ty_reads_a_variable_and_a_command_takes_one_for_a_value() -> None:
    mm = _mm()
    # 3.145: 0 until set; 1..100 integers, 101..120 floats; missing or beyond O, 1.5TY A
    assert mm.send("17TY;100TY;101TY;120TY") == ["17TY0", "100TY0", "101TY0", "120TY0"]
    for bad, code in (("TY", "O"), ("0TY", "O"), ("121TY", "O"), ("1.5TY", "A")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad
    # (YS, which sets one, answers Q: the store is set here as YS would)
    assert mm.send("1YS5") == [] and mm.send("TE") == ["TEQ"]
    mm.machine.variables.set(5, 2)
    mm.machine.variables.set(101, 0.75)
    assert mm.send("5TY;101TY") == ["5TY2", "101TY0.75"]
    assert mm.send("1PA$Y101;1WS;1TP;2VA$y5;2VA?") == ["1TP0.7500", "2VA2.0000"]
    assert mm.send("NB$Y5;NB?") == ["NB2"]  # an integer operand
    assert mm.send("NB$Y101") == [] and mm.send("TE") == ["TEC"]  # 0.75 is not whole
    for bad, code in (("1PA$Y0", "O"), ("1PA$Y121", "O"), ("1PA$Y", "O"), ("1PA$S1", "C"),
                      ("1MO$Y1", "C"), ("1PA$X1", "C")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad
    # read when the command runs: a program line sees the value of its moment
    _enter(mm, 2, ["1PA$Y5;1WS;1TP"])
    mm.machine.variables.set(5, -1)
    assert mm.send("2EX") == []
    mm.run_until_idle()
    assert mm.send("1TP") == ["1TP-1.0000", "1TP-1.0000"]  # the program's, then ours


# ---- the archive ---------------------------------------------------------------------------
def test_stored_programs_survive_a_power_cycle(tmp_path: Path) -> None:
    archive = tmp_path / "mm.programs.json"
    mm = _mm(archive=archive)
    _enter(mm, 12, ["1PA1;1WS", "1TP"])
    mm.reset()
    assert mm.machine.programs.get(12) == ["1PA1;1WS", "1TP"]
    again = MM4005Controller("MM4005-2", archive=archive)  # a new process, the same file
    assert again.machine.programs.get(12) == ["1PA1;1WS", "1TP"]
    again.send("1VA1;1AC5")
    assert again.send("12EX") == []
    again.run_until_idle()
    # the program's own TP went to send()'s session: it comes with the next line's reply
    assert again.send("1TP") == ["1TP1.0000", "1TP1.0000"]
    assert again.send("12XX") == []
    assert MM4005Controller("MM4005-2", archive=archive).machine.programs.get(12) is None


@pytest.mark.parametrize("damage", ["truncate", "edit", "garbage", "foreign", "binary",
                                    "huge", "bad number"])
def test_a_damaged_archive_is_reported_never_a_traceback(
        tmp_path: Path, damage: str, caplog: pytest.LogCaptureFixture) -> None:
    archive = tmp_path / "mm.programs.json"
    store = ProgramStore(archive)
    store.put(1, ["1PA1", "1WS"])
    text = archive.read_text()
    if damage == "truncate":
        archive.write_text(text[: len(text) // 2])
    elif damage == "edit":
        archive.write_text(text.replace("1PA1", "1PA9"))
    elif damage == "garbage":
        archive.write_text("{not json")
    elif damage == "foreign":
        archive.write_text(json.dumps({"format": "something else"}))
    elif damage == "binary":
        archive.write_bytes(b"\xff\xfe\x00\x81" * 50)
    elif damage == "huge":
        archive.write_text(" " * (5 * MEMORY))
    else:
        data = json.loads(text)
        data["programs"] = {"0": ["1PA1"]}
        data["sha256"] = ProgramStore._digest(data["programs"])
        archive.write_text(json.dumps(data))
    with caplog.at_level(logging.ERROR, logger="maxk.mm4005"):
        mm = MM4005Controller("MM4005-2", archive=archive)
    assert mm.machine.programs.programs == {}
    problem = mm.machine.programs.problem
    assert problem is not None and str(archive) in problem
    assert any(str(archive) in r.getMessage() for r in caplog.records)
    assert mm.send("1EX") == [] and mm.send("TE") == ["TEC"]  # nothing stored, it answers
    _enter(mm, 1, ["1TP"])  # the next save writes a whole archive again
    assert ProgramStore(archive).get(1) == ["1TP"] and ProgramStore(archive).problem is None


def test_an_archive_that_cannot_be_written_is_reported(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("")
    mm = _mm(archive=blocker / "sub" / "programs.json")  # a directory under a file
    _enter(mm, 1, ["1TP"])
    assert mm.machine.programs.get(1) == ["1TP"]  # kept in memory
    assert "not written" in (mm.machine.programs.problem or "")


# ---- what a user sees ----------------------------------------------------------------------
def test_help_and_the_command_list_show_the_new_entries() -> None:
    console = MM4005Controller().console()
    for word in ("EP", "QP", "EX", "XX", "WS"):
        lines = console.help(word)
        assert lines is not None and lines[1].endswith("(I)"), word
        assert "ESP300" in lines[1] or "ESP301" in lines[1], word
    assert (console.help("WT") or [""])[0].endswith("(not modelled)")


def test_maxk_commands_shows_the_program_entries_with_source_and_confidence() -> None:
    import subprocess
    import sys

    one = subprocess.run([sys.executable, "-m", "maxk", "commands", "--model", "MM4005", "WS"],
                         capture_output=True, text=True, check=True).stdout
    assert one.startswith("WS: wait for motion stop") and "ESP300 manual p. 3-3" in one
    assert "(I)" in one
