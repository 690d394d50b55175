"""INITIALISE (TrioBASIC help INITIALISE): every axis parameter back to its power-up
value; positions, TABLE, VR and the system parameters stay."""

from __future__ import annotations

from maxk.controllers.trio.controller import MC405


def test_initialise_restores_the_axis_parameters_and_keeps_the_rest() -> None:
    trio = MC405()
    for line in ("UNITS=10: SPEED=50: ACCEL=5000: DECEL=5000: FWD_IN=3: FS_LIMIT=40",
                 "BASE(2): AXIS_MODE=16384: ERRORMASK=284: BASE(0)", "VR(7)=2.5",
                 "TABLE(3, 9)", "WDOG=ON"):
        assert trio.send(line) == [], line
    trio.send("MOVE(12.5)")
    assert trio.run_until_idle() and trio.query("?DPOS") == "12.5000"
    assert trio.send("INITIALISE") == []
    assert [trio.query(q) for q in ("?UNITS", "?SPEED", "?ACCEL", "?FWD_IN", "?FS_LIMIT",
                                    "?AXIS_MODE AXIS(2)", "?ERRORMASK AXIS(2)")] == \
        ["1", "1000", "1000", "-1", "200000000000", "0", "268"]
    # the position stays where it was in counts: 125 counts at UNITS 1
    assert trio.query("?DPOS") == "125"
    assert [trio.query(q) for q in ("?VR(7)", "?TABLE(3)", "?WDOG")] == \
        ["2.5000", "9.0000", "1"]


def test_initialise_reaches_the_move_running_as_a_new_speed_would() -> None:
    """SPEED 500 -> 1000 counts/s mid-move, ACCEL/DECEL 1000 unchanged: the move ramps up
    from 500 to 1000 counts/s over 0.5 s, as writing SPEED=1000 does (respeed)."""
    trio = MC405()
    trio.send("SPEED=500: ACCEL=1000: DECEL=1000")
    twin = MC405()
    twin.send("SPEED=500: ACCEL=1000: DECEL=1000")
    for t in (trio, twin):
        t.send("MOVE(5000)")
        t.advance(ticks=2000)
    assert trio.send("INITIALISE") == []
    assert twin.send("SPEED=1000") == []
    for _ in range(3):
        trio.advance(ticks=400)
        twin.advance(ticks=400)
        assert trio.machine.dpos(0) == twin.machine.dpos(0)
    assert trio.query("?VP_SPEED") == "1000"
