"""TrioBASIC loop words (EXIT_LOOP, CONTINUE), program housekeeping (COPY, RENAME,
PROGRAM_NAME), variables (CLEAR, RESET, LIST_GLOBAL) and data words (TABLEVALUES, CRC16,
STRTOD, IEEE_IN, IEEE_OUT), each from what its help page says happens.

The CRC figures are the published check values of the CRC catalogue for the nine bytes
"123456789" (CRC-16/UMTS alias BUYPASS FEE8, CRC-16/ARC BB3D, CRC-16/MODBUS 4B37,
CRC-8 F4), not values computed by the code under test.
"""

from __future__ import annotations

import struct

import pytest

from maxk.commands.trio import TrioError, compile_program
from tests.trio_helpers import AtrioError, Rig


def started(text: str, name: str = "P") -> Rig:
    rig = Rig()
    rig.load(name, text)
    assert rig.command(f'RUN "{name}"') == b""
    return rig


# ---- EXIT_LOOP and CONTINUE: the help pages' example loop --------------------------------

_PAGE_LOOP = """SPEED=1000
WHILE IN(12) = OFF
  MOVE(5)
  WAIT IDLE
  IF IN(9) = ON THEN
    {word}
  ENDIF
  OP(10, OFF)
  MOVE(-5)
  WAIT IDLE
  OP(10, ON)
  VR(1) = VR(1) + 1
WEND
PRINT "out"; DPOS"""


def test_exit_loop_leaves_the_while_after_the_first_move() -> None:
    rig = Rig()
    rig.machine.inputs[9] = True
    rig.load("P", _PAGE_LOOP.format(word="EXIT_LOOP"))
    rig.command('RUN "P"')
    out = rig.cycles(40).decode()
    # one MOVE(5) at 1000 units/s (1 unit a 1 ms cycle), then out of the loop: the move
    # back, OP(10) and the counter never run
    assert out == "out5\r\n"
    assert rig.machine.dpos[0] == 5
    assert rig.machine.vr_read(1) == 0
    assert not rig.machine.output(10)


def test_without_exit_loop_the_same_loop_comes_back_and_counts() -> None:
    rig = started(_PAGE_LOOP.format(word="EXIT_LOOP"))  # IN(9) off: the word never runs
    assert rig.cycles(60) == b""
    assert rig.machine.vr_read(1) >= 2  # passes of 5 out and 5 back
    assert 0 <= rig.machine.dpos[0] <= 5
    rig.machine.inputs[12] = True
    out = rig.cycles(30)
    assert out == b"out0\r\n" and rig.machine.output(10)  # a whole pass, then out


def test_continue_skips_the_rest_of_the_pass_and_loops_on() -> None:
    rig = Rig()
    rig.machine.inputs[9] = True
    rig.load("P", _PAGE_LOOP.format(word="CONTINUE"))
    rig.command('RUN "P"')
    assert rig.cycles(100) == b""  # never leaves: IN(12) is off
    position = rig.machine.dpos[0]
    assert position >= 50  # only the MOVE(5)s run, pass after pass, never back
    assert rig.machine.vr_read(1) == 0 and not rig.machine.output(10)
    rig.machine.inputs[12] = True  # the WHILE's own test still decides at the WEND
    out = rig.cycles(20).decode()
    end = rig.machine.dpos[0]
    assert end % 5 == 0 and position <= end <= position + 5  # the move under way ends
    assert out == f"out{end:g}\r\n"


def test_continue_in_for_goes_to_next_and_exit_loop_leaves_only_the_inner_loop() -> None:
    text = "\n".join([
        "FOR i = 1 TO 3",
        "  FOR j = 1 TO 5",
        "    IF j = 2 THEN CONTINUE",
        "    IF j = 4 THEN EXIT_LOOP",
        "    PRINT i; j; \" \";",
        "  NEXT j",
        "NEXT i",
        "REPEAT",
        "  k = k + 1",
        "  IF k < 3 THEN CONTINUE",
        "  PRINT \"k\"; k",
        "UNTIL k >= 3",
    ])
    rig = started(text)
    # the loop counters are FLOAT variables (help DIM): 4 decimals each
    assert rig.cycles(40).decode() == ("1.00001.0000 1.00003.0000 2.00001.0000 2.00003.0000 "
                                       "3.00001.0000 3.00003.0000 k3.0000\r\n")


