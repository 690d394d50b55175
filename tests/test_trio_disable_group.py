"""DISABLE_GROUP, MOTION_ERROR, ERROR_AXIS and DATUM(7) on the MC405 (TrioBASIC help
DISABLE_GROUP, AXIS_ENABLE, WDOG, ERRORMASK, MOTION_ERROR, ERROR_AXIS, DATUM).

Figures by hand: SPEED 1000 counts/s reached at ACCEL 100000 in 10 servo cycles (5
counts), so an axis started from rest on tick 0 stands on count t - 5 on tick t >= 10 and
makes one count a cycle; a forward limit switch at p is met on tick p + 5. Switch positions
avoid the few counts the shared profile's float arithmetic reaches a cycle late (2000 is
one: 1999.9999999999998 on tick 2005; left alone, outside this work).
"""

from __future__ import annotations

from maxk.controllers.trio.controller import MC405
from tests.trio_helpers import at, mc405

FAST = "SPEED=1000: ACCEL=100000: DECEL=10000"


def dpos(trio: MC405, axis: int) -> float:
    return round(trio.machine.dpos(axis), 6)


def limited(*axes: int) -> list[str]:
    """Each axis: FAST, a forward limit switch on input 10 + axis, and the limit bit (16)
    in its ERRORMASK (the ERRORMASK page's example adds it so)."""
    return [f"BASE({a}): {FAST}: FWD_IN={10 + a}: ERRORMASK=268+16" for a in axes]


def test_example_2_one_conveyor_jams_the_other_keeps_moving() -> None:
    trio = mc405(*limited(0, 1), "DISABLE_GROUP(0)", "DISABLE_GROUP(1)", "WDOG=ON")
    trio.world_view().set_limits("0", plus=3000)  # the jam: axis 0 meets it at 3000
    trio.send("MOVE(10000) AXIS(0)")
    trio.send("MOVE(10000) AXIS(1)")
    at(trio, 3004)
    assert (dpos(trio, 0), dpos(trio, 1), trio.query("?MOTION_ERROR")) == (2999.0, 2999.0, "0")
    at(trio, 3005)  # axis 0 stands on the switch: its group (itself) stops at once
    assert (dpos(trio, 0), dpos(trio, 1)) == (3000.0, 3000.0)
    assert [trio.query(q) for q in ("?MOTION_ERROR", "?ERROR_AXIS", "?WDOG",
                                    "?AXIS_ENABLE AXIS(0)", "?SERVO AXIS(0)",
                                    "?AXIS_ENABLE AXIS(1)", "?AXISSTATUS AXIS(0)")] == \
        ["1", "0", "1", "0", "0", "1", "16"]
    assert trio.machine.axis_idle(0) and not trio.machine.axis_idle(1)
    at(trio, 4005)  # the other conveyor ran on, a count a cycle
    assert (dpos(trio, 0), dpos(trio, 1)) == (3000.0, 4000.0)
    assert trio.send("MOVE(-10) AXIS(0)") == ["! Axis in error"]
    # the jam is cleared and the group restarted: DATUM(7), AXIS_ENABLE and SERVO ON
    trio.world_view().set_limits("0", plus=None)
    assert trio.send("BASE(0): DATUM(7)") == []
    assert (trio.query("?MOTION_ERROR"), trio.query("?AXISSTATUS AXIS(0)")) == ("0", "0")
    assert trio.send("MOVE(10000) AXIS(0)") == ["! Axis not enabled"]  # not yet enabled
    trio.send("AXIS_ENABLE AXIS(0)=ON: SERVO AXIS(0)=ON")
    trio.send("MOVE(10000) AXIS(0)")
    start = trio.machine.tick
    at(trio, start + 1010)
    assert (dpos(trio, 0), dpos(trio, 1)) == (3000.0 + 1005, 4000.0 + 1010)


def test_a_group_stops_together_and_the_rest_runs_on() -> None:
    trio = mc405(*limited(0, 1, 2), "DISABLE_GROUP(-1)", "DISABLE_GROUP(0, 1)",
                 "DISABLE_GROUP(2)", "WDOG=ON")
    trio.world_view().set_limits("1", plus=2500)
    for a in (0, 1, 2):
        trio.send(f"MOVE(10000) AXIS({a})")
    at(trio, 2505)
    assert [dpos(trio, a) for a in (0, 1, 2)] == [2500.0, 2500.0, 2500.0]
    assert [trio.query(f"?AXIS_ENABLE AXIS({a})") for a in (0, 1, 2)] == ["0", "0", "1"]
    # only axis 1 is in error: axis 0 stopped with its group but has no error of its own
    assert [trio.query(q) for q in ("?MOTION_ERROR", "?ERROR_AXIS", "?WDOG")] == \
        ["2", "1", "1"]
    at(trio, 3005)
    assert [dpos(trio, a) for a in (0, 1, 2)] == [2500.0, 2500.0, 3000.0]


