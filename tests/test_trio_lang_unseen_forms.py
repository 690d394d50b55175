"""Forms of the TrioBASIC help's examples that stopped programs no one here had written
(round 2 of the real-code check): OP's block modes, WAIT IN_POS, the bit operator with its
bit number in a variable, MOTION_ERROR(bank), VRSIZE, IOSIZE and IS_FILE. Each is driven
through an MC405's command line or a program on it; the numbers are worked out by hand."""

from __future__ import annotations

import pytest

from maxk.controllers.trio.controller import MC405
from tests.trio_helpers import mc405


def outputs(trio: MC405, first: int, last: int) -> list[int]:
    """The outputs first..last that are on."""
    return [k for k in range(first, last + 1) if trio.query(f"?READ_OP({k})") == "1"]


# ---- OP: the whole-bank and block modes (TrioBASIC help OP) ------------------------------
def test_op_of_a_state_sets_outputs_8_to_31_from_the_same_bits() -> None:
    trio = mc405("OP(25, ON)", "OP(3, ON)")
    # 37 << 8: 37 = 100101b, so bits 8, 10 and 13: outputs 8, 10, 13; 25 is cleared
    assert trio.send("OP(37 << 8)") == []
    assert outputs(trio, 8, 31) == [8, 10, 13]
    assert outputs(trio, 0, 7) == [3]  # 0..7 are left alone (inputs only on the page)
    assert trio.query("?READ_OP(8, 15)") == "37"


def test_op_read_modify_write_keeps_8_to_15_and_sets_the_high_word() -> None:
    trio = mc405("OP(9, ON)", "OP(14, ON)", "OP(20, ON)")
    # 9 and 14 on: $4200; the high word $2B0C0000 replaces output 20
    trio.load("P", "VR(5) = OP AND $0000FF00\nVR(5) = VR(5) OR $2B0C0000\nOP(VR(5))")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=5)
    assert trio.query("?HEX(OP)") == "2B0C4200"
    # $2B0C: bits 2, 3, 8, 9, 11, 13 of the high word: outputs 18, 19, 24, 25, 27, 29
    assert outputs(trio, 16, 31) == [18, 19, 24, 25, 27, 29]


def test_op_start_end_state_sets_only_that_block() -> None:
    trio = mc405("OP(20, ON)", "OP(23, ON)")
    # 5 = 101b from output 21: 21 and 23 on, 22 off; 20 and 24 are outside the block
    assert trio.send("OP(21, 23, 5)") == []
    assert outputs(trio, 16, 31) == [20, 21, 23]
    assert trio.send("OP(40, 71, $80000001)") == []  # 32 outputs, the widest block
    assert outputs(trio, 40, 71) == [40, 71]


@pytest.mark.parametrize("bad", ["OP(13, 10, 1)", "OP(0, 40, 1)", "OP(8, 9, -1)",
                                 "OP(8, 9, 1.5)", "OP(-1)", "OP(2 ^ 32)", "OP(1, 2, 3, 4)"])
def test_bad_op_arguments_are_refused_and_no_output_changes(bad: str) -> None:
    trio = mc405("OP(9, ON)")
    reply = trio.send(bad)
    assert reply in (["! Parameter out of range"], ["! Syntax error"])
    assert outputs(trio, 0, 80) == [9]


# ---- WAIT IN_POS (TrioBASIC help WAIT) ------------------------------------------------------
def test_wait_in_pos_goes_on_on_the_cycle_in_pos_turns_true() -> None:
    """A 100-count move at SPEED 1000, ACCEL = DECEL 100000 (1 ms cycles): 10 cycles up
    (5 counts), 90 at speed, 10 down (5 counts), 110 cycles. The program loads it on
    tick 1 and it runs on ticks 2..111; on tick 110 the last cycle of the ramp down (its
    speed 50 counts/s at mid-cycle: 0.05 count) is still to come. IN_POS is TRUE on tick
    111, the move over; the program passes its WAIT on that cycle."""
    trio = mc405("SPEED=1000: ACCEL=100000: DECEL=100000", "IN_POS_DIST=0.5",
                 "IN_POS_SPEED=1")
    trio.load("P", "MOVE(100)\nWAIT IN_POS\nVR(2) = 1")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=110)
    assert (trio.query("?IN_POS"), trio.query("?VR(2)"), trio.query("?DPOS")) == \
        ("0", "0.0000", "99.9500")
    trio.advance(ticks=1)
    assert (trio.query("?IN_POS"), trio.query("?VR(2)")) == ("-1", "1.0000")


