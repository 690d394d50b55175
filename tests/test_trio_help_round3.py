"""Forms and ranges the TrioBASIC help's examples use that a run of every page's examples
(tools/trio_corpus_check.py, round 3) showed refused where the pages allow them. Each test
is written from what the keyword's page says, with numbers of our own.

"""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio.controller import MC405
from tests.trio_helpers import Rig


def mc405(*lines: str) -> MC405:
    trio = MC405()
    for line in lines:
        assert trio.send(line) == [], line
    return trio


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


# ---- the inputs a limit or datum may be wired to (help FWD_IN, REV_IN, DATUM_IN) --------

@pytest.mark.parametrize(("line", "ok"), [
    ("FWD_IN = 63", True), ("FWD_IN = 64", False),      # FWD_IN's page: -1, 0..63
    ("REV_IN = 40", True), ("REV_IN = 64", False),      # REV_IN's page: the same
    ("DATUM_IN = 206", True), ("DATUM_IN = 1023", True),  # DATUM_IN's: 0..IO_Max
    ("DATUM_IN = 1024", False), ("DATUM_IN = -2", False),
])
def test_the_input_numbers_the_pages_allow(line: str, ok: bool) -> None:
    trio = mc405("FWD_IN = 5: REV_IN = 6: DATUM_IN = 7")
    name = line.split()[0]
    before = trio.query(f"?{name}")
    reply = trio.send(line)
    if ok:
        assert reply == [] and trio.query(f"?{name}") == line.split()[-1]
    else:
        assert reply == ["! Parameter out of range"] and trio.query(f"?{name}") == before


def test_a_datum_search_on_an_expansion_input() -> None:
    """DATUM_IN's page, example 2, wires the datum to input 205. Here the world's home
    switch of axis 0 (steps -1000..-500, one step a count) is that input, normally closed
    (IN reads 1 away from it, 0 on it). DATUM(4) runs in reverse at SPEED 1000 (ACCEL 1e6:
    0.5 counts lost) until the switch, then forward at CREEP until it is off again, and
    that place becomes 0."""
    trio = mc405("BASE(0): SPEED=1000: CREEP=10: ACCEL=1e6: DECEL=1e6", "DATUM_IN = 205")
    trio.world_view().set_home("0", -1000, -500)
    assert trio.query("?IN(205)") == "1"
    start = trio.tick
    assert trio.send("DATUM(4)") == []  # the command line holds until the search is done
    # 500 counts at 1000 counts/s to the switch, then creeping back out of it at 10
    # counts/s over about the 0.5 counts the stop ran on: 0.5 s and some 0.05 s more
    assert 500 + 40 <= trio.tick - start <= 500 + 120
    assert trio.query("?MTYPE") == "0"
    assert trio.machine.dpos(0) == 0
    assert abs(trio.world_view().reading("0").position - -500) <= 1


# ---- STEP_RATIO(-1, 1) reverses a position axis (help ENCODER_RATIO example 4) -------------

def test_a_negative_step_ratio_turns_the_motor_against_the_demand() -> None:
    """The ENCODER_RATIO page reverses an axis with ENCODER_RATIO(-1, 1) and
    STEP_RATIO(-1, 1): the motor turns backward as DPOS goes forward, and the encoder on
    its shaft, read through the reversed ratio, counts forward with DPOS again."""
    trio = mc405("ATYPE AXIS(0) = 76", "BASE(4): SPEED=1000: ACCEL=100000: DECEL=100000",
                 "STEP_RATIO(-1, 1)")
    trio.world_view().set_shaft_encoder("0", "4", 1.0)
    assert trio.send("ENCODER_RATIO(-1, 1) AXIS(0)") == []
    trio.send("MOVE(300)")
    assert trio.run_until_idle()
    assert trio.query("?DPOS") == "300"
    assert trio.world_view().reading("4").position == -300  # the motor turned backward
    assert trio.query("?MPOS AXIS(0)") == "300"  # the reversed encoder reads forward
    assert trio.send("STEP_RATIO(-3, 2)") == []  # the motor stays where it is
    trio.send("MOVE(-200)")
    assert trio.run_until_idle()
    assert trio.world_view().reading("4").position == -300 + 300  # -200 x -3 / 2


def test_a_step_ratio_beyond_the_page_s_range_either_way_is_refused() -> None:
    trio = mc405("STEP_RATIO(-2, 1)")
    for bad in ("STEP_RATIO(-16777216, 1)", "STEP_RATIO(1, -1)", "STEP_RATIO(-1.5, 1)"):
        assert trio.send(bad) == ["! Parameter out of range"], bad
    trio.send("MOVE(10)")
    assert trio.run_until_idle()
    assert trio.world_view().reading("0").position == -20


# ---- MHELICAL's mode (help MHELICAL): 0 a true helix, 1 the circle's path speed ------------

ARC = 100 * math.pi / 2  # a quarter circle of radius 100 counts
RISE = 200.0


