"""TrioBASIC forms that real controller programs use (a sample of public programs showed
each of them), written here from the language rules: declarations of several names,
arrays of several dimensions, ON ... GOSUB, shifts and bits, channels and files, BASIC
libraries, parameters with arguments, and the command line's line ends. Each runs on the
fake machine through the command line as atrio uploads and runs a program."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from maxk.commands.trio.keywords import KEYWORDS
from maxk.commands.trio.lexer import TrioError
from maxk.commands.trio.parser import parse_line
from maxk.commands.trio.programs import check_name
from maxk.commands.trio.tasks import compile_program, join_continued
from tests.trio_helpers import AtrioError, Rig


def run(program: str, cycles: int = 50, rig: Rig | None = None) -> str:
    rig = rig or Rig()
    rig.load("P", program)
    rig.command('RUN "P"')
    return rig.cycles(cycles).decode()


# ---- ON expr GOSUB / GOTO ----------------------------------------------------------------

@pytest.mark.parametrize(("choice", "printed"), [(1, "a\r\n"), (2, "b\r\n"), (3, "c\r\n"),
                                                 (0, ""), (4, ""), (1.5, ""), (-1, "")])
def test_on_gosub_takes_the_nth_label_and_goes_on_when_out_of_range(
        choice: float, printed: str) -> None:
    out = run(f"""n = {choice}
ON n GOSUB first, second, third
PRINT "back"
STOP
first:
PRINT "a"
RETURN
second:
PRINT "b"
RETURN
third:
PRINT "c"
RETURN""")
    assert out == printed + "back\r\n"


def test_on_goto_jumps_and_works_inside_a_one_line_if() -> None:
    out = run("""k = 2
IF k > 0 THEN ON k GOTO one, two
PRINT "none"
STOP
one:
PRINT "one"
STOP
two:
PRINT "two\"""")
    assert out == "two\r\n"


def test_on_gosub_with_a_missing_label_fails_at_compile() -> None:
    rig = Rig()
    rig.command('SELECT "P",0')
    rig.command("!P,0RON 1 GOSUB here, nowhere")
    rig.command("!P,1Rhere:")
    assert rig.send("COMPILE").split(b"\r\n")[1] == b"%[Program P Line 1] - Label not found"


def test_on_with_a_keyword_as_label_is_a_syntax_error() -> None:
    with pytest.raises(TrioError):
        parse_line("ON n GOSUB MOVE, b")


# ---- DIM ---------------------------------------------------------------------------------

def test_dim_declares_several_names_with_one_type_and_initial_value() -> None:
    assert run("DIM a, b AS INTEGER = 7.9\nDIM ok AS BOOLEAN = 5\nPRINT a; b; ok") == \
        "77-1\r\n"


def test_dim_size_after_the_type_and_a_list_filling_the_array() -> None:
    out = run("""DIM v AS INTEGER(4)
v = 1.5, 2, 3
PRINT v(0); v(1); v(2); v(3)
v = 1, 2, 3, 4, 5""")
    assert out == "1230\r\n%[Process 19:Program P Line 4] - Array index out of range\r\n"


def test_two_dimension_arrays_are_indexed_row_by_row() -> None:
    out = run("""DIM m AS FLOAT(2, 3)
FOR i = 0 TO 1
  FOR j = 0 TO 2
    m(i, j) = 10 * i + j
  NEXT j
NEXT i
PRINT m(1, 2); m(0, 1)
DIM t(2, 2)
t = 4, 5, 6
PRINT t(1, 0)
PRINT m(2, 0)""", cycles=60)
    assert out == ("12.00001.0000\r\n6.0000\r\n"  # FLOAT elements (DIM: the default)
                   "%[Process 19:Program P Line 11] - Array index out of range\r\n")


def test_an_element_with_the_wrong_number_of_indices_is_refused() -> None:
    assert run("DIM m(2, 2)\nPRINT m(1)").endswith(
        "Line 2] - Variable not defined\r\n")


@pytest.mark.parametrize("line", ["DIM a, a", "DIM a(2), b(3)", "DIM MOVE",
                                  "DIM a AS INTEGER(2)(3)", "DIM a AS DOUBLE"])
def test_bad_dims_are_syntax_errors(line: str) -> None:
    with pytest.raises(TrioError):
        parse_line(line)


# ---- operators: shifts and bits -------------------------------------------------------------

@given(st.integers(0, 2 ** 40), st.integers(0, 20))
def test_shifts_follow_the_integer_rule(value: int, places: int) -> None:
    rig = Rig()
    assert rig.command(f"?{value} << {places}") == str(value << places).encode()
    assert rig.command(f"?{value} >> {places}") == str(value >> places).encode()


