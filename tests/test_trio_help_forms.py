"""Language forms the TrioBASIC help's own examples use, which a run of every page's
examples (tools/trio_corpus_check.py) showed stopping: the default BASE array, the FMOD
operator, a FOR loop counting in a VR, a STRING declared without a length. Each test is
written from what the keyword's page says happens, with numbers of our own."""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405
from tests.trio_helpers import Rig


def run(program: str, cycles: int = 50, rig: Rig | None = None) -> str:
    rig = rig or Rig()
    rig.load("P", program)
    rig.command('RUN "P"')
    return rig.cycles(cycles).decode()


# ---- BASE: the default array is 0, 1, 2, ... (help BASE) ---------------------------------

def test_a_two_axis_move_with_no_base_set_runs_on_axes_0_and_1() -> None:
    out = run("MOVEABS(12, -7)\nWAIT IDLE\nPRINT DPOS AXIS(0); \" \"; DPOS AXIS(1)",
              cycles=3000)
    assert out == "12 -7\r\n"


def test_base_of_one_axis_goes_on_with_the_next_axes() -> None:
    # BASE(2) makes the array 2, 3, 4, ...: the second and third distances go to 3 and 4
    out = run("BASE(2)\nMOVE(5, 6, 7)\nWAIT IDLE\n"
              "PRINT DPOS AXIS(2); \" \"; DPOS AXIS(3); \" \"; DPOS AXIS(4); \" \"; "
              "DPOS AXIS(0)", cycles=3000)
    assert out == "5 6 7 0\r\n"


def test_base_wraps_round_to_axis_0_after_the_last_axis() -> None:
    rig = Rig(axis_count=4)
    out = run("BASE(3)\nMOVE(2, 9)\nWAIT IDLE\nPRINT DPOS AXIS(3); \" \"; DPOS AXIS(0)",
              cycles=3000, rig=rig)
    assert out == "2 9\r\n"


# ---- FMOD (help FMOD): the floating point remainder, with the dividend's sign ---------------

@pytest.mark.parametrize(("expr", "text"), [
    ("10.5 FMOD 4", "2.5000"),      # 10.5 - 2 x 4
    ("-7.5 FMOD 2", "-1.5000"),     # -7.5 + 3 x 2: the sign of -7.5
    ("7.5 FMOD -2", "1.5000"),      # the divisor's sign does not matter
    ("1 + 9 FMOD 4", "2.0000"),     # FMOD binds before + (as MOD): 1 + 1, a FLOAT
    ("2 * 9 FMOD 4", "2.0000"),     # and left to right with *: 18 FMOD 4
])
def test_fmod(expr: str, text: str) -> None:
    assert Rig().command("?" + expr).decode() == text


def test_fmod_by_zero_is_divide_by_zero() -> None:
    out = run("x = 5 FMOD 0\nPRINT \"after\"")
    assert "Divide by zero" in out and "after" not in out


# ---- FOR VR(n) = a TO b ... NEXT VR(n) (help VR, example 2) -------------------------------

def test_for_can_count_in_a_vr() -> None:
    out = run("n = 0\nFOR VR(7) = 20 TO 26 STEP 3\n  VR(VR(7)) = 1\n  n = n + 1\nNEXT VR(7)\n"
              "PRINT n; \" \"; VR(7); \" \"; VR(20) + VR(23) + VR(26) + VR(21)")
    # 20, 23, 26: three turns; the counter ends one step past the end (29)
    assert out == "3.0000 29.0000 3.0000\r\n"  # variables and VRs are FLOAT


def test_for_vr_counter_is_the_vr_another_program_sees() -> None:
    rig = Rig()
    rig.load("P", "FOR VR(3) = 1 TO 5\n  WA(10)\nNEXT VR(3)")
    rig.command('RUN "P"')
    rig.cycles(25)  # in its third turn: VR(3) = 3
    assert rig.command("?VR(3)") == b"3.0000"


# ---- DIM s AS STRING with no length (help CHR and HEX examples) ---------------------------

def test_a_string_declared_without_a_length_holds_text() -> None:
    out = run('DIM s AS STRING\ns = "ab" + CHR(90) + HEX(255)\nPRINT s; " "; LEN(s)')
    assert out == "abZFF 5\r\n"


# ---- PRINT formats (help PRINT): [d], [w, d], C format strings ------------------------------

def test_print_one_bracketed_value_is_the_decimals() -> None:
    # the page: [d] is the number of decimal places; [w, d] a width and decimals
    out = run('x = 2.71828\nPRINT x[3]; "|"; x[0]; "|"; x[7, 2]; "|"; x[-7, 2]; "|"')
    assert out == "2.718|3|   2.72|2.72   |\r\n"


