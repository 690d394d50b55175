"""MT/ML linear interpolation: a straight line, every axis within its limits, one end tick."""

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxk import MAXk


def test_manual_three_axis_linear_example():
    # Appendix C: AM; VL5000,5000,5000; AC50000,50000,50000; MT1000,2000,3000; GO; ID;
    b = MAXk()
    b.send("AM; VL5000,5000,5000; AC50000,50000,50000; MT1000,2000,3000; GO; ID;")
    axes = b.board.axes
    assert axes[0].motion_end == axes[1].motion_end == axes[2].motion_end
    # Z has the longest way and sets the pace: 3000 steps at VL5000/AC50000 = 0.7 s
    assert axes[2].motion_end == math.ceil(0.7 * 8192)
    b.advance(0.3)
    x, y, z = (int(p) for p in b.query("PP").split(",")[:3])
    assert abs(2 * x - y) <= 2 and abs(3 * x - z) <= 3  # on the line
    assert b.query("RV").split(",")[:3] == ["1667", "3333", "5000"]
    assert b.run_until_done("X", "Y", "Z", timeout=5)
    assert b.query("PP") == "1000,2000,3000,0,0,0,0,0"


def test_each_axis_keeps_its_own_limits():
    b = MAXk("MAXk-2000")
    b.send("AA; VL1000,100000; AC10000,2000000; ML1000,1000; GO; ID;")
    # X (VL1000) limits both: Y may not outrun it on a 45 degree line
    b.advance(0.5)
    vx, vy = (int(v) for v in b.query("RV").split(","))
    assert vx == vy == 1000
    assert b.run_until_done()
    assert b.query("PP") == "1000,1000"


def test_linear_moves_are_refused_in_single_axis_mode():
    b = MAXk()
    b.send("AX; MT1000; ML5;")
    assert b.command_error
    assert b.last_error.reason == "ML is not allowed in single-axis mode"
    assert b.query("AX RQC") == "2559"


def test_am_linear_move_waits_for_every_axis_go():
    b = MAXk("MAXk-3000")
    b.send("AY; VL1000; MR500;  GO;")  # Y busy for 0.5 s
    b.send("AM; ML100,100; GO; ID;")
    b.advance(0.25)
    assert b.position("X") == 0  # X waits at its GO for Y's
    assert b.run_until_done("X", "Y", timeout=5)
    assert b.query("PP") == "100,600,0"


def test_flushing_one_axis_releases_the_others():
    b = MAXk("MAXk-2000")
    b.send("AY; VL1000; MR500; GO;")
    b.send("AM; MT100,100; GO; ID;")
    b.send("AY; ST")  # Y's linear part is flushed; X goes alone
    assert b.run_until_idle(timeout=5)
    assert b.position("X") == 100


@settings(max_examples=80, deadline=None)
@given(st.lists(st.integers(-100_000, 100_000), min_size=2, max_size=4),
       st.lists(st.integers(1, 200_000), min_size=4, max_size=4),
       st.lists(st.integers(1_000, 4_000_000), min_size=4, max_size=4))
def test_linear_moves_end_exactly_and_together(distances, vls, acs):
    n = len(distances)
    b = MAXk(f"MAXk-{n}000")
    b.send(f"AA; VL{','.join(map(str, vls[:n]))}; AC{','.join(map(str, acs[:n]))};")
    b.send(f"ML{','.join(map(str, distances))}; GO; ID;")
    ends = {a.motion_end for a in b.board.axes if a.motion is not None}
    assert len(ends) <= 1
    assert b.run_until_done(timeout=1e6)
    assert b.query("PP") == ",".join(map(str, distances))


@pytest.mark.parametrize("mode", ["AA", "AM"])
def test_linear_inside_loops(mode):
    b = MAXk("MAXk-2000")
    b.send(f"{mode}; LS3,3; ML10,-20; GO; LE; ID;")
    assert b.run_until_idle(timeout=10)
    assert b.query("PP") == "30,-60"


def test_a_limit_on_one_axis_stops_the_whole_linear_move():
    b = MAXk("MAXk-4000")
    b.set_limits("X", plus=2000)
    b.send("AM; VL10000,10000; MT5000,5000; GO; ID;")
    assert b.run_until_idle(timeout=5)
    x, y = (int(p) for p in b.query("AM RP").split(",")[:2])
    assert 2000 <= x <= 2002 and abs(x - y) <= 2  # both stopped on the line
    assert b.query("QI").startswith("PNLN,PNNN")  # neither done; only X on its limit


def test_a_linear_move_with_a_blocked_axis_is_refused_whole():
    b = MAXk("MAXk-4000")
    b.set_limits("X", plus=0)  # X sits on its plus limit
    b.send("AM; ML5000,5000; GO;")
    b.run_until_idle(timeout=5)
    assert b.query("AM RP") == "0,0,0,0"
    assert b.board.axes[0].flags & 0x2