def test_wait_in_pos_axis_waits_on_that_axis() -> None:
    trio = mc405("IN_POS_DIST=0.5", "IN_POS_SPEED=1", "BASE(1)",
                 "SPEED=1000: ACCEL=100000: DECEL=100000", "IN_POS_DIST=0.5",
                 "IN_POS_SPEED=1", "BASE(0)")
    trio.load("P", "MOVE(100) AXIS(1)\nWAIT IN_POS AXIS(1)\nVR(2) = 1")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=110)
    assert trio.query("?VR(2)") == "0.0000"  # axis 0 is in position all along
    trio.advance(ticks=1)
    assert trio.query("?VR(2)") == "1.0000"


def test_wait_in_pos_takes_no_expression() -> None:
    trio = mc405()
    assert trio.send("WAIT IN_POS AND 1") == ["! Syntax error"]


# ---- the bit operator's bit number in a variable (MOTION_ERROR's, AXISSTATUS's pages) ------
def test_a_variable_names_the_bit_read_and_written() -> None:
    trio = mc405("word = 261", "b = 8")  # 261 = 256 + 4 + 1
    assert trio.query("?word.b") == "1"
    assert trio.send("word.b = 0") == []
    assert trio.query("?word") == "5.0000"
    assert trio.send("b = 1: word.b = 1") == []
    assert trio.query("?word") == "7.0000"
    assert trio.send("VR(3) = 12: b = 2") == []
    assert (trio.query("?VR(3).b"), trio.query("?(12).b")) == ("1", "1")


@pytest.mark.parametrize("bit", ["2.5", "-1", "53"])
def test_a_bit_number_out_of_its_range_is_refused(bit: str) -> None:
    trio = mc405("word = 4", f"b = {bit}")
    assert trio.send("?word.b") == ["! Parameter out of range"]
    assert trio.send("word.b = 1") == ["! Parameter out of range"]
    assert trio.query("?word") == "4.0000"


def test_a_keyword_after_the_dot_is_a_syntax_error() -> None:
    trio = mc405("word = 4")
    assert trio.send("?word.SPEED") == ["! Syntax error"]


# ---- MOTION_ERROR(bank) --------------------------------------------------------------------
def axis_1_in_error() -> MC405:
    """Axis 1 runs into its forward limit (input 3) with ERRORMASK 16: a motion error."""
    trio = mc405("BASE(1)", "SPEED=1000: ACCEL=100000: DECEL=10000", "FWD_IN=3",
                 "ERRORMASK=16", "BASE(0)")
    trio.world_view().set_limits("1", plus=100)
    assert trio.send("MOVE(1000) AXIS(1)") == []
    assert trio.run_until_idle()
    return trio


def test_motion_error_bank_0_holds_the_axes_here_and_the_others_read_0() -> None:
    trio = axis_1_in_error()
    assert [trio.query(q) for q in ("?MOTION_ERROR", "?MOTION_ERROR(0)", "?MOTION_ERROR(1)",
                                    "?MOTION_ERROR(15)", "?MOTION_ERROR(0).1")] == \
        ["2", "2", "0", "0", "1"]
    assert trio.send("?MOTION_ERROR(16)") == ["! Parameter out of range"]
    assert trio.send("?MOTION_ERROR(0.5)") == ["! Parameter out of range"]


def test_a_program_finds_the_axis_in_error_by_its_bit() -> None:
    trio = axis_1_in_error()
    trio.load("P", 'FOR ax = 0 TO 15\n  IF MOTION_ERROR.ax = 1 THEN PRINT "axis "; ax[0]\n'
              "NEXT ax")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=50)
    assert trio.send("?1") == ["axis 1", "1"]