@pytest.mark.parametrize(("spec", "value", "text"), [
    ("<%L>", "-42.9", "<-42>"),                  # a 64-bit integer, truncated
    ("<%+8L>", "300", "<    +300>"),
    ("<%08L>", "-17", "<-0000017>"),
    ("<%X>", "3054", "<BEE>"),
    ("<%+6X>", "255", "<    FF>"),                # no sign for hexadecimal
    ("<%W>", "-1", "<18446744073709551615>"),     # 2^64 - 1: unsigned 64-bit
    ("<%f>", "0.5", "<0.5000>"),                  # 4 decimals unless told
    ("<%.1f>", "0.25", "<0.2>"),
    ("<%-9.3f>", "3.14159", "<3.142    >"),
    ("<%+010.1f>", "-8.25", "<-0000008.2>"),
    ("<%e>", "-0.000123", "<-1.2300e-04>"),
    ("<%.1E>", "98765", "<9.9E+04>"),
    ("<%C>", "65", "<A>"),
    ("<%-3c>", "66", "<B  >"),
])
def test_print_c_format_of_a_number(spec: str, value: str, text: str) -> None:
    assert run(f'PRINT ({value})["{spec}"]') == text + "\r\n"


def test_print_c_format_of_a_string_and_text_around_it() -> None:
    out = run('DIM s AS STRING(20)\ns = "motion"\n'
              'PRINT s["[%S]"]; s["[%9S]"]; s["[%-9S]"]; s["[%.3S]"]; s["[%6.2R]"]')
    assert out == "[motion][   motion][motion   ][mot][    mo]\r\n"


@pytest.mark.parametrize("line", ['PRINT 1["no conversion"]', 'PRINT 1["%L %L"]',
                                  'PRINT 1["%q"]', "PRINT 1[-3]", "PRINT 1[2.5, 1]"])
def test_print_bad_formats_are_syntax_errors(line: str) -> None:
    rig = Rig()
    rig.command('SELECT "P",0')
    rig.command(f"!P,0R{line}")
    assert b"Syntax error" in rig.send("COMPILE")


# ---- a loop of moves that end where they start (help IN, example 2) -----------------------

def test_a_loop_of_zero_moves_and_wait_idle_takes_servo_cycles_not_forever() -> None:
    """MOVEABS to where the axis is ends on the tick it loads; WAIT IDLE then passes. The
    loop still gives up the servo cycle every few wakes, so time goes on (it hung the
    emulator in one tick before: each zero move's end woke the process again)."""
    trio = MC405()
    trio.programs.create("P", 0)
    for n, line in enumerate(["n = 0", "WHILE n < 40", "  MOVEABS(0)", "  WAIT IDLE",
                              "  n = n + 1", "WEND", "VR(9) = n"]):
        trio.programs.edit("P", n, "R", line)
    session = trio.open_session()
    session.feed(b'RUN "P"\r')
    trio.advance(ticks=2)
    assert trio.runtime.tasks  # 40 passes do not fit in a tick or two (8 wakes a tick)
    trio.advance(ticks=100)
    assert trio.query("?VR(9)") == "40.0000"
    assert trio.runtime.tasks == {}


# ---- name(i) = v0, v1, ...: a row of an array (help Array Indexing, example 3) ------------

def test_a_row_of_a_two_dimensional_array_is_set_from_a_list() -> None:
    out = run("DIM m AS FLOAT(3, 2)\nm(2) = 5, 6\nm(0) = 1\n"
              "PRINT m(0, 0); m(0, 1); m(1, 0); m(1, 1); m(2, 0); m(2, 1)")
    assert out == "1.00000.00000.00000.00005.00006.0000\r\n"  # FLOAT elements


def test_a_list_from_an_element_fills_on_to_the_end_of_the_row() -> None:
    out = run("DIM v AS INTEGER(5)\nv(3) = 8.9, 7\nPRINT v(2); v(3); v(4)\n"
              "DIM w AS FLOAT(2, 3)\nw(0, 1) = 4, 3\nPRINT w(0, 1); w(0, 2); w(1, 0)")
    assert out == "087\r\n4.00003.00000.0000\r\n"  # INTEGER elements take 8.9 as 8


@pytest.mark.parametrize("line", ["m(1) = 1, 2, 3", "m(3) = 1, 2", "m(0, 1) = 1, 2"])
def test_a_list_longer_than_its_row_changes_nothing(line: str) -> None:
    out = run(f"DIM m AS FLOAT(3, 2)\nm(0) = 4, 4\n{line}\nPRINT \"not here\"",
              rig=None)
    assert "Array index out of range" in out and "not here" not in out


# ---- CONSTANT "name" / GLOBAL "name" alone clear that one; the keyword alone all ----------

