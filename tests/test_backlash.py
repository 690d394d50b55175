"""Mechanical backlash in the world and its compensation on the board (BC#): exact motor
counter (RP) and stage encoder (RE) positions after moves, jogs, stops and single steps."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxk import MAXk
from maxk.controllers.world_settings import parse_world
from maxk.personalities.maxk.backlash import Backlash


def board(play: int, bc: int, setup: str = "") -> MAXk:
    b = MAXk()
    b.set_backlash("X", play)
    b.send(f"AX; PSE; BC{bc}; VL5000; AC50000; {setup}")
    assert not b.command_error
    return b


def move(b: MAXk, steps: int) -> tuple[int, int]:
    b.send(f"AX MR{steps}; GO;")
    assert b.run_until_idle(timeout=60)
    return int(b.query("AX RP")), int(b.query("AX RE"))


def stage_by_steps(moves: list[int], play: int, bc: int) -> list[tuple[int, int]]:
    """A reference made one step at a time: the drive gives BC extra steps at each
    reversal, the stage follows the drive once it has crossed the gap."""
    motor, drive, stage, last = 0, 0, 0, 1
    out = []
    for m in moves:
        if m == 0:
            out.append((motor, stage))
            continue
        d = 1 if m > 0 else -1
        pulses = abs(m) + (bc if d != last else 0)
        last = d
        for _ in range(pulses):
            drive += d
            if d > 0 and drive > stage:
                stage = drive
            elif d < 0 and drive < stage - play:
                stage = drive + play
        motor += m
        out.append((motor, stage))
    return out


def test_without_compensation_the_stage_lags_after_each_reversal():
    b = board(25, 0)
    assert move(b, 1000) == (1000, 1000)  # power-up: the play is taken up going up
    assert move(b, -500) == (500, 525)  # the first 25 steps down do not move the stage
    assert move(b, -100) == (400, 425)  # no reversal: the lag stays
    assert move(b, 500) == (900, 900)  # up: the motor crosses the gap, the stage follows
    assert move(b, -10) == (890, 900)  # less than the play: the stage does not move
    assert move(b, 10) == (900, 900)


def test_compensation_equal_to_the_backlash_keeps_the_stage_on_the_counter():
    b = board(25, 25)
    for steps in (1000, -500, -100, 500, -10, 10, -3000):
        rp, re = move(b, steps)
        assert re == rp
    assert (rp, re) == (-2100, -2100)


def test_over_compensation_overshoots_by_the_difference():
    b = board(25, 40)
    assert move(b, 1000) == (1000, 1000)
    assert move(b, -500) == (500, 485)
    assert move(b, 500) == (1000, 1000)  # up: 40 extra steps, 15 of them past the gap


def test_compensation_without_backlash_moves_the_stage_off_the_counter():
    b = board(0, 30)
    assert move(b, -100) == (-100, -130)
    assert move(b, 100) == (0, 0)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(-400, 400), min_size=1, max_size=8), st.integers(0, 60),
       st.integers(0, 60))
def test_moves_match_a_step_by_step_stage(moves, play, bc):
    b = board(play, bc)
    expected = stage_by_steps(moves, play, bc)
    for steps, want in zip(moves, expected, strict=True):
        if steps == 0:
            continue
        assert move(b, steps) == want


def test_the_stage_mid_move_and_the_end_tick_are_unchanged():
    plain = board(0, 0)
    lash = board(25, 0)
    for b in (plain, lash):
        move(b, 1000)
        b.send("AX MR-1000; GO;")
        b.advance(0.1)  # 0.1 s: the ramp down to 5000 steps/s is 0.1 s, 250 steps
    assert plain.query("AX RP") == lash.query("AX RP") == "750"
    assert lash.query("AX RE") == "775"
    assert plain.query("AX RE") == "750"
    for b in (plain, lash):
        assert b.run_until_idle(timeout=60)
    assert plain.tick == lash.tick
    assert plain.board.axis("X").rest_since == lash.board.axis("X").rest_since
    assert lash.query("AX RE") == "25"


def test_the_first_25_steps_of_a_reversal_leave_the_stage_still():
    b = board(25, 0)
    move(b, 1000)
    b.send("AX MR-1000; GO;")
    seen = []
    for _ in range(60):
        b.advance(ticks=20)
        seen.append((int(b.query("AX RP")), int(b.query("AX RE"))))
    for rp, re in seen:
        assert re == min(1000, rp + 25)


@pytest.mark.parametrize("bc,lag", [(0, 25), (25, 0)])
def test_a_jog_reversing_inside_one_motion(bc, lag):
    b = board(25, bc, "JG5000;")
    b.advance(0.5)
    b.send("AX JG-5000;")  # decelerates, turns and runs down: one motion
    b.advance(2.0)
    rp, re = int(b.query("AX RP")), int(b.query("AX RE"))
    assert re == rp + lag
    b.send("AX ST;")
    assert b.run_until_idle(timeout=60)
    rp, re = int(b.query("AX RP")), int(b.query("AX RE"))
    assert re == rp + lag


def test_a_stop_and_a_kill_keep_the_stage_where_it_is():
    b = board(25, 0)
    move(b, 1000)
    b.send("AX JG-5000;")
    b.advance(0.3)
    b.send("AX KL;")
    b.run_until_idle(timeout=60)
    rp, re = int(b.query("AX RP")), int(b.query("AX RE"))
    assert re == rp + 25
    assert move(b, 100) == (rp + 100, rp + 100)


def test_single_steps_reverse_too():
    b = board(3, 0)
    b.send("AX MM; MO; MO; MO; MO;")  # four single steps down
    b.run_until_idle(timeout=5)
    assert (b.query("AX RP"), b.query("AX RE")) == ("-4", "-1")
    b2 = board(3, 3)
    b2.send("AX MM; MO; MO; MO; MO;")
    b2.run_until_idle(timeout=5)
    assert (b2.query("AX RP"), b2.query("AX RE")) == ("-4", "-4")


def test_lp_reloads_counters_not_the_stage():
    b = board(25, 0)
    move(b, 1000)
    move(b, -500)
    b.send("AX LP0;")
    assert (b.query("AX RP"), b.query("AX RE")) == ("0", "0")
    assert move(b, -100) == (-100, -100)  # the play is still taken up downward
    assert move(b, 100) == (0, -25)


def test_bc_on_a_servo_is_stored_without_effect():
    b = MAXk()
    b.set_backlash("X", 25)
    b.send("AX PSM; BC25;")
    assert not b.command_error
    assert b.board.axis("X").config.backlash == 25
    assert b.board.axis("X").stage_offset(b.board) == 0


def test_bc_range_and_world_setting():
    b = MAXk()
    b.send("AX BC32768;")
    assert b.command_error
    assert b.board.axis("X").config.backlash == 0
    assert parse_world("X backlash 25")(b) == "X backlash 25"
    assert b.stage("X").backlash == 25
    with pytest.raises(ValueError):
        parse_world("X backlash -1")
    with pytest.raises(ValueError):
        b.set_backlash("X", -1)


def test_the_state_is_the_play_ahead_and_the_extra_steps():
    s = Backlash()
    assert s.leg(-10, 25, 0) == Backlash(-1, 0, 10)
    assert s.leg(-10, 25, 25) == Backlash(-1, -25, 25)
    assert s.leg(-10, 25, 25).offset == 0
    assert Backlash(-1, 0, 25).leg(5, 25, 0) == Backlash(1, 0, 20)
    assert Backlash(1, 0, 0).leg(7, 25, 0) == Backlash(1, 0, 0)


def test_a_reset_keeps_the_stage_where_it_stands():
    b = board(25, 0)
    move(b, 1000)
    move(b, -500)  # the stage stands 25 above the motor
    b.send("RS")
    b.run_until_idle(timeout=5)
    assert (b.query("AX RP"), b.query("AX RE")) == ("0", "0")
    b.send("AX; PSE; VL5000; AC50000;")
    assert move(b, -100) == (-100, -100)  # the play is still taken up downward
    assert move(b, 100) == (0, -25)