# ---- VRSIZE, IOSIZE, IS_FILE ---------------------------------------------------------------
def test_vrsize_names_one_past_the_last_vr() -> None:
    trio = mc405()
    size = int(trio.query("?VRSIZE"))
    assert trio.send("VR(VRSIZE - 1) = 123") == []
    assert trio.query(f"?VR({size - 1})") == "123.0000"
    assert trio.send("VR(VRSIZE) = 1") == ["! VR index out of range"]
    assert trio.send("VRSIZE = 10") == ["! Parameter is read only"]


def test_iosize_names_one_past_the_last_output() -> None:
    trio = mc405()
    size = int(trio.query("?IOSIZE"))
    assert trio.send("OP(IOSIZE - 1, ON)") == []
    assert trio.query(f"?READ_OP({size - 1})") == "1"
    assert trio.send("OP(IOSIZE, ON)") == ["! Parameter out of range"]
    assert trio.send("?IN(IOSIZE)") == ["! Parameter out of range"]


def test_is_file_is_is_prog_under_another_name() -> None:
    trio = mc405()
    trio.load("KNIFE", "PRINT 1")
    for name in ("KNIFE", "OTHER"):
        assert trio.query(f'?IS_FILE "{name}"') == trio.query(f'?IS_PROG "{name}"')
    assert (trio.query('?IS_FILE "KNIFE"'), trio.query('?IS_FILE("OTHER")')) == ("-1", "0")


# ---- BITCOUNT, AXISSIZE, BUFFERSIZE --------------------------------------------------------
@pytest.mark.parametrize(("expr", "count"), [
    ("255", "8"), ("65534", "15"), ("-1", "64"), ("-2", "63"), ("4.8892", "1"),
    ("$2000 + $C9", "5"),  # the page's examples; then our own:
    ("$8000000000000", "1"), ("-2 ^ 63", "1"), ("0", "0"), ("-7.9", "62")])
def test_bitcount_counts_the_ones_of_a_64_bit_integer(expr: str, count: str) -> None:
    """-7.9 is -7: ...11111001 in two's complement, 64 bits less the two zeros: 62."""
    assert mc405().query(f"?BITCOUNT({expr})") == count


def test_bitcount_refuses_what_64_bits_cannot_hold() -> None:
    trio = mc405()
    assert trio.send("?BITCOUNT(2 ^ 63)") == ["! Parameter out of range"]
    assert trio.send("?BITCOUNT(1, 2)") == ["! Syntax error"]


def test_axissize_and_buffersize_bound_base_and_limit_buffered() -> None:
    trio = mc405()
    axes, moves = int(trio.query("?AXISSIZE")), int(trio.query("?BUFFERSIZE"))
    assert trio.send("BASE(AXISSIZE - 1)") == [] and trio.query("?BASE") == str(axes - 1)
    assert trio.send("BASE(AXISSIZE)") == ["! Invalid axis number"]
    assert trio.send("LIMIT_BUFFERED = BUFFERSIZE") == []
    assert trio.query("?LIMIT_BUFFERED") == str(moves)
    assert trio.send("LIMIT_BUFFERED = BUFFERSIZE + 1") == ["! Parameter out of range"]
    assert trio.send("AXISSIZE = 4") == ["! Parameter is read only"]


# ---- help-page words the token table lacks (helpwords.py) -----------------------------------
def test_a_help_page_parameter_is_the_controllers_not_a_local_variable() -> None:
    """Before it was in the table, IP_BIND_ADDRESS = ... in a program made a local variable
    the command line could not see."""
    trio = mc405()
    trio.load("P", "IP_BIND_ADDRESS = 192.168.0.5\nAIN_CONFIG(2) = 3\nNODE_AXIS_MAP(0, 3, 0) = 10")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=10)
    # 192*2^24 + 168*2^16 + 0*2^8 + 5, the dotted address's number
    assert trio.query("?IP_BIND_ADDRESS") == str(192 * 2 ** 24 + 168 * 2 ** 16 + 5)
    assert [trio.query(q) for q in ("?AIN_CONFIG(2)", "?AIN_CONFIG(3)",
                                    "?NODE_AXIS_MAP(0, 3, 0)")] == ["3", "0", "10"]