def test_an_axis_in_no_group_stops_every_axis_and_wdog() -> None:
    trio = mc405(*limited(0, 1), "DISABLE_GROUP(1)", "WDOG=ON")
    trio.world_view().set_limits("0", plus=1000)
    trio.send("MOVE(10000) AXIS(0)")
    trio.send("MOVE(10000) AXIS(1)")
    at(trio, 1100)
    assert (dpos(trio, 0), dpos(trio, 1)) == (1000.0, 1000.0)
    assert [trio.query(q) for q in ("?MOTION_ERROR", "?WDOG", "?AXIS_ENABLE AXIS(0)",
                                    "?AXIS_ENABLE AXIS(1)")] == ["1", "0", "1", "1"]


def test_disable_group_minus_1_removes_the_groups() -> None:
    trio = mc405(*limited(0, 1), "DISABLE_GROUP(0)", "DISABLE_GROUP(1)",
                 "DISABLE_GROUP(-1)", "WDOG=ON")
    trio.world_view().set_limits("0", plus=1000)
    trio.send("MOVE(10000) AXIS(0)")
    trio.send("MOVE(10000) AXIS(1)")
    at(trio, 1100)
    assert (dpos(trio, 0), dpos(trio, 1), trio.query("?WDOG")) == (1000.0, 1000.0, "0")


def test_an_axis_named_again_leaves_its_old_group() -> None:
    trio = mc405(*limited(0, 1, 2), "DISABLE_GROUP(0, 1)", "DISABLE_GROUP(1, 2)",
                 "WDOG=ON")
    trio.world_view().set_limits("0", plus=1000)
    for a in (0, 1, 2):
        trio.send(f"MOVE(10000) AXIS({a})")
    at(trio, 1105)
    assert [dpos(trio, a) for a in (0, 1, 2)] == [1000.0, 1100.0, 1100.0]
    assert trio.query("?WDOG") == "1"


def test_motion_error_example_1_and_datum_7_clears_one_axis() -> None:
    """MOTION_ERROR's example: axes 0, 1 and 3 in error, axis 3 first: 11 and 3."""
    trio = mc405(*limited(0, 1, 3), "DISABLE_GROUP(0)", "DISABLE_GROUP(1)",
                 "DISABLE_GROUP(3)", "WDOG=ON")
    for name, switch in (("3", 1000), ("0", 2500), ("1", 3000)):
        trio.world_view().set_limits(name, plus=switch)
    for a in (0, 1, 3):
        trio.send(f"MOVE(10000) AXIS({a})")
    at(trio, 1005)
    assert (trio.query("?MOTION_ERROR"), trio.query("?ERROR_AXIS")) == ("8", "3")
    at(trio, 3005)
    assert (trio.query("?MOTION_ERROR"), trio.query("?ERROR_AXIS")) == ("11", "3")
    assert [dpos(trio, a) for a in (0, 1, 3)] == [2500.0, 3000.0, 1000.0]
    assert trio.query("?MOTION_ERROR.3") == "1"
    trio.send("BASE(3): DATUM(7)")  # the first axis's error only
    assert (trio.query("?MOTION_ERROR"), trio.query("?ERROR_AXIS")) == ("3", "3")
    assert trio.query("?AXISSTATUS AXIS(3)") == "16"  # still on its switch, not held
    trio.send("DATUM(0)")  # every axis
    assert (trio.query("?MOTION_ERROR"), trio.query("?ERROR_AXIS")) == ("0", "0")


def test_bad_groups_are_refused_and_change_nothing() -> None:
    trio = mc405(*limited(0, 1), "DISABLE_GROUP(0)", "WDOG=ON")
    for bad in ("DISABLE_GROUP(1, 1)", "DISABLE_GROUP(99)", "DISABLE_GROUP(0.5)",
                "DISABLE_GROUP(1, -1)"):
        assert trio.send(bad) == ["! Parameter out of range"], bad
    trio.world_view().set_limits("0", plus=1000)
    trio.send("MOVE(10000) AXIS(0)")
    trio.send("MOVE(10000) AXIS(1)")
    at(trio, 1105)  # the group of axis 0 alone still holds
    assert (dpos(trio, 0), dpos(trio, 1), trio.query("?WDOG")) == (1000.0, 1100.0, "1")


