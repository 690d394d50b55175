"""ERRORMASK is ANDed with AXISSTATUS on every servo cycle (TrioBASIC help ERRORMASK,
DATUM, MOTION_ERROR, AXISSTATUS): an axis still standing on its limit after DATUM(0)
goes back into error on the next cycle, not only when a bit newly sets.

Figures by hand (as test_trio_disable_group): SPEED 1000 counts/s at ACCEL 100000 takes
10 cycles (5 counts), so an axis started from rest on tick 0 meets a forward switch at
p on tick p + 5 and stands there.
"""

from __future__ import annotations

from maxk.controllers.trio.controller import MC405

SETUP = "BASE(0): SPEED=1000: ACCEL=100000: DECEL=10000: FWD_IN=10: ERRORMASK=268+16"


def on_the_switch(*more: str) -> MC405:
    """Axis 0 driven onto a forward switch at 1000 (met on tick 1005): in error there."""
    trio = MC405()
    for line in (SETUP, *more, "WDOG=ON"):
        assert trio.send(line) == [], line
    trio.world_view().set_limits("0", plus=1000)
    trio.send("MOVE(10000) AXIS(0)")
    trio.advance(ticks=1010)
    assert trio.query("?MOTION_ERROR") == "1"
    return trio


def test_datum_0_on_the_limit_clears_then_the_next_cycle_errors_again() -> None:
    trio = on_the_switch()
    assert trio.query("?WDOG") == "0"
    tick = trio.machine.tick
    assert trio.send("DATUM(0)") == []
    assert trio.query("?MOTION_ERROR") == "0"  # cleared on its own cycle
    assert trio.query("?AXISSTATUS AXIS(0)") == "16"  # the switch: on, not held
    trio.advance(ticks=1)
    assert trio.machine.tick == tick + 1
    assert (trio.query("?MOTION_ERROR"), trio.query("?ERROR_AXIS")) == ("1", "0")
    assert trio.query("?AXISSTATUS AXIS(0)") == "16"
    assert trio.query("?WDOG") == "0"  # tripped again: no disable group


def test_off_the_limit_datum_0_clears_for_good() -> None:
    trio = on_the_switch()
    trio.world_view().set_limits("0", plus=5000)  # the switch moves away
    assert trio.send("DATUM(0): WDOG=ON") == []
    trio.advance(ticks=50)
    assert (trio.query("?MOTION_ERROR"), trio.query("?WDOG")) == ("0", "1")


def test_bit_out_of_the_mask_no_error_again() -> None:
    """ERRORMASK without 16: the limit on after DATUM(0) is no error (the AND is 0)."""
    trio = on_the_switch()
    assert trio.send("ERRORMASK AXIS(0) = 268: DATUM(0): WDOG=ON") == []
    trio.advance(ticks=50)
    assert (trio.query("?MOTION_ERROR"), trio.query("?WDOG")) == ("0", "1")
    assert trio.query("?AXISSTATUS AXIS(0)") == "16"


def test_disable_group_datum_7_errors_again_next_cycle_in_a_program() -> None:
    """In a disable group: DATUM(7) in a program clears axis 0, which is in error again
    the next cycle (the program sees 0 on the line after, then 1)."""
    trio = on_the_switch("DISABLE_GROUP(0)")
    assert trio.query("?WDOG") == "1"  # the group's axis stops, the relay stays on
    trio.load("CLR", "BASE(0)\nDATUM(7)\nVR(1) = MOTION_ERROR\nWA(5)\n"
                     "VR(2) = MOTION_ERROR\nVR(3) = AXIS_ENABLE")
    trio.send("RUN CLR")
    assert trio.run_until_idle(5)
    assert [trio.query(f"?VR({i})") for i in (1, 2, 3)] == ["0.0000", "1.0000", "0.0000"]