@given(st.integers(0, 2 ** 30), st.integers(0, 31))
def test_a_bit_of_a_variable_an_element_or_a_bracket(value: int, bit: int) -> None:
    expected = (value >> bit) & 1
    out = run(f"x = {value}\nDIM a(2)\na(1) = x\nPRINT x.{bit}; a(1).{bit}; (x + 0).{bit}",
              cycles=5)
    assert out == f"{expected}{expected}{expected}\r\n"


def test_shift_binds_looser_than_plus_and_tighter_than_comparison() -> None:
    rig = Rig()
    assert rig.command("?1 << 2 + 1") == b"8"
    assert rig.command("?(256 >> 4) AND $FF") == b"16"
    assert rig.command("?1 << 3 = 8") == b"-1"
    with pytest.raises(AtrioError):
        rig.command("?1 << 64")  # Arithmetic error: no such shift


# ---- continuation, CR and comments ------------------------------------------------------------

def test_a_line_continues_after_any_character_that_is_not_part_of_a_name() -> None:
    lines = ["x = 1 +_", "2", "y = f(a)_ ' a comment", "+ 1", "my_ = 3"]
    assert join_continued(lines) == [(1, "x = 1 + 2"), (3, "y = f(a) + 1"), (5, "my_ = 3")]


def test_a_windows_line_end_inside_a_program_line_is_a_blank() -> None:
    assert parse_line("PRINT 1\r") == parse_line("PRINT 1")
    steps = compile_program(["a = 1\r", "IF a THEN\r", "PRINT a\r", "ENDIF\r"])
    assert len(steps) == 4


# ---- declarations -----------------------------------------------------------------------------

def test_defconst_is_a_constant_and_constant_alone_clears_them() -> None:
    rig = Rig()
    out = run("DEFCONST top 12.5\nDEFCONST low = -1\nPRINT top; low\nCONSTANT\nPRINT top",
              rig=rig)
    assert out == "12.5000-1\r\n0.0000\r\n"


# ---- channels ------------------------------------------------------------------------------------

def test_open_reads_a_text_program_with_key_get_input_and_linput() -> None:
    rig = Rig()
    rig.load("0123", "12,7\nhello there\nXY", program_type=3)
    out = run("""OPEN #41 AS "0123" FOR INPUT
INPUT #41, a, b
LINPUT #41, s
GET #41, c
PRINT a; " "; b; " "; s; " "; c
n = 0
WHILE KEY #41
  GET #41, c
  n = n + 1
WEND
PRINT n; KEY#41
CLOSE #41
PRINT KEY #41""", rig=rig)
    assert out == "12.0000 7.0000 hello there 88.0000\r\n3.00000\r\n0\r\n"  # FLOAT variables


def test_channel_errors_and_a_terminal_that_never_types() -> None:
    rig = Rig()
    out = run('OPEN #40 AS "MISSING" FOR INPUT', rig=rig)
    assert out.endswith("Line 1] - Program not found\r\n")
    rig.load("T", "x", program_type=3)
    out = run('OPEN #40 AS "T" FOR INPUT\nOPEN #40 AS "T" FOR INPUT', rig=Rig())
    assert out.endswith("Line 1] - Program not found\r\n")
    out = run('OPEN #40 AS "T" FOR INPUT\nOPEN #40 AS "T" FOR INPUT', rig=rig)
    assert out.endswith("Line 2] - Channel already open\r\n")
    rig = Rig()
    out = run('PRINT KEY #0\nGET #0, k\nPRINT "never"', cycles=100, rig=rig)
    assert out == "0\r\n"  # no character ever arrives: GET waits
    assert b"Running" in rig.command("PROCESS")


@pytest.mark.parametrize("line", ['OPEN #1 AS "F"', 'OPEN 1 AS "F" FOR INPUT',
                                  'OPEN #1 AS "F" FOR SOMETHING', "GET #1", "GET #1, MOVE",
                                  "INPUT #1, 3"])
def test_bad_channel_statements_are_syntax_errors(line: str) -> None:
    with pytest.raises(TrioError):
        parse_line(line)


# ---- BASIC libraries and FUNCTION arrays --------------------------------------------------------

def test_a_library_function_is_called_by_name_from_any_program() -> None:
    rig = Rig()
    rig.load("MATHLIB", "FUNCTION twice(x AS INTEGER) AS INTEGER\nRETURN 2 * x\nENDFUNC",
             program_type=12)
    assert run("PRINT twice(21)", rig=rig) == "42\r\n"
    assert run("PRINT thrice(1)", rig=rig).endswith("Line 1] - Variable not defined\r\n")