def test_a_servo_conveyor_jams_on_its_following_error_the_stepper_runs_on() -> None:
    servo = ("BASE(0): ATYPE=77: P_GAIN=10: D_GAIN=160: SERVO=ON: SPEED=4000: "
             "ACCEL=40000: DECEL=40000: FE_LIMIT=200")

    def conveyors(mask: int) -> MC405:
        trio = mc405(servo, f"ERRORMASK={mask}", f"BASE(1): {FAST}", "DISABLE_GROUP(0)",
                     "DISABLE_GROUP(1)", "WDOG=ON")
        trio.send("FORWARD AXIS(0)")
        trio.send("FORWARD AXIS(1)")
        at(trio, 1000)
        trio.world_view().set_motor("0", coulomb_friction=1.0)  # the belt jams
        return trio

    watch = conveyors(0)  # no error raised: the first cycle |FE| passes 200, by reading
    while abs(float(watch.query("?FE AXIS(0)"))) <= 200:
        watch.advance(ticks=1)
    first = watch.machine.tick
    trio = conveyors(268)
    trio.advance(ticks=first - 1000 + 500)  # one stretch: the error is found inside it
    assert [trio.query(q) for q in ("?MOTION_ERROR", "?ERROR_AXIS", "?WDOG",
                                    "?AXIS_ENABLE AXIS(0)", "?SERVO AXIS(0)",
                                    "?AXISSTATUS AXIS(0)")] == ["1", "0", "1", "0", "0",
                                                                "256"]
    assert trio.machine.axis_idle(0)
    assert dpos(trio, 1) == first + 500 - 5  # the stepper never stopped


def test_a_program_restarts_its_group_as_the_page_does() -> None:
    """Example 2's shape: a watch loop sees AXIS_ENABLE go OFF, waits for a reset input,
    then DATUM(7), AXIS_ENABLE and SERVO ON and FORWARD again."""
    trio = mc405(*limited(0, 1))
    trio.world_view().set_input(5, False)  # the reset button, not pressed
    trio.load("CONV", "\n".join([
        "DISABLE_GROUP(0)", "DISABLE_GROUP(1)", "GOSUB en0", "GOSUB en1", "WDOG = ON",
        "FORWARD AXIS(0)", "FORWARD AXIS(1)", "VR(0) = 0",
        "WHILE TRUE",
        "  IF AXIS_ENABLE AXIS(0) = 0 AND VR(0) = 0 THEN",
        "    VR(0) = 1", "    VR(1) = DPOS AXIS(0)",
        "  ENDIF",
        "  IF VR(0) = 1 AND IN(5) = ON THEN",
        "    GOSUB en0", "    FORWARD AXIS(0)", "    VR(0) = 2",
        "  ENDIF",
        "WEND",
        "en0:", "  BASE(0)", "  DATUM(7)", "  WA(10)", "  AXIS_ENABLE = ON", "  SERVO = ON",
        "RETURN",
        "en1:", "  BASE(1)", "  DATUM(7)", "  WA(10)", "  AXIS_ENABLE = ON", "  SERVO = ON",
        "RETURN"]))
    trio.send('RUN "CONV"')
    trio.advance(ticks=500)
    here = dpos(trio, 1)
    trio.world_view().set_limits("0", plus=dpos(trio, 0) + 100)  # a jam 100 counts ahead
    trio.advance(ticks=200)
    assert (trio.query("?VR(0)"), trio.query("?VR(1)")) == ("1.0000", f"{here + 100:.4f}")
    assert dpos(trio, 1) == here + 200 and dpos(trio, 0) == here + 100
    trio.world_view().set_limits("0", plus=None)
    trio.world_view().set_input(5, True)  # reset pressed
    trio.advance(ticks=100)
    assert trio.query("?VR(0)") == "2.0000"
    assert trio.query("?AXIS_ENABLE AXIS(0)") == "1" and trio.query("?MOTION_ERROR") == "0"
    moving = dpos(trio, 0)
    trio.advance(ticks=100)
    assert dpos(trio, 0) == moving + 100  # at speed again, a count a cycle