@pytest.mark.parametrize("lines, line", [
    (["a = 1", "EXIT_LOOP"], 2),
    (["IF a THEN CONTINUE"], 1),
    (["WHILE 1", "WEND", "CONTINUE"], 3),
])
def test_loop_words_outside_a_loop_are_structure_errors(lines: list[str], line: int) -> None:
    with pytest.raises(TrioError) as err:
        compile_program(lines)
    assert (err.value.message, err.value.line) == ("Structure error", line)


# ---- COPY, RENAME, PROGRAM_NAME ----------------------------------------------------------

def test_copy_makes_a_second_program_with_the_same_lines() -> None:
    rig = Rig()
    rig.load("MOTION", "VR(3) = 7\nPRINT PROGRAM_NAME")
    assert rig.command('COPY "MOTION"  "MOTION_BACK"') == b""
    assert rig.command('LIST "MOTION_BACK"') == b"VR(3) = 7\r\nPRINT PROGRAM_NAME"
    assert rig.command('LIST "MOTION"') == b"VR(3) = 7\r\nPRINT PROGRAM_NAME"
    rig.command('RUN "MOTION_BACK"')
    assert rig.cycles(3) == b"MOTION_BACK\r\n"
    with pytest.raises(AtrioError, match="Program already exists"):
        rig.command('COPY "MOTION" "MOTION_BACK"')
    with pytest.raises(AtrioError, match="Program not found"):
        rig.command('COPY "NOPE" "OTHER"')


def test_rename_moves_name_lines_and_runtype() -> None:
    rig = Rig()
    rig.load("CAR", "PRINT PROGRAM_NAME")
    rig.command('RUNTYPE "CAR", 1, 3')
    assert rig.command("RENAME car voiture") == b""
    assert rig.command('?IS_PROG "CAR"') == b"0"
    directory = rig.command("DIR").decode()
    assert "VOITURE" in directory and "Auto(3)" in directory and "CAR " not in directory
    rig.command('RUN "VOITURE"')
    assert rig.cycles(3) == b"VOITURE\r\n"


def test_rename_of_a_running_program_is_refused() -> None:
    rig = started("WHILE 1\nWEND", "LOOPER")
    with pytest.raises(AtrioError, match="Program is running"):
        rig.command("RENAME LOOPER OTHER")
    assert rig.command('?IS_PROG "LOOPER"') == b"-1"


def test_program_name_of_another_process_and_of_the_command_line() -> None:
    rig = Rig()
    rig.load("DEMO_PROG", "WHILE 1\nWEND")
    rig.command('RUN "DEMO_PROG", 18')
    rig.cycles(2)
    assert rig.command("?PROGRAM_NAME PROC(18)") == b"DEMO_PROG"
    assert rig.command("?PROGRAM_NAME PROC(5)") == b""  # no program on process 5
    assert rig.command("?PROGRAM_NAME") == b""


# ---- CLEAR, RESET, LIST_GLOBAL -----------------------------------------------------------

def test_clear_zeroes_the_vrs_and_the_local_variables_but_not_table() -> None:
    rig = Rig()
    text = ("VR(0) = 44\nVR(10) = 12.3456\nVR(100) = 2\nTABLE(5, 9)\nx = 3\n"
            "PRINT VR(0); \" \"; VR(10); \" \"; VR(100); \" \"; x\nCLEAR\n"
            "PRINT VR(0); \" \"; VR(10); \" \"; VR(100); \" \"; x; \" \"; TABLE(5)")
    rig.load("P", text)
    rig.command('RUN "P"')
    # VRs, variables and TABLE values are FLOAT: 4 decimals
    assert rig.cycles(5) == (b"44.0000 12.3456 2.0000 3.0000\r\n"
                             b"0.0000 0.0000 0.0000 0.0000 9.0000\r\n")