@pytest.mark.parametrize(("mode", "path"), [
    ("", math.hypot(ARC, RISE)),     # mode 0 (the default): SPEED along the helix
    (", 0", math.hypot(ARC, RISE)),
    (", 1", ARC),                    # mode 1: SPEED along the circle, axis 2 following
])
def test_mhelical_mode_sets_which_axes_make_the_path_speed(mode: str, path: float) -> None:
    """From (0, 0) round the centre (0, 100) anticlockwise to (100, 100) while axis 2 rises
    200, at SPEED 100 (ACCEL and DECEL 1e6: 0.005 counts lost to the ramp). After 1 s the
    path has run 100 - 0.005 of its length `path`; axis 2 has risen that share of 200."""
    trio = mc405("BASE(0, 1, 2): SPEED=100: ACCEL=1e6: DECEL=1e6")
    assert trio.send(f"MHELICAL(100, 100, 0, 100, 0, {RISE:g}{mode})") == []
    at(trio, 1000)
    done = 100 * 1.0 - 100 * 100 / 2e6
    assert trio.machine.dpos(2) == pytest.approx(RISE * done / path, abs=1e-6)
    angle = done / path * (math.pi / 2)  # the arc's share turned about the centre
    assert trio.machine.dpos(0) == pytest.approx(100 * math.sin(angle), abs=1e-6)
    assert trio.run_until_idle()
    assert [trio.machine.dpos(a) for a in range(3)] == [100, 100, 200]


def test_mhelical_modes_beyond_the_page_s_two_are_refused() -> None:
    trio = mc405("BASE(0, 1, 2)")
    for bad in ("MHELICAL(100, 100, 0, 100, 0, 20, 2)", "MHELICAL(100, 100, 0, 100, 0, 20, 1, 5)"):
        assert trio.send(bad) == ["! Parameter out of range"], bad
    assert trio.query("?MTYPE") == "0"


# ---- a STRING longer than 1024 characters (help OPEN: a STRING(10000) for a listing) -------

def run(program: str, cycles: int = 50) -> str:
    rig = Rig()
    rig.load("P", program)
    rig.command('RUN "P"')
    return rig.cycles(cycles).decode()


def test_a_string_of_ten_thousand_characters_holds_them_all() -> None:
    out = run('DIM s AS STRING(10000)\nFOR i = 1 TO 1250\n  s = s + "abcdefgh"\nNEXT i\n'
              'PRINT LEN(s); " "; MID(s, 9994, 6)', cycles=3000)
    # 1250 x 8 characters; MID counts from 0: 9994 = 8 x 1249 + 2, a "c"
    assert out == "10000 cdefgh\r\n"


def test_a_string_longer_than_the_limit_is_refused_at_compile() -> None:
    rig = Rig()
    rig.load("P", "DIM s AS STRING(65535)")
    assert b"error" not in rig.send("COMPILE")
    rig.load("P", "DIM s AS STRING(65536)")
    assert b"%[Program P Line 1] - Syntax error" in rig.send("COMPILE")


# ---- CONNPATH(ratio, driving_axis) (help CONNPATH): the page's argument order -------------

@pytest.mark.parametrize(("link", "follows"), [
    ("CONNPATH(3, 2) AXIS(0)", 3 * 10.0),     # ratio 3 of the 6-8-10 path of BASE(2, 3)
    ("CONNPATH(0.25, 2) AXIS(0)", 0.25 * 10),  # the page's quarter turn a unit
    ("CONNPATH(2) AXIS(0)", 10.0),            # one argument: the driving axis, ratio 1
])
def test_connpath_follows_the_driving_group_s_path_distance_at_the_ratio(
        link: str, follows: float) -> None:
    trio = mc405("BASE(2, 3): SPEED=100: ACCEL=1e6: DECEL=1e6", link)
    assert trio.query("?MTYPE AXIS(0)") == "23"  # linked (CONNPATH)
    assert trio.send("MOVE(6, 8)") == []
    trio.advance(0.5)
    assert (trio.machine.dpos(2), trio.machine.dpos(3)) == (6, 8)
    assert trio.machine.dpos(0) == pytest.approx(follows, abs=1e-9)


# ---- FILE "function" name with a variable's name, no comma (help STICK_WRITEVR) ------------

def test_file_takes_a_string_expression_as_its_first_parameter_without_a_comma() -> None:
    # no SD card here: FILE reads FALSE (its entry); the form must compile and run
    out = run('DIM f AS STRING(20)\nf = "DATA1"\nFILE "TYPE" f + ".CSV"\n'
              'v = FILE "TYPE" f + ".CSV"\nIF FILE "DETECT" THEN\n  PRINT "card"\nELSE\n'
              '  PRINT "none "; v\nENDIF')
    assert out == "none 0.0000\r\n"


def test_file_followed_by_a_keyword_leaves_it_to_the_statement() -> None:
    out = run('VR(1) = 5\nIF FILE "DETECT" OR VR(1) = 5 THEN PRINT "yes"')
    assert out == "yes\r\n"
