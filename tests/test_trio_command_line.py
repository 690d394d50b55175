"""The Trio command line byte for byte, as atrio needs it (reference trio-command-line.md)."""

from __future__ import annotations

import random
import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from maxk.commands.trio import ProgramStore, program_checksum
from tests.trio_helpers import AtrioError, Rig, parse_reply

TRAILER = b"\nControl char : 0x10000000A\r\n>>"


def test_the_exact_exchange_for_1_plus_1() -> None:
    """Reference section 2: echo, CR LF, output CR LF, '>>', LF, control-char line, '>>'."""
    assert Rig().send("?1+1") == b"?1+1\r\n2\r\n>>" + TRAILER


def test_echo_comes_char_by_char_and_case_is_kept() -> None:
    rig = Rig()
    out = b""
    for byte in b"?version":
        rig.session.feed(bytes([byte]))
        out += rig.session.read()
    assert out == b"?version"  # echoed as it arrives, lower case kept
    rig.session.feed(b"\r")
    assert rig.session.read() == b"\r\n2.0299\r\n>>"
    rig.session.feed(b"\n")
    assert rig.session.read() == TRAILER


@given(st.binary(min_size=1, max_size=8))
def test_any_split_of_the_input_gives_the_same_bytes(cuts: bytes) -> None:
    data = b"?1+1\r\n?2*3\r\nA=5\r\n?A\r\n"
    whole = Rig()
    whole.session.feed(data)
    expected = whole.session.read()
    pieces, start = Rig(), 0
    out = b""
    for cut in cuts:
        end = min(len(data), start + cut % 5)
        pieces.session.feed(data[start:end])
        out += pieces.session.read()
        start = end
    pieces.session.feed(data[start:])
    out += pieces.session.read()
    assert out == expected


def test_statement_has_no_output_lines() -> None:
    assert Rig().send("VR(3)=7") == b"VR(3)=7\r\n>>" + TRAILER


def test_prompt_has_no_trailing_space_and_lf_is_not_crlf() -> None:
    reply = Rig().send("?1")
    assert b">> " not in reply and b">>\r\nControl" not in reply
    assert reply.count(b">>") == 2


@pytest.mark.parametrize("x", [0, 7, 999999, 123456, 10, 500000])
def test_handshake_integer_prints_exactly(x: int) -> None:
    """Reference 3: `?<x>` must print x exactly: no decimals, no spaces."""
    assert Rig().command(f"?{x}").decode() == str(x)


def test_handshake_with_random_numbers_like_atrio() -> None:
    rig, rng = Rig(), random.Random(5)
    for _ in range(50):
        x = str(int(1000000 * rng.random()))
        assert rig.command("?" + x).decode() == x


def test_mpe_prints_zero_for_int() -> None:
    assert int(Rig().command("?MPE")) == 0
    assert Rig().command("?MPE") == b"0"


def test_version_is_a_float_at_least_2_0297() -> None:
    assert float(Rig().command("?version")) >= 2.0297


def test_error_line_form_is_seen_by_atrio() -> None:
    rig = Rig()
    reply = rig.send("FOO BAR")
    assert reply == b"FOO BAR\r\n%[COMMAND LINE] - Syntax error\r\n>>" + TRAILER
    with pytest.raises(AtrioError, match="Command Error"):
        parse_reply("FOO BAR", reply)


@pytest.mark.parametrize("cmd, message", [
    ("?1/0", b"Divide by zero"),
    ("DPOS=5", b"Parameter is read only"),
    ("PWM_CYCLE=70000", b"Parameter out of range"),
    ("?SPEED AXIS(99)", b"Invalid axis number"),
    ("PWM_MARK AXIS(8)=3", b"Axis 8 has no PWM output"),
    ("PWM_CONTROL(7)", b"PWM_CONTROL(7) is reserved"),
    ("WHILE 1", b"Structure error"),
    ('LIST "NOPE"', b"Program not found"),
])
def test_errors(cmd: str, message: bytes) -> None:
    reply = Rig().send(cmd)
    assert reply == cmd.encode() + b"\r\n%[COMMAND LINE] - " + message + b"\r\n>>" + TRAILER