def test_help_page_functions_and_commands_run_and_read_only_words_refuse_writes() -> None:
    trio = mc405()
    for line in ("MS_BUS(1, 1)", "x = MS_BUS(3, 1)", "AXISLIST", "DV_MAP",
                 'REGISTER_KEYWORD("RUN_A", "a_func", 0, 2)', "y = DEBUG_LOG"):
        assert trio.send(line) == [], line
    assert trio.send("BATTERY_LOW = 1") == ["! Parameter is read only"]
    assert trio.send("DV_IN(3) = 1") == ["! Parameter is read only"]
    assert trio.send("AXISLIST(1)") == ["! Syntax error"]


def test_every_help_word_says_why_it_has_no_effect() -> None:
    from maxk.commands.trio.helpwords import HELP_WORDS
    from maxk.commands.trio.keywords import KEYWORDS

    names = [row.split()[1] for row in HELP_WORDS.splitlines()]
    assert len(names) == len(set(names)) == 32
    for name in names:
        note = KEYWORDS[name].note
        assert note.startswith("Not modelled: ") and "not modelled yet" not in note, name
        assert KEYWORDS[name].source == f"help {name}"


# ---- STATIC in a FUNCTION (TrioBASIC help STATIC) -------------------------------------------
COUNTER = """FUNCTION tally(amount AS INTEGER) AS INTEGER
    STATIC total AS INTEGER = 100
    DIM fresh AS INTEGER = 5
    STATIC seen AS INTEGER(2)
    total = total + amount
    fresh = fresh + amount
    seen(1) = seen(1) + 1
    RETURN total * 10000 + fresh * 100 + seen(1)
ENDFUNC"""


def test_static_keeps_its_value_between_calls_and_dim_starts_again() -> None:
    """total: 100 + 1, + 2, + 3 = 101, 103, 106; fresh: 5 + the step each call (6, 7, 8);
    the STATIC array's element counts the calls (1, 2, 3)."""
    trio = mc405()
    trio.load("LIB", COUNTER, program_type=12)
    trio.load("P", "PRINT tally(1)\nPRINT tally(2)\nPRINT tally(3)")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=20)
    assert trio.send("?0") == ["1010601", "1030702", "1060803", "0"]


def test_a_static_is_one_for_every_process_and_an_edit_starts_it_afresh() -> None:
    trio = mc405()
    trio.load("LIB", COUNTER, program_type=12)
    trio.load("P", "VR(1) = tally(10)")
    trio.load("Q", "VR(2) = tally(20)")
    assert trio.send('RUN "P", 3') == []
    trio.advance(ticks=10)
    assert trio.send('RUN "Q", 4') == []
    trio.advance(ticks=10)
    # P's call: 110, fresh 15, 1 call; Q's: 130, fresh 25, 2 calls (D: one store)
    assert (trio.query("?VR(1)"), trio.query("?VR(2)")) == ("1101501.0000", "1302502.0000")
    trio.load("LIB", COUNTER, program_type=12)  # stored again: compiled afresh
    assert trio.send('RUN "P", 3') == []
    trio.advance(ticks=10)
    assert trio.query("?VR(1)") == "1101501.0000"


def test_static_outside_a_function_is_a_dim() -> None:
    trio = mc405()
    trio.load("P", "STATIC n AS INTEGER = 7\nn = n + 1\nPRINT n")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=10)
    assert trio.send("?0") == ["8", "0"]


