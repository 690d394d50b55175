"""The MC405's move loader from the TrioBASIC help: MOVE_PA / MOVE_PB switching outputs
as each move becomes active (MOVE_PA_CONT, MOVE_PA_IDLE).

Every tick is hand arithmetic: a merged path at SPEED v with ACCEL a ramps over v/a s
(v^2 / 2a units), cruises, and a move boundary's tick is the first servo tick at or after
the time the path reaches the move's end (1 ms ticks).
"""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio import MC405


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def op(trio: MC405, number: int) -> bool:
    return trio.machine.output(number)


def tick_of(seconds: float) -> int:
    return math.ceil(seconds * 1000 - 1e-6)


# ---- MOVE_PA / MOVE_PA_CONT -------------------------------------------------------------
SET_UP = ("BASE(0): UNITS=1: SPEED=15: FORCE_SPEED=15: ENDMOVE_SPEED=15: MERGE=ON: "
          "ACCEL=300: DECEL=300")


def test_move_pa_page_example_switches_output_10_as_each_move_starts() -> None:
    """The MOVE_PA page's first example: output 10 on with the 200 move, off with the 20
    move, on again with the 100 move; MOVE_PA_IDLE (output 10, bit 12 clear) turns it off
    when the last move ends. Ramps: 15/300 = 0.05 s over 0.375 units."""
    trio = MC405()
    assert trio.send(SET_UP) == []
    assert trio.send("MOVE_PA = 10: MOVE_PA_CONT = 1: MOVE_PA_IDLE = 10") == []
    assert not op(trio, 10)
    assert trio.send("MOVE_PA.12 = ON: MOVESP(200): MOVE_PA.12 = OFF: MOVESP(20): "
                     "MOVE_PA.12 = ON: MOVESP(100)") == []
    assert op(trio, 10)  # the first move is active from the tick it is loaded
    first = tick_of(0.05 + (200 - 0.375) / 15)
    second = tick_of(0.05 + (220 - 0.375) / 15)
    end = tick_of(0.05 + (320 - 0.75) / 15 + 0.05)
    assert (first, second, end) == (13359, 14692, 21384)
    at(trio, first - 1)
    assert op(trio, 10)
    at(trio, first)
    assert not op(trio, 10)
    at(trio, second - 1)
    assert not op(trio, 10)
    at(trio, second)
    assert op(trio, 10)
    at(trio, end - 1)
    assert op(trio, 10)
    at(trio, end)
    assert not op(trio, 10)
    assert float(trio.query("?MTYPE")) == 0


def test_move_pa_is_copied_when_the_move_loads_not_when_it_starts() -> None:
    """MOVE_PA changed after a move is loaded does not change what that move switches."""
    trio = MC405()
    assert trio.send(SET_UP + ": MOVE_PA_CONT = 1") == []
    assert trio.send("MOVE_PA = 4096 + 9: MOVE(30): MOVE_PA = 4096 + 11: MOVE(30): "
                     "MOVE_PA = 12") == []
    assert op(trio, 9) and not op(trio, 11)
    boundary = tick_of(0.05 + (30 - 0.375) / 15)
    at(trio, boundary - 1)
    assert not op(trio, 11)
    at(trio, boundary)
    assert op(trio, 11) and op(trio, 9) and not op(trio, 12)


def test_move_pa_cont_4_sets_a_pattern_on_outputs_8_to_15() -> None:
    """The page's second example: $AA on the 8 outputs from 8 as the move starts."""
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1: SPEED=15: ACCEL=300: DECEL=300: OP(9, ON)") == []
    assert trio.send("MOVE_PA_CONT = 4: MOVE_PA = ($AA << 20) + (8 << 12) + 8") == []
    assert [op(trio, n) for n in range(8, 16)] == [False, True] + [False] * 6
    assert trio.send("MOVE(200)") == []
    assert [op(trio, n) for n in range(8, 16)] == [False, True] * 4