def test_motion_error_banks_read_as_the_page_gives_them() -> None:
    trio = mc405(*limited(0, 1, 3), "DISABLE_GROUP(0)", "DISABLE_GROUP(1)",
                 "DISABLE_GROUP(3)", "WDOG=ON")
    trio.world_view().set_limits("3", plus=1000)
    trio.send("MOVE(10000) AXIS(3)")
    at(trio, 1100)
    assert [trio.query(q) for q in ("?MOTION_ERROR(0)", "?MOTION_ERROR(0).3",
                                    "?MOTION_ERROR(0).2", "?MOTION_ERROR(1)",
                                    "?MOTION_ERROR(1).6")] == ["8", "1", "0", "0", "0"]
    assert trio.send("?MOTION_ERROR(16)") == ["! Parameter out of range"]
    assert trio.send("?MOTION_ERROR(0.5)") == ["! Parameter out of range"]


def test_a_motion_error_ends_the_links_and_the_drive_off_ends_a_link() -> None:
    """Without groups every axis stops: a CONNECT on axis 2 ends with it (the demand
    stays); with its drive switched off a linked axis stops following too."""
    trio = mc405(*limited(0, 1), "BASE(2): CONNECT(1, 1)", "WDOG=ON")
    trio.world_view().set_limits("0", plus=1000)
    trio.send("MOVE(10000) AXIS(0)")
    trio.send("MOVE(10000) AXIS(1)")
    at(trio, 1005)
    assert [dpos(trio, a) for a in (0, 1, 2)] == [1000.0, 1000.0, 1000.0]
    assert trio.machine.axes[2].link is None and trio.machine.axis_idle(2)
    trio.world_view().set_limits("0", plus=None)  # (still on it, axis 0 would be in
    trio.send("DATUM(0)")  # error again the next cycle: ERRORMASK's every cycle)
    trio.send("BASE(2): CONNECT(1, 1)")
    trio.send("MOVE(1000) AXIS(1)")
    at(trio, 1505)  # from tick 1005: 500 - 5 counts each
    assert (dpos(trio, 1), dpos(trio, 2)) == (1495.0, 1495.0)
    trio.send("AXIS_ENABLE AXIS(2)=OFF")
    at(trio, 1605)
    assert (dpos(trio, 1), dpos(trio, 2)) == (1595.0, 1495.0)


def test_a_clear_does_not_wait_for_the_base_axis_to_stop() -> None:
    """DATUM(0) and DATUM(7) act and return at once, while the base axis moves (a
    group's program clears one conveyor while the other runs)."""
    trio = mc405(*limited(0, 1))
    trio.load("CLR", "BASE(1)\nMOVE(5000)\nDATUM(0)\nVR(2) = 1\nDATUM(7)\nVR(3) = 1")
    trio.send('RUN "CLR"')
    trio.advance(ticks=20)
    assert (trio.query("?VR(2)"), trio.query("?VR(3)")) == ("1.0000", "1.0000")
    assert not trio.machine.axis_idle(1)


def test_the_two_conveyors_example_script_passes() -> None:
    """examples/mc405_disable_group.maxk, as `maxk run` runs it."""
    from pathlib import Path

    from maxk.script import load_script, run_script

    script = load_script(Path(__file__).parent.parent / "examples" / "mc405_disable_group.maxk")
    transcript = run_script(script)
    assert not transcript.failures, transcript.failures


def test_a_soft_limit_bit_in_errormask_errors_on_the_cycle_dpos_passes_it() -> None:
    """FS_LIMIT 300 is met on tick 305 (DPOS 300, not yet beyond it); the ramp down at
    DECEL 10000 makes 1 - 10000 x 0.001^2 / 2 = 0.995 count on tick 306: DPOS 300.995 >
    300 sets bit 9 (512), in ERRORMASK: the motion error stops the axis there."""
    trio = mc405(FAST, "FS_LIMIT=300: ERRORMASK=268+512")
    trio.send("MOVE(10000)")
    at(trio, 305)
    assert (dpos(trio, 0), trio.query("?MOTION_ERROR")) == (300.0, "0")
    at(trio, 306)
    assert (dpos(trio, 0), trio.query("?MOTION_ERROR"), trio.query("?AXISSTATUS")) == \
        (300.995, "1", "512")
    assert trio.machine.axis_idle(0)
    at(trio, 500)
    assert dpos(trio, 0) == 300.995
