"""AXIS_MODE bit 14 (TrioBASIC help AXIS_MODE: ignore software limits) on the MC405: with
it set FS_LIMIT/RS_LIMIT neither stop a move nor show in AXISSTATUS; clear, they act as
before (bit 9 = 512 beyond FS_LIMIT, bit 10 = 1024 below RS_LIMIT)."""

from __future__ import annotations

from maxk.controllers.trio.controller import MC405

FAST = "SPEED=1000: ACCEL=100000: DECEL=100000"


def mc405(*lines: str) -> MC405:
    trio = MC405()
    for line in lines:
        assert trio.send(line) == [], line
    return trio


def dpos(trio: MC405) -> float:
    return round(trio.machine.dpos(0), 6)


def test_bit_14_lets_a_move_run_through_the_software_limits() -> None:
    trio = mc405(FAST, "FS_LIMIT=200: RS_LIMIT=-50",
                 "AXIS_MODE AXIS(0) = AXIS_MODE AXIS(0) OR 16384")  # the page's OR form
    assert trio.query("?AXIS_MODE") == "16384"
    trio.send("MOVE(500)")
    assert trio.run_until_idle()
    # 500 units at 1000/s, ramps of 0.01 s each way: 0.51 s, every count of it made
    assert (dpos(trio), trio.machine.tick, trio.query("?AXISSTATUS")) == (500.0, 510, "0")
    trio.send("AXIS_MODE.14 = 0")  # the limits act again: DPOS is beyond FS_LIMIT
    assert trio.query("?AXISSTATUS") == "512"
    trio.send("MOVE(1)")  # into the limit: cancelled as it starts
    assert trio.run_until_idle() and dpos(trio) == 500.0
    trio.send("AXIS_MODE.14 = 1: MOVEABS(-100)")
    assert trio.run_until_idle()
    assert (dpos(trio), trio.query("?AXISSTATUS")) == (-100.0, "0")
    trio.send("AXIS_MODE = 0")
    assert trio.query("?AXISSTATUS") == "1024"


def test_without_bit_14_the_same_move_stops_at_the_limit() -> None:
    """The control: the move of the test above, bit 14 clear, is stopped at FS_LIMIT and
    ramps down at DECEL (0.01 s from 1000/s: 5 units past it)."""
    trio = mc405(FAST, "FS_LIMIT=200")
    trio.send("MOVE(500)")
    assert trio.run_until_idle()
    assert (dpos(trio), trio.query("?AXISSTATUS")) == (205.0, "512")
