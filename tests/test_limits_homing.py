"""Limits and homing against the world model: switches sit at physical positions."""

import pytest

from maxk import MAXk
from maxk.personalities.maxk import flags as F


@pytest.fixture
def b():
    board = MAXk("MAXk-4000")
    board.set_limits("X", plus=5000, minus=-5000)
    return board


def test_limit_mid_move_stops_at_once_flags_and_flushes(b):
    b.send("AX; VL10000; AC100000; MR10000; GO; ID; MR5; GO;")
    assert b.run_until_idle(timeout=5)
    pos = b.position("X")
    assert 5000 <= pos <= 5000 + 10000 // 8192 + 1  # the first update cycle on the switch
    assert b.query("QA") == "PNLN"
    assert not b.done("X")  # the ID was flushed with the rest of the queue
    assert b.query("RQC") == "2559"
    assert b.doorbell == 1 << 8  # overtravel X
    assert b.board.limit_status_word() == 1 << 8


def test_soft_limit_decelerates_into_the_switch(b):
    b.send("AX; LMS; VL10000; AC100000; MR10000; GO;")
    assert b.run_until_idle(timeout=5)
    # 10000 steps/s stopping at 100000 steps/s^2 runs on 500 steps past the switch
    assert b.position("X") == pytest.approx(5500, abs=2)
    assert b.board.axes[0].flags & F.AXIS_OVERTRAVEL


def test_sl_and_sf_choose_the_stop_style(b):
    b.send("AX; SL;")
    assert b.query("LM?") == "=s"
    b.send("SF")
    assert b.query("LM?") == "=h"


def test_moving_off_a_limit_is_allowed_into_it_refused(b):
    b.send("AX; VL10000; MR10000; GO;")
    b.run_until_idle(timeout=5)
    at = b.position("X")
    b.send("IC; MR100; GO; ID;")  # further into the limit: refused, the queue goes on
    assert b.position("X") == at
    assert b.board.axes[0].flags & F.AXIS_OVERTRAVEL
    assert b.query("QA") == "PDLN"  # done + L: what EPICS reads as "stopped at a limit"
    b.send("IC; MR-1000; GO; ID;")  # away from it: fine
    assert b.run_until_done("X", timeout=5)
    assert b.position("X") == at - 1000
    assert b.query("QA") == "MDNN"


def test_jog_into_a_limit_and_limits_off(b):
    b.send("AX; JG-20000;")
    assert b.run_until_idle(timeout=5)
    assert b.position("X") <= -5000
    assert b.query("QA")[2] == "L"
    b.send("IC; LF; JG-20000;")
    b.advance(0.5)
    assert b.position("X") < -7000  # no limit checking at all
    b.send("LN")  # limits on while running into a pressed one: it trips at once
    assert b.query("RV") == "0"
    assert b.board.axes[0].flags & F.AXIS_OVERTRAVEL


def test_stuck_limit_fault(b):
    b.fault("X", "plus", "active")
    b.send("AX; VL1000; MR10; GO; MR20; GO;")
    b.run_until_idle()
    assert b.position("X") == 0 and b.board.axes[0].flags & F.AXIS_OVERTRAVEL
    b.send("IC; MR-10; GO; ID;")
    assert b.run_until_done("X")
    b.fault("X", "plus", None)
    b.send("MR10; GO; ID;")
    b.send("CA")
    assert b.run_until_idle() and b.position("X") == 0


def test_limit_moved_under_a_running_move(b):
    b.send("AX; VL10000; MR4000; GO;")
    b.advance(0.2)
    b.set_limits("X", plus=1000)  # the stage changed: the switch is now behind the axis
    assert b.position("X") >= 1000
    assert b.query("RV") == "0"
    assert b.query("QA")[2] == "L"


def test_limits_see_the_stage_not_the_counter(b):
    b.send("AX; LP-1000000;")  # the counter moves, the switch does not
    b.send("VL10000; MR10000; GO;")
    b.run_until_idle(timeout=5)
    assert b.board.axes[0].steps >= 5000
    assert b.position("X") == b.board.axes[0].steps - 1000000


