"""Review 5A: S-curve paths and their neighbours attacked as a user and a real program
would; each test reproduces a defect found (it failed before its fix) or pins a limit
the review checked. Expected values are hand arithmetic, written out in each test."""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio import MC405
from maxk.personalities.trio import runs

SET_UP = "BASE(0,1): UNITS AXIS(0)=1000: UNITS AXIS(1)=1000: SPEED=10: ACCEL=100: DECEL=100"


def _load_chain(trio: MC405, count: int) -> None:
    """`count` merged moves of 0.01 units round a slow curve, each loaded as soon as the
    move buffer takes it (as a program's loop of MOVEs does)."""
    for k in range(count):
        while not trio.machine.can_load([0, 1]):
            trio.advance(ticks=1)
        angle = k * 0.01
        assert trio.send(f"MOVE({0.01 * math.cos(angle):.5f},"
                         f"{0.01 * math.sin(angle):.5f})") == []


@pytest.mark.parametrize("mode", ["", ": SRAMP=50", ": VP_MODE=6: JERK=1000"])
def test_a_long_merged_chain_costs_a_bounded_work_per_move(
        mode: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """A contour of 400 merged tiny moves: each move loaded works out the seams of the
    moves it adds, not of the whole chain again (was: every load rebuilt every move's
    definition, n^2/2 = 80,000 seam look-ups here, and converted every segment to arrays
    again: a 10,000-move contour took half an hour to load). At most 2 look-ups a move
    (its own seam and the one before it, re-read as it merges) and one array row each."""
    calls = 0
    seam = runs.Run.seam

    def counted(self: runs.Run, j: int) -> float:
        nonlocal calls
        calls += 1
        return seam(self, j)

    monkeypatch.setattr(runs.Run, "seam", counted)
    trio = MC405()
    assert trio.send(SET_UP + ": MERGE=ON" + mode) == []
    _load_chain(trio, 400)
    run = trio.machine.queues[0][0]
    kept = len(run.segments)  # (the moves completed may have been let go: runs.py)
    assert kept + run.dropped == 400 and kept <= 100
    assert calls <= 2 * 400
    arrays = run.arrays
    assert arrays is not None and arrays.table.count == kept  # one row a kept move
    assert len(arrays.seg_s0) == kept
    trio.advance(ticks=60_000)
    assert trio.machine.axis_idle(0)
    # (each move whole counts: the text's value x UNITS, rounded)
    x = sum(round(float(f"{0.01 * math.cos(k * 0.01):.5f}") * 1000) for k in range(400))
    y = sum(round(float(f"{0.01 * math.sin(k * 0.01):.5f}") * 1000) for k in range(400))
    assert (trio.machine.dpos(0), trio.machine.dpos(1)) == (x / 1000, y / 1000)


# ---- CANCEL and RAPIDSTOP at FASTDEC (CANCEL, RAPIDSTOP and FASTDEC pages) ----------------
ONE = "BASE(0): UNITS=1000: SPEED=10: ACCEL=100: DECEL=50"
TWO = "BASE(0,1): UNITS AXIS(0)=1000: UNITS AXIS(1)=1000: SPEED=10: ACCEL=100: DECEL=50"


def _stop_at_500(program: str, stop: str) -> MC405:
    trio = MC405()
    assert trio.send(program) == []
    trio.advance(ticks=500)
    assert trio.send(stop) == []
    return trio


@pytest.mark.parametrize("stop", ["CANCEL", "RAPIDSTOP"])
@pytest.mark.parametrize(("fastdec", "end", "tick"), [
    # 0.5 s in: ramped up over 0.1 s (0.5 units), cruised 0.4 s: at 4.5, speed 10.
    (200, 4.75, 550),  # FASTDEC 200: 10/200 = 0.05 s, 10 x 0.05 / 2 = 0.25 units
    (0, 5.5, 700),     # none: DECEL 50, 0.2 s, 1.0 unit
    (40, 5.5, 700),    # below DECEL: DECEL (FASTDEC page)
])
def test_a_cancelled_move_ramps_down_at_fastdec(stop: str, fastdec: float, end: float,
                                               tick: int) -> None:
    trio = _stop_at_500(f"{ONE}: FASTDEC={fastdec}: MOVE(100)", stop)
    trio.advance(ticks=tick - 1 - trio.tick)
    assert trio.machine.dpos(0) < end
    trio.advance(ticks=1)
    assert trio.machine.dpos(0) == pytest.approx(end, abs=1e-9)
    trio.advance(ticks=50)
    assert trio.machine.dpos(0) == pytest.approx(end, abs=1e-9)


@pytest.mark.parametrize("stop", ["CANCEL", "RAPIDSTOP"])
def test_a_cancelled_s_curve_move_ramps_down_at_fastdec(stop: str) -> None:
    """SRAMP 20 ms: up over 10/100 + 0.02 s covering 0.6, so at 0.5 s it is at
    0.6 + 10 x 0.38 = 4.4; down at FASTDEC 200 over 10/200 + 0.02 = 0.07 s covering
    10 x 0.07 / 2 = 0.35: at rest on 4.75 at tick 570 (at DECEL 50 it would be
    0.22 s and 1.1 units)."""
    trio = _stop_at_500(f"{ONE}: SRAMP=20: FASTDEC=200: MOVE(100)", stop)
    trio.advance(ticks=69)
    assert trio.machine.dpos(0) < 4.75
    trio.advance(ticks=1)
    assert trio.machine.dpos(0) == pytest.approx(4.75, abs=1e-9)


@pytest.mark.parametrize("stop", ["CANCEL", "RAPIDSTOP"])
@pytest.mark.parametrize(("extra", "s_end", "tick"), [
    ("", 4.75, 550),          # linear: at 4.5, 0.05 s and 0.25 at FASTDEC 200
    (": SRAMP=20", 4.75, 570),  # S-curve: at 4.4, 0.07 s and 0.35 (as above)
])
def test_a_cancelled_path_ramps_down_at_fastdec(stop: str, extra: str, s_end: float,
                                               tick: int) -> None:
    """MOVE(300,400): the vector as the single axis above; X carries 3/5, Y 4/5."""
    trio = _stop_at_500(f"{TWO}{extra}: FASTDEC=200: MOVE(300,400)", stop)
    trio.advance(ticks=tick - 1 - trio.tick)
    assert trio.machine.dpos(1) < 0.8 * s_end
    trio.advance(ticks=1)
    assert trio.machine.dpos(0) == pytest.approx(0.6 * s_end, abs=1e-9)
    assert trio.machine.dpos(1) == pytest.approx(0.8 * s_end, abs=1e-9)


def test_a_released_jog_still_ramps_at_decel() -> None:
    """FASTDEC is CANCEL's, RAPIDSTOP's and a limit's: a jog input going high stops the
    jog at DECEL (FWD_JOG entry). JOGSPEED 10 reached after 0.1 s: released at 0.5 s it
    is at 4.5 and stops 10^2 / (2 x 50) = 1.0 further."""
    trio = MC405()
    trio.world_view().set_input(7, True)
    assert trio.send(f"{ONE}: JOGSPEED=10: FASTDEC=200: FWD_JOG=7") == []
    trio.world_view().set_input(7, False)
    trio.advance(ticks=500)
    assert trio.machine.dpos(0) == pytest.approx(4.5, abs=1e-9)
    trio.world_view().set_input(7, True)
    trio.advance(ticks=300)
    assert trio.machine.dpos(0) == pytest.approx(5.5, abs=1e-9)


# ---- feed hold, RAPIDSTOP and speed writes on S-curve paths ---------------------------------
def test_rapidstop_during_a_feed_hold_on_an_s_curve_path_leaves_it_where_it_holds() -> None:
    """SRAMP 50 ms, SPEED 10, ACCEL = DECEL 100, FHSPEED 0: up over 0.15 s (0.75 units),
    at 0.3 s on 0.75 + 10 x 0.15 = 2.25; the hold S-ramps 10 -> 0 over 0.15 s (0.75):
    held on 3.0 from tick 450. RAPIDSTOP at 0.8 s ends the held move and drops the one
    buffered behind it: nothing moves, MTYPE 0."""
    trio = MC405()
    trio.world_view().set_input(5, True)
    assert trio.send(f"{TWO}: DECEL=100: SRAMP=50: FHOLD_IN=5: FHSPEED=0: MERGE=ON: "
                     "MOVE(5,0): MOVE(0,5)") == []
    trio.advance(ticks=300)
    trio.world_view().set_input(5, False)
    trio.advance(ticks=150)
    assert trio.machine.dpos(0) == pytest.approx(3.0, abs=1e-9)
    trio.advance(ticks=350)
    assert trio.machine.dpos(0) == pytest.approx(3.0, abs=1e-9)
    assert trio.send("RAPIDSTOP") == []
    trio.advance(ticks=1)
    assert trio.query("?MTYPE") == "0"
    trio.world_view().set_input(5, True)
    trio.advance(ticks=2000)
    assert (trio.machine.dpos(0), trio.machine.dpos(1)) == (3.0, 0.0)
    assert trio.machine.axis_idle(0)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("mode", ["SRAMP=50", "VP_MODE=6: JERK=2000"])
def test_writes_stops_and_holds_at_random_keep_speed_and_acceleration_bounded(
        seed: int, mode: str) -> None:
    """A merged chain of lines and arcs (radius down to half a count) with SPEED, VP_MODE,
    CANCEL, RAPIDSTOP, feed hold and more moves thrown at it at random ticks: on every
    tick VP_SPEED is within the highest SPEED given and changes by no more than the
    highest rate in force (FASTDEC 300) allows; it ends at rest, no error."""
    import random

    rnd = random.Random(seed)
    trio = MC405()
    trio.world_view().set_input(5, True)
    assert trio.send(f"{SET_UP}: FASTDEC=300: MERGE=ON: FHOLD_IN=5: FHSPEED=2: {mode}") == []
    moves = []
    for _ in range(6):
        if rnd.random() < 0.3:
            r = rnd.choice([0.0005, 0.01, 0.5, 2])
            moves.append(f"MOVECIRC({2 * r},0,{r},0,{rnd.randint(0, 1)})")
        else:
            moves.append(f"MOVE({rnd.uniform(-3, 3):.3f},{rnd.uniform(-3, 3):.3f})")
    assert trio.send(": ".join(moves)) == []
    top, speeds = 10.0, []
    for _ in range(30_000):
        if rnd.random() < 0.012:
            event = rnd.choice(["SPEED=2", "SPEED=30", "SPEED=0", "CANCEL", "RAPIDSTOP",
                                "hold", "go", "VP_MODE=0: SRAMP=30", "JERK=10",
                                "MOVE(0.5,0.5)"])
            if event in ("hold", "go"):
                trio.world_view().set_input(5, event == "go")
            else:
                assert trio.send(event) == [], event
                top = max(top, 30.0 if event == "SPEED=30" else 0.0)
        speeds.append(float(trio.query("?VP_SPEED")))
        trio.advance(ticks=1)
        if trio.machine.axis_idle(0) and len(speeds) > 10:
            break
    assert trio.machine.axis_idle(0)
    assert max(speeds) <= top * (1 + 1e-9)
    steps = [abs(b - a) for a, b in zip(speeds, speeds[1:], strict=False)]
    assert max(steps) <= 300 * 0.001 * (1 + 1e-6)


# ---- REP_DIST and FRAME_REP_DIST folds of any size -------------------------------------------
@pytest.mark.parametrize(("rep", "option", "expected"), [
    # 100000 folded by 30000 into -30000..30000: 100000 - 2 x 60000 = -20000; into
    # 0..30000 (REP_OPTION 1): 100000 - 3 x 30000 = 10000
    ("30000", 0, -20000.0),
    ("30000", 1, 10000.0),
    # a fold far finer than the position (1e-310 units, below the least normal float):
    # a value inside the fold (was: OverflowError, PRINT DPOS answered nothing and the
    # command line's next command waited 600 s)
    ("1e-310", 0, None),
    ("1e-310", 1, None),
])
def test_dpos_reads_folded_by_any_rep_dist(rep: str, option: int,
                                           expected: float | None) -> None:
    trio = MC405()
    assert trio.send(f"BASE(0): UNITS=1: DEFPOS(100000): REP_OPTION={option}: "
                     f"REP_DIST={rep}") == []
    reply = trio.send("PRINT DPOS")
    assert len(reply) == 1 and not reply[0].startswith("!")
    value = trio.machine.wrapped(0, 100000.0)
    if expected is None:
        span = float(rep)
        assert (0 <= value <= span) if option else (-span <= value <= span)
    else:
        assert value == expected
        assert float(reply[0]) == expected
    assert trio.send("PRINT 1") == ["1"]  # the session goes on


def test_a_position_switch_on_an_axis_folded_finer_than_a_float_step_keeps_running() -> None:
    """PSWITCH on an axis whose REP_DIST is 1e-310: the switch's edge search divided by
    the fold and failed on every servo tick the move ran (OverflowError out of advance);
    now the move runs to its end, 100 counts."""
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1: PSWITCH(0,ON,0,8,1,10,20): REP_DIST=1e-310: "
                     "MOVE(100)") == []
    trio.advance(ticks=3000)
    assert trio.machine.dpos(0) == 100.0
    assert trio.query("?MTYPE") == "0"


