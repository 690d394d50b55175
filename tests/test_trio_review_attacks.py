"""Issue 35's new TrioBASIC words under attack (the review): each test is a defect found by
driving an MC405 as a hostile user or a runaway program would, and stays as its guard."""

from __future__ import annotations

import pytest

from maxk.commands.trio.programs import MAX_PROGRAM_BYTES
from maxk.controllers.trio import MC405


def test_a_file_written_without_line_ends_stops_at_the_programs_limit() -> None:
    """OPEN FOR OUTPUT then PRINT #40, text; for ever: the unfinished line may not grow
    without end. 250 characters a write: the line passes MAX_PROGRAM_BYTES after
    MAX_PROGRAM_BYTES // 250 + 1 writes, well inside 2 * that many servo cycles; then the
    process stops with the store's error and the file holds nothing half-written."""
    trio = MC405()
    text = "x" * 250
    assert trio.load("LOGA", f'OPEN #40 AS "OUTA" FOR OUTPUT\nWHILE TRUE\n'
                             f'  PRINT #40, "{text}";\nWEND\n') == []
    assert trio.send('RUN "LOGA", 2') == []
    trio.advance(ticks=2 * (MAX_PROGRAM_BYTES // 250 + 1))
    reply = trio.send("PRINT PROC_STATUS PROC(2)")
    assert reply == ["%[Process 2:Program LOGA Line 3] - Program too large", "0"]
    listing = trio.send("DIR")
    assert any(line.split()[:2] == ["OUTA", "0"] for line in listing)


@pytest.mark.parametrize("channel", ["1e300", "2 ^ 40", "-65536"])
def test_regist_20_refuses_a_channel_beyond_its_gate_inputs(channel: str) -> None:
    """REGIST(20, channel, ...): channel 0 or 1, with the gate input in bits 16 and up.
    1e300 or 2 ^ 40 (low 16 bits 0, a gate input far past the last) or -65536 were
    taken as channel A: a channel whose gate is no input is 'Parameter out of range'."""
    trio = MC405()
    assert trio.send(f"REGIST(20, {channel}, 1, 0, 0)") == ["! Parameter out of range"]


def test_a_pswitch_sequence_position_where_the_move_ends_switches_the_output() -> None:
    """PSWITCH TABLE sequence (the page's example 4 form, mode 9 = bits 0 and 3, output
    64 ON first): a move that stops exactly on the first position's whole count must set
    the output on the tick it gets there. UNITS 1: TABLE 2.67 is reached at count 3;
    MOVEABS(3) at SPEED 10, ACCEL = DECEL 1000 takes 10 ms + 0.29 s + 10 ms = 310 ticks
    of 1 ms. The switch's event fell on the move's end and was lost: the output stayed
    OFF with the axis at 3."""
    trio = MC405()
    assert trio.send("BASE(10): SPEED = 10: ACCEL = 1000: DECEL = 1000") == []
    assert trio.send("TABLE(1000, 2.67, 9.07)") == []
    assert trio.send("PSWITCH(1, 9, 10, 64, ON, 1000, 1001)") == []
    start = trio.tick
    assert trio.send("MOVEABS(3)") == []
    trio.advance(ticks=start + 309 - trio.tick)
    assert trio.send("PRINT READ_OP(64), DPOS") == ["0\t2.9995"]
    trio.advance(ticks=1)
    assert trio.send("PRINT READ_OP(64), DPOS") == ["1\t3"]
    trio.advance(ticks=1000)
    assert trio.send("PRINT READ_OP(64)") == ["1"]


@pytest.mark.parametrize("channel", [0, 5, 10, 39, 49, 255])
def test_open_takes_a_file_only_on_the_file_channels(channel: int) -> None:
    """OPEN's page: a file or string variable goes on channels 40 to 48. OPEN #5 AS a file
    took the command line's channel 5 over (PRINT #5 then went into the file, and the
    channel stayed taken): any other channel is 'Parameter out of range', nothing opened
    and no file made; the same OPEN on #40 works."""
    trio = MC405()
    assert trio.send(f'OPEN #{channel} AS "LOGZ" FOR OUTPUT') == ["! Parameter out of range"]
    assert not any(line.startswith("LOGZ") for line in trio.send("DIR"))
    assert trio.send('OPEN #40 AS "LOGZ" FOR OUTPUT') == []
    assert any(line.startswith("LOGZ") for line in trio.send("DIR"))


@pytest.mark.parametrize("command", ['DEL "LOGX"', 'RENAME "LOGX" "LOGQ"'])
def test_a_file_deleted_or_renamed_while_a_program_writes_it_stops_that_program(
        command: str) -> None:
    """A host DELs or RENAMEs the file a running program has OPEN FOR OUTPUT: the next
    PRINT #40 raised a Python KeyError out of the servo cycle (a traceback). Now the
    program stops on that line with the controller's error and the machine runs on."""
    trio = MC405()
    assert trio.load("W1", 'OPEN #40 AS "LOGX" FOR OUTPUT\nWHILE TRUE\n'
                           '  PRINT #40, "line"; VR(1)\n  VR(1) = VR(1) + 1\n  WA(1)\nWEND\n') == []
    assert trio.send('RUN "W1", 2') == []
    trio.advance(ticks=5)
    assert trio.send(command) == []
    trio.advance(ticks=5)
    assert trio.send("PRINT PROC_STATUS PROC(2)") == [
        "%[Process 2:Program W1 Line 3] - Program not found", "0"]
    assert trio.send("PRINT 1 + 1") == ["2"]
