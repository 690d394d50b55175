"""Every axis type as the ATYPE help page wires it (maxk/personalities/trio/axistypes.py).

ATYPE 44 is the MC405 flexible axis's analogue servo: a program setting it, gains, WDOG
and SERVO ON and a MOVE must run the same servo loop as 36 and 77, tick for tick. The
first cycles are worked out by hand: ACCEL 100000 counts/s^2 at 1 ms a cycle puts the
demand at 0.05 n^2 counts on cycle n; the loop's output on cycle n is P_GAIN times the
error of cycle n-1 (one cycle of computation), on the shared 16-bit output 16 x DAC_OUT;
while that output is below the world motor's Coulomb friction (0.005 N m over
0.1 x 3 / 2 x 10 / 32767 N m a count: about 109 shared counts) the motor does not turn,
so MPOS stays 0 and FE = DPOS.
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405
from tests.trio_helpers import at, mc405

SERVO_TYPES = (36, 44, 46, 47, 48, 60, 77, 92, 94, 102, 103)
TORQUE_PER_COUNT = 0.1 * 3.0 / 2.0 * 10.0 / 32767.0
FRICTION = 0.005 / TORQUE_PER_COUNT  # shared output counts the motor's friction holds


def program(atype: int, move: str = "MOVE(8000)") -> str:
    return (f"BASE(0)\nATYPE = {atype}\nP_GAIN = 10\nD_GAIN = 160\nVFF_GAIN = 5\n"
            "SPEED = 4000\nACCEL = 40000\nDECEL = 40000\nFE_LIMIT = 2000\n"
            f"WDOG = ON\nSERVO = ON\n{move}\nWAIT IDLE\n")


def run(atype: int, move: str = "MOVE(8000)") -> MC405:
    trio = MC405()
    trio.load("SERVOTEST", program(atype, move))
    assert trio.send('RUN "SERVOTEST"') == []
    return trio


READS = ("?DPOS", "?MPOS", "?FE", "?DAC_OUT", "?AXISSTATUS", "?ENCODER")
TICKS = (1, 2, 3, 5, 10, 40, 100, 101, 250, 1000, 2100, 2200, 2500, 4000)


def trace(trio: MC405) -> list[list[str]]:
    rows = []
    for tick in TICKS:
        at(trio, tick)
        rows.append([trio.query(q) for q in READS])
    return rows


def test_a_program_on_atype_44_runs_the_loop_of_atype_36_tick_for_tick() -> None:
    reference = trace(run(36))
    servo = trace(run(44))
    assert servo == reference
    at_cruise = servo[TICKS.index(1000)]
    assert float(at_cruise[2]) != 0.0  # a real loop: the motor lags its demand ...
    assert float(at_cruise[1]) == float(at_cruise[0]) - float(at_cruise[2])
    assert at_cruise[3] != "0"  # ... driven by an output
    assert float(servo[-1][0]) == 8000.0 and abs(float(servo[-1][2])) < 20  # settled


def test_the_first_cycles_of_an_atype_44_move_worked_out_by_hand() -> None:
    trio = mc405("ATYPE=44: P_GAIN=2: SPEED=1000: ACCEL=100000: DECEL=100000",
                 "WDOG=ON: SERVO=ON", "MOVE(100)")
    for n in range(1, 6):
        at(trio, n)
        demand = 0.05 * n * n
        output = 2.0 * 0.05 * (n - 1) ** 2  # shared counts: P_GAIN x last cycle's error
        assert output < FRICTION  # (the motor stands: MPOS 0, FE = DPOS)
        assert trio.query("?DPOS") == f"{demand:.4f}"
        assert trio.query("?FE") == f"{demand:.4f}"
        assert trio.query("?MPOS") == "0"
        assert float(trio.query("?DAC_OUT")) == pytest.approx(output / 16.0, abs=1e-4)
        exact = trio.machine.drive.following.dac_out(0)  # (DAC_OUT before printing)
        assert exact == pytest.approx(output / 16.0, rel=1e-9, abs=1e-12)
    assert trio.machine.axes[0].servo is not None


@pytest.mark.parametrize("atype", [t for t in SERVO_TYPES if t not in (36, 44)])
def test_every_servo_type_runs_the_same_loop(atype: int) -> None:
    reference = run(36)
    servo = run(atype)
    for tick in (100, 1000, 2200):
        at(reference, tick)
        at(servo, tick)
        for q in ("?DPOS", "?MPOS", "?FE", "?DAC_OUT"):
            assert servo.query(q) == reference.query(q), (atype, tick, q)
    assert float(servo.query("?FE")) != 0.0


def test_fe_limit_raises_the_motion_error_on_atype_44_on_the_cycle_of_atype_77() -> None:
    ticks = []
    for atype in (77, 44):
        trio = mc405(f"ATYPE={atype}: P_GAIN=10: D_GAIN=160: SERVO=ON: WDOG=ON",
                     "SPEED=4000: ACCEL=40000: DECEL=40000: FE_LIMIT=30")
        trio.send("MOVE(8000)")
        while trio.query("?MOTION_ERROR") == "0" and trio.machine.tick < 1000:
            trio.advance(ticks=1)
        ticks.append(trio.machine.tick)
        assert [trio.query(q) for q in ("?MOTION_ERROR", "?ERROR_AXIS", "?WDOG",
                                        "?AXISSTATUS")] == ["1", "0", "0", "256"]
        assert abs(float(trio.query("?FE_LATCH"))) > 30
    assert ticks[0] == ticks[1] < 1000


def test_atype_44_needs_wdog_and_servo_on_and_puts_out_dac_open_loop() -> None:
    trio = mc405("ATYPE=44: P_GAIN=10: REP_DIST=1e9")  # (MPOS unwrapped)
    assert trio.send("MOVE(10)") == ["! Axis not enabled"]  # WDOG and SERVO OFF
    trio.send("WDOG=ON")
    assert trio.send("MOVE(10)") == ["! Axis not enabled"]  # SERVO still OFF
    trio.send("DAC=1024")  # SERVO OFF, WDOG ON: the open-loop output (help DAC)
    assert trio.query("?DAC_OUT") == "1024"
    at(trio, 500)
    start = float(trio.query("?MPOS"))
    at(trio, 1500)  # the motor's steady speed under +5 V, as test_trio_servo_output works
    # it out: g (u - f) / a counts/s
    g = TORQUE_PER_COUNT / 5e-6 * 8000.0 / (2.0 * 3.141592653589793)
    a = (2e-5 + 0.1 ** 2 / 2.0) / 5e-6
    assert abs(float(trio.query("?MPOS")) - start - g * (1024 * 16.0 - FRICTION) / a) <= 1.0


def test_an_absolute_servo_s_encoder_holds_its_data_bits_and_mpos_does_not_wrap() -> None:
    trio = run(48, "ENCODER_BITS = 12\nMOVE(8000)")  # SSI, 12 data bits
    at(trio, 4000)
    assert trio.query("?DPOS") == "8000"
    mpos = float(trio.query("?MPOS"))
    assert abs(mpos - 8000) < 20  # MPOS: the encoder's count, no DATUM needed
    assert trio.query("?ENCODER") == f"{int(mpos) % 4096}"
    trio.send("MOVEABS(-100)")
    assert trio.run_until_idle()
    trio.advance(1.0)
    mpos = float(trio.query("?MPOS"))
    assert abs(mpos + 100) < 20
    assert trio.query("?ENCODER") == f"{int(mpos) % 4096}"  # (4096 - about 100)


def test_an_endat_servo_s_total_bits_and_a_binary_ssi_flag_are_read_as_the_page_gives() -> None:
    endat = run(47, "ENCODER_BITS = 25 + 256 * 12\nMOVE(8000)")  # the page's 25-bit EnDat
    ssi = run(48, "ENCODER_BITS = 64 + 10\nMOVE(8000)")  # binary (bit 6), 10 bits
    incremental = run(44)
    for trio in (endat, ssi, incremental):
        at(trio, 4000)
    counts = int(float(incremental.query("?MPOS")))
    assert endat.query("?MPOS") == ssi.query("?MPOS") == incremental.query("?MPOS")
    assert endat.query("?ENCODER") == str(counts)  # 25 bits hold it whole
    assert ssi.query("?ENCODER") == str(counts % 1024)


def test_an_absolute_servo_without_encoder_bits_reads_its_whole_count() -> None:
    trio = run(48)  # ENCODER_BITS 0: the register as an incremental one's (D)
    at(trio, 4000)
    assert trio.query("?ENCODER") == str(int(float(trio.query("?MPOS"))))


def test_an_encoder_output_axis_puts_its_demand_out_for_an_encoder_input_to_read() -> None:
    trio = mc405("ATYPE AXIS(4) = 45: SPEED AXIS(4) = 4000: ACCEL AXIS(4) = 40000",
                 "DECEL AXIS(4) = 40000: P_GAIN AXIS(4) = 10", "ATYPE AXIS(0) = 76")
    trio.world_view().set_shaft_encoder("0", "4")
    trio.send("MOVE(1234) AXIS(4)")
    at(trio, 200)  # mid-move: 4000 counts/s reached in 100 cycles (200 counts), then
    # 100 cycles more at 4 counts a cycle: 600 counts, exact
    assert trio.query("?DPOS AXIS(4)") == "600"
    assert trio.query("?MPOS AXIS(0)") == "600"
    assert trio.query("?FE AXIS(4)") == "0"  # no loop: an output type follows its demand
    assert trio.machine.axes[4].servo is None
    assert trio.run_until_idle()
    assert trio.query("?MPOS AXIS(0)") == "1234"


@pytest.mark.parametrize("atype", [0, 43, 45, 63, 78, 84])
def test_types_without_a_loop_follow_their_demand_exactly(atype: int) -> None:
    trio = mc405(f"ATYPE={atype}: P_GAIN=10: SPEED=4000: ACCEL=40000: DECEL=40000",
                 "MOVE(1234)")
    at(trio, 200)
    assert (trio.query("?DPOS"), trio.query("?MPOS"), trio.query("?FE")) == \
        ("600", "600", "0")


@pytest.mark.parametrize("value", ["1", "2", "99", "106", "255", "44.5", "-1"])
def test_a_type_the_page_does_not_list_is_refused_and_the_type_kept(value: str) -> None:
    trio = mc405("ATYPE=44")
    assert trio.send(f"ATYPE={value}") == ["! Parameter out of range"]
    assert trio.query("?ATYPE") == "44"


def test_atype_44_set_in_mc_config_style_with_the_axis_modifier() -> None:
    trio = mc405("ATYPE AXIS(2) = 44", "ATYPE AXIS(3) = 48")  # the page's example 3
    assert (trio.query("?ATYPE AXIS(2)"), trio.query("?ATYPE AXIS(3)")) == ("44", "48")
    trio.send("BASE(2): P_GAIN=10: WDOG=ON: SERVO=ON")
    assert trio.machine.axes[2].servo is not None
    assert trio.machine.axes[3].servo is None  # (its P_GAIN is 0: profile-only)


def test_a_servo_axis_s_motor_follows_what_addax_superimposes_as_its_own_move() -> None:
    """ADDAX puts axis 5's move on axis 0's demand: the servo's motor follows DPOS, as a
    stepper's does, and lags it as if the move were axis 0's own (the same loop, the
    same demand; equal to within the rounding of the superimposed sum)."""
    added = mc405("BASE(0): ATYPE=44: P_GAIN=10: D_GAIN=160: SERVO=ON: WDOG=ON",
                  "REP_DIST=1e9: ADDAX(5)", "BASE(5): SPEED=4000: ACCEL=40000",
                  "DECEL=40000", "MOVE(8000) AXIS(5)")
    own = mc405("BASE(0): ATYPE=44: P_GAIN=10: D_GAIN=160: SERVO=ON: WDOG=ON",
                "REP_DIST=1e9: SPEED=4000: ACCEL=40000: DECEL=40000", "MOVE(8000)")
    for tick in (10, 100, 1000, 2200, 4000):
        at(added, tick)
        at(own, tick)
        for q in ("?DPOS", "?MPOS", "?FE"):
            assert added.query(q + " AXIS(0)") == own.query(q), (tick, q)
        a, b = added.machine.axes[0].servo, own.machine.axes[0].servo
        assert a is not None and b is not None
        assert abs(a.p - b.p) < 1e-6
    assert added.query("?DPOS AXIS(0)") == "8000"
    assert abs(float(added.query("?FE AXIS(0)"))) < 20  # (settled: the motor moved)
    added.send("ADDAX(-1) AXIS(0)")  # what ADDAX added stays on the demand (links.py):
    at(added, 5000)  # the motor stays there too
    assert added.query("?DPOS AXIS(0)") == "8000"
    assert abs(float(added.query("?FE AXIS(0)"))) < 20