def test_move_pb_acts_alongside_move_pa_and_mode_0_does_nothing() -> None:
    trio = MC405()
    assert trio.send(SET_UP + ": MOVE_PB_CONT = 3: MOVE_PB = 4096 + 20: MOVE_PA = 4096 + 21")\
        == []
    assert trio.send("MOVE(10)") == []
    assert op(trio, 20) and not op(trio, 21)


def test_move_pa_cont_2_copies_the_values_into_axis_debug_a_and_b() -> None:
    """Mode 2: MOVE_PA into AXIS_DEBUG_A, MOVE_PB into AXIS_DEBUG_B as the move becomes
    active (the second 30 of a merged pair: 0.05 + 29.625 / 15 s)."""
    trio = MC405()
    assert trio.send(SET_UP + ": MOVE_PA_CONT = 2: MOVE_PB_CONT = 2") == []
    assert trio.send("MOVE_PA = 7: MOVE_PB = 70: MOVE(30): MOVE_PA = 8: MOVE_PB = 80: "
                     "MOVE(30)") == []
    assert float(trio.query("?AXIS_DEBUG_A")) == 7
    assert float(trio.query("?AXIS_DEBUG_B")) == 70
    boundary = tick_of(0.05 + (30 - 0.375) / 15)
    at(trio, boundary - 1)
    assert float(trio.query("?AXIS_DEBUG_A")) == 7
    at(trio, boundary)
    assert float(trio.query("?AXIS_DEBUG_A")) == 8
    assert float(trio.query("?AXIS_DEBUG_B")) == 80


def test_move_pa_cont_out_of_range_is_refused() -> None:
    trio = MC405()
    assert trio.send("MOVE_PA_CONT = 7") != []
    assert float(trio.query("?MOVE_PA_CONT")) == 0


# ---- INTERP_FACTOR ----------------------------------------------------------------------
def test_interp_factor_0_leaves_z_out_of_the_vector_speed() -> None:
    """The INTERP_FACTOR page's example: X 30, Y 40, Z 120 at SPEED 10 with Z out of the
    interpolation: X and Y run their 50 at 10 (ACCEL 100: 0.1 s ramps over 0.5 units)
    and Z ends with them; VP_SPEED reads the XY speed."""
    trio = MC405()
    assert trio.send("BASE(0, 1, 2): UNITS AXIS(0)=1: UNITS AXIS(1)=1: UNITS AXIS(2)=1: "
                     "SPEED=10: ACCEL=100: DECEL=100") == []
    assert float(trio.query("?INTERP_FACTOR AXIS(2)")) == 1
    assert trio.send("INTERP_FACTOR AXIS(2) = 0: MOVEABS(30, 40, 120)") == []
    end = tick_of(0.1 + (50 - 1.0) / 10 + 0.1)
    assert end == 5100
    at(trio, 1000)  # cruising: XY 0.5 + 10 x 0.9 = 9.5 of 50
    assert trio.machine.dpos(0) == pytest.approx(9.5 * 30 / 50, abs=1e-9)
    assert trio.machine.dpos(1) == pytest.approx(9.5 * 40 / 50, abs=1e-9)
    assert trio.machine.dpos(2) == pytest.approx(9.5 * 120 / 50, abs=1e-9)
    assert float(trio.query("?VP_SPEED")) == pytest.approx(10, abs=1e-9)
    at(trio, end - 1)
    assert trio.machine.dpos(2) < 120
    at(trio, end)
    assert [trio.machine.dpos(a) for a in range(3)] == [30, 40, 120]


