"""PRINT writes a FLOAT with 4 decimals even when it is whole, and an INTEGER bare: the
firmware types its values (TrioBASIC help INT, example 2: ROUND's FLOAT prints with
decimals, INT of it without). Local variables and VRs are FLOAT (help DIM, help VR), as are
TABLE values and the float functions' results; integer literals, comparisons, bit
operations and parameters print bare, so atrio's handshake (?<integer>, ?MPE) holds.
Every number here is our own."""

from __future__ import annotations

import pytest

from tests.trio_helpers import Rig


def ask(rig: Rig, expr: str) -> str:
    return rig.command("?" + expr).decode()


@pytest.mark.parametrize(("expr", "text"), [
    ("ROUND(3.62)", "4.0000"),          # a FLOAT, whole
    ("INT(ROUND(3.62))", "4"),          # INT of it: an INTEGER
    ("SQR(81)", "9.0000"),
    ("VECTOR_MAG(5, 12)", "13.0000"),   # 25 + 144 = 169
    ("SGN(-0.25)", "-1.0000"),
    ("COS(0) * 3", "3.0000"),           # a FLOAT operand makes a FLOAT
    ("25 MOD 7", "4.0000"),             # MOD's page prints its result so
    ("7.5 FMOD 2.5", "0.0000"),
    ("4.0", "4.0000"),                  # a decimal point: a FLOAT literal
    ("2e2", "200.0000"),                # an exponent too
    ("-SQR(16)", "-4.0000"),
    ("ABS(-6.0)", "6.0000"),            # ABS keeps its argument's type
    ("ABS(-6)", "6"),
])
def test_float_results_print_four_decimals_when_whole(expr: str, text: str) -> None:
    assert ask(Rig(), expr) == text


@pytest.mark.parametrize(("expr", "text"), [
    ("654321", "654321"),               # atrio: ?<integer> comes back as typed
    ("40 + 2", "42"),
    ("6 * 7", "42"),
    ("9 / 2", "4.5000"),                # not whole: decimals whatever the type
    ("12 AND 10", "8"),
    ("3 > 2", "-1"),
    ("$1F", "31"),
    ("ASC(\"Z\")", "90"),
    ("MPE", "0"),                       # atrio reads it with int()
    ("DPOS", "0"),                      # parameters print as before (pages disagree, D)
])
def test_integers_and_parameters_print_bare(expr: str, text: str) -> None:
    assert ask(Rig(), expr) == text


def test_variables_and_vrs_are_float() -> None:
    rig = Rig()
    rig.command("speed_mm = 120")
    assert ask(rig, "speed_mm") == "120.0000"   # a local variable: FLOAT (help DIM)
    assert ask(rig, "unset_name") == "0.0000"   # never assigned: a FLOAT 0
    rig.command("VR(31) = 8")
    assert ask(rig, "VR(31)") == "8.0000"       # a VR: 64-bit floating point (help VR)
    assert ask(rig, "VR(31)[0]") == "8"         # [0]: the way programs print it bare
    rig.command("TABLE(4, 75)")
    assert ask(rig, "TABLE(4)") == "75.0000"


def test_dim_types_and_function_types_decide() -> None:
    rig = Rig()
    rig.load("P", "\n".join([
        "DIM whole AS INTEGER", "DIM real_v AS FLOAT", "DIM row AS INTEGER(2)",
        "whole = 9.7", "real_v = 3", "row(1) = 5", "FOR k = 1 TO 1", "NEXT k",
        "PRINT whole; \" \"; real_v; \" \"; row(1); \" \"; k; \" \"; half(9); \" \"; "
        "twice(4)",
        "FUNCTION half(v AS INTEGER) AS FLOAT", "  RETURN v / 2", "ENDFUNC",
        "FUNCTION twice(v AS FLOAT) AS INTEGER", "  RETURN v * 2", "ENDFUNC"]))
    rig.command('RUN "P"')
    # INTEGER 9 (9.7 truncated), FLOAT 3, an INTEGER element, the loop counter (a FLOAT
    # variable, 2 after its last NEXT), half: 4.5 as a FLOAT, twice: 8 as an INTEGER
    assert rig.cycles(10) == b"9 3.0000 5 2.0000 4.5000 8\r\n"


def test_print_formats_still_decide_the_decimals() -> None:
    rig = Rig()
    rig.command("x = 2")
    assert ask(rig, "x[0]; \" \"; x[6, 2]; \" \"; STR(x, 0)") == "2   2.00 2"
