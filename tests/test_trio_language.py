"""TrioBASIC: lexing, expressions, printing, parameters and modifiers, control flow."""

from __future__ import annotations

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from maxk.commands.trio import (
    KEYWORDS,
    FakeTrioMachine,
    Kind,
    TrioError,
    compile_program,
    format_number,
    parse_line,
    tokenize,
)
from maxk.commands.trio.interpreter import base_array
from tests.trio_helpers import AtrioError, Rig


def ask(expr: str, rig: Rig | None = None) -> str:
    return (rig or Rig()).command("?" + expr).decode()


# ---- numbers and printing -----------------------------------------------------------------

@pytest.mark.parametrize("value, text", [
    (2.0, "2"), (-7.0, "-7"), (0.0, "0"), (-0.0, "0"), (1 / 3, "0.3333"), (-0.5, "-0.5000"),
    (2.5, "2.5000"), (123456.0, "123456"), (1e15, "1000000000000000"),
])
def test_integer_printing_rule(value: float, text: str) -> None:
    assert format_number(value) == text


@given(st.integers(-10**12, 10**12))
def test_integers_print_like_python_int(n: int) -> None:
    assert format_number(float(n)) == str(n)


@pytest.mark.parametrize("expr, text", [
    ("1+2*3", "7"), ("(1+2)*3", "9"), ("2^3^2", "64"), ("-2^2", "-4"), ("7/2", "3.5000"),
    ("10 MOD 3", "1.0000"), ("-7 MOD 3", "-1.0000"), ("1=1", "-1"), ("1<>1", "0"), ("2>=2", "-1"),
    ("TRUE", "-1"), ("FALSE", "0"), ("ON", "1"), ("OFF", "0"), ("NOT 0", "-1"),
    ("NOT TRUE", "0"), ("6 AND 3", "2"), ("6 OR 3", "7"), ("6 XOR 3", "5"),
    ("1<2 AND 3<4", "-1"), ("1>2 OR 3<4", "-1"), ("NOT 1=2", "-1"), ("$FF", "255"),
    ("1.5e3", "1500.0000"), ("ABS(-3)", "3"), ("INT(-2.7)", "-2"), ("FRAC(2.25)", "0.2500"),
    ("SGN(-4)", "-1.0000"), ("SQR(16)", "4.0000"), ("ATAN2(0,1)", "0.0000"),
    ("COS(0)", "1.0000"),  # FLOAT results print 4 decimals (help INT example 2)
    ("2*-3", "-6"), ("--2", "2"),
])
def test_expressions(expr: str, text: str) -> None:
    assert ask(expr) == text


def test_print_separators_and_strings() -> None:
    rig = Rig()
    rig.command("a=2")
    assert rig.command('PRINT "a=";a, a*2') == b"a=2.0000\t4.0000"  # a is FLOAT
    assert rig.command('?"say ""hi"""') == b'say "hi"'
    assert rig.send("PRINT 1;") == b"PRINT 1;\r\n1>>\nControl char : 0x10000000A\r\n>>"


def test_variables_are_case_insensitive_and_start_at_zero() -> None:
    rig = Rig()
    assert ask("never", rig) == "0.0000"  # an unset variable: a FLOAT 0
    rig.command("Mult=0.1")
    assert ask("MULT*10", rig) == "1.0000"  # 0.1 is a FLOAT literal


def test_comments_after_statements() -> None:
    assert parse_line("PWM_CYCLE=1000' sets 20khz PWM") == parse_line("PWM_CYCLE=1000")
    assert parse_line("' only a comment") == []
    assert parse_line("REM also") == []
    assert [t.text for t in tokenize("a='x':b")] == ["A", "=", ""]  # "" is the END token


@pytest.mark.parametrize("line", ["?1+", "a==1", "MOVE(1", "?\"open", "1=a", "PRINT )",
                                  "?SPEED AXIS 2", "IF 1 ELSE", "FOR 1=1 TO 2", "?#", "?MOVE"])
def test_syntax_errors(line: str) -> None:
    with pytest.raises(TrioError, match="Syntax error"):
        parse_line(line)


# ---- parameters, modifiers, BASE --------------------------------------------------------------

def test_axis_parameters_with_axis_modifier_and_base() -> None:
    rig = Rig()
    rig.command("SPEED AXIS(2)=250")
    rig.command("BASE(2)")
    assert ask("SPEED", rig) == "250"
    assert ask("SPEED AXIS(0)", rig) == "1000"
    rig.command("SPEED=300")
    assert rig.machine.axis_parameter("SPEED", 2) == 300
    assert ask("BASE", rig) == "2"