def test_a_merged_seam_between_shares_is_taken_at_the_lower_path_speed() -> None:
    """The page's move merged into a plain XY move: the first runs its 130 of path at 26
    (XY 10; path ACCEL 260) and slows to the second's 10 at its end ((26^2 - 10^2) / 520
    of path in 16/260 s), so XY never runs over 10; the second runs 50 at 10."""
    trio = MC405()
    assert trio.send("BASE(0, 1, 2): UNITS AXIS(0)=1: UNITS AXIS(1)=1: UNITS AXIS(2)=1: "
                     "SPEED=10: ACCEL=100: DECEL=100: MERGE=ON") == []
    assert trio.send("INTERP_FACTOR AXIS(2) = 0: MOVE(30, 40, 120): MOVE(50, 0, 0)") == []
    slow = (26 ** 2 - 10 ** 2) / 520
    seam = 0.1 + (130 - 1.3 - slow) / 26 + 16 / 260
    end = tick_of(seam + (50 - 0.5) / 10 + 0.1)
    assert end == 10119
    at(trio, tick_of(seam) - 1)
    assert trio.machine.dpos(2) < 120
    assert float(trio.query("?VP_SPEED")) < 10
    at(trio, tick_of(seam) + 100)
    assert trio.machine.dpos(2) == pytest.approx(120, abs=1e-9)
    assert float(trio.query("?VP_SPEED")) == pytest.approx(10, abs=1e-9)
    at(trio, end - 1)
    assert trio.machine.dpos(0) < 80
    at(trio, end)
    assert [trio.machine.dpos(a) for a in range(3)] == pytest.approx([80, 40, 120], abs=1e-9)


def test_with_every_axis_interpolated_the_vector_is_the_whole_path() -> None:
    """The same move with INTERP_FACTOR 1: 130 units at 10 (the 3-4-12 path is 130)."""
    trio = MC405()
    assert trio.send("BASE(0, 1, 2): UNITS AXIS(0)=1: UNITS AXIS(1)=1: UNITS AXIS(2)=1: "
                     "SPEED=10: ACCEL=100: DECEL=100: MOVEABS(30, 40, 120)") == []
    at(trio, tick_of(0.1 + (130 - 1.0) / 10 + 0.1) - 1)
    assert trio.machine.dpos(2) < 120
    at(trio, 13200)
    assert [trio.machine.dpos(a) for a in range(3)] == [30, 40, 120]


def test_a_move_of_only_non_interpolated_axes_completes_without_moving() -> None:
    trio = MC405()
    assert trio.send("BASE(0, 1): UNITS AXIS(0)=1: UNITS AXIS(1)=1: SPEED=10: ACCEL=100: "
                     "DECEL=100: INTERP_FACTOR AXIS(1) = 0: MOVE(0, 50)") == []
    assert float(trio.query("?MTYPE")) == 0
    at(trio, 100)
    assert trio.machine.dpos(1) == 0


# ---- FORCE_DWELL ------------------------------------------------------------------------
def test_force_dwell_page_example_pauses_25_ms_after_the_third_move() -> None:
    """The FORCE_DWELL page's sequence, merged: the first three 50-unit moves run as one
    path (ramps 100/1000 = 0.1 s over 5 units) that ends at rest on the third (its dwell),
    waits 25 ms, then the fourth (20 units: 0.1 s up, 0.1 s at 100, 0.1 s down) starts
    from rest."""
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1: SPEED=100: FORCE_SPEED=100: ACCEL=1000: "
                     "DECEL=1000: MERGE=ON") == []
    assert trio.send("MOVESP(50): MOVESP(50): FORCE_DWELL = 25: MOVESP(50): "
                     "FORCE_DWELL = 0: MOVESP(20)") == []
    third = tick_of(0.1 + (150 - 10) / 100 + 0.1)
    assert third == 1600
    at(trio, third - 1)
    assert trio.machine.dpos(0) < 150
    at(trio, third)
    assert trio.machine.dpos(0) == pytest.approx(150, abs=1e-9)
    at(trio, third + 25)  # the dwell's last tick: the fourth move starts here
    assert trio.machine.dpos(0) == pytest.approx(150, abs=1e-9)
    at(trio, third + 26)  # one servo cycle of ACCEL from rest
    assert trio.machine.dpos(0) == pytest.approx(150 + 1000 * 0.001 ** 2 / 2, abs=1e-9)
    end = third + 25 + tick_of(0.3)
    at(trio, end - 1)
    assert trio.machine.dpos(0) < 170
    at(trio, end)
    assert trio.machine.dpos(0) == pytest.approx(170, abs=1e-9)


