"""TrioBASIC as real programs are written: structure, declarations, strings, errors,
processes and I/O, each run on the fake machine through the command line as atrio
uploads and runs a program (tests/trio_helpers.Rig)."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from maxk.commands.trio.keywords import KEYWORDS, Kind, _index
from maxk.commands.trio.tasks import STATEMENTS_PER_CYCLE, join_continued
from maxk.commands.trio.tokentable import TOKENS
from tests.trio_helpers import AtrioError, Rig


def run(program: str, cycles: int = 50, rig: Rig | None = None) -> str:
    rig = rig or Rig()
    rig.load("P", program)
    rig.command('RUN "P"')
    return rig.cycles(cycles).decode()


def test_labels_goto_gosub_and_return() -> None:
    out = run("""n = 0
again:
n = n + 1
IF n < 3 THEN GOTO again
GOSUB show
GOSUB show
STOP
show:
  PRINT "n="; n
RETURN""")
    assert out == "n=3.0000\r\nn=3.0000\r\n"  # n is a FLOAT variable (help DIM)


def test_return_without_gosub_is_the_programs_error_line() -> None:
    assert run("PRINT 1\nRETURN") == \
        "1\r\n%[Process 19:Program P Line 2] - RETURN without GOSUB\r\n"


def test_a_missing_label_fails_at_compile_with_its_line() -> None:
    rig = Rig()
    rig.command('SELECT "P",0')
    rig.command("!P,0RPRINT 1")
    rig.command("!P,1RGOTO nowhere")
    assert rig.send("COMPILE").split(b"\r\n")[1] == b"%[Program P Line 2] - Label not found"


def test_gosub_depth_is_bounded() -> None:
    out = run("deep:\nGOSUB deep", cycles=20)
    assert out.endswith("Line 2] - Stack overflow\r\n")


@pytest.mark.parametrize(("value", "printed"), [(1, "one"), (2, "two"), (5, "range"),
                                                 (7, "range"), (9, "else")])
def test_select_case_forms(value: int, printed: str) -> None:
    out = run(f"""x = {value}
SELECT_CASE x
  CASE 1
    PRINT "one"
  CASE 2, 3
    PRINT "two"
  CASE 4 TO 8
    PRINT "range"
  CASE ELSE
    PRINT "else"
END_CASE""")
    assert out == printed + "\r\n"


@pytest.mark.parametrize(("value", "printed"), [(1, "a"), (2, "b"), (3, "c"), (4, "d")])
def test_elseif_chains(value: int, printed: str) -> None:
    out = run(f"""x = {value}
IF x = 1 THEN
  PRINT "a"
ELSEIF x = 2 THEN
  PRINT "b"
ELSEIF x = 3 THEN
  PRINT "c"
ELSE
  PRINT "d"
ENDIF""")
    assert out == printed + "\r\n"


def test_line_continuation_joins_lines_and_reports_the_first() -> None:
    assert join_continued(["a = 1 + _", "  2", "b = 3"]) == [(1, "a = 1 +    2"), (3, "b = 3")]
    assert run("x = 1 + _\n 2 * _\n 3\nPRINT x") == "7.0000\r\n"


def test_dim_types_arrays_and_strings() -> None:
    out = run("""DIM n AS INTEGER