def test_raw_limit_levels_in_ql(b):
    b.send("AX; JG20000;")
    b.run_until_idle(timeout=5)
    assert int(b.query("QL"), 16) == 0x0F0F & ~(1 << 8)  # X plus pressed: active low reads 0
    b.send("LTH")
    assert int(b.query("QL"), 16) == (0x0F0F & ~0x0101) | (1 << 8)


# ---- homing ---------------------------------------------------------------------------
def test_e4_home_exchange_ends_done_at_zero():
    b = MAXk()
    b.send("AX;AC200000;VL10000;VB100;HM;MA0;GO;ID;")
    assert b.run_until_done("X", timeout=5)
    assert b.query("AX RP") == "0"
    assert b.board.axes[0].steps == 1234  # the default home switch's lower edge
    assert b.query("AX QA") == "MDNH"


def test_home_loads_the_operand_where_home_was_seen():
    b = MAXk()
    b.send("AX; VL10000; AC100000; HM500; ID;")
    assert b.run_until_done("X", timeout=5)
    # ramps to a stop past home: 10000^2 / (2 * 100000) = 500 steps
    assert b.position("X") == pytest.approx(500 + 500, abs=2)
    assert b.board.axes[0].steps == pytest.approx(1234 + 500, abs=2)


def test_homing_that_starts_on_the_switch_finds_it_at_once():
    b = MAXk()
    b.send("AX; LO0; MA1250; GO; ID;")  # onto the home switch (1234..1333)
    b.run_until_done("X")
    b.send("CA; HR-7; ID;")
    assert b.run_until_done("X")
    assert b.query("RP") == "-7"
    assert b.board.axes[0].steps == 1250  # no motion at all


def test_homing_that_starts_beyond_the_switch_runs_into_the_limit():
    b = MAXk()
    b.set_limits("X", plus=20000)
    b.send("AX; MA5000; GO;")
    b.run_until_idle()
    b.send("VL50000; HM; ID;")
    assert b.run_until_idle(timeout=5)
    assert b.query("QA") == "PNLN"  # overtravel, home never found, done not set
    assert b.board.axes[0].homing is None
    assert b.position("X") >= 20000


def test_reverse_homing_from_beyond_finds_it():
    b = MAXk()
    b.send("AX; MA5000; GO;")
    b.run_until_idle()
    b.send("VL10000; AC1000000; HR0; ID;")
    assert b.run_until_done("X", timeout=5)
    assert b.board.axes[0].steps == pytest.approx(1333 - 50, abs=2)
    assert b.position("X") == pytest.approx(-50, abs=2)


def test_limit_hit_during_homing():
    b = MAXk()
    b.set_home("X", None, None)  # no home switch at all
    b.set_limits("X", minus=-3000)
    b.send("AX; VL20000; HR; ID;")
    assert b.run_until_idle(timeout=5)
    assert b.query("QA") == "MNLN"
    assert not b.done("X")


def test_encoder_homing_needs_index_quadrant_and_switch():
    b = MAXk()
    b.send("AX; HE; VL4000; AC400000; HM0; ID;")
    assert b.run_until_done("X", timeout=5)
    steps = b.board.axes[0].steps
    # home at the index mark inside the window (1280), then 20 steps of ramp down
    assert steps - b.position("X") == 1280
    b.send("CA; EH11X1; MA-100; GO; HM0; ID;")  # ignore the index: first A+/B- count in window
    assert b.run_until_done("X", timeout=5)
    assert b.board.axes[0].steps - b.position("X") == 1236


def test_km_finds_home_without_touching_the_counter():
    b = MAXk()
    b.send("AX; LP777; VL10000; KM; ID;")
    assert b.run_until_done("X", timeout=5)
    assert b.position("X") == 777 + b.board.axes[0].steps