def test_nothing_half_applied_on_error() -> None:
    rig = Rig()
    rig.command("BASE(0,1)")
    with pytest.raises(AtrioError):
        rig.command("MOVE(10, 1/0)")
    assert all(rig.machine.axis_idle(a) for a in (0, 1))
    with pytest.raises(AtrioError):
        rig.command("PWM_CONTROL(2, 0.1, 50, 500, 99)")
    assert rig.command("?PWM_MARK") == b"0"
    with pytest.raises(AtrioError):
        rig.command("TABLE(511999, 1, 2)")
    assert rig.command("?TABLE(511999)") == b"0.0000"  # a TABLE value is FLOAT


def test_telnet_negotiation_and_nul_are_ignored() -> None:
    rig = Rig()
    rig.session.feed(b"\xff\xfc\x01\xff\xfe\x03?1\xff\xfa\x18\x01\xff\xf0+1\r\x00\n")
    assert rig.session.read() == b"?1+1\r\n2\r\n>>" + TRAILER


def test_banner_before_echo_is_group_one() -> None:
    data = b"Welcome\r\n>>" + Rig().send("?5")
    assert parse_reply("?5", data) == b"5"


def test_other_control_chars_are_reported_the_same_way() -> None:
    rig = Rig()
    rig.session.feed(b"\x03")
    assert rig.session.read() == b"\x03Control char : 0x100000003\r\n>>"


def test_empty_line_gives_a_prompt() -> None:
    assert Rig().send("") == b"\r\n>>" + TRAILER


def test_wait_holds_the_prompt_and_queues_later_input() -> None:
    rig = Rig()
    assert rig.send("WA(3)") == b"WA(3)\r\n"
    rig.session.feed(b"?2\r\n")
    assert rig.session.read() == b""  # kept until WA ends
    assert rig.cycles(2) == b""
    assert rig.cycles(1) == b">>" + TRAILER + b"?2\r\n2\r\n>>" + TRAILER


def test_wait_idle_on_the_command_line() -> None:
    rig = Rig()
    rig.command("SPEED=1000")
    assert rig.send("MOVE(10):WAIT IDLE:?DPOS") == b"MOVE(10):WAIT IDLE:?DPOS\r\n"
    out = rig.cycles(10)
    assert out == b"10\r\n>>" + TRAILER
    assert rig.machine.tick == 10


def test_ex_echoes_and_never_sends_the_trailer() -> None:
    """Reference 5: atrio expects 'Cannot parse answer to b'EX': b'EX\\r\\n...'."""
    rig = Rig()
    reply = rig.send("EX")
    assert reply == b"EX\r\n"
    with pytest.raises(AtrioError, match=re.escape("Cannot parse answer to b'EX': b'EX\\r\\n")):
        parse_reply("EX", reply)
    assert rig.session.restart_requested
    assert rig.send("?1") == b""


def test_system_commands_atrio_sends() -> None:
    rig = Rig()
    assert int(rig.command("?SYSTEM_ERROR")) == 0
    rig.command("SYSTEM_LOAD_MAX=0")
    assert float(rig.command("?SYSTEM_LOAD_MAX")) == 0.0
    assert int(rig.command("?FLASH_STATUS")) == 0
    assert int(rig.command("ETHERCAT($22,0,-1)")) in range(4)
    for cmd in ("ETHERCAT($87,0)", "ETHERCAT($21, 0, 3, 0) ", "ETHERCAT(0, 0)",
                "ETHERCAT(1, 0)", "PROCESS", "HALT", "&M"):
        assert rig.command(cmd) == b""


# ---- program handling (reference section 5) ------------------------------------------

PROGRAM = ["' test", "VR(42) = 42", "a=1 : b = a+1", "PRINT b"]


def crc_atrio(lines: list[str]) -> int:
    """An independent bitwise CRC-16 (0x8005, init 0, MSB first), as crcmod computes it."""
    crc = 0
    for line in lines:
        for byte in line.encode() + b"\xaa":
            for bit in range(7, -1, -1):
                top = (crc >> 15) & 1
                crc = (crc << 1) & 0xFFFF
                if top ^ ((byte >> bit) & 1):
                    crc ^= 0x8005
    return crc


