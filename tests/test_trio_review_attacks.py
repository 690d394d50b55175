"""Issue 35's new TrioBASIC words under attack (the review): each test is a defect found by
driving an MC405 as a hostile user or a runaway program would, and stays as its guard."""

from __future__ import annotations

from maxk.commands.trio.programs import MAX_PROGRAM_BYTES
from maxk.controllers.trio import MC405


def test_a_file_written_without_line_ends_stops_at_the_programs_limit() -> None:
    """OPEN FOR OUTPUT then PRINT #5, text; for ever: the unfinished line may not grow
    without end. 250 characters a write: the line passes MAX_PROGRAM_BYTES after
    MAX_PROGRAM_BYTES // 250 + 1 writes, well inside 2 * that many servo cycles; then the
    process stops with the store's error and the file holds nothing half-written."""
    trio = MC405()
    text = "x" * 250
    assert trio.load("LOGA", f'OPEN #5 AS "OUTA" FOR OUTPUT\nWHILE TRUE\n'
                             f'  PRINT #5, "{text}";\nWEND\n') == []
    assert trio.send('RUN "LOGA", 2') == []
    trio.advance(ticks=2 * (MAX_PROGRAM_BYTES // 250 + 1))
    reply = trio.send("PRINT PROC_STATUS PROC(2)")
    assert reply == ["%[Process 2:Program LOGA Line 3] - Program too large", "0"]
    listing = trio.send("DIR")
    assert any(line.split()[:2] == ["OUTA", "0"] for line in listing)