def test_force_dwell_acts_on_sp_moves_only() -> None:
    """A plain MOVE ignores FORCE_DWELL: the two moves merge without a stop (the path of
    100 at 100 with 0.1 s ramps ends at 1.1 s)."""
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1: SPEED=100: ACCEL=1000: DECEL=1000: MERGE=ON: "
                     "FORCE_DWELL = 25: MOVE(50): MOVE(50)") == []
    at(trio, 1099)
    assert trio.machine.dpos(0) < 100
    at(trio, 1100)
    assert trio.machine.dpos(0) == pytest.approx(100, abs=1e-9)


# ---- CORNER_MODE bit 2: CORNER_STATE and RAISE_ANGLE ------------------------------------
XY = ("BASE(0, 1): UNITS AXIS(0)=1: UNITS AXIS(1)=1: SPEED=10: ACCEL=100: DECEL=100: "
      "MERGE=ON: CORNER_MODE = 4")


def xy(trio: MC405) -> tuple[float, float]:
    return (trio.machine.dpos(0), trio.machine.dpos(1))


def test_corner_state_handshake_holds_the_move_after_a_sharp_corner() -> None:
    """The CORNER_STATE page's sequence on a 90 degree corner beyond RAISE_ANGLE 15: the
    first 20 (0.1 s ramps over 0.5) ends at rest at 2.1 s; the held move waits for 3,
    loads at zero speed (state 7, MTYPE MOVEABS, TANG_DIRECTION up Y = 0), and ramps up
    from the tick the program writes 0."""
    trio = MC405()
    assert trio.send(XY + ": RAISE_ANGLE = 15 * PI / 180") == []
    assert trio.send("MOVEABS(20, 0): MOVEABS(20, 20)") == []
    assert float(trio.query("?CORNER_STATE")) == 1  # the held move is the next one
    at(trio, 2099)
    assert xy(trio)[0] < 20
    at(trio, 2100)
    assert xy(trio) == (20, 0)
    assert float(trio.query("?MTYPE")) == 0  # the path stopped: the move is not loaded
    at(trio, 2150)
    assert xy(trio) == (20, 0)
    assert trio.send("CORNER_STATE = 3") == []
    assert float(trio.query("?CORNER_STATE")) == 7
    assert float(trio.query("?MTYPE")) == 2
    assert float(trio.query("?VP_SPEED")) == 0
    assert float(trio.query("?TANG_DIRECTION")) == 0
    at(trio, 2200)
    assert xy(trio) == (20, 0)
    assert trio.send("CORNER_STATE = 0") == []
    at(trio, 2300)  # 0.1 s of ACCEL 100
    assert xy(trio) == (20, pytest.approx(0.5, abs=1e-9))
    at(trio, 4299)
    assert xy(trio)[1] < 20
    at(trio, 4300)
    assert xy(trio) == (20, 20)
    assert float(trio.query("?CORNER_STATE")) == 0


def test_a_corner_within_raise_angle_merges_and_raise_angle_0_never_holds() -> None:
    """45 degrees under RAISE_ANGLE 60: one merged path (20 + 28.28 at 10, no stop)."""
    length = 20 + 20 * math.sqrt(2)
    for raise_angle in ("60 * PI / 180", "0"):
        trio = MC405()
        assert trio.send(XY + f": RAISE_ANGLE = {raise_angle}") == []
        assert trio.send("MOVE(20, 0): MOVE(20, 20)") == []
        end = tick_of(0.1 + (length - 1.0) / 10 + 0.1)
        at(trio, end - 1)
        assert float(trio.query("?CORNER_STATE")) == 0
        assert xy(trio)[1] < 20
        at(trio, end)
        assert xy(trio) == (pytest.approx(40, abs=1e-9), pytest.approx(20, abs=1e-9))


