"""The MC405's limits, drive enables, motion errors and Z-mark datums on the shared engine.

Every figure is worked out by hand from the profile: SPEED 1000 counts/s reached at
ACCEL 100000 in 10 servo cycles (5 counts), so a move from rest passes count p (p >= 5) on
tick 5 + p; DECEL 10000 stops it from 1000 counts/s in 100 cycles over 50 counts.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxk.controllers.trio.controller import MC405
from tests.trio_helpers import at, mc405


def dpos(trio: MC405, axis: int = 0) -> float:
    """DPOS to 1e-6 (the demand is exact to a float's rounding)."""
    return round(trio.machine.dpos(axis), 6)


FAST = "SPEED=1000: ACCEL=100000: DECEL=10000"


# ---- hard limits ---------------------------------------------------------------------
def test_forward_limit_switch_stops_the_move_on_its_tick_at_decel() -> None:
    trio = mc405(FAST, "FWD_IN=3")
    trio.world_view().set_limits("0", plus=5000)
    trio.send("MOVE(10000)")
    at(trio, 5004)
    assert (dpos(trio), trio.query("?VP_SPEED"), trio.query("?AXISSTATUS")) == (4999.0, "1000",
                                                                               "0")
    at(trio, 5005)  # the switch is reached: the ramp down starts here
    assert (dpos(trio), trio.query("?AXISSTATUS"), trio.query("?IN(3)")) == (5000.0, "16", "0")
    at(trio, 5006)
    assert trio.machine.vp_speed(0) == 990.0
    assert trio.run_until_idle()
    assert (trio.machine.tick, dpos(trio)) == (5105, 5050.0)
    assert trio.query("?AXISSTATUS") == "16"
    assert trio.query("?MOTION_ERROR") == "0"  # not in ERRORMASK: no motion error


def test_fastdec_sets_the_ramp_at_a_limit() -> None:
    trio = mc405(FAST, "FWD_IN=3: FASTDEC=100000")
    trio.world_view().set_limits("0", plus=5000)
    trio.send("MOVE(10000)")
    assert trio.run_until_idle()
    assert (trio.machine.tick, dpos(trio)) == (5015, 5005.0)


def test_a_move_into_an_active_limit_is_cancelled_and_one_away_runs() -> None:
    trio = mc405(FAST, "FWD_IN=3")
    trio.world_view().set_limits("0", plus=5000)
    trio.send("MOVE(10000)")
    assert trio.run_until_idle()
    start = trio.machine.tick
    trio.send("MOVE(100)")
    assert trio.run_until_idle()
    assert (trio.machine.tick, dpos(trio)) == (start, 5050.0)  # no step, idle at once
    trio.send("FORWARD")
    assert trio.run_until_idle() and dpos(trio) == 5050.0
    trio.send("MOVE(-100)")
    assert trio.run_until_idle()
    assert (dpos(trio), trio.query("?AXISSTATUS")) == (4950.0, "0")


def test_reverse_limit_stops_reverse() -> None:
    trio = mc405(FAST, "REV_IN=4")
    trio.world_view().set_limits("0", minus=-300)
    trio.send("REVERSE")
    assert trio.run_until_idle()
    # -300 reached on tick 305, then 100 cycles and 50 counts of ramp
    assert (trio.machine.tick, dpos(trio), trio.query("?AXISSTATUS")) == (405, -350.0, "32")


def test_a_limit_moved_under_a_running_move_is_found_again() -> None:
    trio = mc405(FAST, "FWD_IN=3")
    trio.send("MOVE(10000)")
    at(trio, 1000)
    trio.world_view().set_limits("0", plus=3000)
    assert trio.run_until_idle()
    assert (trio.machine.tick, dpos(trio)) == (3105, 3050.0)


def test_a_limit_switch_the_world_turns_on_as_a_level_stops_at_once_looked_at() -> None:
    trio = mc405(FAST, "FWD_IN=7")
    trio.send("FORWARD")
    at(trio, 2000)
    trio.world_view().set_input(7, False)  # the input itself goes low: active low
    assert trio.run_until_idle()
    assert (trio.machine.tick, dpos(trio)) == (2100, 1995.0 + 50.0)


def test_an_unwired_limit_switch_does_not_stop_the_axis() -> None:
    trio = mc405(FAST)
    trio.world_view().set_limits("0", plus=500)
    trio.send("MOVE(1000)")
    assert trio.run_until_idle() and dpos(trio) == 1000.0


def test_a_path_reaching_one_axis_limit_ramps_down_along_itself() -> None:
    trio = mc405("BASE(0,1)", FAST, "REV_IN AXIS(1)=-1", "FWD_IN AXIS(1)=2")
    trio.world_view().set_limits("1", plus=2000)
    trio.send("MOVE(3000,4000)")  # 0.8 of the path on axis 1: 2000 at path 2500
    assert trio.run_until_idle()
    # 2500 along the path on tick 2505, then 10 cycles at ACCEL: 5 more along it
    assert trio.machine.tick == 2515
    assert (dpos(trio, 0), dpos(trio, 1)) == (1503.0, 2004.0)
    assert trio.query("?AXISSTATUS AXIS(1)") == "16"


# ---- soft limits ---------------------------------------------------------------------
def test_forward_soft_limit_in_user_units_stops_and_sets_bit_9() -> None:
    trio = mc405("UNITS=10", "SPEED=100: ACCEL=10000: DECEL=1000", "FS_LIMIT=200")
    trio.send("MOVE(500)")  # 2000 counts to the limit
    at(trio, 2005)  # the profile's float is a hair short of count 2000 on tick 2005 ...
    assert trio.machine.demand(0) == pytest.approx(2000.0) and trio.machine.demand(0) < 2000
    assert trio.query("?AXISSTATUS") == "0"
    at(trio, 2006)  # ... so the whole count is made, and the limit met, on tick 2006
    assert trio.query("?AXISSTATUS") == "512"
    assert trio.run_until_idle()
    assert (trio.machine.tick, dpos(trio), trio.query("?AXISSTATUS")) == (2106, 205.1, "512")
    trio.send("MOVE(1)")
    assert trio.run_until_idle() and dpos(trio) == 205.1
    trio.send("MOVEABS(150)")
    assert trio.run_until_idle()
    assert (dpos(trio), trio.query("?AXISSTATUS")) == (150.0, "0")


def test_reverse_soft_limit_follows_defpos() -> None:
    trio = mc405(FAST, "DEFPOS(1000)", "RS_LIMIT=700")
    trio.send("MOVE(-1000)")
    assert trio.run_until_idle()
    assert (trio.machine.tick, dpos(trio), trio.query("?AXISSTATUS")) == (405, 650.0, "1024")


# ---- motion errors ------------------------------------------------------------------------
def test_errormask_puts_a_limit_into_motion_error_all_axes_stop_wdog_off() -> None:
    trio = mc405(FAST, "FWD_IN=3", "ERRORMASK=268+16", "WDOG=ON",
                 "BASE(1)", FAST, "BASE(0)")
    assert trio.query("?ERRORMASK") == "284"
    trio.world_view().set_limits("0", plus=5000)
    trio.send("MOVE(10000)")
    trio.send("MOVE(10000) AXIS(1)")
    at(trio, 5005)
    # the error stops every axis at once where it is: no ramp
    assert (dpos(trio, 0), dpos(trio, 1)) == (5000.0, 5000.0)
    assert trio.machine.axis_idle(0) and trio.machine.axis_idle(1)
    assert [trio.query(q) for q in ("?MOTION_ERROR", "?ERROR_AXIS", "?WDOG",
                                    "?AXISSTATUS", "?AXISSTATUS AXIS(1)")] == \
        ["1", "0", "0", "16", "0"]
    assert trio.send("MOVE(-10)") == ["! Axis in error"]
    assert trio.send("MOVE(10) AXIS(1)") == []  # only the axis in error refuses
    assert trio.send("DATUM(0)") == []
    assert [trio.query(q) for q in ("?MOTION_ERROR", "?ERROR_AXIS", "?WDOG")] == \
        ["0", "0", "0"]  # WDOG stays OFF until the program sets it; ERROR_AXIS 0 (page)
    trio.send("MOVE(-100)")
    assert trio.run_until_idle() and dpos(trio) == 4900.0


def test_an_error_latches_its_bits_and_acts_on_newly_set_bits_only() -> None:
    trio = mc405(FAST, "FWD_IN=3", "ERRORMASK=16")
    trio.world_view().set_limits("0", plus=100)
    trio.send("MOVE(1000)")
    assert trio.run_until_idle()
    trio.world_view().set_limits("0", plus=None)  # the switch goes away
    assert trio.query("?AXISSTATUS") == "16"  # held by the error
    trio.send("DATUM(0)")
    assert trio.query("?AXISSTATUS") == "0"
    trio.world_view().set_limits("0", plus=100)  # back on under the standing axis
    assert trio.query("?MOTION_ERROR") == "1"


def test_an_error_drops_the_buffered_moves() -> None:
    trio = mc405(FAST, "FWD_IN=3", "ERRORMASK=16")
    trio.world_view().set_limits("0", plus=500)
    trio.send("MOVE(1000): MOVE(-2000): MOVE(-3000)")
    assert trio.run_until_idle()
    assert dpos(trio) == 500.0


# ---- drive enables --------------------------------------------------------------------------
def test_a_servo_axis_moves_only_with_servo_and_wdog_on() -> None:
    trio = mc405("BASE(2)", FAST, "ATYPE=77")
    assert trio.send("MOVE(100)") == ["! Axis not enabled"]
    trio.send("SERVO=ON")
    assert trio.send("MOVE(100)") == ["! Axis not enabled"]
    assert trio.query("?DRIVE_STATUS") == str(0x50 | 0x400)
    trio.send("WDOG=ON")
    assert trio.query("?DRIVE_STATUS") == str(0x37 | 0x400)
    trio.send("MOVE(10000)")
    assert trio.query("?DRIVE_STATUS") == str(0x37)
    at(trio, 1000)
    here = dpos(trio, 2)
    trio.send("WDOG=OFF")  # the drive goes off under the move: it stops at once
    assert trio.machine.axis_idle(2) and dpos(trio, 2) == here
    trio.advance(ticks=100)
    assert dpos(trio, 2) == here


def test_a_stepper_runs_without_wdog_and_stops_on_axis_enable_off() -> None:
    trio = mc405(FAST)
    assert trio.query("?WDOG") == "0" and trio.query("?AXIS_ENABLE") == "1"
    trio.send("MOVE(100)")
    assert trio.run_until_idle() and dpos(trio) == 100.0
    trio.send("AXIS_ENABLE=OFF")
    assert trio.send("MOVE(100)") == ["! Axis not enabled"]
    assert trio.query("?DRIVE_STATUS") == str(0x50 | 0x400)


def test_following_error_is_zero_and_mpos_follows_dpos() -> None:
    trio = mc405(FAST, "FE_LIMIT=0: FE_RANGE=0")
    trio.send("MOVE(1000)")
    trio.advance(ticks=300)
    assert trio.query("?FE") == "0" and trio.query("?MPOS") == trio.query("?DPOS") == "295"
    assert trio.query("?AXISSTATUS") == "0" and trio.query("?MOTION_ERROR") == "0"


def test_motion_error_and_error_axis_are_read_only() -> None:
    trio = mc405()
    assert trio.send("MOTION_ERROR=1") == ["! Parameter is read only"]
    assert trio.send("ERROR_AXIS=1") == ["! Parameter is read only"]
    assert trio.send("AXISSTATUS=1") == ["! Parameter is read only"]
    assert trio.send("ERRORMASK=-1") == ["! Parameter out of range"]


# ---- Z-mark datums -----------------------------------------------------------------------
def test_datum_1_finds_the_z_mark_forward_at_creep_and_zeroes_there() -> None:
    trio = mc405("CREEP=100: ACCEL=10000: DECEL=100000")
    trio.world_view().set_index("0", 4000, 4, 1280)
    host = trio.open_session()  # a second host: its prompt waits while the search runs
    host.feed(b"DATUM(1)\r\n")
    at(trio, 500)
    assert trio.query("?AXISSTATUS") == "64"  # datuming
    # CREEP 100 reached in 10 cycles (0.5 count); count 1280 on tick 10 + 1279.5 x 10
    at(trio, 12804)
    assert dpos(trio) == 1279.9
    at(trio, 12805)
    assert dpos(trio) == 0.0  # the mark's first count is 0
    assert trio.run_until_idle()
    assert (trio.machine.tick, dpos(trio), trio.query("?AXISSTATUS")) == (12806, 0.0, "0")
    assert trio.world_view().reading("0").position == 1280


def test_datum_2_finds_the_mark_reverse_from_its_last_count() -> None:
    trio = mc405("CREEP=100: ACCEL=10000: DECEL=100000")
    trio.world_view().set_index("0", 4000, 4, 1280)
    trio.send("DEFPOS(50)")
    trio.console().session.feed(b"DATUM(2)\r\n")
    assert trio.run_until_idle()
    # the mark behind 0 covers -2720..-2717: its last count is met first
    assert trio.world_view().reading("0").position == -2717
    assert dpos(trio) == 0.0


def test_datum_0_without_an_error_and_bad_datum_modes() -> None:
    trio = mc405()
    assert trio.send("DATUM(0)") == []
    assert trio.send("DATUM(7)") == []  # one axis's errors (DATUM page)
    assert trio.send("DATUM(8)") == ["! Parameter out of range"]
    assert trio.send("CREEP=0: DATUM(1)") == ["! Parameter out of range"]


# ---- servo axes: the shared servo loop on the world's motor ---------------------------------
SERVO = ("BASE(0): ATYPE=77: P_GAIN=10: D_GAIN=160: SERVO=ON: WDOG=ON: SPEED=4000: "
         "ACCEL=40000: DECEL=40000")


def fe_counts(trio: MC405) -> float:
    return round(float(trio.query("?FE")), 6)


def test_factory_gains_keep_a_servo_axis_profile_only_and_exact() -> None:
    trio = mc405(SERVO, "P_GAIN=0")
    trio.send("MOVE(8000)")
    at(trio, 1000)
    assert trio.machine.axes[0].servo is None
    assert (fe_counts(trio), trio.query("?MPOS")) == (0.0, trio.query("?DPOS"))
    assert trio.run_until_idle() and dpos(trio) == 8000.0


def test_a_servo_axis_lags_its_demand_and_mpos_reads_its_encoder() -> None:
    trio = mc405(SERVO)
    trio.send("MOVE(8000)")
    at(trio, 1000)
    lag = fe_counts(trio)
    assert lag > 0  # at 4000 counts/s a P+D loop lags by a steady error ...
    at(trio, 1500)
    assert fe_counts(trio) == lag  # ... the same all along the cruise
    assert float(trio.query("?MPOS")) == dpos(trio) - lag
    encoder = trio.machine.axes[0].servo.encoder_counts()  # type: ignore[union-attr]
    assert float(trio.query("?MPOS")) == encoder  # (no DEFPOS: counts)
    assert trio.run_until_idle()
    trio.advance(1.0)
    assert dpos(trio) == 8000.0 and abs(fe_counts(trio)) < 20  # settled, friction left
    assert trio.query("?AXISSTATUS") == "0"


def test_fe_range_sets_the_warning_bit() -> None:
    trio = mc405(SERVO, "FE_RANGE=10")
    trio.send("MOVE(8000)")
    at(trio, 1000)
    assert trio.query("?AXISSTATUS") == "2" and trio.query("?MOTION_ERROR") == "0"


def _servo_run(mask: int) -> MC405:
    trio = mc405(SERVO, f"FE_LIMIT=30: ERRORMASK={mask}")
    trio.send("MOVE(8000)")
    return trio


def test_fe_limit_raises_the_motion_error_on_the_cycle_it_is_passed_whatever_the_slicing() -> None:
    watch = _servo_run(0)  # no error raised: find the first cycle |FE| > 30 by reading
    first = None
    while first is None:
        watch.advance(ticks=1)
        if abs(fe_counts(watch)) > 30:
            first = watch.machine.tick
    assert first == 81 and watch.query("?AXISSTATUS") == "256"
    stepped = _servo_run(268)
    while stepped.query("?MOTION_ERROR") == "0":
        stepped.advance(ticks=1)
    assert stepped.machine.tick == first
    at(stepped, 400)
    whole = _servo_run(268)
    whole.advance(ticks=400)  # one stretch: the error is found inside it
    for trio in (stepped, whole):
        assert [trio.query(q) for q in ("?MOTION_ERROR", "?ERROR_AXIS", "?WDOG",
                                        "?AXISSTATUS")] == ["1", "0", "0", "256"]
        assert trio.machine.axis_idle(0)
    assert dpos(stepped) == dpos(whole) == 128.0  # the demand stopped on that cycle
    assert stepped.query("?MPOS") == whole.query("?MPOS")


def test_after_an_error_the_loop_closes_again_on_the_encoder() -> None:
    trio = _servo_run(268)
    trio.advance(ticks=400)
    assert trio.send("MOVE(10)") == ["! Axis in error"]
    trio.send("DATUM(0)")
    assert trio.send("MOVE(10)") == ["! Axis not enabled"]  # WDOG is still OFF
    trio.advance(0.5)  # the motor coasts to a stop with its drive off
    mpos = trio.query("?MPOS")
    trio.send("WDOG=ON")
    assert trio.query("?DPOS") == mpos and fe_counts(trio) == 0.0
    trio.send("FE_LIMIT=2000: MOVEABS(0)")
    assert trio.run_until_idle()
    trio.advance(1.0)
    assert dpos(trio) == 0.0 and abs(fe_counts(trio)) < 20


def test_a_cancelled_z_search_is_forgotten() -> None:
    trio = mc405("CREEP=100: ACCEL=10000: DECEL=100000")
    host = trio.open_session()
    host.feed(b"DATUM(1)\r\n")
    at(trio, 500)
    assert trio.query("?AXISSTATUS") == "64"
    trio.send("CANCEL")
    assert trio.query("?AXISSTATUS") == "0"
    assert trio.run_until_idle()
    start = dpos(trio)
    trio.send("SPEED=1000: MOVE(3000)")  # over the mark at 1280: no zero there now
    assert trio.run_until_idle() and dpos(trio) == start + 3000


def test_a_restart_clears_the_motion_errors() -> None:
    trio = mc405(FAST, "FWD_IN=3", "ERRORMASK=16")
    trio.world_view().set_limits("0", plus=100)
    trio.send("MOVE(1000)")
    assert trio.run_until_idle() and trio.query("?MOTION_ERROR") == "1"
    trio.reset()
    assert [trio.query(q) for q in ("?MOTION_ERROR", "?ERROR_AXIS", "?ERRORMASK")] == \
        ["0", "0", "268"]


@settings(max_examples=20, deadline=None)
@given(speed=st.integers(50, 5000), accel=st.integers(1000, 200000),
       switch=st.integers(1, 2999))
def test_the_limit_acts_on_the_first_servo_tick_the_free_move_stands_on_the_switch(
        speed: int, accel: int, switch: int) -> None:
    setup = f"SPEED={speed}: ACCEL={accel}: DECEL={accel}"
    free = mc405(setup)
    free.send("MOVE(3000)")
    end = free.machine.axes[0].motion_end
    assert end is not None
    ticks = np.arange(0, end + 1)
    whole = np.floor(free.machine.demand_counts(0, ticks))  # the whole steps made
    reached = int(np.argmax(whole >= switch))  # the first tick on the switch
    limited = mc405(setup, "FWD_IN=3")
    limited.world_view().set_limits("0", plus=switch)
    limited.send("MOVE(3000)")
    at(limited, reached)
    at(free, reached)
    assert limited.machine.demand(0) == free.machine.demand(0)
    assert limited.query("?AXISSTATUS") == "16"
    assert limited.run_until_idle()
    stop = limited.machine.demand(0)
    speed_then = free.machine.vp_speed(0)  # the ramp down starts from here, at DECEL
    assert stop >= switch
    assert abs(stop - (free.machine.demand(0) + speed_then ** 2 / (2 * accel))) <= 1.0
    assert limited.machine.tick == reached + math.ceil(speed_then / accel * 1000 - 1e-9)


def test_a_switch_stuck_active_stops_the_axis_now_and_refuses_moves_into_it() -> None:
    trio = mc405(FAST, "FWD_IN=3")
    trio.send("FORWARD")
    at(trio, 1000)
    trio.world_view().fault("0", "plus", "active")
    assert trio.run_until_idle()
    assert (trio.machine.tick, dpos(trio), trio.query("?AXISSTATUS")) == (1100, 1045.0, "16")
    trio.send("MOVE(10)")
    assert trio.run_until_idle() and dpos(trio) == 1045.0
    trio.send("MOVE(-45)")
    assert trio.run_until_idle() and dpos(trio) == 1000.0


def test_a_movecirc_reaching_a_soft_limit_stops_the_arc() -> None:
    trio = mc405("BASE(0,1)", FAST, "FS_LIMIT AXIS(0)=1500")
    trio.send("MOVECIRC(0,0,1000,0,1)")  # a whole circle through x = 2000
    assert trio.run_until_idle()
    x, y = dpos(trio, 0), dpos(trio, 1)
    # x passes 1500 at y = 866 going clockwise; 10 cycles at ACCEL take the path 5 further
    assert (x, y) == (1505.0, 863.0) and trio.query("?AXISSTATUS AXIS(0)") == "512"
    assert abs((x - 1000) ** 2 + y ** 2 - 1000 ** 2) < 2 * 1000  # still on the circle
    free = mc405("BASE(0,1)", FAST)
    free.send("MOVECIRC(0,0,1000,0,1)")
    assert free.run_until_idle() and (dpos(free, 0), dpos(free, 1)) == (0.0, 0.0)
