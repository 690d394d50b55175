"""Session 4's merged work under attack (review 4): each test is a defect found by
driving the controllers as a hostile user or a real program would, and stays as its
guard."""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405


@pytest.mark.parametrize("frame", [6, 10])
def test_a_frames_scale_zeroed_while_it_runs_does_not_stop_the_machine(frame: int) -> None:
    """TABLE(0) is frame 6 / 10's counts per radian. Zeroed while the frame is on (the
    page warns against it, a careless program does it): the engine raised a Python
    ValueError out of the servo cycle (frame 10) or every MPOS read and FRAME = 0 answered
    'Parameter out of range' for ever (frame 6). Now the frame keeps the last scale it
    could use: the move ends where it would have, and FRAME = 0 turns it off."""
    trio = MC405()
    assert trio.send("TABLE(0, 1000)") == []
    assert trio.send(f"FRAME = {frame}") == []
    assert trio.send("TABLE(0, 0)") == []
    assert trio.send("MOVE(5, 5)") == []
    trio.advance(ticks=2000)
    assert trio.send("PRINT DPOS AXIS(0), DPOS AXIS(1)") == ["5\t5"]
    reference = MC405()
    for line in ("TABLE(0, 1000)", f"FRAME = {frame}", "MOVE(5, 5)"):
        assert reference.send(line) == []
    reference.advance(ticks=2000)
    expected = reference.send("PRINT MPOS AXIS(0), MPOS AXIS(1)")
    assert trio.send("PRINT MPOS AXIS(0), MPOS AXIS(1)") == expected
    assert trio.send("FRAME = 0") == []
    assert trio.send("PRINT FRAME") == ["0"]


def test_a_frame_switch_that_is_refused_leaves_the_old_frame_on() -> None:
    """FRAME = 5 on, then FRAME = 6 with TABLE(0) 0 (no scale): refused, but the
    refusal came after frame 5 had been turned off (PRINT FRAME read 0). Nothing may be
    half-applied: frame 5 stays on, DPOS where it was."""
    trio = MC405()
    assert trio.send("TABLE(0, 0, 1, 1, 0, 0, 1, 1, 0)") == []  # swap x and y
    assert trio.send("FRAME = 5") == []
    assert trio.send("MOVE(3, 0)") == []
    trio.advance(ticks=2000)
    assert trio.send("PRINT DPOS AXIS(0), DPOS AXIS(1)") == ["3\t0"]
    assert trio.send("TABLE(0, 0)") == []
    assert trio.send("FRAME = 6") == ["! Parameter out of range"]
    assert trio.send("PRINT FRAME, DPOS AXIS(0), DPOS AXIS(1)") == ["5\t3\t0"]


@pytest.mark.parametrize("args", ["ON, 1e300, 1, 1", "ON, 1, 1e300, 1", "ON, 1, 1, 1e300",
                                  "ON, -1e17, 1, 1"])
def test_backlash_beyond_the_position_range_is_refused(args: str) -> None:
    """BACKLASH(ON, 1e300, 1e300, 1e300) was taken: after MOVE(1) MPOS read some
    -5.8e303 (the trapezoid's arithmetic overflowed), after MOVE(-1) BACKLASH_DIST stayed
    ~8.6e302. A distance, speed or acceleration beyond the machine's position range
    (2^53 counts, as MOVE and DEFPOS) is 'Parameter out of range', nothing changed."""
    trio = MC405()
    assert trio.send(f"BACKLASH({args})") == ["! Parameter out of range"]
    assert trio.send("MOVE(1)") == []
    trio.advance(ticks=1000)
    assert trio.send("PRINT DPOS, MPOS, BACKLASH_DIST") == ["1\t1\t0"]
    assert trio.send("BACKLASH(ON, 1e15, 1e15, 1e15)") == []  # inside the range: taken


@pytest.mark.parametrize("offset", ["1e300", "512000", "2 ^ 40"])
def test_frame_group_refuses_a_table_offset_past_the_table(offset: str) -> None:
    """FRAME_GROUP(0, 1e300, 0, 1) was taken: FRAME_GROUP(0) then printed a 301-digit
    offset and FRAME = 5 on the group failed later with 'TABLE index out of range'. The
    TABLE holds 512,000 values (memory.TABLE_SIZE): an offset past it is refused at once
    and the group stays as it was (none)."""
    trio = MC405()
    assert trio.send(f"FRAME_GROUP(0, {offset}, 0, 1)") == ["! Parameter out of range"]
    assert trio.send("FRAME_GROUP(0)") == ["0 [-1] :"]
    assert trio.send("FRAME_GROUP(0, 511992, 0, 1)") == []  # frame 5's 8 values fit
    assert trio.send("FRAME = 5") == []


@pytest.mark.parametrize("mode", ["1.5", "3.9"])
def test_a_fractional_move_pa_cont_acts_as_its_whole_mode(mode: str) -> None:
    """MOVE_PA_CONT = 3.9 was taken (0..6) but then matched no mode, so the move's
    MOVE_PA did nothing at all. The control's fraction is cut, as an integer
    parameter's: 1.5 and 3.9 act as 1 and 3, output 8 ON (8 + bit 12) when the move
    becomes active."""
    trio = MC405()
    assert trio.send(f"MOVE_PA_CONT = {mode}") == []
    assert trio.send("MOVE_PA = 8 + 4096") == []
    assert trio.send("MOVE(1)") == []
    trio.advance(ticks=100)
    assert trio.send("PRINT READ_OP(8)") == ["1"]
