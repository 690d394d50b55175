"""The MM4005's flow-control, variable-setting and program-listing commands whose pages
were searched for again and not found (WT WP UH UL DL JL LP ... YA..YY): each stays Q,
says so in `help`, and refuses without acting, on a command line and inside a stored
program, where the refusal ends the program on that line.

Times are worked by hand from the trapezoid: VA 1, AC 5, a move of 2 units takes
1/5 + 2/1 = 2.2 s, 4400 ticks at 2000 Hz."""

from __future__ import annotations

import pytest

from maxk.commands.mm4005.manual_list import GROUP
from maxk.commands.mm4005.table import COMMANDS, SEARCHED_AGAIN
from maxk.controllers.mm4005.controller import MM4005Controller

RATE = 2000  # ticks a second
PRIORITY = ("WT", "WP", "UH", "UL", "DL", "JL", "LP")  # the ones asked for first


def _mm() -> MM4005Controller:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("1VA1;1AC5;2VA2;2AC10") == []
    return mm


def test_the_searched_commands_are_the_flow_variable_and_program_groups_and_answer_q() -> None:
    assert set(PRIORITY) <= SEARCHED_AGAIN and len(SEARCHED_AGAIN) == 43
    assert {GROUP[w] for w in SEARCHED_AGAIN} == {
        "sequencing and flow control", "variables", "programming"}
    for word in SEARCHED_AGAIN:
        spec = COMMANDS[word]
        assert spec.confidence == "I" and spec.note.endswith("answers Q"), word
        assert "MM4005, MM4006 or ESP300 manual pages (searched again" in spec.note, word
    # the ones the machinery already models are not among them
    assert not SEARCHED_AGAIN & {"EP", "QP", "EX", "XX", "XM", "WS", "TY"}


@pytest.mark.parametrize("word", PRIORITY)
def test_help_says_the_page_was_searched_for_and_not_found(word: str) -> None:
    lines = MM4005Controller().console().help(word)
    assert lines is not None and lines[0].endswith("(not modelled)")
    assert lines[2].startswith("  note: ") and "not found in the MM4005, MM4006" in lines[2]


def test_a_refused_wait_ends_its_line_there_and_nothing_after_it_runs() -> None:
    mm = _mm()
    assert mm.send("1PA2;1WT500;2PA3") == [] and mm.send("TE") == ["TEQ"]
    assert mm.machine.status(1).moving and not mm.machine.status(2).moving
    mm.machine.advance_to(round(2.2 * RATE))
    assert mm.send("1TP;2TP") == ["1TP2.0000", "2TP0.0000"]
    for line in ("1WP1.5", "1UH", "3UL", "1DL", "1JL5", "1LP", "1YA3", "AS"):
        assert mm.send(f"1TP;{line};2TP") == ["1TP2.0000"], line
        assert mm.send("TE") == ["TEQ"], line
    assert mm.send("TE") == ["TE@"]  # read once, the register is clear


def test_a_stored_program_stops_at_the_unmodelled_line_with_its_error() -> None:
    mm = _mm()
    assert mm.send("1EP") == []
    for line in ("1PA2", "1WS", "1WT500", "1PA0"):
        assert mm.send(line) == []  # stored as entered, not evaluated
    assert mm.send("QP") == [] and mm.send("TE") == ["TE@"]
    assert mm.send("1EX") == [] and mm.machine.status(1).moving
    end = round(2.2 * RATE)  # 4400: the WS of line 2 ends, line 3 is refused
    mm.machine.advance_to(end - 1)
    assert mm.send("TE") == ["TE@"] and mm.machine.tasks.program is not None
    mm.machine.advance_to(end)
    assert mm.machine.tasks.program is None  # ended at line 3
    assert mm.send("TE") == ["TEQ"]
    mm.machine.advance_to(end + 10 * RATE)  # line 4 (1PA0) never ran
    assert mm.send("1TP") == ["1TP2.0000"] and not mm.machine.status(1).moving