# ---- JERK is a limit on a move too short to reach SPEED too ---------------------------------
@pytest.mark.parametrize(("program", "share"), [
    ("BASE(0): UNITS=1000: MOVE(16)", (1.0, 0.0)),
    ("BASE(0,1): UNITS AXIS(0)=1000: UNITS AXIS(1)=1000: MOVE(9.6,12.8)", (0.6, 0.8)),
])
def test_a_move_too_short_for_speed_keeps_its_jerk_at_jerk(
        program: str, share: tuple[float, float]) -> None:
    """VP_MODE 6, JERK 1, SPEED = ACCEL = DECEL 1000, a move of 16 units: SPEED is out of
    reach, so the move peaks at the speed v whose two jerk-limited ramps fill it; ACCEL is
    never reached (sqrt(v x JERK) < 1000), each ramp is a triangle of acceleration over
    2 sqrt(v / JERK) s covering v sqrt(v / JERK): 2 v^1.5 = 16, v = 4, ramps of 4 s
    each. Distance J t^3 / 6 for t <= 2 s (1/6 at 1 s, 4/3 at 2 s), half (8) at 4 s,
    16 - 4/3 at 6 s, at rest on 16 at 8 s exactly (was: the ramps to SPEED squeezed into
    the move: at rest on 16 after 2.012 s, its acceleration up to 31.6, its jerk 63)."""
    trio = MC405()
    assert trio.send(f"SPEED AXIS(0)=1000: ACCEL AXIS(0)=1000: DECEL AXIS(0)=1000: "
                     f"VP_MODE AXIS(0)=6: JERK AXIS(0)=1: {program}") == []
    for tick, s in ((1000, 1 / 6), (2000, 4 / 3), (4000, 8.0), (6000, 16 - 4 / 3)):
        trio.advance(ticks=tick - trio.tick)
        assert trio.machine.dpos(0) == pytest.approx(share[0] * s, abs=1e-9), tick
        assert trio.machine.dpos(1) == pytest.approx(share[1] * s, abs=1e-9), tick
    assert float(trio.query("?VP_SPEED")) == pytest.approx(2.0, abs=1e-4)
    trio.advance(ticks=7999 - trio.tick)
    assert trio.query("?MTYPE") == "1"
    trio.advance(ticks=1)
    assert (trio.machine.dpos(0), trio.machine.dpos(1)) == (16 * share[0], 16 * share[1])
    assert trio.query("?MTYPE") == "0"