def test_home_level_reporting():
    b = MAXk()
    b.send("AX; MA1300; GO; ID;")
    b.run_until_done("X")
    assert b.query("QA")[3] == "H"
    assert b.board.home_status_word() == 1
    assert b.query("HT?") == "=l"
    b.send("HH")
    assert b.query("HT?") == "=h"


def test_lexer_splits_the_dll_home_templates():
    b = MAXk()
    b.send("AXHSHM0;ID")
    assert b.run_until_done("X", timeout=5)
    b.send("CA;AXHEHR0;ID")
    assert b.run_until_done("X", timeout=5)
    assert not b.command_error


def test_refused_move_inside_a_queue_leaves_the_queue_running(b):
    b.send("AX; VL10000; MR6000; GO; MR100; GO; MR-200; GO; ID;")
    assert b.run_until_idle(timeout=5)
    # the first move trips the limit and flushes everything after it
    assert not b.done("X")
    b.send("IC; MR100; GO; MR-200; GO; ID;")  # queued behind nothing: refused, then away
    assert b.run_until_done("X", timeout=5)
    assert b.query("QA") == "MDNN"


def test_home_loads_the_counter_at_the_exact_count_even_at_speed():
    b = MAXk()
    b.send("AX; PSE; VL200000; HM500; ID;")  # ~24 steps per update cycle
    assert b.run_until_done("X", timeout=5)
    axis = b.board.axes[0]
    assert b.position("X") - axis.steps == 500 - 1234  # counter read 500 at step 1234
    assert b.encoder("X") - axis.steps == 500 - 1234  # and the encoder, on PSE


def test_st_kl_ks_end_a_home_search():
    for stop in ("KL", "AX KS", "AX ST"):
        b = MAXk()
        b.send("AX; VL10000; MA-5000; GO;")
        b.run_until_idle()
        b.send("HM0; ID;")
        b.advance(0.1)
        b.send(stop)
        b.run_until_idle()
        b.send("MR20000; GO; ID;")
        assert b.run_until_done("X", timeout=10)
        assert b.board.axes[0].homing is None
        assert b.position("X") > 15000, stop  # the counter was never reloaded at home


def test_direction_after_a_limit_trips_during_a_jog_reversal():
    b = MAXk()
    b.set_limits("X", minus=-4000)
    b.send("AX; VL10000; AC20000; JG-10000;")
    b.advance(0.6)
    b.send("JG10000")
    assert b.run_until_idle(timeout=5)
    assert b.query("QA") == "MNLN"  # stopped moving minus, on the minus limit


def test_status_shows_the_way_the_axis_is_travelling():
    b = MAXk()
    b.send("AX; VL10000; AC20000; JG-10000;")
    b.advance(1.0)
    b.send("JG10000")
    b.advance(0.1)  # still decelerating in the minus direction
    assert int(b.query("RV")) < 0
    assert b.query("QA")[0] == "M"


def test_a_move_ending_exactly_on_either_limit_trips_it():
    for target, status in (("5000", "PNLN"), ("-5000", "MNLN")):
        b = MAXk()
        b.set_limits("X", plus=5000, minus=-5000)
        b.send(f"AX; VL10000; MA{target}; GO; ID;")
        b.run_until_idle(timeout=5)
        assert b.query("QA") == status, target
        assert b.board.axes[0].flags & F.AXIS_OVERTRAVEL


def test_encoder_homing_far_away():
    b = MAXk()
    b.set_home("X", 300000, 300100)
    b.send("AX; PSE; HE; EH11X1; VL400000; AC8000000; HM0; ID;")
    assert b.run_until_done("X", timeout=5)
    assert b.encoder("X") - b.board.axes[0].steps == -300000


def test_homing_from_inside_a_bounce_zone():
    b = MAXk()
    b.bounce("X", "home", 5)
    b.send("AX; MA1235; GO;")
    b.run_until_idle()
    b.send("VL1000; HM0; ID;")
    assert b.run_until_done("X", timeout=5)
    assert b.position("X") - b.board.axes[0].steps == -1236