DIM f AS FLOAT
DIM b AS BOOLEAN
DIM s AS STRING(5)
DIM a(3) AS INTEGER
n = 7.9 : f = 7.9 : b = 5 : s = "abcdefgh"
a(2) = 2.5
PRINT n; " "; f; " "; b; " "; s; " "; a(2); " "; a(0)
a(3) = 1""")
    assert out == ("7 7.9000 -1 abcde 2 0\r\n"
                   "%[Process 19:Program P Line 9] - Array index out of range\r\n")


def test_constant_and_global_are_seen_by_every_program() -> None:
    rig = Rig()
    rig.load("SETUP", 'CONSTANT "LIMIT", 42\nGLOBAL "counter", 7')
    rig.command('RUN "SETUP"')
    rig.cycles(2)
    assert run("counter = counter + LIMIT\nPRINT VR(7); \" \"; LIMIT", rig=rig) == \
        "42.0000 42\r\n"  # a VR is FLOAT; the CONSTANT 42 as written
    assert run("LIMIT = 1", rig=rig).endswith("Line 1] - Cannot assign to a constant\r\n")


def test_print_channels_and_formats() -> None:
    out = run('x = 3.14159\nPRINT #5, "x="; x[8,3]; "|"; x[0]\nPRINT #0, 12[5,1]')
    assert out == "x=   3.142|3\r\n 12.0\r\n"
    assert run("PRINT #300, 1").endswith("Parameter out of range\r\n")


@pytest.mark.parametrize(("expr", "printed"), [
    ('CHR(65) + CHR(66)', "AB"), ("HEX(255)", "FF"), ('ASC("A")', "65"),
    ('LEN("abc")', "3"), ('LEFT("motion", 3)', "mot"), ('RIGHT("motion", 2)', "on"),
    ('MID("motion", 2, 3)', "tio"), ('UCASE("ab") + LCASE("CD")', "ABcd"),
    ('VAL("12.5") * 2', "25"), ('INSTR("pick place", "place")', "5"),
    ('"n=" + 5', "n=5"), ('"a" < "b"', "-1")])
def test_string_functions(expr: str, printed: str) -> None:
    assert run(f"PRINT {expr}") == printed + "\r\n"


@given(st.text(alphabet="abcXYZ019 ", max_size=20), st.integers(0, 25), st.integers(0, 25))
def test_mid_is_python_slicing_from_zero(text: str, start: int, count: int) -> None:
    """MID's start counts from 0 (the help page's examples)."""
    assert run(f'PRINT MID("{text}", {start}, {count}); "|"') == \
        text[start:start + count] + "|\r\n"


def test_on_basicerror_sets_run_error_and_error_line() -> None:
    out = run("""ON BASICERROR GOTO handler
x = 1
y = x / 0
PRINT "not reached"
handler:
PRINT RUN_ERROR; " "; ERROR_LINE
z = 1 / 0""")
    assert out == "9 3\r\n%[Process 19:Program P Line 7] - Divide by zero\r\n"  # page: 9


def test_ticks_counts_down_a_servo_cycle_at_a_time() -> None:
    rig = Rig()
    rig.load("P", "TICKS = 100\nWAIT UNTIL TICKS < 0\nPRINT \"late\"")
    rig.command('RUN "P"')
    assert rig.cycles(100) == b""
    assert rig.cycles(2) == b"late\r\n"


def test_processes_run_side_by_side_and_proc_status_reads_them() -> None:
    rig = Rig()
    rig.load("SLOW", "WA(20)\nVR(1) = 1")
    rig.load("P", 'RUN "SLOW", 3\nWA(2)\nVR(2) = PROC_STATUS PROC(3)\n'
             "WAIT UNTIL PROC_STATUS PROC(3) = 0\nVR(3) = PROCNUMBER")
    rig.command('RUN "P", 5')
    rig.cycles(5)
    assert rig.command("PROCESS").count(b"Running") == 2
    rig.cycles(30)
    # VR(2): 8, SLEEP, as SLOW waits in its WA(20) (help PROC_STATUS)
    assert [rig.command(f"?VR({i})") for i in (1, 2, 3)] == [b"1.0000", b"8.0000", b"5.0000"]


def test_stop_alone_ends_the_program_there() -> None:
    assert run('PRINT "a"\nSTOP\nPRINT "b"') == "a\r\n"


def test_include_brings_in_another_programs_lines() -> None:
    rig = Rig()
    rig.load("DEFS", "speed_fast = 250")
    assert run('INCLUDE "DEFS"\nPRINT speed_fast', rig=rig) == "250.0000\r\n"
    rig.load("SELFISH", 'INCLUDE "SELFISH"')
    with pytest.raises(AtrioError):
        rig.command('RUN "SELFISH"')


def test_io_inputs_outputs_and_analog() -> None:
    rig = Rig()
    rig.machine.inputs[3] = True
    rig.machine.analog[1] = 5.0
    out = run("OP(9, ON)\nOP(10, ON)\nOP(10, OFF)\n"
              "PRINT IN(3); IN(4); READ_OP(9); READ_OP(9, 10); AIN(1)\n"
              "AOUT(0) = 100\nPRINT AOUT(0)\nPRINT IN(40)\nPRINT IN(1024)", rig=rig)
    assert out == ("10111024\r\n100\r\n"  # IN(3) IN(4) READ_OP(9) READ_OP(9,10) AIN(1)
                   "0\r\n"  # expansion I/O: off unless set
                   "%[Process 19:Program P Line 8] - Parameter out of range\r\n")


def test_limit_inputs_show_in_axisstatus() -> None:
    rig = Rig()
    rig.machine.inputs[6] = False  # the limit inputs are active low
    rig.command("FWD_IN AXIS(1)=6")
    rig.command("FS_LIMIT AXIS(2)=-1")
    assert rig.command("?AXISSTATUS AXIS(1), AXISSTATUS AXIS(2), AXISSTATUS.4 AXIS(1)") == \
        b"16\t512\t1"


def test_every_token_table_word_is_a_keyword_never_a_variable() -> None:
    names = [row.split()[1] for row in TOKENS.split("\n") if row.split()]
    assert set(names) <= set(KEYWORDS)
    rig = Rig()
    for word in ("COMPILE_MODE", "SERVO", "JERK", "FE_LIMIT_MODE", "DRIVE_STATUS"):
        assert rig.command(f"?{word}") == b"0"
    with pytest.raises(AtrioError):
        rig.command("CREEP = 10 + ")  # still a statement of the keyword: a syntax error
    rig.command("CREEP AXIS(1) = 10")
    assert rig.command("?CREEP AXIS(1)") == b"10"
    with pytest.raises(AtrioError, match="read only"):
        rig.command("MTYPE = 1")


def test_a_keyword_listed_twice_is_an_error_at_import() -> None:
    entry = KEYWORDS["MOVE"]
    with pytest.raises(ValueError, match="MOVE is listed twice"):
        _index([entry, entry])
    assert all(k.kind in Kind for k in KEYWORDS.values())


def test_a_busy_loop_costs_servo_cycles() -> None:
    rig = Rig()
    body = "\n".join("VR(1) = VR(1) + 1" for _ in range(250))
    rig.load("P", f"WHILE 1\n{body}\nWEND")
    rig.command('RUN "P"')
    rig.cycles(1)
    one_slice = f"{STATEMENTS_PER_CYCLE - 1}.0000".encode()  # WHILE, then the body
    assert rig.command("?VR(1)") == one_slice
    rig.command("HALT")
    rig.cycles(5)
    assert rig.command("?VR(1)") == one_slice


def test_functions_return_values_recurse_and_keep_their_own_variables() -> None:
    out = run("""x = 5