def test_reset_zeroes_only_the_local_variables() -> None:
    rig = Rig()
    rig.load("P", 'VR(2) = 5\ncounter = 4\nDIM s AS STRING(8)\ns = "ab"\nRESET\n'
             'PRINT counter; "/"; s; "/"; VR(2)')
    rig.command('RUN "P"')
    assert rig.cycles(5) == b"0.0000//5.0000\r\n"


def test_list_global_numbers_definitions_in_the_order_they_were_made() -> None:
    rig = Rig()
    rig.command('CONSTANT "cutter", 23')
    rig.command('GLOBAL "conveyor", 5')
    global_table = ["Global" + " " * 27 + "VR", "-" * 16 + " " * 17 + "----",
                    "conveyor" + " " * 25 + "5"]
    constant_table = ["Constant" + " " * 25 + "Value", "-" * 16 + " " * 17 + "-------",
                      "cutter" + " " * 27 + "23.00000"]
    assert rig.command("LIST_GLOBAL").decode().split("\r\n") == global_table + constant_table
    assert rig.command("LIST_GLOBAL 1").decode().split("\r\n") == global_table
    assert rig.command("LIST_GLOBAL 0,1").decode().split("\r\n") == constant_table
    assert rig.command("LIST_GLOBAL 0,-1").decode().split("\r\n") == \
        global_table + constant_table
    assert rig.command("LIST_GLOBAL 2") == b""
    with pytest.raises(AtrioError, match="Parameter out of range"):
        rig.command("LIST_GLOBAL -1")


# ---- TABLEVALUES -------------------------------------------------------------------------

def test_tablevalues_plain_and_compressed_as_the_page_shows() -> None:
    rig = Rig()
    rig.command("TABLE(1, 0.0, 0.1, 0.1, 0.1, 0.2, 0.2, 0.0)")
    plain = "0.0000,0.1000,0.1000,0.1000,0.2000,0.2000,0.0000"
    assert rig.command("TABLEVALUES(1, 7, 0)").decode() == plain
    assert rig.command("TABLEVALUES(1, 7)").decode() == plain
    assert rig.command("TABLEVALUES(1, 7, 1)").decode() == "0.0000,k3,0.1000,k2,0.2000,0.0000"
    for bad in ("TABLEVALUES(7, 1)", "TABLEVALUES(1, 7, 2)", "TABLEVALUES(-1, 3)"):
        with pytest.raises(AtrioError, match="Parameter out of range"):
            rig.command(bad)


# ---- CRC16 -------------------------------------------------------------------------------

def _digits_in_vr(rig: Rig, first: int) -> None:
    for k, char in enumerate(b"123456789"):
        rig.command(f"VR({first + k}) = {char}")


@pytest.mark.parametrize("setup, initial, expected", [
    ("CRC16(0, $8005)", "0", 0xFEE8),  # CRC-16/UMTS (BUYPASS)
    ("CRC16(0, $8005, TRUE, FALSE, 16)", "$FFFF", 0x4B37),  # the page's Modbus form
    ("CRC16(0, $8005, TRUE)", "0", 0xBB3D),  # CRC-16/ARC
    ("CRC16(0, 7, 0, 0, 8)", "0", 0xF4),  # CRC-8
    ("CRC16(0, $1021)", "0", 0x31C3),  # CRC-16/XMODEM
    # reverse_output turns the result's bits end for end (our decision): ARC's, reversed
    ("CRC16(0, $8005, 1, 1)", "0", int(f"{0xBB3D:016b}"[::-1], 2)),
])
def test_crc16_mode_2_gives_the_catalogue_check_values(setup: str, initial: str,
                                                        expected: int) -> None:
    rig = Rig()
    _digits_in_vr(rig, 100)
    rig.command(setup)
    assert rig.command(f"?CRC16(2, 1, 100, 108, {initial})") == str(expected).encode()


def test_crc16_mode_2_carries_on_from_a_previous_result() -> None:
    rig = Rig()
    _digits_in_vr(rig, 0)
    rig.command("CRC16(0, $8005)")
    rig.command("VR(20) = CRC16(2, 1, 0, 3, 0)")
    assert rig.command("?CRC16(2, 1, 4, 8, VR(20))") == str(0xFEE8).encode()


