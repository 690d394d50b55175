"""MOVELINK_MODIFY from its TrioBASIC help page: the running MOVELINK completes at its end
plus the offset, if it has not begun to decelerate and there is room; applied, the
parameter reads 0; not applied, it keeps the offset; a MOVELINK of no distance has its
link distance changed.

The link axis 1 runs FORWARD at 1000 counts/s (UNITS 1, ACCEL 1e6) from tick 0: its
position at tick t >= 1 is t - 0.5. MOVELINK(18000, 10000, 1000, 1000, 1) on axis 0 from
tick 0 (linear ramps): peak ratio 1.8 / (1 - 0.1) = 2, so between the ramps the axis is
at 2 (u - 500) after u of link travel. The offset is added (our decision, recorded on
the entry) over the link travel from now to the decel start (9000) as the S 2z^2 /
1 - 2(1 - z)^2: the expected numbers below are that arithmetic.
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio.controller import MC405


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def dpos(trio: MC405, axis: int) -> float:
    return trio.machine.axis_parameter("DPOS", axis)


def s_curve(z: float) -> float:
    z = min(max(z, 0.0), 1.0)
    return 2 * z * z if z < 0.5 else 1 - 2 * (1 - z) ** 2


def linked(move: str = "MOVELINK(18000, 10000, 1000, 1000, 1)") -> MC405:
    trio = MC405()
    assert trio.send(f"BASE(0): MOVELINK_MODIFY = 0: {move}") == []
    assert trio.send("BASE(1): SPEED=1000: ACCEL=1e6: DECEL=1e6: FORWARD: BASE(0)") == []
    assert trio.tick == 0
    return trio


def test_the_pages_first_example_moves_the_end_by_the_offset() -> None:
    trio = linked()
    assert trio.query("?ENDMOVE") == "18000"
    at(trio, 3000)  # link 2999.5
    assert dpos(trio, 0) == pytest.approx(2 * (2999.5 - 500), abs=1e-9)
    assert trio.send("MOVELINK_MODIFY = -7000") == []
    assert trio.query("?MOVELINK_MODIFY") == "0"  # applied
    assert trio.query("?ENDMOVE") == "11000"
    assert dpos(trio, 0) == pytest.approx(2 * (2999.5 - 500), abs=1e-9)  # no jump
    stretch = 9000 - 2999.5
    for tick in (4000, 6000, 8999, 9500):
        at(trio, tick)
        u = tick - 0.5
        base = 2 * (u - 500) if u <= 9000 else 18000 - (10000 - u) ** 2 / 1000
        expected = base - 7000 * s_curve((u - 2999.5) / stretch)
        assert dpos(trio, 0) == pytest.approx(expected, abs=1e-6), tick
    at(trio, 10000)  # link 9999.5: not yet there
    assert trio.query("?MTYPE") == "22"
    at(trio, 10001)
    assert dpos(trio, 0) == pytest.approx(11000, abs=1e-9)
    assert trio.query("?MTYPE") == "0"


def test_no_room_or_decelerating_keeps_the_offset_for_the_next_movelink() -> None:
    trio = linked()
    at(trio, 8000)  # 1000.5 of link before the decel: 4 x 7000 / 1000.5^2 > 2 / 1000
    assert trio.send("MOVELINK_MODIFY = -7000") == []
    assert trio.query("?MOVELINK_MODIFY") == "-7000"
    assert trio.query("?ENDMOVE") == "18000"
    at(trio, 9500)  # decelerating: still not applied
    assert trio.send("MOVELINK_MODIFY = -100") == []
    assert trio.query("?MOVELINK_MODIFY") == "-100"
    at(trio, 10001)
    assert dpos(trio, 0) == pytest.approx(18000, abs=1e-9)
    # the next MOVELINK takes the kept offset as it starts (from link 10000.5)
    assert trio.send("MOVELINK(1000, 1000, 0, 0, 1)") == []
    assert trio.query("?MOVELINK_MODIFY") == "0"
    assert trio.query("?ENDMOVE") == "18900"
    at(trio, 10501)  # link 500 in: ratio 1, less the S half done (z = 0.5)
    assert dpos(trio, 0) == pytest.approx(18000 + 500 - 100 * 0.5, abs=1e-9)
    at(trio, 11002)
    assert dpos(trio, 0) == pytest.approx(18900, abs=1e-9)


def test_the_pages_second_example_shortens_a_delay_by_distance() -> None:
    trio = linked("MOVELINK(0, 5000, 0, 0, 1)")
    at(trio, 1500)
    assert trio.send("MOVELINK_MODIFY = -1500") == []
    assert trio.query("?MOVELINK_MODIFY") == "0"
    assert trio.send("WAIT IDLE") == []
    assert trio.tick == 3501  # the link at 3500.5: past 5000 - 1500
    assert dpos(trio, 0) == 0.0