# ---- OPEN as a value (TrioBASIC help OPEN: value = OPEN #n AS ... FOR ...) -----------------
def test_open_as_a_value_is_0_when_it_opens_and_the_error_number_when_not() -> None:
    """The RUN_ERROR page's numbers: 19 Parameter out of range, 27 Program not found."""
    trio = mc405()
    trio.load("P", 'IF (OPEN #40 AS "SD:shift_log.txt" FOR OUTPUT(0)) = 0 THEN\n'
              '  PRINT #40, "ok"\n  CLOSE #40\nELSE\n  PRINT "failed"\nENDIF\n'
              'VR(1) = OPEN #41 AS "missing" FOR INPUT\nVR(2) = OPEN #7 AS "x" FOR INPUT')
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=10)
    assert (trio.query("?VR(1)"), trio.query("?VR(2)")) == ("27.0000", "19.0000")
    trio.load("Q", 'OPEN #42 AS "SHIFT_LOG" FOR INPUT\nLINPUT #42, VR(10)\nCLOSE #42')
    assert trio.send('RUN "Q"') == []
    trio.advance(ticks=10)
    assert trio.query("?VRSTRING(10)") == "ok"  # the program wrote its file


def test_open_as_a_value_keeps_running_where_the_statement_stops() -> None:
    trio = mc405()
    trio.load("P", 'x = OPEN #40 AS "a" FOR OUTPUT\nVR(3) = OPEN #40 AS "b" FOR OUTPUT\n'
              'OPEN #40 AS "c" FOR OUTPUT\nVR(4) = 1')
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=10)
    assert trio.send("?VR(4)") == ["%[Process 19:Program P Line 3] - Channel already open",
                                   "0.0000"]  # the statement form stopped the program
    # the value form gave the error's number and went on (139: the file is already open)
    assert trio.query("?VR(3)") == "139.0000"


def test_open_of_a_network_connection_as_a_value_is_false() -> None:
    trio = mc405()
    assert trio.query('?OPEN #20 AS "TCP:192.168.0.250(8000)" FOR READ_WRITE') == "0"
    assert trio.query('?OPEN #21 AS "DGRAM:127.0.0.1(8000)" FOR READ_WRITE') == "0"


# ---- THROW_ERROR (TrioBASIC help THROW_ERROR; RUN_ERROR 268) --------------------------------
def test_throw_error_stops_the_program_with_its_message_and_run_error_268() -> None:
    trio = mc405()
    trio.load("P", 'axis_no = 40\nIF axis_no > 15 THEN\n  THROW_ERROR("axis " + STR(axis_no, 0)'
              ' + " too high")\nENDIF\nVR(1) = 1')
    assert trio.send('RUN "P", 2') == []
    trio.advance(ticks=10)
    assert trio.send("?RUN_ERROR PROC(2)") == ["%[Process 2:Program P Line 3] - axis 40 too high",
                                               "268"]
    assert (trio.query("?ERROR_LINE PROC(2)"), trio.query("?VR(1)")) == ("3", "0.0000")


def test_on_basicerror_catches_a_thrown_error() -> None:
    trio = mc405()
    trio.load("P", 'ON BASICERROR GOTO caught\nTHROW_ERROR("stop here")\nSTOP\ncaught:\n'
              'VR(2) = RUN_ERROR\nVR(3) = ERROR_LINE')
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=10)
    assert (trio.query("?VR(2)"), trio.query("?VR(3)")) == ("268.0000", "2.0000")


def test_throw_error_wants_a_string() -> None:
    trio = mc405()
    assert trio.send('THROW_ERROR("typed here")') == ["! typed here"]
    assert trio.send("THROW_ERROR(5)") == ["! Type mismatch"]
    assert trio.send("THROW_ERROR") == ["! Syntax error"]


# ---- INPUTS0/INPUTS1 and MOTION_ERROR_COUNT ------------------------------------------------
def test_inputs0_and_inputs1_are_the_inputs_as_two_16_bit_numbers() -> None:
    trio = mc405()
    world = trio.world_view()
    for number in (0, 3, 15, 16, 31):
        world.set_input(number, True)
    # 2^0 + 2^3 + 2^15 = 32777; 2^(16-16) + 2^(31-16) = 32769
    assert (trio.query("?INPUTS0"), trio.query("?INPUTS1")) == ("32777", "32769")
    assert trio.query("?INPUTS0") == trio.query("?IN(0, 15)")
    assert trio.send("INPUTS0 = 1") == ["! Parameter is read only"]