def test_an_array_passed_alone_goes_by_reference() -> None:
    out = run("""DIM data AS INTEGER(3)
ok = fill(data, 5)
PRINT ok; data(0); data(2)
FUNCTION fill(values AS INTEGER(), start AS INTEGER) AS BOOLEAN
  FOR k = 0 TO 2
    values(k) = start + k
  NEXT k
  RETURN TRUE
ENDFUNC""")
    assert out == "-1.000057\r\n"  # ok is a FLOAT variable; data is INTEGER


# ---- keywords of the controller that the emulator keeps but does not model ----------------------

def test_parameters_with_arguments_and_slot_modifiers_keep_what_is_written() -> None:
    out = run("""NODE_PROFILE(1, 2) = 5
PRINT NODE_PROFILE(1, 2); NODE_PROFILE(2, 1)
NW_NODE_AXIS_MAP(0, 1, 0) = 3
PRINT NW_NODE_AXIS_MAP(0, 1, 0)
PRINT COMMSTYPE SLOT(0)
POKE($30be0004, 1, 4)
PROFINET(5, 0, $f)""")
    assert out == "50\r\n3\r\n0\r\n"


def test_a_keyword_is_never_taken_as_a_variable() -> None:
    for line in ("PROFINET = 3", "FOR WDOG = 1 TO 2", "DEFCONST MOVE 2", "KEY = 1"):
        with pytest.raises(TrioError):
            parse_line(line)


# ---- I/O, clock, OFFPOS, WAIT LOADED ---------------------------------------------------

def test_op_alone_reads_the_outputs_and_expansion_io_numbers_exist() -> None:
    rig = Rig()
    out = run("OP(8, ON)\nOP(10, ON)\nOP(100, ON)\nPRINT OP; READ_OP(100); IN(1000)",
              rig=rig)
    assert out == f"{(1 << 8) | (1 << 10)}10\r\n"


def test_time_and_date_come_from_virtual_time() -> None:
    rig = Rig()
    rig.cycles(61_000)
    out = run('PRINT TIME$; " "; DATE$; " "; DAY$', rig=rig, cycles=2)
    assert out == "00:01:01 01/01/2000 Saturday\r\n"


def test_offpos_shifts_the_position_and_reads_zero_again() -> None:
    rig = Rig()
    out = run("DEFPOS(10)\nOFFPOS = -4\nWAIT UNTIL OFFPOS = 0\nPRINT DPOS; OFFPOS", rig=rig)
    assert out == "60\r\n"


def test_wait_loaded_waits_until_the_move_buffer_takes_another() -> None:
    rig = Rig()
    rig.load("P", "FOR k = 1 TO 16\n  MOVE(100)\nNEXT k\nWAIT LOADED\nPRINT \"loaded\"")
    rig.command('RUN "P"')
    assert rig.cycles(60) == b""  # sixteen moves of 0.1 s fill the buffer: it holds
    assert rig.cycles(60) == b"loaded\r\n"  # the first move ended: one place free


# ---- program names and the command line's line ends ------------------------------------

def test_a_program_name_may_start_with_a_digit_but_never_be_a_path() -> None:
    assert check_name("0123") == "0123"
    for bad in ("../X", "A.B", "", "A" * 33, "A B"):
        with pytest.raises(TrioError):
            check_name(bad)


def test_lf_alone_ends_a_line_and_cr_lf_keeps_atrios_answer() -> None:
    rig = Rig()
    rig.session.feed(b"?1+1\n")
    assert rig.session.read() == b"?1+1\r\n2\r\n>>"
    rig.session.feed(b"?2+2\r")
    rig.session.feed(b"\n")  # the LF of CR LF, in a feed of its own
    assert rig.session.read() == b"?2+2\r\n4\r\n>>\nControl char : 0x10000000A\r\n>>"
    rig.session.feed(b"\n\n")  # LF after LF: two empty lines
    assert rig.session.read() == b"\r\n>>\r\n>>"


# ---- the harness that measures real programs -------------------------------------------

