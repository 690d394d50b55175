"""The MC405 under abuse (issue 30's Trio items), each through the telnet door as atrio
uses it: a busy program costs virtual time and stops on HALT from another host, the
program store checks names and survives a hostile index, the store has limits, and every
numeric path refuses an overflowing operand with the controller's error."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from maxk.commands.trio.programs import MAX_PROGRAM_BYTES, MAX_PROGRAMS
from maxk.commands.trio.tasks import STATEMENTS_PER_CYCLE
from maxk.controllers.trio.controller import MC405
from tests.test_trio_doors import HostError, TrioHost, host, hosted  # noqa: F401
from tests.trio_helpers import AtrioError, parse_reply


def _upload(client: TrioHost, name: str, lines: list[str]) -> None:
    client.cmd(f'SELECT "{name}",0')
    for n, line in enumerate(lines):
        client.cmd(f"!{name},{n}R{line}")
    client.cmd("COMPILE")


def test_a_busy_program_costs_virtual_time_and_halt_from_another_host_stops_it(
        hosted, host) -> None:  # noqa: F811
    body = [f"VR(1) = VR(1) + {k % 7} * 2 - {k % 7} * 2 + 1" for k in range(500)]
    _upload(host, "BUSY", ["VR(1) = 0", "WHILE 1", *body, "  VR(2) = VR(2) + 1", "WEND"])
    host.cmd('RUN "BUSY"')
    hosted.advance(0.003)  # three servo cycles: the program is sliced, not run to the end
    # each cycle runs STATEMENTS_PER_CYCLE statements: VR(1)=0 and WHILE, then the body
    assert host.cmd_float("?VR(1)") == 3 * STATEMENTS_PER_CYCLE - 2
    assert host.cmd_int("?VR(2)") == 0  # 500 lines are more than one cycle's slice
    other = TrioHost(hosted.ports[0])
    other.connect()
    assert other.cmd("HALT") == ""
    stopped = host.cmd_float("?VR(1)")
    hosted.advance(0.1)
    assert host.cmd_float("?VR(1)") == stopped
    assert host.cmd("PROCESS") == ""
    other.close()


EXTREMES = ["1e308", "-1e308", "1e-320", "9223372036854775808", "1" * 250,
            "1e309", "-1e309"]


@pytest.mark.parametrize("value", EXTREMES)
def test_move_refuses_an_overflow_with_the_controllers_error(hosted, host, value) -> None:  # noqa: F811
    host.cmd("UNITS AXIS(0)=16")
    try:
        host.cmd(f"MOVE({value}) AXIS(0)")
    except HostError as exc:
        assert "Parameter out of range" in str(exc) or "Arithmetic error" in str(exc)
        assert host.cmd_float("?DPOS AXIS(0)") == 0
        hosted.advance(0.1)
        assert host.cmd("?IDLE AXIS(0)") == "-1"
    else:  # only a tiny value is a move (of no counts)
        assert float(value) < 1
        hosted.advance(0.1)
        assert host.cmd_float("?DPOS AXIS(0)") == 0


@pytest.mark.parametrize("statement", [
    "MOVEABS({v}) AXIS(0)", "DEFPOS({v}) AXIS(0)", "SPEED AXIS(0)={v}", "VR(3)={v}*{v}",
    "TABLE(0,{v}*10)", "WA({v}+2e12)", "PWM_MARK AXIS(4)={v}", "VR({v})=1", "?{v}*{v}*{v}",
    "?SQR({v})", "?EXP({v})", "?INT({v})*1e10", "?{v} MOD 3", "?{v} AND 1"])
@pytest.mark.parametrize("value", ["1e308", "-1e308", "1e-320", "9223372036854775808",
                                   "1" * 250, "1e309"])
def test_every_numeric_path_answers_overflow_with_an_error_line(
        hosted, host, statement, value) -> None:  # noqa: F811
    """Never a traceback, never a dead door: the controller's error, or a value."""
    host.cmd("UNITS AXIS(0)=16")
    try:
        host.cmd(statement.format(v=value))
    except HostError as exc:
        assert re.fullmatch(r"Command Error b'\[COMMAND LINE\] - [A-Z][A-Za-z ]+'", str(exc))
    hosted.advance(0.05)
    assert host.cmd("?1+1") == "2"  # the door still answers


def test_move_overflow_behind_a_wait_is_an_error_line_not_an_escape(hosted, host) -> None:  # noqa: F811
    _upload(host, "OVER", ["UNITS AXIS(0)=16", "WA(5)", "MOVE(1e308) AXIS(0)"])
    host.cmd('RUN "OVER"')
    hosted.advance(0.02)
    said = host.unasked()
    assert said == b"%[Process 19:Program OVER Line 3] - Parameter out of range\r\n"
    assert host.cmd("?1") == "1"


