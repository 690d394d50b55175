"""CLUTCH_RATE from its TrioBASIC help page and CONNECT's: a second CONNECT on the same link
axis moves the ratio at CLUTCH_RATE (ratio per second) instead of at once.

The link axis 0 runs FORWARD at 1000 counts/s (UNITS 1, ACCEL 1e6: it is at speed after
one servo cycle), so from then on it moves exactly 1 count every 1 ms servo cycle. With
CLUTCH_RATE c the ratio of the k-th cycle after the change is r0 + k c / 1000 (capped at
the new ratio), and the axis moves that ratio x 1 count in the cycle: the expected
positions below are those sums, worked out by hand (sum of k for k = 1..n is n(n+1)/2).
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio.controller import MC405


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def dpos(trio: MC405, axis: int) -> float:
    return trio.machine.axis_parameter("DPOS", axis)


def running_link(start: int = 100) -> MC405:
    """Axis 0 FORWARD from tick 0, at 1 count a cycle from tick 1 on."""
    trio = MC405()
    assert trio.send("BASE(0): SPEED=1000: ACCEL=1e6: DECEL=1e6: FORWARD") == []
    at(trio, start)
    assert dpos(trio, 0) == pytest.approx(start - 0.5, abs=1e-9)  # v t - v^2/2a
    return trio


def test_the_connect_pages_example_clutches_in_and_out_without_a_step() -> None:
    """CONNECT(0) then CLUTCH_RATE 0.5, CONNECT(2): 0.0005 more ratio a cycle, 4000 cycles
    to reach 2 (travel 0.0005 x 4000 x 4001 / 2 = 4001); 4000 cycles at 2 (8000); then
    CONNECT(0): 4000 cycles down (8000 - 4001 = 3999). 16000 counts in all."""
    trio = running_link()
    assert trio.send("BASE(1): CONNECT(0, 0): CLUTCH_RATE = 0.5: CONNECT(2, 0)") == []
    assert trio.tick == 100
    for n in (1, 2, 1000, 3999, 4000, 4001, 6000):
        at(trio, 100 + n)
        k = min(n, 4000)
        expected = 0.0005 * k * (k + 1) / 2 + 2 * (n - k)
        assert dpos(trio, 1) == pytest.approx(expected, abs=1e-6), n
    trio = running_link()
    trio.send("BASE(1): CONNECT(0, 0): CLUTCH_RATE = 0.5: CONNECT(2, 0)")
    at(trio, 1100)
    assert trio.query("?VP_SPEED AXIS(1)") == "500.0000"  # ratio 0.5 x 1000 counts/s
    assert trio.query("?MTYPE AXIS(1)") == "21"
    at(trio, 8100)
    assert trio.send("CONNECT(0, 0) AXIS(1)") == []
    for n in (1, 2000, 4000, 9000):
        at(trio, 8100 + n)
        k = min(n, 4000)
        expected = 4001 + 8000 + 2 * k - 0.0005 * k * (k + 1) / 2
        assert dpos(trio, 1) == pytest.approx(expected, abs=1e-6), n
    assert dpos(trio, 1) == pytest.approx(16000, abs=1e-6)
    assert trio.send("CANCEL AXIS(1)") == []
    at(trio, 20000)
    assert dpos(trio, 1) == pytest.approx(16000, abs=1e-6)


def test_the_clutch_rate_pages_example_in_a_program() -> None:
    """The page: CLUTCH_RATE 3, CONNECT(0), wait for input 1, CONNECT(6): 2 s to ratio 6
    (0.003 a cycle: 0.003 x 2000 x 2001 / 2 = 6003 counts over the ramp)."""
    trio = running_link()
    program = "BASE(1)\nCLUTCH_RATE = 3\nCONNECT(0, 0)\nWAIT UNTIL IN(1) = ON\n" \
              "CONNECT(6, 0)\nVR(10) = TICKS\n"
    assert trio.load("CLUTCH", program) == []
    assert trio.send('RUN "CLUTCH"') == []
    at(trio, 500)
    assert dpos(trio, 1) == 0.0  # connected at ratio 0
    trio.world_view().set_input(1, True)
    at(trio, 600)
    # the ramp began on the cycle the program saw the input: n cycles ago, where
    # 0.003 n (n + 1) / 2 is what the axis has moved
    moved = dpos(trio, 1)
    n = round((-1 + (1 + 8 * moved / 0.003) ** 0.5) / 2)
    assert moved == pytest.approx(0.003 * n * (n + 1) / 2, abs=1e-9)
    change = 600 - n
    assert 500 <= change <= 501
    at(trio, change + 2000)
    assert dpos(trio, 1) == pytest.approx(6003, abs=1e-6)
    at(trio, change + 3000)
    assert dpos(trio, 1) == pytest.approx(6003 + 6000, abs=1e-6)


def test_the_default_rate_changes_the_ratio_at_once() -> None:
    """1,000,000 a second is 1000 a cycle: a change from 2 to -0.5 is taken in one."""
    trio = running_link()
    assert trio.query("?CLUTCH_RATE AXIS(1)") == "1000000"
    trio.send("CONNECT(2, 0) AXIS(1)")
    at(trio, 300)
    trio.send("CONNECT(-0.5, 0) AXIS(1)")
    at(trio, 400)
    assert dpos(trio, 1) == pytest.approx(2 * 200 - 0.5 * 100, abs=1e-9)


def test_a_fresh_connect_takes_its_ratio_at_once_and_a_slow_rate_holds_the_change() -> None:
    """The CONNECT page: a fresh CONNECT steps to its ratio (hence its example's
    CONNECT(0) first); CLUTCH_RATE 0 never changes a running ratio; negative: refused."""
    trio = running_link()
    trio.send("BASE(1): CLUTCH_RATE = 0.1: CONNECT(3, 0)")
    at(trio, 200)
    assert dpos(trio, 1) == pytest.approx(300, abs=1e-9)
    assert trio.send("CLUTCH_RATE = -1") == ["! Parameter out of range"]
    assert trio.query("?CLUTCH_RATE") == "0.1000"
    trio.send("CLUTCH_RATE = 0: CONNECT(1, 0)")
    at(trio, 300)
    assert dpos(trio, 1) == pytest.approx(600, abs=1e-9)  # still 3 a count
    assert trio.machine.clutch.next_event() is None  # (no fold each tick at rate 0)
    trio.send("CLUTCH_RATE = 1")  # from now on 0.001 a cycle down towards 1
    at(trio, 400)
    assert dpos(trio, 1) == pytest.approx(600 + 3 * 100 - 0.001 * 100 * 101 / 2, abs=1e-9)


def test_the_web_line_example_runs_with_its_hand_worked_replies() -> None:
    """examples/mc405_clutch_and_live_cam.maxk under `maxk run`: its expected replies
    (worked out by hand in its header) must come back exactly."""
    from pathlib import Path

    from maxk.cli import main

    script = Path(__file__).parent.parent / "examples" / "mc405_clutch_and_live_cam.maxk"
    assert main(["run", str(script)]) == 0


def test_connect_takes_the_pages_mode_argument() -> None:
    """The CONNECT page's example 4: CONNECT(1, 2, 1) AXIS(3) follows axis 2's DPOS; mode
    0 (MPOS) is the default; no other mode."""
    trio = MC405()
    assert trio.send("CONNECT(1, 2, 1) AXIS(3)") == []
    assert trio.send("CONNECT(-2, 2, 0) AXIS(4)") == []
    assert trio.send("CONNECT(1, 2, 2) AXIS(5)") == ["! Parameter out of range"]
    assert trio.query("?MTYPE AXIS(5)") == "0"
    assert trio.send("BASE(2): SPEED=120: ACCEL=1000: DECEL=1000: MOVE(30)") == []
    at(trio, 150)  # 0.12 s to speed (7.2), then 0.03 s at 120: 3.6
    assert dpos(trio, 3) == pytest.approx(7.2 + 3.6, abs=1e-9)
    assert dpos(trio, 4) == pytest.approx(-2 * (7.2 + 3.6), abs=1e-9)


def test_a_movelink_on_a_clutching_axis_ends_on_the_exact_tick() -> None:
    """Axis 2 MOVELINKs over 5000 of axis 1's travel while axis 1 clutches in (0.0005 a
    cycle to 2): axis 1 is at 4001 after 4000 cycles, then 2 a cycle, so 5000 is reached
    on cycle 4500 (4001 + 2 x 499.5): the MOVELINK's end is found that far ahead."""
    trio = running_link()
    trio.send("BASE(1): CONNECT(0, 0): CLUTCH_RATE = 0.5: CONNECT(2, 0)")
    assert trio.send("MOVELINK(10, 5000, 0, 0, 1) AXIS(2)") == []
    at(trio, 4599)
    assert trio.query("?MTYPE AXIS(2)") == "22"
    assert dpos(trio, 1) == pytest.approx(4999, abs=1e-6)
    at(trio, 4600)
    assert trio.query("?MTYPE AXIS(2)") == "0"
    assert dpos(trio, 2) == pytest.approx(10, abs=1e-9)