def test_crc_matches_an_independent_implementation() -> None:
    assert program_checksum(PROGRAM) == crc_atrio(PROGRAM)
    assert program_checksum([]) == 0


def test_write_program_like_atrio(tmp_path) -> None:
    rig = Rig(tmp_path)
    assert int(rig.command('?IS_PROG "TEST"')) == 0
    assert int(rig.command('?PROG_TYPE "TEST"')) == -1
    rig.load("TEST", "\n".join(PROGRAM))
    rig.command("!TEST,M")
    rig.command("!TEST,Z")
    assert rig.command('?IS_PROG "TEST"') == b"-1"
    assert int(rig.command('?PROG_TYPE "TEST"')) == 0
    assert rig.command('LIST "TEST"').decode().replace("\r\n", "\n") == "\n".join(PROGRAM)
    assert int(rig.command('EDPROG"TEST",10')) == crc_atrio(PROGRAM)
    rig.command('DEL "TEST"')
    assert int(rig.command('?IS_PROG "TEST"')) == 0


DIR_LINE = re.compile(r"^(?P<progname>[^\s]+)\s+(?P<source>\d+)\s+(?P<code>\d+)\s+(None|Manual|"
                      r"Power Up|Auto\((?P<autorun>[\-\d]+)\))\s+(?P<codetype>Normal|BASIC Lib|"
                      r"Text|MC_CONFIG|Project)")


def list_files(rig: Rig) -> dict[str, dict[str, str | None]]:
    """atrio's Trio.list_files."""
    dirlist = rig.command("DIR").decode().replace("\r\n", "\n")
    match = re.match(".*---------\n(.*)OK", dirlist, re.MULTILINE | re.DOTALL)
    assert match is not None
    files = {}
    for line in match.group(1).splitlines():
        m = DIR_LINE.match(line)
        assert m is not None, line
        files[m.group("progname")] = m.groupdict()
    return files


def test_dir_parses_with_atrios_regex(tmp_path) -> None:
    rig = Rig(tmp_path)
    assert list_files(rig) == {}
    rig.command('SELECT "TMP",0')
    rig.command('RUNTYPE"TMP",1,10')
    rig.load("NOTES", "just text", program_type=3)
    rig.command('SELECT "MC_CONFIG",9')
    files = list_files(rig)
    assert files["TMP"]["code"] == "0" and files["TMP"]["autorun"] == "10"
    assert files["TMP"]["codetype"] == "Normal"
    assert files["NOTES"]["codetype"] == "Text"
    assert files["MC_CONFIG"]["codetype"] == "MC_CONFIG"
    rig.command('RUNTYPE"TMP",0,-1')
    assert list_files(rig)["TMP"]["autorun"] is None


def test_autorun_reports_running_and_programs_survive_restart(tmp_path) -> None:
    rig = Rig(tmp_path)
    rig.load("TMP", "VR(42) = 42")
    rig.command('RUNTYPE"TMP",1,-1')
    rig.command("VR(42) = 40")
    out = rig.command("AUTORUN").decode()
    assert "Program TMP] - Running" in out
    rig.cycles(1)
    assert float(rig.command("?VR(42)")) == 42
    # a restart: a new session (and machine) on the same program directory
    rig.send("EX")
    again = Rig(tmp_path)
    again.command("VR(42) = 40")
    again.session.power_up()
    again.cycles(1)
    assert float(again.command("?VR(42)")) == 42
    assert again.command('LIST "TMP"') == b"VR(42) = 42"


def test_store_writes_atomically_leaving_no_temporaries(tmp_path) -> None:
    rig = Rig(tmp_path)
    rig.load("A", "PRINT 1\nPRINT 2")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["A.BAS", "directory.json"]
    assert (tmp_path / "A.BAS").read_text() == "PRINT 1\nPRINT 2\n"
    assert ProgramStore(tmp_path).lines["A"] == ["PRINT 1", "PRINT 2"]
    rig.command('SELECT "B",3')
    rig.command("!B,0R")  # one empty line survives the round trip
    assert ProgramStore(tmp_path).lines["B"] == [""]


