"""ADD_DAC (TrioBASIC help ADD_DAC): a second servo axis's loop output added to a servo
axis's DAC, for dual feedback on one motor (maxk/personalities/trio/add_dac.py).

The page's set-up: the motor's axis (1) with P_GAIN 0 and ADD_DAC(2); the measuring
wheel's axis (2), a servo type with the gains, its demand made axis 1's by ADDAX(1).

What follows by arithmetic, not by running the code:
- A wheel that turns count for count with the motor reads what the motor's encoder
  reads, so axis 2's filter sees axis 1's error, and with axis 1's gains 0 the output
  is exactly the single loop's with axis 2's gains on axis 1 (0 + x = x in floating
  point): the same motor position and the same DAC_OUT on every cycle.
- A wheel that slips, making 0.99 counts a motor count: the loop closes on the wheel,
  so at rest the wheel's MPOS is at the demand within the loop's friction band, and the
  motor has turned 1 / 0.99 as far.
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405
from tests.trio_helpers import at, mc405

MOTOR = "BASE(1): ATYPE=44: SPEED=4000: ACCEL=40000: DECEL=40000: REP_DIST=1e9"
GAINS = "P_GAIN=10: D_GAIN=160: VFF_GAIN=5"
TICKS = (1, 2, 3, 10, 100, 101, 1000, 2100, 2200, 2300, 4000)


def page_setup(wheel: float | None = None) -> MC405:
    trio = MC405()
    trio.load("ROLLFEED", "BASE(1)\nATYPE = 44\nENCODER_RATIO(1,1)\nADD_DAC(2)\n"
                          "P_GAIN = 0\nSERVO = ON\nREP_DIST = 1e9\n"
                          "BASE(2)\nATYPE = 44\nADDAX(1)\n"
                          f"{GAINS.replace(': ', chr(10))}\nSERVO = ON\nREP_DIST = 1e9\n"
                          "WDOG = ON\nBASE(1)\nSPEED = 4000\nACCEL = 40000\nDECEL = 40000\n"
                          "MOVE(8000)\nWAIT IDLE\n")
    if wheel is not None:
        trio.world_view().set_shaft_encoder("2", "1", wheel)
    assert trio.send('RUN "ROLLFEED"') == []
    return trio


def motor_state(trio: MC405) -> tuple[float, float, float]:
    """Axis 1's motor position and speed (loop counts) and its output: full floats."""
    loop = trio.machine.axes[1].servo
    assert loop is not None
    return loop.p, loop.w, trio.machine.drive.following.dac_out(1)


def typed_setup() -> MC405:
    """The page's set-up typed at the command line (the move starts on tick 0)."""
    return mc405(MOTOR, "BASE(1): ENCODER_RATIO(1,1): ADD_DAC(2): P_GAIN=0: SERVO=ON",
                 f"BASE(2): ATYPE=44: ADDAX(1): {GAINS}: SERVO=ON: REP_DIST=1e9",
                 "WDOG=ON", "MOVE(8000) AXIS(1)")


def test_a_wheel_turning_with_the_motor_gives_the_single_loop_on_every_cycle() -> None:
    added = typed_setup()
    single = mc405(MOTOR, f"BASE(1): {GAINS}: SERVO=ON: WDOG=ON", "MOVE(8000) AXIS(1)")
    for tick in TICKS:
        at(added, tick)
        at(single, tick)
        assert motor_state(added) == motor_state(single), tick
        for q in ("?DPOS AXIS(1)", "?MPOS AXIS(1)", "?FE AXIS(1)", "?DAC_OUT AXIS(1)"):
            assert added.query(q) == single.query(q), (tick, q)
    assert float(added.query("?FE AXIS(1)")) != 0.0  # (a loop that really ran)
    # the wheel's axis reads the same encoder, and its own filter's output
    assert added.query("?MPOS AXIS(2)") == added.query("?MPOS AXIS(1)")
    assert added.query("?DPOS AXIS(2)") == "8000"
    assert added.query("?DAC_OUT AXIS(2)") == added.query("?DAC_OUT AXIS(1)")
    assert added.machine.axes[2].servo is not None  # (its own motor never turned:)
    assert added.machine.world.axes[2] is not None


def test_a_slipping_wheel_is_brought_to_the_demand_and_the_motor_turns_further() -> None:
    trio = page_setup(wheel=0.99)
    at(trio, 4000)
    wheel = float(trio.query("?MPOS AXIS(2)"))
    motor = float(trio.query("?MPOS AXIS(1)"))
    assert abs(wheel - 8000) < 20  # the loop closes on the wheel ...
    assert abs(motor - wheel / 0.99) <= 1.0  # ... the motor made up the slip
    assert motor > 8060
    assert trio.query("?FE AXIS(2)") == f"{8000 - wheel:g}"