def test_constant_and_global_named_alone_are_cleared() -> None:
    rig = Rig()
    out = run('CONSTANT "lim", 40\nCONSTANT "gap", 3\nGLOBAL "count", 12\n'
              'GLOBAL "spare", 13\ncount = 8\nCONSTANT "lim"\nGLOBAL "spare"\n'
              "lim = 1\nspare = 2\nPRINT lim; gap; count; spare; VR(13)", rig=rig)
    # lim and spare are plain variables again; gap and count are still declared
    assert out == "1.000038.00002.00000.0000\r\n"  # gap: the CONSTANT 3 as written


def test_global_alone_clears_every_global() -> None:
    out = run('GLOBAL "a1", 20\nGLOBAL "a2", 21\nGLOBAL\na1 = 5\na2 = 6\n'
              "PRINT a1; a2; VR(20); VR(21)")
    assert out == "5.00006.00000.00000.0000\r\n"


# ---- VR(n) = "text" (help VR, example 4) ---------------------------------------------------

def test_a_string_into_vrs_one_character_code_each_then_0() -> None:
    out = run('VR(40) = "Cut 7"\nPRINT VR(40); " "; VR(43); " "; VR(44); " "; VR(45); '
              '" "; VRSTRING(40)')
    assert out == "67.0000 32.0000 55.0000 0.0000 Cut 7\r\n"  # C, space, 7, the 0 after them


def test_a_string_past_the_last_vr_writes_nothing() -> None:
    out = run('VR(65534) = 9\nVR(65533) = "abc"\nPRINT "not here"\n')
    assert "Parameter out of range" in out and "not here" not in out
    rig = Rig()
    rig.load("P", 'VR(65534) = 9\nVR(65533) = "abc"')
    rig.command('RUN "P"')
    rig.cycles(10)
    assert rig.command("?VR(65533); VR(65534)") == b"0.00009.0000"


# ---- x[w.d]: the REGIST and MARK pages write the width and decimals so (D) ----------------

def test_print_width_dot_decimals() -> None:
    assert run('x = 12.345\nPRINT "<"; x[8.1]; ">"') == "<    12.3>\r\n"


# ---- ROUND, ULPDIFF, LENB (their help pages) -------------------------------------------------

@pytest.mark.parametrize(("expr", "text"), [
    ("ROUND(2.5)", "3.0000"),          # INT(2.5 + 0.5)
    ("ROUND(-2.5)", "-3.0000"),        # INT(-2.5 - 0.5): away from zero both ways
    ("ROUND(7.49)", "7.0000"),
    ("ROUND(2.71828, 2)", "2.7200"),   # INT(271.828 + 0.5) / 100
    ("ROUND(-2.71828, 3)", "-2.7180"),  # INT(-2718.28 - 0.5) / 1000
    ("ROUND(86420, -2)", "86400.0000"),     # INT(864.2 + 0.5) x 100
    ("ROUND(49, -2)", "0.0000"),
    ("ULPDIFF(1, 1)", "0"),
    ("ULPDIFF(1, 1 + 2^-52)", "1"),    # the next double after 1
    ("ULPDIFF(2 + 2^-50, 2)", "2"),    # above 2 a step is 2^-51
    ("ULPDIFF(-2^-1074, 2^-1074)", "2"),  # across zero: -min, 0, +min
    ('LENB("abc")', "3"),
])
def test_round_ulpdiff_lenb(expr: str, text: str) -> None:
    assert Rig().command("?" + expr).decode() == text


def test_round_of_a_string_is_a_type_mismatch() -> None:
    assert "Type mismatch" in run('x = ROUND("7")\nPRINT "not here"')


# ---- SET_BIT / CLEAR_BIT / READ_BIT with mode 1: a TABLE value (their help pages) ----------

def test_bit_functions_on_table_with_mode_1() -> None:
    out = run("TABLE(30, 8)\nVR(30) = 8\nSET_BIT(0, 30, 1)\nCLEAR_BIT(3, 30, 1)\n"
              "SET_BIT(1, 30, 0)\n"
              "PRINT TABLE(30); \" \"; VR(30); \" \"; READ_BIT(0, 30, 1); READ_BIT(0, 30)")
    # a TABLE value is FLOAT; TABLE 8 -> 9 -> 1; VR 8 -> 10 (mode 0 is the VR)
    assert out == "1.0000 10.0000 10\r\n"


def test_a_bit_function_mode_other_than_0_or_1_is_refused() -> None:
    out = run("TABLE(2, 0)\nSET_BIT(0, 2, 2)\nPRINT \"not here\"")
    assert "Parameter out of range" in out and "not here" not in out


# ---- IS_PROG "text" + name: a joined name after the keyword (help IS_PROG) ----------------

def test_is_prog_takes_a_joined_name() -> None:
    rig = Rig()
    rig.command('SELECT "CUT2",0')
    out = run('n = "2"\nPRINT IS_PROG "CUT" + n; IS_PROG "CUT" + "3"; IS_PROG "CUT2"', rig=rig)
    assert out == "-10-1\r\n"