def test_a_knife_program_runs_the_handshake_at_each_corner_of_a_square() -> None:
    """A program of our own in the page's shape: one task feeds a square, another lifts,
    turns and lowers a knife (VRs count it) at each of its three corners."""
    trio = MC405()
    assert trio.send(XY + ": RAISE_ANGLE = 15 * PI / 180") == []
    trio.load("KNIFE", "BASE(0)\nREPEAT\n  WAIT UNTIL CORNER_STATE > 0\n"
              "  WAIT UNTIL MTYPE = 0\n  VR(20 + VR(10)) = DPOS AXIS(0) * 100 + DPOS AXIS(1)\n"
              "  VR(10) = VR(10) + 1\n  WA(20)\n  CORNER_STATE = 3\n"
              "  WAIT UNTIL CORNER_STATE = 7\n  VR(30 + VR(10)) = TANG_DIRECTION\n  WA(20)\n"
              "  CORNER_STATE = 0\nUNTIL VR(10) = 3\n")
    trio.load("FEED", "BASE(0, 1)\nMOVEABS(20, 0)\nMOVEABS(20, 20)\nMOVEABS(0, 20)\n"
              "MOVEABS(0, 0)\n")
    assert trio.send('RUN "KNIFE", 1') == []
    assert trio.send('RUN "FEED", 2') == []
    trio.advance(12.0)  # 4 x 2.1 s of moves, 3 x about 45 ms of knife
    assert xy(trio) == (0, 0)
    assert float(trio.query("?VR(10)")) == 3
    corners = [float(trio.query(f"?VR({20 + k})")) for k in range(3)]
    assert corners == [2000, 2020, 20]  # (20, 0), (20, 20), (0, 20)
    turns = [trio.machine.vr_read(30 + k) for k in range(1, 4)]
    assert turns == pytest.approx([0, -math.pi / 2, math.pi], abs=1e-6)


# ---- FORCE_RAMP and LOOKAHEAD_FACTOR ----------------------------------------------------
def test_force_ramp_page_example_slows_from_100_to_75_over_the_move() -> None:
    """The FORCE_RAMP page's ramp on a 10-unit move after a move ending at 100: the rate
    (75^2 - 100^2) / (2 x 10) = -218.75 over 20/175 s; the first move (50, 0.1 s ramp
    over 5 units) reaches its end at 0.55 s; the last (30 at 75) cruises and stops at
    ACCEL 1000 (0.075 s over 2.8125 units)."""
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1: ACCEL=1000: DECEL=1000: MERGE=ON: SPEED=100: "
                     "FORCE_SPEED=100: ENDMOVE_SPEED=100: MOVESP(50)") == []
    ramp = (75 ** 2 - 100 ** 2) / (2 * 10)
    assert trio.send(f"ENDMOVE_SPEED=75: FORCE_RAMP={ramp}: MOVESP(10)") == []
    assert trio.send("FORCE_RAMP=0: FORCE_SPEED=75: ENDMOVE_SPEED=-1: MOVESP(30)") == []
    at(trio, 600)  # 0.05 s into the ramp
    assert trio.machine.dpos(0) == pytest.approx(50 + 100 * 0.05 + ramp * 0.05 ** 2 / 2,
                                                 abs=1e-9)
    assert float(trio.query("?VP_SPEED")) == pytest.approx(100 + ramp * 0.05, abs=1e-3)
    ramp_end = 0.55 + 10 * 2 / 175
    at(trio, 700)  # past it: at 75
    assert trio.machine.dpos(0) == pytest.approx(60 + 75 * (0.7 - ramp_end), abs=1e-9)
    end = tick_of(ramp_end + (30 - 2.8125) / 75 + 0.075)
    assert end == 1102
    at(trio, end - 1)
    assert trio.machine.dpos(0) < 90
    at(trio, end)
    assert trio.machine.dpos(0) == pytest.approx(90, abs=1e-9)