def test_crc16_legacy_mode_needs_the_two_zero_bytes_to_flush() -> None:
    rig = Rig()
    rig.command("TABLE(0, 49, 50, 51, 52, 53, 54, 55, 56, 57, 0, 0)")
    assert rig.command("?CRC16(1, 0, 0, 10, 0)") == b"0"  # not initialised yet (page)
    assert rig.command("?CRC16(0, $8005)") == b"-1"
    assert rig.command("?CRC16(1, 0, 0, 10, 0)") == str(0xFEE8).encode()
    # the page's example 2: the data, then each flush byte from VR(0) = 0 on its own
    rig.command("VR(0) = 0")
    rig.command("c = CRC16(1, 0, 0, 8, 0)")
    rig.command("c = CRC16(1, 1, 0, 0, c)")
    assert rig.command("?CRC16(1, 1, 0, 0, c)") == str(0xFEE8).encode()


def test_crc16_bad_arguments() -> None:
    rig = Rig()
    for bad in ("CRC16(0, $10000)", "CRC16(0, 7, 0, 0, 40)", "?CRC16(3, 0, 0, 1, 0)",
                "?CRC16(2, 2, 0, 1, 0)", "?CRC16(2, 1, 5, 1, 0)"):
        with pytest.raises(AtrioError, match="Parameter out of range"):
            rig.command(bad)


# ---- IEEE_IN, IEEE_OUT -------------------------------------------------------------------

def test_ieee_out_and_in_round_trip_single_and_double() -> None:
    rig = Rig()
    # -2.5 is sign 1, exponent 128, mantissa .25: C0 20 00 00 (single)
    assert [rig.command(f"?IEEE_OUT(-2.5, {n})") for n in range(4)] == \
        [b"192", b"32", b"0", b"0"]
    # 1.0 as a double: 3F F0 00 00 00 00 00 00
    assert [int(rig.command(f"?IEEE_OUT(1, {n}, 64)")) for n in range(8)] == \
        [0x3F, 0xF0, 0, 0, 0, 0, 0, 0]
    assert rig.command("?IEEE_IN(192, 32, 0, 0)") == b"-2.5000"
    assert rig.command("?IEEE_IN(63, 240, 0, 0, 0, 0, 0, 0)") == b"1"
    rig.command("a = 1234.5")
    bytes_ = [int(rig.command(f"?IEEE_OUT(a, {n})")) for n in range(4)]
    assert bytes_ == list(struct.pack(">f", 1234.5))
    for bad in ("?IEEE_OUT(1, 4)", "?IEEE_OUT(1, 0, 16)", "?IEEE_IN(256, 0, 0, 0)",
                "?IEEE_OUT(1e300, 0)"):
        with pytest.raises(AtrioError, match="Parameter out of range"):
            rig.command(bad)


# ---- STRTOD ------------------------------------------------------------------------------

def _text_in_vr(rig: Rig, first: int, text: str) -> None:
    for k, char in enumerate(text + "\0"):
        rig.command(f"VR({first + k}) = {ord(char)}")


@pytest.mark.parametrize("text, fmt, value, used", [
    ("12.7E-3x", 0, "0.0127", 7), ("+12.6;", 0, "12.6000", 5), (".125", 0, "0.1250", 4),
    ("-0.12", 0, "-0.1200", 5), ("1.6e+3", 0, "1600", 6), ("12.", 0, "12", 3),
    ("12.5", 2, "0", 4), ("42,", 2, "42", 2), ("abc", 0, "0", 0),
])
def test_strtod_from_vrs(text: str, fmt: int, value: str, used: int) -> None:
    rig = Rig()
    _text_in_vr(rig, 200, text)
    assert rig.command(f"?STRTOD({fmt}, 200, 10)") == value.encode()
    assert rig.command("?VR(10)") == f"{200 + used}.0000".encode()


def test_strtod_from_a_channel_as_the_pages_example() -> None:
    rig = Rig()
    rig.load("N", "123.456")
    rig.load("P", 'OPEN #40 AS "N" FOR INPUT\nVR(100) = STRTOD(1, 40, 101, 102)\n'
             'PRINT VR(100); " "; VR(101); " "; VR(102)\nCLOSE #40')
    rig.command('RUN "P"')
    assert rig.cycles(5) == b"123.4560 7.0000 13.0000\r\n"


