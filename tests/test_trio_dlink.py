"""DLINK on the MC405 (TrioBASIC help DLINK): no SLM module answers, so every function
returns what the page gives for that case, and a bad call is refused with nothing done."""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405


@pytest.mark.parametrize(("call", "reply"), [
    ("DLINK(2,0,0)", "0"),  # is an SLM module on slot 0, channel 0? no
    ("DLINK(3,1,2)", "0"),  # is an SLM drive there? no
    ("DLINK(4,0,0,3)", "0"),  # assign axis 3 to it: FALSE
    ("DLINK(5,0,1)", "-1"),  # read SLM parameter 1 of axis 0: the command fails
    ("DLINK(6,0,0,0)", "0"),  # write an SLM parameter: FALSE
    ("DLINK(7,0,250)", "0"),  # write SLM command 250: FALSE
    ("DLINK(8,0,53248)", "-1"),  # read a drive parameter: fails
    ("DLINK(9,2)", "-1"),  # slot and channel of axis 2: fails
    ("DLINK(10,0,29)", "-1"),  # read an EEPROM parameter: fails
])
def test_each_function_answers_as_with_no_slm_present(call: str, reply: str) -> None:
    assert MC405().send("?" + call) == [f"{float(reply):.4f}"]  # FLOAT (page: 463.0000)


def test_a_failed_assignment_leaves_the_axis_type() -> None:
    trio = MC405()
    trio.send("ATYPE AXIS(3) = 77")
    assert trio.send("DLINK(4,0,0,3)") == []  # as a command: accepted, nothing returned
    assert trio.query("?ATYPE AXIS(3)") == "77"  # not 11: the assignment failed


def test_a_set_up_program_sees_the_drive_missing() -> None:
    trio = MC405()
    trio.load("SETUP", "IF DLINK(2,0,0) = 1 THEN\n  VR(10) = 1\nELSE\n  VR(10) = 2\nENDIF\n"
              "ok = DLINK(4,0,0,0)\nVR(11) = ok\nVR(12) = DLINK(9,0)\n")
    trio.send('RUN "SETUP"')
    trio.advance(0.01)
    assert [trio.query(f"?VR({n})") for n in (10, 11, 12)] == ["2.0000", "0.0000", "-1.0000"]


@pytest.mark.parametrize(("call", "error"), [
    ("DLINK(0,0)", "Parameter out of range"),  # reserved
    ("DLINK(1,0)", "Parameter out of range"),  # reserved
    ("DLINK(11,0)", "Parameter out of range"),
    ("DLINK(2.5,0,0)", "Parameter out of range"),
    ("DLINK(5,64,1)", "Parameter out of range"),  # no axis 64
    ("DLINK(4,0,0,-1)", "Parameter out of range"),
    ("DLINK(2,-1,0)", "Parameter out of range"),
    ("DLINK(9,2,3)", "Syntax error"),  # function 9 takes the axis only
    ("DLINK(4,0,0)", "Syntax error"),  # function 4 needs the axis
])
def test_bad_calls_are_refused(call: str, error: str) -> None:
    trio = MC405()
    assert trio.send("?" + call) == ["! " + error]
    assert trio.send(call) == ["! " + error]