PRINT square(x) + 1; " "; hyp(3, 4); " "; fact(5); " "; noret()
show("hi")
FUNCTION square(v AS FLOAT) AS FLOAT
  RETURN v * v
ENDFUNC
FUNCTION hyp(a, b)
  RETURN SQR(square(a) + square(b))
ENDFUNC
FUNCTION fact(n)
  IF n <= 1 THEN RETURN 1
  RETURN n * fact(n - 1)
ENDFUNC
FUNCTION noret()
  y = 1
ENDFUNC
FUNCTION show(t AS STRING(10))
  PRINT t; " x="; x
ENDFUNC""")
    assert out == "26.0000 5.0000 120.0000 0\r\nhi x=0.0000\r\n"  # FLOAT results


def test_a_function_may_not_wait_and_recursion_is_bounded() -> None:
    assert run("PRINT f()\nFUNCTION f()\nWA(10)\nENDFUNC").endswith(
        "Line 1] - Function cannot wait\r\n")
    assert run("PRINT f(1)\nFUNCTION f(n)\nRETURN f(n + 1)\nENDFUNC").endswith(
        "Line 1] - Stack overflow\r\n")


def test_docs_list_every_keyword_with_its_source() -> None:
    from pathlib import Path

    text = (Path(__file__).parent.parent / "docs" / "trio.md").read_text()
    for name, keyword in KEYWORDS.items():
        assert f"| `{name}` | {keyword.kind.value} |" in text, name


def _mc405_run(lines: list[str], seconds: float) -> tuple[str, object]:
    from maxk.controllers.trio.controller import MC405

    controller = MC405()
    session = controller.open_session()
    for text in ['SELECT "H",0', *[f"!H,{n}R{line}" for n, line in enumerate(lines)],
                 "COMPILE", 'RUN "H"']:
        session.feed(text.encode() + b"\r\n")
    session.read()
    controller.advance(seconds)
    return session.read().decode(), controller


def test_datum_homes_on_the_worlds_home_switch_with_creep() -> None:
    out, controller = _mc405_run(
        ["DATUM_IN AXIS(0)=5", "SPEED=2000", "ACCEL=20000", "DECEL=20000", "CREEP=100",
         "DATUM(3)", 'PRINT "homed "; DPOS; " "; SPEED', "MOVEABS(-34)", "WAIT IDLE",
         "PRINT IN(5)"], 3.0)
    assert out == "homed 0 2000\r\n1\r\n"  # off the normally closed switch: 1
    # the world's home window starts at 1234 counts: the zero is its lower edge
    assert controller.world_view().reading("0").position == 1234 - 34  # type: ignore[attr-defined]


def test_datum_without_a_datum_input_is_refused() -> None:
    out, _ = _mc405_run(["DATUM(4)"], 0.01)
    assert out == "%[Process 19:Program H Line 1] - Parameter out of range\r\n"


@pytest.mark.parametrize("line", ["?" + "(" * 400 + "1" + ")" * 400, "?" + "-" * 900 + "1",
                                  "?" + "NOT " * 250 + "1", "?1" + "+1" * 500,
                                  "IF 1 THEN " * 100 + "PRINT 1"])
def test_deep_expressions_are_refused_never_a_crash(line: str) -> None:
    rig = Rig()
    with pytest.raises(AtrioError, match="Expression too complex"):
        rig.command(line)
    assert rig.command("?1+1") == b"2"


def test_the_repl_lists_processes_and_explains_every_keyword() -> None:
    from maxk.controllers.trio.controller import MC405

    console = MC405().console()
    for line in ('SELECT "SLOW",0', "!SLOW,0RWA(5000)", 'RUN "SLOW", 4'):
        console.execute(line)
    console.controller.advance(0.01)
    assert console.repl_word(":programs", "") == [
        "process 4: SLOW line 1, waiting until tick 5001",
        "1 program(s) in the store, 9 bytes"]
    for name in KEYWORDS:
        assert console.help(name)


@pytest.mark.parametrize(("direction", "y_sign"), [(1, 1), (0, -1)])
def test_movecirc_draws_the_arc_on_the_shared_planner(direction: int, y_sign: int) -> None:
    import math

    from maxk.controllers.trio.controller import MC405

    controller = MC405()
    console = controller.console()
    for line in ("BASE(0,1)", "SPEED=100", "ACCEL=100000", "DECEL=100000",
                 f"MOVECIRC(200,0,100,0,{direction})"):
        assert console.execute(line) == [] and console.new_errors() == []
    controller.advance(1.6)
    x, y = (float(v) for v in console.execute("?DPOS AXIS(0), DPOS AXIS(1)")[0].split())
    assert math.hypot(x - 100, y) == pytest.approx(100, abs=1e-3)  # on the circle
    travelled = 100 * 1.6 - 100 * 0.001 / 2  # at SPEED after a 1 ms ramp
    assert math.atan2(y_sign * y, 100 - x) == pytest.approx(travelled / 100, abs=2e-3)
    controller.advance(2.0)
    assert console.execute("?DPOS AXIS(0), DPOS AXIS(1), IDLE") == ["200\t0\t-1"]
    assert console.execute("MOVECIRC(0,0,0,0,0)") == []
    assert console.new_errors() == ["! Parameter out of range"]


def test_the_docs_keyword_table_is_the_one_keywords_py_writes() -> None:
    """docs/trio.md's table is generated from the keyword table, not kept by hand: a
    keyword whose entry changes (or is lost in a merge) shows in the page at once."""
    from pathlib import Path

    from maxk.commands.trio.keyword_doc import table

    text = (Path(__file__).parent.parent / "docs" / "trio.md").read_text()
    assert table() in text


def test_a_word_the_interpreter_acts_on_is_never_listed_as_not_modelled() -> None:
    from maxk.commands.trio import interpreter

    acted_on = (interpreter._MACHINE_COMMANDS | interpreter._BIT_COMMANDS
                | set(interpreter._MATH) | interpreter.PROCESS_PARAMETERS)
    listed = {name for name in acted_on if KEYWORDS[name].note.startswith("Not modelled")}
    assert listed == set()