def test_the_wheel_s_encoder_ratio_scales_its_counts_to_the_motor_s() -> None:
    """The page: a 4096-count wheel for a 10000-count motor turn, ENCODER_RATIO(10000,
    4096) on the wheel's axis so that both count alike."""
    plain = typed_setup()
    trio = MC405()
    trio.world_view().set_shaft_encoder("2", "1", 4096 / 10000)
    for line in ("BASE(2): ATYPE=44: ENCODER_RATIO(10000,4096)", MOTOR, "ADD_DAC(2)",
                 "P_GAIN=0: SERVO=ON", f"BASE(2): ADDAX(1): {GAINS}: SERVO=ON: "
                 "REP_DIST=1e9", "WDOG=ON", "MOVE(8000) AXIS(1)"):
        assert trio.send(line) == [], line
    at(trio, 4000)
    at(plain, 4000)
    assert abs(float(trio.query("?MPOS AXIS(1)")) - float(plain.query("?MPOS AXIS(1)"))) <= 1
    assert abs(float(trio.query("?MPOS AXIS(2)")) - 8000) < 20


def test_without_add_dac_the_motor_axis_with_p_gain_0_follows_its_demand() -> None:
    trio = mc405(MOTOR, "BASE(1): P_GAIN=0: SERVO=ON: WDOG=ON", "MOVE(500) AXIS(1)")
    at(trio, 100)
    assert trio.machine.axes[1].servo is None  # (profile-only: no loop)
    assert trio.query("?FE AXIS(1)") == "0"


def test_add_dac_minus_1_ends_it_and_the_base_output_is_its_own_again() -> None:
    trio = typed_setup()
    at(trio, 4000)
    assert trio.machine.axes[1].servo is not None
    assert trio.machine.axes[1].servo.added is not None
    mpos = trio.query("?MPOS AXIS(1)")
    trio.send("ADD_DAC(-1) AXIS(1)")
    loop = trio.machine.axes[1].servo
    assert loop is not None and loop.added is None  # (the base keeps its loop, D)
    assert trio.machine.drive.following.filters == {}
    at(trio, 4100)  # P_GAIN 0: no output, the motor stands where the wheel's loop left it
    assert (trio.query("?DAC_OUT AXIS(1)"), trio.query("?MPOS AXIS(1)")) == ("0", mpos)
    trio.send("D_GAIN AXIS(1) = 160: P_GAIN AXIS(1) = 10")  # its own loop takes over
    at(trio, 6000)
    assert abs(float(trio.query("?FE AXIS(1)"))) < 20


def test_the_added_output_stops_with_the_added_axis_s_drive() -> None:
    trio = mc405(MOTOR, "BASE(1): ADD_DAC(2): P_GAIN=0: SERVO=ON",
                 f"BASE(2): ATYPE=44: {GAINS}: SERVO=OFF", "WDOG=ON", "DEFPOS(0) AXIS(2)")
    trio.send("BASE(2): SERVO=ON")
    trio.send("MOVE(100) AXIS(2)")  # the wheel's own demand: the motor turns for it
    at(trio, 600)
    assert abs(float(trio.query("?MPOS AXIS(1)")) - 100) < 20
    trio.send("SERVO AXIS(2) = OFF")  # (its demand stands: its loop adds 0)
    at(trio, 602)
    assert trio.machine.drive.following.filters[1].u == 0.0
    assert trio.query("?DAC_OUT AXIS(1)") == "0"


@pytest.mark.parametrize("arg", ["1", "16", "-2", "0.5"])
def test_a_bad_axis_is_refused_and_nothing_changes(arg: str) -> None:
    trio = mc405(MOTOR)
    assert trio.send(f"ADD_DAC({arg}) AXIS(1)") == ["! Parameter out of range"]
    assert trio.machine.drive.following.adds == {}


def test_a_chain_is_refused_and_a_second_base_takes_the_added_axis() -> None:
    trio = mc405(MOTOR, "ADD_DAC(2) AXIS(1)")
    assert trio.send("ADD_DAC(3) AXIS(2)") == ["! Parameter out of range"]
    assert trio.send("ADD_DAC(1) AXIS(0)") == ["! Parameter out of range"]
    assert trio.send("ADD_DAC(2) AXIS(3)") == []
    assert trio.machine.drive.following.adds == {3: 2}