def test_strtod_letter_codes_from_a_channel() -> None:
    rig = Rig()
    rig.load("G", "G1 X12.5 Y-3 F100")
    rig.load("P", 'OPEN #41 AS "G" FOR INPUT\nm = STRTOD(7, 41, 10, 11, 20)\n'
             'PRINT m; " "; VR(20 + 6); " "; VR(20 + 23); " "; VR(20 + 24); " "; VR(25); '
             '" "; VR(10)\nCLOSE #41')
    rig.command('RUN "P"')
    mask = (1 << 6) | (1 << 23) | (1 << 24) | (1 << 5)  # G, X, Y, F
    assert rig.cycles(5).decode() == f"{mask}.0000 1.0000 12.5000 -3.0000 100.0000 17.0000\r\n"


# ---- INTEGER_READ, INTEGER_WRITE -----------------------------------------------------

def test_integer_read_splits_the_float_pattern_of_a_vr() -> None:
    rig = Rig()
    rig.command("VR(1) = 0.9999")
    rig.command("INTEGER_READ(VR(1), VR(4), VR(5))")
    pattern = struct.unpack(">Q", struct.pack(">d", 0.9999))[0]  # 3FEFFF2E 48E8A71E
    assert rig.command("?VR(4)") == f"{pattern & 0xFFFFFFFF}.0000".encode()
    assert rig.command("?HEX(VR(5)), HEX(VR(4))") == b"3FEFFF2E\t48E8A71E"


def test_integer_write_then_read_gives_the_words_back() -> None:
    rig = Rig()
    rig.command("INTEGER_WRITE(VR(1), $1234, $5678)")
    rig.command("INTEGER_READ(VR(1), VR(4), TABLE(9))")
    assert rig.command("?HEX(VR(4)), HEX(TABLE(9))") == b"1234\t5678"
    rig.command("INTEGER_WRITE(VR(1), $48E8A71E, $3FEFFF2E)")
    assert rig.command("?VR(1)") == b"0.9999"


def test_integer_read_of_a_parameter_is_its_integer_pattern() -> None:
    rig = Rig()
    rig.command("DEFPOS(-3)")
    rig.command("INTEGER_READ(DPOS, lo, hi)")
    assert rig.command("?lo; \" \"; HEX(hi)") == f"{2**32 - 3}.0000".encode() + b" FFFFFFFF"
    for bad in ("INTEGER_WRITE(VR(1), 0, $7FF00000)",  # +infinity
                "INTEGER_WRITE(VR(1), 1.5, 0)", "INTEGER_WRITE(VR(1), $100000000, 0)"):
        with pytest.raises(AtrioError, match="Parameter out of range"):
            rig.command(bad)
    assert rig.command("?VR(1)") == b"0.0000"  # nothing written by the refused ones


def test_io_and_analogue_counts() -> None:
    rig = Rig()
    assert [rig.command(f"?{word}") for word in ("NIO", "N_ANA_IN", "N_ANA_OUT")] == \
        [b"32", b"8", b"8"]
    rig.command("?IN(31)")  # the last point NIO counts is addressable
    with pytest.raises(AtrioError, match="read only"):
        rig.command("NIO = 48")


# ---- OPEN ... FOR OUTPUT / APPEND: files a program writes -----------------------------

def test_strtod_page_example_writes_a_file_then_reads_it_back() -> None:
    rig = Rig()
    rig.load("P", "\n".join([
        'OPEN #40 AS "N" FOR OUTPUT(1)', 'PRINT #40, "123.456"', "CLOSE #40",
        'OPEN #40 AS "N" FOR INPUT', "VR(100) = STRTOD(1, 40, 101, 102)",
        'PRINT #5, "Value = "; VR(100)', 'PRINT #5, "Length of string = "; VR(101)[0]',
        'PRINT #5, "Terminating character = "; VR(102)[0]', "CLOSE #40"]))
    rig.command('RUN "P"')
    assert rig.cycles(5).decode().split("\r\n") == [
        "Value = 123.4560", "Length of string = 7", "Terminating character = 13", ""]
    assert rig.command('?PROG_TYPE "N"') == b"3"  # a text file of the store


