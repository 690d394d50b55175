"""RUN_ERROR and ERROR_LINE as the RUN_ERROR help page numbers them: after an error stops a
program (read with PROC(n) from the command line), after a normal stop (31), and inside an
ON BASICERROR handler. The expected numbers are the page's, written here by hand."""

from __future__ import annotations

import pytest

from tests.trio_helpers import Rig


def ask(rig: Rig, question: str) -> str:
    return rig.command(question).decode().strip()


def stopped_on_5(program: str, cycles: int = 20) -> Rig:
    rig = Rig()
    rig.load("P", program)
    rig.command('RUN "P",5')
    rig.cycles(cycles)
    return rig


def test_a_divide_by_zero_that_stopped_process_5_reads_9() -> None:
    """The page's first example: ?RUN_ERROR PROC(5) after a divide by zero answers 9."""
    rig = stopped_on_5("a = 2\nb = 0\nc = a / b\nPRINT c")
    assert ask(rig, "?PROC_STATUS PROC(5)") == "0"
    assert ask(rig, "?RUN_ERROR PROC(5)") == "9"
    assert ask(rig, "?ERROR_LINE PROC(5)") == "3"


@pytest.mark.parametrize(("program", "number", "line"), [
    ("x = 1\nx = 10 ^ 400", 141, 2),  # Numerical error: Invalid Floating-Point operation
    ("UNITS AXIS(0) = 0", 19, 1),  # Parameter out of range
    ("x = 1\nRETURN", 50, 2),  # RETURN without GOSUB
    ("DIM a(3)\na(3) = 1", 19, 2),  # an array index past the DIM: out of range (D)
    ("x = 1\nBASE(99)", 19, 2),  # an axis the controller has not (D)
    ("MPOS AXIS(0) = 5", 21, 1),  # Value is read only
])
def test_each_error_reads_the_pages_number(program: str, number: int, line: int) -> None:
    rig = stopped_on_5(program)
    assert (ask(rig, "?RUN_ERROR PROC(5)"), ask(rig, "?ERROR_LINE PROC(5)")) == \
        (str(number), str(line))


def test_a_normal_end_stop_and_halt_read_31() -> None:
    """Page: 31 is a normal completion ("Program is stopped")."""
    rig = stopped_on_5("VR(1) = 7")
    assert ask(rig, "?VR(1)") == "7.0000"
    assert ask(rig, "?RUN_ERROR PROC(5)") == "31"
    for stop in ('STOP "P"', "HALT"):
        rig.load("P", "WHILE 1\nWA(1)\nWEND")
        rig.command('RUN "P",5')
        rig.cycles(3)
        assert ask(rig, "?PROC_STATUS PROC(5)") == "8"  # SLEEP in its WA(1) (page)
        assert ask(rig, "?RUN_ERROR PROC(5)") == "0"  # running: no error yet
        rig.command(stop)
        assert ask(rig, "?RUN_ERROR PROC(5)") == "31"


def test_a_process_that_never_ran_reads_0() -> None:
    rig = Rig()
    assert ask(rig, "?RUN_ERROR PROC(7)") == "0"
    assert ask(rig, "?ERROR_LINE PROC(7)") == "0"


def test_an_error_after_a_caught_one_stops_with_its_own_number_and_line() -> None:
    """ON BASICERROR catches the first (page numbers 19), the handler's own error (a
    divide by zero, 9) stops the program: PROC(5) reads the second."""
    rig = stopped_on_5("ON BASICERROR GOTO h\nSPEED AXIS(0) = -1\nh:\n"
                       "VR(2) = RUN_ERROR\nVR(3) = ERROR_LINE\nx = 1 / 0")
    assert (ask(rig, "?VR(2)"), ask(rig, "?VR(3)")) == ("19.0000", "2.0000")
    assert (ask(rig, "?RUN_ERROR PROC(5)"), ask(rig, "?ERROR_LINE PROC(5)")) == ("9", "6")


def test_the_pages_handler_selects_on_run_error() -> None:
    """The page's second example: a SELECT_CASE on RUN_ERROR in an ON BASICERROR handler."""
    rig = Rig()
    rig.load("P", "\n".join([
        "ON BASICERROR GOTO report",
        "n = 0",
        "r = 10 / n",
        "STOP",
        "report:",
        "SELECT_CASE RUN_ERROR",
        "  CASE 1",
        '    PRINT "not recognised"',
        "  CASE 9",
        '    PRINT "zero divide at "; ERROR_LINE[0]',
        "  CASE ELSE",
        '    PRINT "other "; RUN_ERROR[0]',
        "END_CASE",
        "STOP"]))
    rig.command('RUN "P"')
    assert rig.cycles(10) == b"zero divide at 3\r\n"