def test_the_corpus_harness_reports_parsing_keywords_and_runs(tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]
                                                               ) -> None:
    project = tmp_path / "cell"
    project.mkdir()
    (project / "MAIN.BAS").write_text("' a cell\r\nspeed_x = 10\r\nSPEED = speed_x\r\n"
                                      "PRINT twice(2)\r\nWA(20)\r\n")
    (project / "HELPER.BAS").write_text("x = 1 +\nPRINT y_only_read\n")
    (project / "LIB.BAL").write_text("FUNCTION twice(v)\nRETURN 2 * v\nENDFUNC\n")
    sys.path.insert(0, str(Path(__file__).parent.parent / "tools"))
    try:
        import trio_corpus
    finally:
        sys.path.pop(0)
    assert trio_corpus.main([str(tmp_path), "--seconds", "1"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "programs: 3"
    assert out[1] == "lines parsed: 8/9 = 88.9%"
    assert out[2] == ("keywords used: 7: modelled 6, accepted only 0, not in the table 1 "
                      "= 85.7% understood")
    assert "Y_ONLY_READ(1)" in out[4]
    assert out[5] == "programs running 1 s clean: 1/2 = 50.0%"
    assert "cell/HELPER line 1: Syntax error" in "\n".join(out)


def test_every_new_keyword_says_where_it_comes_from() -> None:
    for name in ("DEFCONST", "OPEN", "CLOSE", "GET", "INPUT", "LINPUT", "KEY", "DATE$",
                 "TIME$", "DAY$", "PROFINET", "NW_NODE_AXIS_MAP", "OFFPOS"):
        keyword = KEYWORDS[name]
        assert keyword.source and keyword.confidence in "CID" and keyword.note


def test_reading_a_file_channel_that_is_not_open_is_an_error() -> None:
    assert run("GET #41, c").endswith("Line 1] - Channel not open\r\n")
    assert run("PRINT KEY #41") == "0\r\n"


def test_values_kept_for_parameters_with_arguments_are_bounded() -> None:
    out = run("FOR k = 0 TO 5000\n  NODE_PROFILE(0, k) = 1\nNEXT k\nPRINT k", cycles=4200)
    assert out.endswith("Line 2] - Parameter out of range\r\n")


def test_a_library_that_does_not_compile_offers_nothing_until_it_is_edited() -> None:
    rig = Rig()
    rig.command('SELECT "LIB",12')
    rig.command("!LIB,0RFUNCTION one()")
    rig.command("!LIB,1RRETURN 1 +")
    rig.command("!LIB,2RENDFUNC")
    assert run("PRINT one()", rig=rig).endswith("Line 1] - Variable not defined\r\n")
    rig.command("!LIB,1RRETURN 1")
    assert run("PRINT one()", rig=rig) == "1\r\n"


@pytest.mark.parametrize(("a", "b", "printed"), [(1, 0, "one"), (0, 1, "two"),
                                                 (0, 0, "none")])
def test_else_of_a_block_if_may_carry_a_statement_or_a_nested_if(
        a: int, b: int, printed: str) -> None:
    out = run(f"""a = {a}
b = {b}
IF a THEN
  PRINT "one"
ELSE IF b THEN
    PRINT "two"
  ELSE PRINT "none"
  ENDIF
ENDIF""")
    assert out == printed + "\r\n"


def test_vr_bits_and_user_flags() -> None:
    out = run("""VR(10) = 5
SET_BIT(4, 10)
CLEAR_BIT(0, 10)
PRINT VR(10); READ_BIT(4, 10); READ_BIT(1, 10)
FLAG(3, ON)
PRINT FLAG(3); FLAG(2); FLAGS
FLAGS(1)
PRINT FLAGS; FLAG(3)
FLAG(24, ON)""")
    assert out == ("20.000010\r\n-108\r\n10\r\n"  # a VR is FLOAT
                   "%[Process 19:Program P Line 9] - Parameter out of range\r\n")


@pytest.mark.parametrize("line", ["x = DPOS(1)", "SPEED(2) = 5", "x = WDOG(0)",
                                  "x = SPEED SLOT(0)"])
def test_a_modelled_parameter_takes_no_arguments(line: str) -> None:
    with pytest.raises(TrioError):
        parse_line(line)


def test_lf_only_lines_held_behind_a_wait_run_a_bounded_slice_a_cycle() -> None:
    rig = Rig()
    rig.session.feed(b"WA(2)\n" + b"?12\n" * 2000)
    assert rig.cycles(1) == b"WA(2)\r\n"  # held: nothing after it has run
    first = rig.cycles(1)  # the WA ends: 2 KiB of held lines, cut at a line end
    assert first.count(b"?12\r\n12\r\n>>") == 2048 // 4
    rest = rig.cycles(20)
    assert (first + rest).count(b"?12\r\n12\r\n>>") == 2000
    assert b"Control char" not in first + rest
