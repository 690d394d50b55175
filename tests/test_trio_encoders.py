"""ENCODER and ENCODER_RATIO (TrioBASIC help ENCODER, ENCODER_RATIO) on the MC405: the
raw feedback register and the scaling of an encoder input's MPOS."""

from __future__ import annotations

from maxk.controllers.trio import MC405
from tests.trio_helpers import mc405


def encoder_stage(counts_per_step: float = 1.0) -> MC405:
    """A stepper on axis 4 whose shaft encoder feeds axis 0's encoder input (ATYPE 76)."""
    trio = mc405("ATYPE AXIS(0) = 76", "ATYPE AXIS(4) = 43", "SPEED AXIS(4) = 4000",
                 "ACCEL AXIS(4) = 40000", "DECEL AXIS(4) = 40000")
    trio.world_view().set_shaft_encoder("0", "4", counts_per_step)
    return trio


def test_encoder_reads_the_raw_count_whatever_defpos_and_units() -> None:
    trio = encoder_stage(2.0)  # two encoder counts a step
    trio.send("MOVE(1000) AXIS(4)")
    assert trio.run_until_idle()
    assert trio.query("?ENCODER AXIS(0)") == "2000"
    trio.send("UNITS AXIS(0) = 4: DEFPOS(100) AXIS(0)")
    assert (trio.query("?MPOS AXIS(0)"), trio.query("?ENCODER AXIS(0)")) == ("100", "2000")


def test_encoder_ratio_scales_the_encoder_input_as_the_page_s_rotary_table() -> None:
    """Page example 1: 8192 counts a turn scaled to 7200, UNITS 20: degrees."""
    trio = encoder_stage(8192 / 3200)  # the stepper makes 3200 steps a turn
    trio.send("BASE(0): ENCODER_RATIO(7200,8192): UNITS=20")
    trio.send("MOVE(1600) AXIS(4)")  # half a turn: 4096 encoder counts
    assert trio.run_until_idle()
    # 4096 x 7200 / 8192 = 3600 MPOS counts = 180 degrees at 20 counts a degree
    assert (trio.query("?ENCODER AXIS(0)"), trio.query("?MPOS AXIS(0)")) == ("4096", "180")


def test_a_negative_ratio_reverses_the_axis_and_mpos_keeps_its_value_at_the_change() -> None:
    trio = encoder_stage()
    trio.send("MOVE(500) AXIS(4)")
    assert trio.run_until_idle()
    trio.send("ENCODER_RATIO(-1,1) AXIS(0)")
    assert trio.query("?MPOS AXIS(0)") == "500"
    trio.send("MOVE(200) AXIS(4)")
    assert trio.run_until_idle()
    assert (trio.query("?MPOS AXIS(0)"), trio.query("?ENCODER AXIS(0)")) == ("300", "700")
    trio.send("ENCODER_RATIO AXIS(0)")  # back to 1:1 (MPOS kept)
    trio.send("MOVE(-100) AXIS(4)")
    assert trio.run_until_idle()
    assert trio.query("?MPOS AXIS(0)") == "200"


def test_bad_ratios_are_refused_and_leave_the_ratio() -> None:
    trio = encoder_stage()
    trio.send("ENCODER_RATIO(2,1) AXIS(0)")
    for bad in ("ENCODER_RATIO(1,0)", "ENCODER_RATIO(0,1)", "ENCODER_RATIO(1.5,1)",
                "ENCODER_RATIO(1,-2)", "ENCODER_RATIO(16777216,1)"):
        assert trio.send(bad + " AXIS(0)") == ["! Parameter out of range"], bad
    assert trio.send("ENCODER_RATIO(3) AXIS(0)") == ["! Syntax error"]
    trio.send("MOVE(10) AXIS(4)")
    assert trio.run_until_idle()
    assert trio.query("?MPOS AXIS(0)") == "20"


def test_encoder_of_a_servo_axis_and_of_a_stepper() -> None:
    trio = mc405("ATYPE=77: WDOG=ON: SERVO=OFF: DAC=200")
    trio.advance(ticks=100)
    assert trio.query("?ENCODER") == trio.query("?MPOS")  # (UNITS 1, no offset)
    assert float(trio.query("?ENCODER")) > 0
    stepper = mc405("ATYPE AXIS(2)=43: UNITS AXIS(2)=10", "MOVE(12.34) AXIS(2)")
    assert stepper.run_until_idle()
    assert stepper.query("?ENCODER AXIS(2)") == "123"  # whole demand counts


def test_the_register_wraps_at_32_bits() -> None:
    trio = mc405("ATYPE AXIS(2)=43: SPEED AXIS(2)=1e9: ACCEL AXIS(2)=1e12: "
                 "DECEL AXIS(2)=1e12: REP_DIST AXIS(2)=1e12", "MOVE(2147483648) AXIS(2)")
    assert trio.run_until_idle()
    assert trio.query("?ENCODER AXIS(2)") == "-2147483648"
    assert trio.query("?DPOS AXIS(2)") == "2147483648"


def test_endat_register_access_fails_with_no_endat_encoder_and_sets_parameter_mode() -> None:
    trio = mc405("BASE(1)")
    assert trio.query("?ENCODER_CONTROL AXIS(1)") == "0"
    trio.load("ENDAT", "BASE(1)\nIF ENCODER_READ($A700) = -1 THEN VR(5) = 1\n"
              "ENCODER_CONTROL = 0\nIF NOT ENCODER_WRITE(3, 7) THEN VR(6) = 1\n")
    trio.send('RUN "ENDAT"')
    trio.advance(0.01)
    assert (trio.query("?VR(5)"), trio.query("?VR(6)")) == ("1.0000", "1.0000")
    assert trio.query("?ENCODER_CONTROL AXIS(1)") == "1"  # the write set it again
    assert trio.send("?ENCODER_READ(-1)") == ["! Parameter out of range"]
    assert trio.send("?ENCODER_READ(1,2)") == ["! Syntax error"]


def test_pp_step_multiplies_the_encoder_value_with_encoder_ratio_and_units() -> None:
    """PP_STEP (its page: an integer multiplier on the encoder value): 2 counts a step x
    PP_STEP 4 x ENCODER_RATIO 3/2 = 12 MPOS counts a step, UNITS 6: 2 units a step."""
    trio = encoder_stage(2.0)
    trio.send("BASE(0): PP_STEP=4: ENCODER_RATIO(3,2): UNITS=6")
    assert trio.query("?PP_STEP") == "4"
    trio.send("MOVE(250) AXIS(4)")
    assert trio.run_until_idle()
    # 250 steps x 2 = 500 encoder counts; x 4 x 3/2 = 3000 MPOS counts; / 6 = 500 units
    assert (trio.query("?ENCODER AXIS(0)"), trio.query("?MPOS AXIS(0)")) == ("500", "500")
    trio.send("PP_STEP AXIS(0) = -1")  # MPOS keeps its value; the axis now counts down
    trio.send("MOVE(100) AXIS(4)")
    assert trio.run_until_idle()
    # 200 more encoder counts x -1 x 3/2 = -300 MPOS counts = -50 units
    assert trio.query("?MPOS AXIS(0)") == "450"


def test_bad_pp_steps_are_refused_and_leave_it() -> None:
    trio = encoder_stage()
    trio.send("PP_STEP AXIS(0) = 3")
    for bad in ("0", "1.5", "1024", "-1025"):
        assert trio.send(f"PP_STEP AXIS(0) = {bad}") == ["! Parameter out of range"], bad
    assert trio.query("?PP_STEP AXIS(0)") == "3"
