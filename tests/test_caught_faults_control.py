"""Faults the suite once let through (issue 41), caught at the control door: the tick a
position trigger fires on, the level a JSON input setting gives, and a switch stuck
inactive. Every expected value is arithmetic in the test (the MAX manual's trapezoid:
VL, AC, a linear ramp) or the setting's own words, never the engine's functions.

The boards run on the door's paused clock (tests/hosting.py's manual clock): every tick
below is exact.
"""

from __future__ import annotations

import asyncio
import math
from fractions import Fraction

import pytest

from maxk.control import Client
from maxk.host.control import ControlDoor
from tests.hosting import HostedBoards


class Hosted:
    """Served boards with a control door on the same loop (as tests/test_control.py)."""

    def __init__(self, models: tuple[str, ...]) -> None:
        self.boards = HostedBoards(models=models)
        self.door = ControlDoor(self.boards.services)

        async def start() -> tuple[str, int]:
            return await self.door.start("127.0.0.1", 0)

        address = asyncio.run_coroutine_threadsafe(start(), self.boards.loop).result(10)
        self.client = Client(f"http://127.0.0.1:{address[1]}", self.door.token)

    def close(self) -> None:
        asyncio.run_coroutine_threadsafe(self.door.close(), self.boards.loop).result(10)
        self.boards.close()


@pytest.fixture
def hosted():
    h = Hosted(("MAXk-8000",))
    yield h
    h.close()


RATE = 8192  # the MAXk's update rate, ticks per second (docs/commands.md, UR default)
VL, AC = 10_000, 100_000  # steps/s, steps/s^2


def _trapezoid_position(t: Fraction) -> Fraction:
    """Steps from the start of `MR` with a linear ramp: AC up to VL, then VL (the target
    is far enough that the ramp down is not reached in the times used here)."""
    ramp = Fraction(VL, AC)
    if t <= ramp:
        return Fraction(AC) * t * t / 2
    return Fraction(VL * VL, 2 * AC) + VL * (t - ramp)


def _first_tick_at_or_past(target: int) -> int:
    """The first tick whose (whole-step) position is >= target, by arithmetic."""
    # on the constant-speed stretch: VL*t - VL^2/(2 AC) >= target
    t = (Fraction(target) + Fraction(VL * VL, 2 * AC)) / VL
    tick = math.ceil(t * RATE)
    assert math.floor(_trapezoid_position(Fraction(tick, RATE))) >= target
    assert math.floor(_trapezoid_position(Fraction(tick - 1, RATE))) < target
    return tick


def test_position_trigger_fires_on_the_first_tick_the_axis_has_passed(hosted: Hosted) -> None:
    """Fault 1 (a position trigger 20% late): `when X passes 12003` fires on the tick the
    trapezoid first reaches 12003 steps, not one tick later, and the limit it sets stops
    the host's move there."""
    c = hosted.client
    c.pause()
    host = hosted.boards.connect(1)
    host.command(f"AX; VL{VL}; AC{AC}; LA; MR40000; GO;")
    start = c.clock()[0]["tick"]
    trip = c.arm(1, "X fault plus active", axis="X", passes=12003)
    expected = start + _first_tick_at_or_past(12003)
    assert expected == start + 10243  # 1.2503 s * 8192 = 10242.46 -> the next tick
    c.step(ticks=expected - 1 - start)
    assert c.triggers(1)[0]["fired_tick"] is None
    before = c.reading(1, "X")["position"]
    assert before == 12002  # floor(10000 * 10242/8192 - 500)
    c.step(ticks=1)
    fired = c.triggers(1)[0]
    assert fired["id"] == trip["id"] and fired["fired_tick"] == expected
    assert fired["did"] == "X fault plus active"
    assert c.reading(1, "X")["position"] == 12003
    c.step(2.0)
    assert host.query("QA")[2] == "L"  # the host sees the limit its own way
    # the factory limit style is hard (manual 2.14, LMH): the axis stops where the limit
    # found it, on the tick the trigger set it
    assert int(host.query("RP")) == 12003


