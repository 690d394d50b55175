"""A contour axis's QA/RI direction on the first tick of its contour motion: a one-way
ContourMotion reads its direction (MotionAxis.travel_direction), where the velocity at
that tick may be a float residue (-6e-14 on an arc leaving a Y extreme), the incoming
segment's slope (a restart at a line/arc corner), or the plan extrapolated before its
start. These pin the behaviour since 19f9aee: before it, the first tick read M in all
three cases while every later tick read P."""

from __future__ import annotations

from maxk import MAXk


def test_an_arc_leaving_a_y_extreme_reads_its_direction_from_the_first_tick() -> None:
    board = MAXk("MAXk-2000", 2048)
    board.send("AA; VOA0,5; VV1000,1000; VP0,0; VIO0100,,0100; VC0,500,-180;")
    b = board.board
    y = b.axes[1]
    assert b.tick == y.motion_start == 0
    assert abs(y.velocity(b)) < 1e-9  # (-6.1e-14: cos(-90 degrees) is not 0)
    assert board.send("AY QA") == ["PNNN"]
    board.advance(ticks=1)
    assert board.send("AY QA") == ["PNNN"]


def test_a_contour_axis_that_does_not_move_reads_the_same_on_its_first_tick() -> None:
    board = MAXk("MAXk-A000", 2048)
    for text in ("A", "A;RAKI1,3,4,5,,2V", "P,,-13456,-3", "251,-4126,-10313\r"):
        board.write(text)
    board.advance(1.0)
    board.write("AA; VA130645; VV3560,625; VP-3338,2889; VC0,0,90; VV3811,0; VP4240,3938; VE;")
    b = board.board
    v = b.axes[5]
    assert v.motion is not None and v.motion_start == b.tick and v.motion.final_offset == 0
    assert board.send("AV QA") == ["PNNN"]  # was MNNN: the plan read before its start
    board.advance(ticks=1)
    assert board.send("AV QA") == ["PNNN"]


def test_an_arc_restarted_after_a_line_reads_the_arc_way_on_its_first_tick() -> None:
    board = MAXk("MAXk-2000", 8192)
    for text in ("AA;BL3;LF; MP\tSS4\n", "MO #UR", "\tIDVP-15570,-17995; A"):
        board.write(text)
    board.advance(0.5)
    board.write("RQCWT13;VC1982,-9")
    board.write("620,-90\tBXMR")
    b = board.board
    y = b.axes[1]
    assert y.motion is not None and y.motion_start == b.tick
    assert y.velocity(b) < 0  # the line's slope at the corner (unchanged, one tick)
    assert y.status_string(b) == "PDNN"  # QA's answer; was MDNN
    board.advance(ticks=1)
    assert y.status_string(b) == "PDNN"