def test_fe_limit_on_the_base_axis_stops_on_the_single_loop_s_cycle_whatever_the_slicing(
) -> None:
    def limited(added: bool) -> MC405:
        setup = ("BASE(1): ADD_DAC(2): P_GAIN=0: SERVO=ON",
                 f"BASE(2): ATYPE=44: ADDAX(1): {GAINS}: SERVO=ON: REP_DIST=1e9") if added \
            else (f"BASE(1): {GAINS}: SERVO=ON",)
        return mc405(MOTOR, *setup, "FE_LIMIT AXIS(1) = 30: WDOG=ON", "MOVE(8000) AXIS(1)")

    ticks = []
    for trio in (limited(False), limited(True)):
        while trio.query("?MOTION_ERROR") == "0" and trio.machine.tick < 1000:
            trio.advance(ticks=1)
        ticks.append(trio.machine.tick)
    whole = limited(True)
    whole.advance(ticks=1000)  # one stretch: the loops go back to the error's cycle
    stepped = limited(True)
    while stepped.query("?MOTION_ERROR") == "0":
        stepped.advance(ticks=1)
    at(stepped, 1000)
    assert ticks[0] == ticks[1] < 1000
    for trio in (whole, stepped):
        assert [trio.query(q) for q in ("?MOTION_ERROR", "?ERROR_AXIS", "?WDOG")] == \
            ["2", "1", "0"]
    assert whole.query("?DPOS AXIS(1)") == stepped.query("?DPOS AXIS(1)")
    assert motor_state(whole) == motor_state(stepped)


def test_the_base_with_servo_off_puts_out_its_dac_plus_the_added_loop_tj1_example_2(
) -> None:
    """The TJ1 manual's second example: axis 0's own loop off (SERVO OFF, S_REF 0), the
    motor under axis 1's loop alone, the moves run on axis 1."""
    trio = mc405("BASE(0): ATYPE=44: REP_DIST=1e9", "OUTLIMIT AXIS(1) = 2047",
                 "ADD_DAC(1) AXIS(0)", "ADDAX(0) AXIS(1)", "WDOG = ON", "SERVO = OFF",
                 "S_REF = 0", f"BASE(1): ATYPE=44: {GAINS}: REP_DIST=1e9",
                 "SPEED=4000: ACCEL=40000: DECEL=40000", "SERVO = ON", "MOVE(8000)")
    single = mc405("BASE(0): ATYPE=44: REP_DIST=1e9", f"{GAINS}: SPEED=4000",
                   "ACCEL=40000: DECEL=40000: SERVO=ON: WDOG=ON", "MOVE(8000)")
    for tick in TICKS:
        at(trio, tick)
        at(single, tick)
        loop = trio.machine.axes[0].servo
        alone = single.machine.axes[0].servo
        assert loop is not None and alone is not None
        assert (loop.p, loop.w) == (alone.p, alone.w), tick
        assert trio.query("?DAC_OUT AXIS(1)") == single.query("?DAC_OUT AXIS(0)")
        assert trio.query("?MPOS AXIS(1)") == single.query("?MPOS AXIS(0)")
    assert trio.query("?DPOS AXIS(0)") == trio.query("?MPOS AXIS(0)")  # (SERVO OFF)
    trio.send("S_REF AXIS(0) = 100")  # its DAC is added to the loop's output: the
    at(trio, 4001)  # motor is pushed off, the loop of axis 1 holds it against the push
    assert float(trio.query("?DAC_OUT AXIS(0)")) == pytest.approx(
        100 + float(trio.query("?DAC_OUT AXIS(1)")), abs=1e-3)


def test_the_added_axis_s_fe_limit_acts_on_the_single_loop_s_cycle_whatever_the_slicing(
) -> None:
    """A 1:1 wheel: the wheel axis's error is the single loop's, so its FE_LIMIT is
    passed on the cycle the single loop's is (both read with 30 counts)."""
    def limited() -> MC405:
        return mc405(MOTOR, "BASE(1): ADD_DAC(2): P_GAIN=0: SERVO=ON",
                     f"BASE(2): ATYPE=44: ADDAX(1): {GAINS}: SERVO=ON: REP_DIST=1e9",
                     "FE_LIMIT AXIS(2) = 30: WDOG=ON", "MOVE(8000) AXIS(1)")

    single = mc405(MOTOR, f"BASE(1): {GAINS}: SERVO=ON", "FE_LIMIT AXIS(1) = 30: WDOG=ON",
                   "MOVE(8000) AXIS(1)")
    while single.query("?MOTION_ERROR") == "0" and single.machine.tick < 1000:
        single.advance(ticks=1)
    stepped = limited()
    while stepped.query("?MOTION_ERROR") == "0" and stepped.machine.tick < 1000:
        stepped.advance(ticks=1)
    assert stepped.machine.tick == single.machine.tick < 1000
    whole = limited()
    whole.advance(ticks=1000)
    at(stepped, 1000)
    for trio in (whole, stepped):
        assert [trio.query(q) for q in ("?MOTION_ERROR", "?ERROR_AXIS", "?WDOG")] == \
            ["4", "2", "0"]
        assert int(trio.query("?AXISSTATUS AXIS(2)")) & 256
    assert whole.query("?FE_LATCH AXIS(2)") == stepped.query("?FE_LATCH AXIS(2)") == \
        single.query("?FE_LATCH AXIS(1)")
    assert whole.query("?DPOS AXIS(1)") == stepped.query("?DPOS AXIS(1)")
    assert motor_state(whole) == motor_state(stepped)
