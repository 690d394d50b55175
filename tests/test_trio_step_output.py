"""A stepper's output stage on the MC405: STEP_RATIO and BACKLASH (TrioBASIC help
STEP_RATIO, BACKLASH, BACKLASH_DIST), seen by the world's motor through an encoder the
world mounts on its shaft (one count a step) and by its limit switches.

Figures by hand. FAST moves: SPEED 1000 counts/s reached at ACCEL 100000 in 10 servo
cycles (5 counts), so a move from rest passes count p (p >= 5) on tick 5 + p; DECEL 10000
stops it from 1000 counts/s in 100 cycles over 50 counts. The backlash moves (UNITS 100):
0.5 mm = 50 counts at 1 mm/s = 100 counts/s and 10 mm/s^2 = 1000 counts/s^2: 0.1 s to
reach the speed over 5 counts (k^2 / 2000 counts k ms in), 40 counts flat in 0.4 s, 5
counts to stop: 0.6 s in all.
"""

from __future__ import annotations

from maxk.controllers.trio.controller import MC405
from tests.trio_helpers import at, mc405

FAST = "SPEED=1000: ACCEL=100000: DECEL=10000"


def shaft(*lines: str) -> MC405:
    """Axis 4 a stepper (BASE 4) whose shaft encoder feeds axis 0's input (ATYPE 76)."""
    trio = mc405("ATYPE AXIS(0) = 76", "BASE(4)", *lines)
    trio.world_view().set_shaft_encoder("0", "4", 1.0)
    return trio


def motor(trio: MC405) -> str:
    return trio.query("?ENCODER AXIS(0)")


# ---- STEP_RATIO ----------------------------------------------------------------------
def test_the_page_s_degrees_example_turns_400_steps_a_turn_for_360_counts() -> None:
    """Example 2: 400 steps a turn, programmed as 360 counts a turn; MOVE(360*16) is one
    turn: the world's steps are the step generator's (16 a motor step, see stepratio.py),
    so the motor turns 400 x 16 = 6400 steps while DPOS moves 5760."""
    trio = shaft(FAST, "STEP_RATIO(400, 360)")
    trio.send("MOVE(360*16)")
    assert trio.run_until_idle()
    assert (trio.query("?DPOS"), motor(trio)) == ("5760", "6400")
    assert trio.world_view().reading("4").position == 6400  # the stage, as the world shows it


def test_a_limit_switch_is_met_where_the_motor_reaches_it() -> None:
    """Two steps a count: the switch 5000 steps out is reached at demand 2500, on tick
    5 + 2500; the move ramps down from there over 50 counts (100 cycles)."""
    trio = mc405(FAST, "FWD_IN=3", "STEP_RATIO(2,1)")
    trio.world_view().set_limits("0", plus=5000)
    trio.send("MOVE(10000)")
    at(trio, 2504)
    assert (trio.query("?DPOS"), trio.query("?IN(3)"), trio.query("?AXISSTATUS")) == (
        "2499", "1", "0")
    at(trio, 2505)
    assert (trio.query("?DPOS"), trio.query("?IN(3)"), trio.query("?AXISSTATUS")) == (
        "2500", "0", "16")
    assert trio.run_until_idle()
    assert (trio.machine.tick, trio.query("?DPOS")) == (2605, "2550")


def test_a_new_ratio_leaves_the_motor_where_it_is_and_1_1_removes_it() -> None:
    trio = shaft(FAST)
    trio.send("MOVE(100)")
    assert trio.run_until_idle() and motor(trio) == "100"
    trio.send("STEP_RATIO(3,1)")
    assert motor(trio) == "100"  # no step at the change
    trio.send("MOVE(100)")
    assert trio.run_until_idle()
    assert (trio.query("?DPOS"), motor(trio)) == ("200", "400")
    trio.send("STEP_RATIO(1,1)")  # example 3: the ratio removed
    trio.send("MOVE(-50)")
    assert trio.run_until_idle()
    assert (trio.query("?DPOS"), motor(trio)) == ("150", "350")


def test_bad_ratios_are_refused_and_change_nothing() -> None:
    trio = shaft(FAST, "STEP_RATIO(2,1)")
    for bad in ("STEP_RATIO(1,0)", "STEP_RATIO(-16777216,1)", "STEP_RATIO(1.5,1)",
                "STEP_RATIO(16777216,1)"):
        assert trio.send(bad) == ["! Parameter out of range"], bad
    assert trio.send("STEP_RATIO(1)") == ["! Syntax error"]
    trio.send("MOVE(10)")
    assert trio.run_until_idle() and motor(trio) == "20"


# ---- BACKLASH ------------------------------------------------------------------------
BACKLASH = ("UNITS=100", "SPEED=100", "ACCEL=1000", "DECEL=1000", "BACKLASH(ON,0.5,1,10)")
"""The page's example 3 in this test's numbers: a 20 mm move at 100 mm/s, ACCEL and DECEL
1000 mm/s^2 (0.1 s each: 5 mm), so MOVE(20) takes 0.3 s and is at 5 mm at 0.1 s, 15 mm at
0.2 s."""


def test_the_compensation_runs_on_top_of_the_first_forward_move_to_the_tick() -> None:
    trio = shaft(*BACKLASH)
    trio.send("MOVE(20)")
    start = trio.machine.tick
    expected = {  # ms in: (DPOS, BACKLASH_DIST, MPOS, motor steps)
        50: ("1.2500", "0.0125", "1.2625", "126"),  # 1.25 mm; 2500/2000 = 1.25 counts
        100: ("5", "0.0500", "5.0500", "505"),
        300: ("20", "0.2500", "20.2500", "2025"),  # 5 + 20 counts at 100/s
        550: ("20", "0.4875", "20.4875", "2049"),  # 50 - 0.05^2 x 1000 / 2 = 48.75
        600: ("20", "0.5000", "20.5000", "2050"),
        900: ("20", "0.5000", "20.5000", "2050"),
    }
    for ms, values in expected.items():
        at(trio, start + ms)
        got = (trio.query("?DPOS"), trio.query("?BACKLASH_DIST"), trio.query("?MPOS"),
               motor(trio))
        assert got == values, ms


