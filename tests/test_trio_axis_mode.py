"""AXIS_MODE bit 14 (TrioBASIC help AXIS_MODE: ignore software limits) on the MC405: with
it set FS_LIMIT/RS_LIMIT neither stop a move nor show in AXISSTATUS; clear, they act as
before (bit 9 = 512 beyond FS_LIMIT, bit 10 = 1024 below RS_LIMIT)."""

from __future__ import annotations

from maxk.controllers.trio.controller import MC405
from tests.trio_helpers import mc405

FAST = "SPEED=1000: ACCEL=100000: DECEL=100000"


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


# ---- bit 8 on a servo axis: the software limits compare DPOS (set) or MPOS (clear) -------
SERVO_MOVE = ("ATYPE=77: P_GAIN=8: D_GAIN=120: SERVO=ON: WDOG=ON: SPEED=2000: ACCEL=40000: "
              "DECEL=40000: FS_LIMIT=500")
"""MOVE(1000) from 0: 50 cycles of ramp (50 counts), then 2 counts a cycle, so DPOS reaches
500 on cycle 50 + 225 = 275; MPOS lags it by the following error (about 35 counts)."""


def servo_rows(mode: int, cycles: int = 330) -> tuple[MC405, list[tuple[int, float, float]]]:
    trio = MC405()
    assert trio.send(f"{SERVO_MOVE}: AXIS_MODE={mode}") == []
    trio.advance(ticks=10)
    trio.send("MOVE(1000)")
    start = trio.machine.tick
    rows = []
    for k in range(1, cycles):
        trio.advance(ticks=start + k - trio.machine.tick)
        rows.append((k, float(trio.query("?MPOS")), float(trio.query("?VP_SPEED"))))
    return trio, rows


def test_bit_8_set_stops_a_servo_axis_where_dpos_reaches_the_limit() -> None:
    _trio, rows = servo_rows(256)
    speeds = {k: v for k, _mpos, v in rows}
    assert (speeds[275], speeds[276]) == (2000.0, 1960.0)  # DECEL from cycle 275


def test_bit_8_clear_stops_a_servo_axis_where_mpos_reaches_the_limit() -> None:
    trio, rows = servo_rows(0)
    reached = next(k for k, mpos, _v in rows if mpos >= 500)
    assert reached > 275 + 10  # (the following error's worth of cycles later)
    speeds = {k: v for k, _mpos, v in rows}
    assert (speeds[reached], speeds[reached + 1]) == (2000.0, 1960.0)
    assert trio.query("?AXISSTATUS") == "512"  # MPOS beyond FS_LIMIT (bit 9)
    assert trio.run_until_idle()
    final = trio.query("?DPOS")
    # the same stop with time taken in one stretch (the loop watched on every cycle)
    again = MC405()
    assert again.send(f"{SERVO_MOVE}: AXIS_MODE=0") == []
    again.advance(ticks=10)
    again.send("MOVE(1000)")
    assert again.run_until_idle()
    assert again.query("?DPOS") == final