def test_a_soft_limit_set_by_a_trigger_decelerates_at_ac(hosted: Hosted) -> None:
    """The same trigger with the soft limit style (SL): the axis decelerates at AC from
    VL, VL^2 / (2 AC) = 500 steps past where the limit tripped."""
    c = hosted.client
    c.pause()
    host = hosted.boards.connect(1)
    host.command(f"AX; VL{VL}; AC{AC}; LA; SL; MR40000; GO;")
    start = c.clock()[0]["tick"]
    c.arm(1, "X fault plus active", axis="X", passes=12003)
    c.step(3.0)
    assert c.triggers(1)[0]["fired_tick"] == start + 10243
    assert host.query("QA")[2] == "L"
    stop = int(host.query("RP"))
    assert stop - 12003 == pytest.approx(VL * VL / (2 * AC), abs=2)


def test_position_trigger_downward_fires_on_the_first_tick_at_or_below(hosted: Hosted) -> None:
    """The same trigger on a move down: `when X passes -7001` fires on the first tick
    whose position is <= -7001."""
    c = hosted.client
    c.pause()
    host = hosted.boards.connect(1)
    host.command(f"AX; VL{VL}; AC{AC}; LA; MR-40000; GO;")
    start = c.clock()[0]["tick"]
    c.arm(1, "input 4 high", axis="X", passes=-7001)
    # -floor? positions going down are -floor(|x|) or -ceil; find the tick by the rule
    # "the first tick with position <= -7001" from arithmetic on |x| = 7001
    t = (Fraction(7001) + Fraction(VL * VL, 2 * AC)) / VL
    expected = start + math.ceil(t * RATE)  # 0.7501 s -> 6144.8 -> 6145
    assert expected - start == 6145
    c.step(ticks=expected - 1 - start)
    assert c.triggers(1)[0]["fired_tick"] is None
    assert c.reading(1, "X")["position"] > -7001
    assert host.query("BX") == "0000"
    c.step(ticks=1)
    assert c.triggers(1)[0]["fired_tick"] == expected
    assert c.reading(1, "X")["position"] <= -7001
    assert host.query("BX") == "0010"  # input 4 high: bit 4 of the host's BX


def test_json_input_level_false_sets_the_input_low(hosted: Hosted) -> None:
    """Fault 2 (`{"input": n, "level": false}` setting the input high): the host's BX
    reads the input low after the JSON form says false, high after true."""
    c = hosted.client
    c.pause()
    host = hosted.boards.connect(1)
    assert c.world(1, input=3, level=True) == "input 3 high"
    c.step(ticks=2)
    assert host.query("BX") == "0008"  # bit 3
    assert c.board(1)["inputs"]["3"] is True
    assert c.world(1, input=3, level=False) == "input 3 low"
    c.step(ticks=2)
    assert host.query("BX") == "0000"
    assert c.board(1)["inputs"]["3"] is False
    assert c.world(1, input=5, level=0) == "input 5 low"
    assert c.world(1, input=5, level=1) == "input 5 high"
    c.step(ticks=2)
    assert host.query("BX") == "0020"


def test_a_switch_stuck_inactive_is_never_seen(hosted: Hosted) -> None:
    """Fault 3 (`fault ... inactive` taken as `none`): a plus limit at 5000 stuck
    inactive lets a move to 20000 end at 20000 exactly, with no limit in QA; cleared
    (`none`) the same switch stops the next move."""
    c = hosted.client
    c.pause()
    host = hosted.boards.connect(1)
    c.world(1, "X plus-limit 5000")
    assert c.world(1, "X fault plus inactive") == "X fault plus inactive"
    assert c.board(1)["axes"][0]["switches"]["plus"]["fault"] == "inactive"
    host.command(f"AX; VL{VL}; AC{AC}; LA; MA20000; GO;")
    # 20000 steps: 0.1 s up, 1.9 s at VL, 0.1 s down = 2.1 s; 3 s is plenty
    c.step(3.0)
    assert int(host.query("RP")) == 20000
    assert host.query("QA")[2] != "L"
    # parked on the switch's active side, stuck inactive: the host still reads no limit
    assert "overtravel" not in c.reading(1, "X")["flags"]
    c.world(1, "X fault plus none")
    host.command("AX; MA0; GO;")
    c.step(3.0)
    assert int(host.query("RP")) == 0
    c.world(1, "X fault plus inactive")
    host.command("AX; MA30000; GO;")
    c.step(4.0)
    assert int(host.query("RP")) == 30000  # straight through the switch again