def test_motion_error_count_counts_the_axes_in_error() -> None:
    trio = mc405()
    assert trio.query("?MOTION_ERROR_COUNT") == "0"
    trio = axis_1_in_error()
    assert trio.query("?MOTION_ERROR_COUNT") == "1"


# ---- OPEN #n AS "STRING:name" (OPEN's examples 8 and 9) -------------------------------------
def test_a_string_variable_opened_for_output_collects_what_is_printed() -> None:
    trio = mc405()
    trio.load("P", 'DIM note AS STRING(100)\nnote = "old"\n'
              'OPEN #41 AS "STRING:note" FOR OUTPUT(0)\nPRINT #41, "e = "; EXP(1)[3];\n'
              'PRINT #41, "!";\nCLOSE #41\nPRINT note; " "; LEN(note)[0]\n'
              'OPEN #41 AS "STRING:note" FOR APPEND\nPRINT #41, "?";\nCLOSE #41\nPRINT note')
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=10)
    # "e = 2.718!": 10 characters; OUTPUT emptied "old" first, APPEND kept what was there
    assert trio.send("?0") == ["e = 2.718! 10", "e = 2.718!?", "0"]


def test_a_string_variable_opened_for_input_is_read_a_character_at_a_time() -> None:
    trio = mc405()
    trio.load("P", 'DIM word AS STRING(8)\nword = "Hi"\nOPEN #45 AS "STRING:word" FOR INPUT\n'
              "GET #45, VR(1)\nGET #45, VR(2)\nCLOSE #45")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=10)
    assert (trio.query("?VR(1)"), trio.query("?VR(2)")) == ("72.0000", "105.0000")  # H, i


def test_a_string_channel_needs_a_string_variable_and_holds_its_length() -> None:
    trio = mc405()
    trio.load("P", 'DIM short AS STRING(3)\nOPEN #41 AS "STRING:short" FOR OUTPUT\n'
              'PRINT #41, "abcdef";\nCLOSE #41\nVR(1) = LEN(short)\nn = 5\n'
              'OPEN #42 AS "STRING:n" FOR OUTPUT')
    assert trio.send('RUN "P", 4') == []
    trio.advance(ticks=10)
    assert trio.send("?VR(1)") == ["%[Process 4:Program P Line 7] - Variable not defined",
                                   "3.0000"]  # cut to its 3 characters, as an assignment


# ---- a label spelled as a keyword (LTS-AS's manager program has `function:`) ---------------
def test_a_label_spelled_as_a_keyword_is_refused_at_compile() -> None:
    """FUNCTION is a keyword of this firmware (library functions): `function:` is no label
    (D, docs/trio.md), where an ordinary name is one."""
    trio = mc405()
    assert trio.load("P", "x = 1\nSTOP\nfunction:\nPRINT 1\nRETURN") == \
        ["%[Program P Line 3] - Syntax error"]
    assert trio.send('RUN "P"') == ["! Program P line 3: Syntax error"]
    assert trio.load("Q", "GOSUB routine\nSTOP\nroutine:\nVR(1) = 4\nRETURN") == []
    assert trio.send('RUN "Q"') == []
    trio.advance(ticks=5)
    assert trio.query("?VR(1)") == "4.0000"


# ---- the field operator's dims and dimsize (its page; FUNCTION's example 4) -----------------
SIZES = """FUNCTION largest(values AS INTEGER()) AS INTEGER
  DIM k, top AS INTEGER
  top = values(0)
  FOR k = 1 TO values.dimsize(0) - 1
    IF values(k) > top THEN top = values(k)
  NEXT k
  RETURN top
ENDFUNC
FUNCTION layout(grid AS FLOAT()) AS INTEGER
  RETURN grid.dims * 100 + grid.dimsize(0) * 10 + grid.dimsize(1)
ENDFUNC"""