def test_output_clears_append_adds_and_a_partial_line_waits_for_close() -> None:
    rig = Rig()
    rig.load("LOG", "old line", program_type=3)
    rig.load("P", "\n".join([
        'OPEN #41 AS "LOG" FOR OUTPUT', 'PRINT #41, "shift"; 2', 'PRINT #41, 7; " parts";',
        "WA(3)", "CLOSE #41", 'OPEN #42 AS "LOG" FOR APPEND', 'PRINT #42, "end"',
        "CLOSE #42"]))
    rig.command('RUN "P"')
    rig.cycles(1)
    assert rig.command('LIST "LOG"') == b"shift2"  # the open line is not written yet
    assert rig.cycles(10) == b""  # nothing reaches the terminal
    assert rig.command('LIST "LOG"') == b"shift2\r\n7 parts\r\nend"


def test_append_to_a_missing_file_is_an_error_and_opens_nothing() -> None:
    rig = Rig()
    rig.load("P", 'OPEN #43 AS "NOFILE" FOR APPEND\nPRINT "not here"')
    rig.command('RUN "P"')
    assert b"Program not found" in rig.cycles(3)
    assert rig.command('?IS_PROG "NOFILE"') == b"0"


# ---- LOADED on the MC405 ----------------------------------------------------------------

def test_loaded_turns_true_on_the_tick_the_held_move_starts() -> None:
    from maxk.controllers.trio import MC405

    trio = MC405()
    assert trio.send("BASE(0): SPEED=1000: ACCEL=10000: DECEL=10000") == []
    assert trio.send("MOVE(100): MOVE(50)") == []
    # the first move: peak speed 1000 reached after 0.1 s at 10000/s^2 covers 50, so a
    # triangle of 0.1 s up and 0.1 s down ends at 100 on tick 200 (1 ms ticks)
    trio.advance(ticks=199)
    assert (trio.query("?LOADED"), trio.machine.dpos(0) < 100) == ("0", True)
    trio.advance(ticks=1)
    assert (trio.query("?LOADED"), trio.machine.dpos(0)) == ("-1", 100.0)
    assert trio.send("LOADED = 1") == ["! Parameter is read only"]


def test_is_open_follows_open_and_close() -> None:
    rig = Rig()
    rig.load("N", "x", program_type=3)
    rig.load("P", 'PRINT IS_OPEN #40\nOPEN #40 AS "N" FOR INPUT\nPRINT IS_OPEN #40; '
             'IS_OPEN #41\nCLOSE #40\nIF FALSE = IS_OPEN #40 THEN PRINT "closed"')
    rig.command('RUN "P"')
    assert rig.cycles(5) == b"0\r\n-10\r\nclosed\r\n"


def test_demand_edges_is_dpos_in_encoder_edges_at_each_tick() -> None:
    from maxk.controllers.trio import MC405

    trio = MC405()
    assert trio.send("UNITS=400: SPEED=10: ACCEL=100: DECEL=100: MOVE(2.5)") == []
    trio.advance(ticks=100)  # 0.1 s into the ramp at 100 units/s^2: 0.5 units
    assert trio.query("?DEMAND_EDGES") == str(round(0.5 * 100 * 0.1 ** 2 * 400))
    trio.advance(ticks=2000)  # long done: 2.5 units of 400 edges
    assert trio.query("?DEMAND_EDGES AXIS(0)") == "1000"
    assert trio.send("DEMAND_EDGES = 5") == ["! Parameter is read only"]


def test_seek_moves_where_the_next_read_starts() -> None:
    rig = Rig()
    rig.load("P", "\n".join([
        "DIM s AS STRING(40)",
        'OPEN #40 AS "MY_FILE" FOR OUTPUT(1)',
        'PRINT #40, "Trio Motion Technology MC range"', "CLOSE #40",
        'OPEN #40 AS "MY_FILE" FOR INPUT',
        "SEEK #40, 0, 23", "LINPUT #40, s", "PRINT s",  # 23 characters in: the M of MC
        "SEEK #40, 0, 5", "GET #40, c", "SEEK #40, 1, 1", "GET #40, d",
        "PRINT CHR(c); CHR(d)",  # M of Motion, then one skipped: t
        "SEEK #40, 1, 1000"]))
    rig.command('RUN "P"')
    out = rig.cycles(10).decode()
    assert out.startswith("MC range\r\nMt\r\n")
    assert "Parameter out of range" in out