def test_a_reversal_takes_the_compensation_back_from_where_it_has_got() -> None:
    """MOVE(-20) as MOVE(20) ends at 0.3 s: the compensation, 25 counts then, goes back
    to 0 from rest: 5 counts in 0.1 s, 15 flat in 0.15 s, 5 more: 0.35 s. The move is
    at 1.25 mm 0.25 s in (0.05 s of its ramp down left: 1000 x 0.05^2 / 2)."""
    trio = shaft(*BACKLASH)
    trio.send("MOVE(20)")
    assert trio.run_until_idle()
    assert trio.query("?BACKLASH_DIST") == "0.2500"
    trio.send("MOVE(-20)")
    start = trio.machine.tick
    for ms, dist, steps in ((100, "0.2000", "1520"), (250, "0.0500", "130"),
                            (350, "0", "0"), (500, "0", "0")):
        at(trio, start + ms)
        assert (trio.query("?BACKLASH_DIST"), motor(trio)) == (dist, steps), ms
    trio.send("MOVE(-5)")  # the same way again: no compensation move
    assert trio.run_until_idle()
    assert (trio.query("?BACKLASH_DIST"), motor(trio)) == ("0", "-500")


def test_a_first_move_in_reverse_and_off_leave_no_compensation() -> None:
    trio = shaft(*BACKLASH)
    trio.send("MOVE(-3)")  # a triangle: 1.25 mm in 0.05 s
    start = trio.machine.tick
    at(trio, start + 50)
    assert (trio.query("?BACKLASH_DIST"), trio.query("?MPOS")) == ("0", "-1.2500")
    assert trio.run_until_idle()
    trio.send("MOVE(3)")  # forward: the whole 0.5 mm over 0.6 s
    assert trio.run_until_idle()
    at(trio, trio.machine.tick + 600)
    assert (trio.query("?BACKLASH_DIST"), motor(trio)) == ("0.5000", "50")
    trio.send("BACKLASH(OFF)")  # taken back at its speed: the same 0.6 s
    off = trio.machine.tick
    at(trio, off + 100)
    assert trio.query("?BACKLASH_DIST") == "0.4500"
    at(trio, off + 600)
    trio.send("MOVE(-1)")
    trio.send("MOVE(2)")
    assert trio.run_until_idle()
    assert (trio.query("?BACKLASH_DIST"), motor(trio)) == ("0", "100")


def test_bad_backlash_arguments_are_refused_and_backlash_dist_is_read_only() -> None:
    trio = shaft(*BACKLASH)
    assert trio.send("BACKLASH(ON,1,-1,1)") == ["! Parameter out of range"]
    assert trio.send("BACKLASH(ON,1,1,-1)") == ["! Parameter out of range"]
    assert trio.send("BACKLASH_DIST=1") == ["! Parameter is read only"]
    trio.send("MOVE(20)")  # the settings given before still act
    assert trio.run_until_idle()
    at(trio, trio.machine.tick + 300)
    assert trio.query("?BACKLASH_DIST") == "0.5000"


def test_the_example_script_runs_as_recorded() -> None:
    """examples/mc405_stepper_output.maxk (STEP_RATIO and BACKLASH, its replies worked out
    by hand in its comments) under `maxk run`: every expected reply matches."""
    from pathlib import Path

    from maxk.cli import main

    script = Path(__file__).parent.parent / "examples" / "mc405_stepper_output.maxk"
    assert main(["run", str(script)]) == 0


def comp_by_hand(k: float) -> float:
    """The 50-count compensation move (100 counts/s, 1000 counts/s^2) k ms after it
    starts: 5 counts of ramp in 0.1 s, 40 flat in 0.4 s, 5 to stop."""
    t = k / 1000
    if t <= 0:
        return 0.0
    if t <= 0.1:
        return 500 * t * t
    if t <= 0.5:
        return 5 + 100 * (t - 0.1)
    if t <= 0.6:
        return 50 - 500 * (0.6 - t) ** 2
    return 50.0


def test_on_a_servo_axis_the_loop_follows_the_demand_and_the_compensation() -> None:
    """Each cycle's output is P e + D (e - e_prev) with e = demand + compensation -
    measured (the page: the compensation is superimposed on the commanded movement);
    MPOS ends advanced by it, FE is the loop's own error."""
    p_gain, d_gain = 8.0, 120.0
    trio = mc405(f"ATYPE=77: P_GAIN={p_gain}: D_GAIN={d_gain}: SERVO=ON: WDOG=ON",
                 *BACKLASH)
    trio.send("MOVE(1)")  # 100 counts: a triangle, 0.1 s
    m = trio.machine
    loop = m.axes[0].servo
    assert loop is not None
    start = m.tick
    e_prev = m.demand(0) + comp_by_hand(0) - loop.p
    for k in range(0, 700):
        e = m.demand(0) + comp_by_hand(k) - loop.p
        trio.advance(ticks=1)
        expected = (p_gain * e + d_gain * (e - e_prev)) / 16.0
        assert abs(m.drive.following.dac_out(0) - expected) < 1e-6, k
        e_prev = e
    assert m.tick == start + 700
    mpos, dpos, fe = (float(trio.query(f"?{n}")) for n in ("MPOS", "DPOS", "FE"))
    assert dpos == 1.0 and abs(mpos - (1.5 - fe)) < 1e-9 and abs(fe) < 0.2