# ---- the program store ---------------------------------------------------------------------

@pytest.mark.parametrize("index", [
    '[{"name": "../VICTIM", "type": 0}]',
    '[{"name": "lower", "type": 0}]',
    "{",
    '[{"name": "A", "type": 0, "evil": 1}]',
    '{"name": "A"}',
    '[{"name": "A", "type": 99}]',
    '[{"name": "A", "type": 0}, {"name": "A", "type": 0}]',
    '[{"name": "A/B", "type": 0}]',
    '"not a list"',
])
def test_a_hostile_index_reads_as_damaged_and_start_up_goes_on(tmp_path: Path,
                                                                 index: str) -> None:
    store = tmp_path / "mc.programs"
    store.mkdir()
    (store / "directory.json").write_text(index)
    (tmp_path / "VICTIM.BAS").write_text("secret\n")
    controller = MC405(store)
    assert controller.programs.damage is not None
    assert "set aside as mc.programs.damaged-1" in controller.programs.damage
    assert (tmp_path / "mc.programs.damaged-1" / "directory.json").read_text() == index
    session = controller.open_session()
    session.feed(b"DIR\r\n")
    out = session.read()
    assert b"KeyError" not in out and b"VICTIM" not in out
    for command in ('LIST "../VICTIM"', 'DEL "../VICTIM"', 'SELECT "../VICTIM",0'):
        session.feed(command.encode() + b"\r\n")
        out = session.read()
        assert b"%[COMMAND LINE] - " in out
    assert (tmp_path / "VICTIM.BAS").read_text() == "secret\n"
    session.feed(b'SELECT "GOOD",0\r\n')
    parse_reply('SELECT "GOOD",0', session.read())
    assert json.loads((store / "directory.json").read_text())[0]["name"] == "GOOD"


def test_the_store_has_the_controllers_limits(hosted, host) -> None:  # noqa: F811
    for n in range(MAX_PROGRAMS):
        host.cmd(f'SELECT "P{n}",0')
    with pytest.raises(HostError, match="Too many programs"):
        host.cmd('SELECT "ONEMORE",0')
    host.cmd('SELECT "P0",0')  # selecting an existing one is no creation
    line = "VR(1)=" + "1" * 1000
    count = MAX_PROGRAM_BYTES // (len(line) + 1)
    for n in range(count):
        host.cmd(f"!P0,{n}R{line}")
    with pytest.raises(HostError, match="Program too large"):
        host.cmd(f"!P0,{count}R{line}")
    size = count * (len(line) + 1)
    assert re.search(rf"^P0\s+{size}\s", host.cmd("DIR"), re.MULTILINE)
    host.cmd("!P0,0D")  # a deletion always fits
    host.cmd(f"!P0,0I{line}")


def test_a_bad_program_name_is_refused_by_every_command(hosted, host) -> None:  # noqa: F811
    for command in ('SELECT "../X",0', 'SELECT "A.B",0', 'LIST "../X"',
                    'DEL "/etc/passwd"', 'RUN "..\\X"', 'SELECT "' + "A" * 33 + '",0'):
        with pytest.raises(HostError):
            host.cmd(command)
    with pytest.raises(AtrioError):
        raise AtrioError  # (the in-process parse agrees, see test_trio_command_line)


def test_a_real_style_program_uploads_compiles_and_runs_over_the_door(hosted, host) -> None:  # noqa: F811
    """atrio's upload of a program with labels, GOSUB, a FUNCTION, DIM, CONSTANT and
    PRINT #, then RUN: what it prints arrives unasked, the axis ends where it must."""
    _upload(host, "CELL", [
        'CONSTANT "PITCH", 250',
        "DIM spots(3) AS FLOAT",
        "FOR i = 0 TO 2 : spots(i) = offset(i) : NEXT i",
        "BASE(0) : SPEED = 1000 : ACCEL = 100000 : DECEL = 100000",
        "GOSUB visit",
        'PRINT #5, "done at "; DPOS[6,1]',
        "STOP",
        "visit:",
        "  FOR i = 0 TO 2 : MOVEABS(spots(i)) : WAIT IDLE : NEXT i",
        "RETURN",
        "FUNCTION offset(k)",
        "  RETURN (k + 1) * PITCH",
        "ENDFUNC"])
    host.cmd('RUN "CELL"')
    hosted.advance(2.0)  # 750 units at 1000/s with 10 ms ramps: done well within
    assert host.unasked() == b"done at  750.0\r\n"
    assert host.cmd("?DPOS, IDLE") == "750\t-1"