def test_checksum_changes_with_programs() -> None:
    rig = Rig()
    rig.load("A", "PRINT 1")
    rig.command("COMPILE_ALL")
    first = int(rig.command("?CHECKSUM"))
    rig.command("!A,0RPRINT 2")
    assert int(rig.command("?CHECKSUM")) != first


def test_compile_reports_errors_with_line() -> None:
    rig = Rig()
    rig.load("BAD", "a=1\nWHILE a\nb=2")
    assert rig.command("COMPILE") == b"%[Program BAD Line 2] - Structure error"
    with pytest.raises(AtrioError):
        rig.command('RUN "BAD"')


def test_run_halt_and_program_output() -> None:
    rig = Rig()
    rig.load("LOOP", "n=0\nWHILE TRUE\nn=n+1\nIF n=3 THEN PRINT \"three\"\nWEND")
    rig.command('RUN "LOOP"')
    assert rig.command("PROCESS") == b"Process 19:Program LOOP - Running"  # highest free
    assert rig.cycles(2) == b""  # one loop pass per servo cycle
    assert rig.cycles(1) == b"three\r\n"
    assert rig.command("PROCESS") == b"Process 19:Program LOOP - Running"
    with pytest.raises(AtrioError, match="Program is running"):
        rig.command('RUN "LOOP"')
    with pytest.raises(AtrioError, match="Program is running"):
        rig.command("!LOOP,0Rn=5")
    rig.command("HALT")
    assert rig.command("PROCESS") == b""


def test_program_run_time_error_line() -> None:
    rig = Rig()
    rig.load("ERR", "a=1\nb=a/0")
    rig.command('RUN "ERR",3')
    assert rig.cycles(1) == b"%[Process 3:Program ERR Line 2] - Divide by zero\r\n"
    assert rig.command("PROCESS") == b""


# ---- robustness: whatever is typed, the controller answers and the session survives ---------

_WORDS = ["?", "PRINT ", "1", "0", "2.5", "-", "+", "*", "/", "^", "(", ")", ",", ";", ":",
          "=", "<>", " AND ", " NOT ", " MOD ", "SPEED", " AXIS(", "AXIS(99)", "PWM_MARK",
          "PWM_CONTROL(", "TABLE(", "VR(", '"', "'", "a", "IF ", " THEN ", " ELSE ", "MOVE(",
          "BASE(", "DEFPOS(", "CAMBOX(", "CONNPATH(", "1e999", "$FFFFFFFFFFFFFFFFFFF", "SQR(",
          "LN(", "DIR", "SELECT ", '"X"', "RUNTYPE", "EDPROG", "ETHERCAT(", "FOR ", "WHILE ",
          "!X,0R", "NEW", "DEL ", "LIST ", "COMPILE", "HALT", "STOP ", "RUN ", "PWM_ENCODER",
          "IDLE", " ", "MPE", "ACC(", "SERVO_PERIOD", "UNITS", "INT(", "EXP(", "1e300", "NEXT"]


@given(st.lists(st.sampled_from(_WORDS), max_size=12))
def test_any_line_gets_an_answer(words: list[str]) -> None:
    rig = Rig()
    rig.command('SELECT "X",0')
    line = "".join(words)
    reply = rig.send(line)
    assert reply.startswith(line.encode() + b"\r\n")
    assert reply.endswith(TRAILER)
    assert rig.send("?1+1").endswith(b"2\r\n>>" + TRAILER)


@given(st.binary(max_size=64))
def test_any_bytes_leave_the_session_working(data: bytes) -> None:
    rig = Rig()
    rig.session.feed(data.replace(b"\r", b"") + b"\xff\xf0")  # whatever: no exception
    rig.session.read()
    rig.session.feed(b"\r\n")
    rig.session.read()
    assert rig.send("?3").endswith(b"3\r\n>>" + TRAILER)