def test_dims_and_dimsize_of_arrays_here_and_passed_to_a_function() -> None:
    trio = mc405()
    trio.load("LIB", SIZES, program_type=12)
    trio.load("P", "DIM v(6) AS INTEGER\nv = 4, 11, 2, 8, 15, 3\nVR(1) = largest(v)\n"
              "DIM g AS FLOAT(4, 7)\nVR(2) = layout(g)\nn = 2\n"
              "VR(3) = v.dims * 1000 + v.dimsize(0) * 100 + g.dimsize(1) * 10 + n.dims")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=10)
    # the largest of 4, 11, 2, 8, 15, 3 is 15; g: 2 dimensions of 4 and 7: 247;
    # v: 1 dimension of 6, g's second 7, n no array: 1000 + 600 + 70 + 0
    assert [trio.query(f"?VR({n})") for n in (1, 2, 3)] == ["15.0000", "247.0000",
                                                           "1670.0000"]


@pytest.mark.parametrize(("line", "error"), [
    ("?v.dimsize(1)", "Parameter out of range"), ("?v.dimsize(-1)", "Parameter out of range"),
    ("?n.dimsize(0)", "Parameter out of range"), ("?v.dimsize", "Syntax error"),
    ("?v.dims(0)", "Syntax error"), ("?nothing.dims", "Variable not defined")])
def test_dimsize_out_of_its_dimensions_is_refused(line: str, error: str) -> None:
    trio = mc405("DIM v(3) AS INTEGER", "n = 4")
    assert trio.send(line) == [f"! {error}"]


# ---- BASE alone prints the base array (BASE's example 3) ------------------------------------
def test_base_alone_prints_the_whole_array() -> None:
    trio = mc405()
    assert trio.send("BASE") == ["(" + ", ".join(str(a) for a in range(16)) + ")"]
    assert trio.send("BASE(2, 6, 11)") == []
    # after 11 the sequence goes on (12..15), then the axes left out, in order
    assert trio.send("BASE") == ["(2, 6, 11, 12, 13, 14, 15, 0, 1, 3, 4, 5, 7, 8, 9, 10)"]
    assert trio.query("?BASE") == "2"
    trio.load("P", "BASE(3)\nBASE")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=5)
    assert trio.send("?1") == ["(3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 0, 1, 2)", "1"]


def test_is_file_takes_a_string_variable_without_brackets() -> None:
    trio = mc405()
    trio.load("RECIPE1", "x = 1")
    trio.load("P", 'DIM wanted AS STRING(12)\nwanted = "recipe1"\n'
              'IF IS_FILE wanted THEN VR(1) = 1\nwanted = "recipe2"\n'
              'VR(2) = IS_FILE wanted\nVR(3) = IS_PROG wanted + "X"')
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=5)
    assert [trio.query(f"?VR({n})") for n in (1, 2, 3)] == ["1.0000", "0.0000", "0.0000"]


# ---- EX in a program (EX's page: "EX may be included in a program") ------------------------
def test_ex_in_a_program_restarts_the_controller_after_its_cycle() -> None:
    trio = mc405()
    trio.load("BOOT", 'PRINT "booted"')
    assert trio.send('RUNTYPE "BOOT", 1') == []  # an autorun program: it starts on EX
    trio.load("P", "SPEED = 123\nWDOG = ON\nEX\nSPEED = 5")
    assert trio.send('RUN "P", 3') == []
    trio.advance(ticks=20)
    # the line after EX never ran; SPEED and WDOG are at power-up again; BOOT ran once
    assert trio.send("?SPEED") == ["booted", "1000"]
    assert (trio.query("?WDOG"), trio.query("?PROC_STATUS PROC(3)")) == ("0", "0")


def test_ex_inside_a_command_line_is_still_refused() -> None:
    trio = mc405()
    assert trio.send("x = 1: EX") == ["! Syntax error"]
    trio.load("P", "EX(1, 2)")
    assert trio.send('RUN "P", 3') == ["! Program P line 1: Syntax error"]