# ---- CHANNEL_WRITE, CHANNEL_READ ------------------------------------------------------

def test_channel_write_then_read_a_string_as_the_page_example_1() -> None:
    rig = Rig()
    rig.load("P", "\n".join([
        "DIM output_string AS STRING(10)", "DIM input_string AS STRING(10)",
        'output_string = "0123456789"', 'OPEN #40 AS "test.txt" FOR OUTPUT(1)',
        "n = CHANNEL_WRITE(40, output_string)", "CLOSE #40",
        'OPEN #41 AS "test.txt" FOR INPUT', "CHANNEL_READ(41, input_string)",
        "PRINT #5, input_string; \" \"; n", "CLOSE #41"]))
    rig.command('RUN "P"')
    assert rig.cycles(5) == b"0123456789 10.0000\r\n"
    assert rig.command('LIST "TEST"') == b"0123456789"


def test_channel_write_from_vrs_and_an_integer_array() -> None:
    rig = Rig()
    rig.load("P", "\n".join([
        "DIM buf AS INTEGER(3)", "buf(0) = 84", "buf(1) = 82", "buf(2) = 73",
        'OPEN #40 AS "ram:out" FOR OUTPUT(1)', "CHANNEL_WRITE(40, buf, 3)",
        "VR(100) = 79", "VR(101) = 10", "CHANNEL_WRITE(40, 100, 2)", "CLOSE #40",
        'CHANNEL_WRITE(0, "to the terminal", 6)']))
    rig.command('RUN "P"')
    assert rig.cycles(5) == b"to the"
    assert rig.command('LIST "OUT"') == b"TRIO"


def test_channel_read_into_vrs_stops_at_each_delimiter() -> None:
    rig = Rig()
    rig.load("P", "\n".join([
        'OPEN #40 AS "ram:test" FOR OUTPUT(1)', "FOR i = 9 TO 11", "  PRINT #40, i[0]",
        "NEXT i", "CLOSE #40", "VR(10) = 13", "VR(11) = 10",
        'OPEN #40 AS "ram:test" FOR INPUT', "REPEAT",
        "  c = CHANNEL_READ(40, 100, 100, 10, 2)",
        "  PRINT c[0]; \" \"; VR(100)[0]; \" \"; VRSTRING(101)", "UNTIL NOT KEY #40",
        "CLOSE #40"]))
    rig.command('RUN "P"')
    # each line: its digits up to the CR (reason 1), then the LF alone (reason 2)
    assert rig.cycles(40).decode().split("\r\n") == [
        "1 1 9", "0 2 ", "2 1 10", "0 2 ", "2 1 11", "0 2 ", ""]


def test_channel_read_string_form_escape_and_crc() -> None:
    rig = Rig()
    rig.load("SRC", "ab\\,c,def", program_type=3)
    rig.load("P", "\n".join([
        "DIM b AS STRING(20)", "CRC16(0, $8005)", 'OPEN #40 AS "SRC" FOR INPUT',
        's = CHANNEL_READ(40, b, ",;", 92, 7)', 'PRINT s; " "; b; " "; VR(7)',
        "CLOSE #40"]))
    rig.command('RUN "P"')
    crc = 0  # CRC-16 (poly $8005, MSB first, init 0) of "ab,c" worked by hand below
    for byte in b"ab,c":
        for k in range(7, -1, -1):
            feedback = ((crc >> 15) & 1) ^ ((byte >> k) & 1)
            crc = (crc << 1) & 0xFFFF
            if feedback:
                crc ^= 0x8005
    assert rig.cycles(5).decode() == f"-1.0000 ab,c {crc}.0000\r\n"


def test_channel_words_on_a_closed_file_channel() -> None:
    rig = Rig()
    for bad in ('?CHANNEL_WRITE(40, "x")', "?CHANNEL_READ(41, 100, 10)"):
        with pytest.raises(AtrioError, match="Channel not open"):
            rig.command(bad)