def test_indexed_pwm_forms() -> None:
    rig = Rig()
    rig.command("PWM_MARK AXIS(4)=300")
    assert ask("PWM_MARK AXIS(4)", rig) == "300"
    with pytest.raises(AtrioError, match="Axis 8 has no PWM output"):
        rig.command("?PWM_MARK AXIS(8)")


def test_table_and_vr() -> None:
    rig = Rig()
    rig.command("TABLE(10, 1.5, 2, 3)")
    assert ask("TABLE(11)+TABLE(10)", rig) == "3.5000"
    rig.command("VR(5)=TABLE(12)*2")
    assert ask("VR(5)", rig) == "6.0000"
    for bad in ("?TABLE(-1)", "?VR(65536)", "VR(1.5)=2", "TABLE(1)"):
        with pytest.raises(AtrioError):
            rig.command(bad)


def test_base_array_fills_with_the_following_axes() -> None:
    assert base_array([4], 8) == [4, 5, 6, 7, 0, 1, 2, 3]
    assert base_array([0, 1], 4) == [0, 1, 2, 3]
    assert base_array([2, 0], 4) == [2, 0, 1, 3]
    with pytest.raises(TrioError):
        base_array([1, 1], 4)


def test_move_uses_the_base_group_and_axis_modifier() -> None:
    rig = Rig()
    rig.command("BASE(3,5)")
    rig.command("MOVE(4,6)")
    rig.command("MOVEABS(9) AXIS(7)")
    rig.cycles(20)
    assert rig.machine.dpos[3:8] == [4.0, 0.0, 6.0, 0.0, 9.0]
    rig.command("DEFPOS(100) AXIS(5)")
    assert ask("DPOS AXIS(5)", rig) == "100"
    assert ask("IDLE", rig) == "-1"


def test_acc_sets_accel_and_decel() -> None:
    rig = Rig()
    rig.command("ACC(50000)")
    assert ask("ACCEL", rig) == ask("DECEL", rig) == "50000"


def test_mpe_accepts_only_zero() -> None:
    rig = Rig()
    rig.command("MPE(0)")
    with pytest.raises(AtrioError, match="out of range"):
        rig.command("MPE(1)")


def test_servo_period_applies_at_restart() -> None:
    rig = Rig()
    rig.command("SERVO_PERIOD=500")
    assert ask("SERVO_PERIOD", rig) == "500"
    assert rig.machine.servo_period_us() == 1000
    with pytest.raises(AtrioError):
        rig.command("SERVO_PERIOD=300")


# ---- programs: control flow ---------------------------------------------------------------------

def run(text: str, cycles: int = 50) -> tuple[Rig, str]:
    rig = Rig()
    rig.load("P", text)
    rig.command('RUN "P"')
    return rig, rig.cycles(cycles).decode()


def test_while_wend_and_repeat_until() -> None:
    _, out = run("i=0\nWHILE i<3\nPRINT i\ni=i+1\nWEND\nREPEAT\ni=i-1\nUNTIL i=0\nPRINT \"end\";i")
    assert out == "0.0000\r\n1.0000\r\n2.0000\r\nend0.0000\r\n"


def test_block_if_else_and_single_line_if() -> None:
    text = "\n".join([
        "FOR k=1 TO 4",
        "IF k MOD 2 = 0 THEN",
        "  PRINT k;\" even\"",
        "ELSE",
        "  PRINT k;\" odd\"",
        "ENDIF",
        "IF k=4 THEN PRINT \"four\" : PRINT \"!\" ELSE PRINT \"-\"",
        "NEXT k",
    ])
    _, out = run(text)
    assert out.split("\r\n") == ["1.0000 odd", "-", "2.0000 even", "-", "3.0000 odd", "-",
                                 "4.0000 even", "four", "!", ""]


def test_for_step_negative_and_skipped_loop() -> None:
    _, out = run("FOR i=3 TO 1 STEP -1\n?i\nNEXT\nFOR j=5 TO 1\n?\"never\"\nNEXT j\n?\"done\"")
    assert out == "3.0000\r\n2.0000\r\n1.0000\r\ndone\r\n"


def test_nested_loops_and_blocks_compile() -> None:
    steps = compile_program(["WHILE a<2", "a=a+1", "REPEAT", "b=b+1", "UNTIL b>=2", "WEND"])
    assert [s.line for s in steps] == [1, 2, 3, 4, 5, 6]