def test_lookahead_factor_halves_the_sp_moves_in_the_buffer_as_they_run() -> None:
    """Two 100-unit SP moves at FORCE_SPEED 100 (ACCEL 1000); at 0.5 s the factor 0.5:
    the path slows from 100 to 50 at ACCEL (0.05 s over 3.75 units), and a plain move
    behind them keeps SPEED 100."""
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1: ACCEL=1000: DECEL=1000: MERGE=ON: SPEED=100: "
                     "FORCE_SPEED=100: MOVESP(100): MOVESP(100)") == []
    at(trio, 500)
    here = 5 + 100 * 0.4
    assert trio.machine.dpos(0) == pytest.approx(here, abs=1e-9)
    assert trio.send("LOOKAHEAD_FACTOR = 0.5") == []
    at(trio, 550)
    assert trio.machine.dpos(0) == pytest.approx(here + 3.75, abs=1e-9)
    at(trio, 1550)
    assert trio.machine.dpos(0) == pytest.approx(here + 3.75 + 50, abs=1e-9)
    # the rest at 50: 200 - 98.75 less the final ramp (50/1000 s over 1.25)
    end = tick_of(0.55 + (200 - here - 3.75 - 1.25) / 50 + 0.05)
    at(trio, end - 1)
    assert trio.machine.dpos(0) < 200
    at(trio, end)
    assert trio.machine.dpos(0) == pytest.approx(200, abs=1e-9)


def test_lookahead_factor_is_taken_by_sp_moves_loaded_after_it() -> None:
    """LOOKAHEAD_FACTOR 2 on FORCE_SPEED 50: a 100-unit MOVESP runs at 100 (0.1 s ramps
    at 1000 over 5 units: 1.1 s), a plain MOVE at its SPEED 50."""
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1: ACCEL=1000: DECEL=1000: SPEED=50: FORCE_SPEED=50:"
                     " LOOKAHEAD_FACTOR = 2: MOVESP(100)") == []
    at(trio, 1099)
    assert trio.machine.dpos(0) < 100
    at(trio, 1100)
    assert trio.machine.dpos(0) == pytest.approx(100, abs=1e-9)
    assert trio.send("MOVE(100)") == []  # 0.05 s ramps over 1.25: 2.05 s
    at(trio, 1100 + 2049)
    assert trio.machine.dpos(0) < 200
    at(trio, 1100 + 2050)
    assert trio.machine.dpos(0) == pytest.approx(200, abs=1e-9)


# ---- LIMIT_BUFFERED ---------------------------------------------------------------------
def test_limit_buffered_1_makes_the_third_move_wait_for_the_first_to_end() -> None:
    """LIMIT_BUFFERED 1: one move behind the running one. Three 10-unit moves (MERGE
    OFF: 0.1 s ramps over 0.5 units, 1.1 s each): the command line hands over the third
    only when the first ends, at tick 1100; with the power-up depth it returns at once."""
    trio = MC405()
    assert float(trio.query("?LIMIT_BUFFERED")) == 15
    assert trio.send("BASE(0): UNITS=1: SPEED=10: ACCEL=100: DECEL=100") == []
    assert trio.send("MOVE(10): MOVE(10): MOVE(10)") == []
    assert trio.tick == 0 and float(trio.query("?MOVES_BUFFERED")) == 2
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1: SPEED=10: ACCEL=100: DECEL=100: "
                     "LIMIT_BUFFERED = 1") == []
    assert trio.send("MOVE(10): MOVE(10): MOVE(10)") == []
    assert trio.tick == 1100
    assert trio.machine.dpos(0) == 10
    assert float(trio.query("?MOVES_BUFFERED")) == 1


def test_limit_buffered_outside_1_to_64_is_refused() -> None:
    trio = MC405()
    for value in ("0", "65"):
        reply = trio.send(f"LIMIT_BUFFERED = {value}")
        assert reply and reply[0].endswith("Parameter out of range")
    assert float(trio.query("?LIMIT_BUFFERED")) == 15


def test_the_move_loader_example_script_runs_clean() -> None:
    """examples/mc405_move_loader.maxk under `maxk run`: every expected reply matches."""
    from pathlib import Path

    from maxk.cli import main

    script = Path(__file__).parent.parent / "examples" / "mc405_move_loader.maxk"
    assert main(["run", str(script)]) == 0