def test_channel_write_page_example_2_text_stored_in_vrs() -> None:
    rig = Rig()
    rig.load("P", "\n".join([
        'OPEN #40 AS "sd:test.txt" FOR OUTPUT(1)',
        'VR(100) = "Brevity is the soul of wit."', "CHANNEL_WRITE(#40, 100, 27)",
        "CLOSE #40", 'OPEN #41 AS "sd:test.txt" FOR INPUT',
        "n = CHANNEL_READ(41, 500, 42)", "PRINT #5, VRSTRING(501); \"|\"; n; VR(500)",
        "CLOSE #41"]))
    rig.command('RUN "P"')
    # 27 characters, then the file's CR LF line end: read on to the end (reason 0)
    assert rig.cycles(5) == b"Brevity is the soul of wit.|29.00000.0000\r\n"
    assert rig.command("?VR(100); \" \"; VR(126); \" \"; VR(127)") == \
        b"66.0000 46.0000 0.0000"


def test_channel_read_string_buffer_with_delimiters_in_vrs() -> None:
    rig = Rig()
    rig.load("SRC", "12\n34", program_type=3)
    rig.load("P", "\n".join([
        "DIM b AS STRING(100)", "VR(10) = 13", "VR(11) = 10",
        'OPEN #40 AS "SRC" FOR INPUT', "s = CHANNEL_READ(40, b, 10, 2)",
        "t = CHANNEL_READ(40, b, 10, 2)", "u = CHANNEL_READ(40, b, 10, 2)",
        'PRINT s; t; " "; b; u', "CLOSE #40"]))
    rig.command('RUN "P"')
    assert rig.cycles(5) == b"-1.0000-2.0000 34-1.0000\r\n"


# ---- OUTDEVICE, INDEVICE ---------------------------------------------------------------

def test_outdevice_and_indevice_redirect_print_and_reads_of_this_process() -> None:
    rig = Rig()
    rig.load("P", "\n".join([
        'OPEN #40 AS "LOG" FOR OUTPUT', "OUTDEVICE = 40", 'PRINT "into the file"',
        "PRINT OUTDEVICE", "OUTDEVICE = 0", "CLOSE #40", 'PRINT "terminal"',
        'OPEN #41 AS "LOG" FOR INPUT', "INDEVICE = 41", "LINPUT s", "PRINT KEY",
        "GET c", "PRINT c; INDEVICE", "CLOSE #41"]))
    rig.command('RUN "P"')
    # the file's first line is read whole; its second starts with "4" (code 52)
    assert rig.cycles(10) == b"terminal\r\n-1\r\n52.000041\r\n"
    assert rig.command('LIST "LOG"') == b"into the file\r\n40"
    assert rig.command("?OUTDEVICE") == b"0"  # the command line's own, untouched
    for bad in ("OUTDEVICE = 256", "INDEVICE = 1.5"):
        with pytest.raises(AtrioError, match="Parameter out of range"):
            rig.command(bad)


# ---- SCOPE_CYCLE_COUNT ------------------------------------------------------------------

def test_scope_cycle_count_counts_triggers_and_repeated_scans() -> None:
    from maxk.controllers.trio import MC405

    trio = MC405()
    assert trio.query("?SCOPE_CYCLE_COUNT") == "0"
    trio.send("TRIGGER")  # nothing armed: no cycle starts
    assert trio.query("?SCOPE_CYCLE_COUNT") == "0"
    trio.send("SCOPE(ON, 1, 0, 3, TICKS)")  # TABLE 0..3: 4 samples
    trio.send("TRIGGER")
    trio.advance(ticks=10)  # 4 samples, then the capture ends
    assert trio.query("?SCOPE_CYCLE_COUNT") == "1"
    trio.send("TRIGGER(1)")  # repeating: a new scan every 4 samples (ticks 0-3, 4-7, ...)
    trio.advance(ticks=9)  # scans start on ticks 0, 4 and 8 of these 9
    assert trio.query("?SCOPE_CYCLE_COUNT") == "4"
    assert trio.send("SCOPE_CYCLE_COUNT = 0") == ["! Parameter is read only"]