@pytest.mark.parametrize("lines, line", [
    (["WEND"], 1), (["WHILE 1", "x=1"], 1), (["REPEAT", "WEND"], 2), (["ENDIF"], 1),
    (["IF 1 THEN", "ELSE", "ELSE", "ENDIF"], 3), (["NEXT"], 1), (["a=1", "b=="], 2),
])
def test_structure_errors_name_the_line(lines: list[str], line: int) -> None:
    with pytest.raises(TrioError) as err:
        compile_program(lines)
    assert err.value.line == line


def test_loops_take_one_servo_cycle_per_pass() -> None:
    rig, _ = run("WHILE TRUE\nVR(1)=VR(1)+1\nWEND", cycles=25)
    assert rig.machine.vr_read(1) == 25


def test_wa_and_wait_idle_in_a_program_yield_to_time() -> None:
    rig, out = run("SPEED=100\nMOVE(1)\nWAIT IDLE\nPRINT \"idle\"\nWA(5)\nPRINT \"woke\"",
                   cycles=11)
    assert out == "idle\r\n"  # the 1-unit move at 100/s takes 10 cycles
    assert rig.cycles(4) == b""
    assert rig.cycles(1) == b"woke\r\n"


def test_wait_until() -> None:
    rig, out = run("WAIT UNTIL VR(7)=1\nPRINT \"go\"", cycles=5)
    assert out == ""
    rig.command("VR(7)=1")
    assert rig.cycles(1) == b"go\r\n"


def test_two_programs_run_beside_the_command_line() -> None:
    rig = Rig()
    rig.load("A", "WHILE TRUE\nVR(1)=VR(1)+1\nWEND")
    rig.load("B", "WHILE TRUE\nVR(2)=VR(2)+2\nWA(2)\nWEND")
    rig.command('RUN "A"')
    rig.command('RUN "B"')
    rig.cycles(10)
    assert ask("VR(1)", rig) == "10.0000" and ask("VR(2)", rig) == "10.0000"
    rig.command('STOP "A"')
    rig.cycles(2)
    assert ask("VR(1)", rig) == "10.0000"


def test_a_full_move_buffer_makes_the_program_wait() -> None:
    rig, _ = run("FOR i=1 TO 20\nMOVE(1)\nNEXT i\nVR(0)=1", cycles=10)
    assert rig.machine.vr_read(0) == 0  # 16 moves buffered, the rest waiting
    rig.cycles(30)
    assert rig.machine.vr_read(0) == 1


# ---- the keyword table -------------------------------------------------------------------------

def test_every_keyword_records_kind_source_and_confidence() -> None:
    for keyword in KEYWORDS.values():
        assert keyword.source and keyword.confidence in ("C", "I", "D"), keyword.name
        assert isinstance(keyword.kind, Kind)
        if keyword.confidence != "C":
            assert keyword.note, keyword.name


def test_table_defaults_are_what_the_fake_powers_up_with() -> None:
    machine = FakeTrioMachine()
    for keyword in KEYWORDS.values():
        if keyword.kind is Kind.AXIS_PARAMETER and keyword.writable:
            assert machine.axis_parameter(keyword.name, 0) == keyword.default, keyword.name


_INTS = st.integers(-999, 999)


@st.composite
def integer_expressions(draw: st.DrawFn, depth: int = 3) -> tuple[str, float]:
    """(TrioBASIC text, its value) for +, - and * on integers, with brackets. The value
    is computed in doubles, as the controller computes (I): exact while every step fits
    in 53 bits, rounded as a double beyond."""
    if depth == 0 or draw(st.booleans()):
        n = draw(_INTS)
        return (f"({n})" if n < 0 else str(n)), float(n)
    op = draw(st.sampled_from("+-*"))
    (a, x), (b, y) = draw(integer_expressions(depth - 1)), draw(integer_expressions(depth - 1))
    value = x + y if op == "+" else x - y if op == "-" else x * y
    return f"({a}{op}{b})", value


@given(integer_expressions())
@example(("(((233*695)*695)*((0+497)*(233*693)))", 9031732672918724.0))  # past 2**53
def test_integer_arithmetic_prints_exactly(case: tuple[str, float]) -> None:
    """Whole values print as integers, exactly the double the arithmetic gives (a value
    past 2**53 is the nearest double, as on the controller)."""
    text, value = case
    assert ask(text) == str(int(value))