# ---- CANCEL and RAPIDSTOP modes (CANCEL and RAPIDSTOP pages) --------------------------------
@pytest.mark.parametrize(("stop", "end"), [
    # MOVE(10): MOVE(10) at SPEED 10, ACCEL = DECEL 100; stopped at 0.5 s on 4.5 at 10/s,
    # a ramp down covers 10^2 / 200 = 0.5
    ("CANCEL", 15.0),        # the running move stops on 5.0, the buffered one loads: 15
    ("CANCEL(0)", 15.0),
    ("CANCEL(1)", 10.0),     # the buffered move goes, the running one ends on 10
    ("CANCEL(2)", 5.0),      # both: at rest on 5.0
    ("RAPIDSTOP", 15.0),     # mode 0: 'motion will not stop', the buffered move loads
    ("RAPIDSTOP(1)", 10.0),
    ("RAPIDSTOP(2)", 5.0),
    ("CANCEL(7)", 20.0),     # not a mode: refused, nothing stopped
    ("CANCEL(1.5)", 20.0),
    ("RAPIDSTOP(3)", 20.0),
])
def test_cancel_and_rapidstop_modes(stop: str, end: float) -> None:
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1000: SPEED=10: ACCEL=100: DECEL=100: "
                     "MOVE(10): MOVE(10)") == []
    trio.advance(ticks=500)
    assert trio.send(stop) == ([] if end != 20.0 else ["! Parameter out of range"])
    trio.advance(ticks=5000)
    assert trio.machine.dpos(0) == end
    assert trio.query("?MTYPE") == "0"


def test_cancel_1_drops_a_buffered_group_move_from_every_axis_of_it() -> None:
    """A MOVE(1,1) buffered behind MOVE(5) AXIS(0)'s group: CANCEL(1) on axis 0 takes it
    out of axis 1's buffer too (axis 1 never moves); the running move ends on 5."""
    trio = MC405()
    assert trio.send("BASE(0,1): UNITS AXIS(0)=1000: UNITS AXIS(1)=1000: SPEED=10: "
                     "ACCEL=100: DECEL=100: MOVE(5,0): MOVE(1,1)") == []
    trio.advance(ticks=100)
    assert trio.send("CANCEL(1)") == []
    trio.advance(ticks=3000)
    assert (trio.machine.dpos(0), trio.machine.dpos(1)) == (5.0, 0.0)
    assert trio.machine.axis_idle(0) and trio.machine.axis_idle(1)
