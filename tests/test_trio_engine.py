"""The MC405 on the shared engine: the seed's three examples as written, exact in virtual
time (one tick = one servo cycle of 1 ms), with ramps, MERGE, CONNPATH and CAMBOX.

Expected values come from the kinematics worked out here by hand (trapezoids and
triangles at ACCEL), not from the planner, and the marks from the seed's formulas.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from maxk.controllers.trio.controller import MC405
from tests.trio_helpers import EXAMPLE_1, EXAMPLE_2, EXAMPLE_3

DT = 0.001  # s per servo cycle (SERVO_PERIOD 1000 us)


def started(text: str, name: str, edit: tuple[int, str] | None = None) -> MC405:
    trio = MC405()
    assert trio.load(name, text) == []
    if edit is not None:
        assert trio.send(f"!{name},{edit[0]}R{edit[1]}") == []
    assert trio.send(f'RUN "{name}"') == []
    return trio


def read(trio: MC405, what: str) -> float:
    return float(trio.query(f"?{what}"))


def mark_rule(speed: float) -> int:
    """Example 1: VP_SPEED * 0.1 + 50, held at 500 (the seed's numbers)."""
    return min(500, int(speed * 0.1 + 50))


# ---- example 1: the mark follows the path speed around the square --------------------------
def test_example_1_every_servo_cycle_along_the_square() -> None:
    trio = started(EXAMPLE_1, "EX1")
    trace = trio.trace(pwm_axes=(4,), xy=(0, 1))
    # RUN at tick 0; the program's first cycle (tick 1) loads the four merged moves and
    # reaches WA(10); PWM_CONTROL(2,...) runs on tick 11.
    trio.advance(ticks=10)
    assert read(trio, "PWM_MARK AXIS(4)") == 0  # mode 0 still: the register
    samples = []
    for _ in range(8200):  # the square takes 8.1 s: 0.1 s ramps at 50000, 40000 at 5000
        trio.advance(ticks=1)
        samples.append((trio.tick, read(trio, "VP_SPEED AXIS(0)"),
                        read(trio, "PWM_MARK AXIS(4)")))
    for tick, speed, mark in samples:
        t = (tick - 1) * DT
        expected = 50000 * t if t < 0.1 else 5000 if t <= 8.0 else max(0.0, 50000 * (8.1 - t))
        assert speed == pytest.approx(expected, abs=1e-6), tick
        value = min(500.0, expected * 0.1 + 50)  # truncated: float noise may sit below
        assert math.floor(value - 1e-6) <= mark <= math.floor(value + 1e-6), tick
    by_tick = {t: m for t, _s, m in samples}
    assert by_tick[12] == 105  # 550 units/s on the ramp: 55 + 50
    assert by_tick[100] == 500  # 4950 -> 545, held at 500
    assert by_tick[91] == 500 and by_tick[90] == 495  # 4500 -> exactly the limit
    assert by_tick[4000] == 500  # corners merged: no stop, still at 5000
    assert by_tick[8101] == 50 and by_tick[8200] == 50  # at rest again: the offset
    assert (read(trio, "DPOS AXIS(0)"), read(trio, "DPOS AXIS(1)")) == (0, 0)
    # the trace holds the very same mark of every servo cycle
    ticks, marks = trace.column("tick"), trace.column("mark4")
    assert list(ticks) == list(range(0, 8211))
    assert [int(marks[t]) for t, _s, _m in samples] == [int(m) for *_x, m in samples]


def test_example_1_mark_250_at_speed_2000() -> None:
    trio = started(EXAMPLE_1, "EX1", edit=(1, "SPEED=2000"))
    trio.advance(ticks=300)
    assert read(trio, "VP_SPEED AXIS(0)") == 2000
    assert read(trio, "PWM_MARK AXIS(4)") == 250  # the comment: 2000 * 0.1 + 50
    assert trio.machine.duty(4) == 0.25  # WDOG ON, ATYPE 35, PWM_CYCLE 1000


@pytest.mark.parametrize("speed, mark", [(4000, 450), (4500, 500), (4600, 500), (9000, 500)])
def test_example_1_held_at_the_limit_above_4500(speed: int, mark: int) -> None:
    trio = started(EXAMPLE_1, "EX1", edit=(1, f"SPEED={speed}"))
    trio.advance(ticks=400)
    assert read(trio, "VP_SPEED AXIS(0)") == speed
    assert read(trio, "PWM_MARK AXIS(4)") == mark


def test_example_1_mark_50_at_rest_and_it_stays_after_the_mode_ends() -> None:
    trio = started(EXAMPLE_1, "EX1")
    assert trio.run_until_idle(20)
    assert read(trio, "PWM_MARK AXIS(4)") == 50
    trio.send("BASE(0,1): MOVE(1000,0)")
    trio.advance(ticks=150)
    assert read(trio, "PWM_MARK AXIS(4)") == 500
    trio.send("PWM_CONTROL(1) AXIS(4)")  # the last loaded mark stays in the register
    trio.advance(ticks=200)
    assert read(trio, "PWM_MARK AXIS(4)") == 500


# ---- example 2: the mark follows the CAMBOX profile along the box path ----------------------
PROFILE = [0, 0, 0, 0, 1000, 1000, 1000, 0, 0]  # TABLE(1000..1008), 5000 path units apart


def profile_at(distance: float) -> float:
    x = min(max(distance / 5000.0, 0.0), 8.0)
    j = min(int(x), 7)
    return PROFILE[j] + (PROFILE[j + 1] - PROFILE[j]) * (x - j)


def test_example_2_mark_follows_the_cambox_profile_along_the_40000_path() -> None:
    trio = started(EXAMPLE_2, "EX2")
    trace = trio.trace(pwm_axes=(4,), xy=(0, 1))
    # the program reaches the WHILE loop after its WA(10): the first pass's path runs from
    # tick 11 to 4211 (ramps of 0.2 s at 50000 to 10000, 4.2 s in all)
    trio.advance(ticks=4215)
    ticks = trace.column("tick")
    first = int(np.searchsorted(ticks, 12))  # PWM_CONTROL(8,...) ran on tick 11
    x, y, mark = trace.column("x")[first:], trace.column("y")[first:], trace.column("mark4")[
        first:]
    # path distance along the square from the XY position (10000-long sides)
    side = np.select([(y == 0) & (x > 0), x == 10000, y == -10000], [x, 10000 - y,
                     20000 + 10000 - x], 30000 + 10000 + y)
    moving = ticks[first:] <= 4211
    for i in np.flatnonzero(moving)[::7]:
        tick = int(ticks[first + i])
        t = (tick - 11) * DT
        speed = 50000 * t if t < 0.2 else 10000 if t <= 4.0 else max(0.0, 50000 * (4.2 - t))
        amplitude = profile_at(side[i])
        value = min(500.0, speed * amplitude / 10000 + 50)
        assert math.floor(value - 1e-6) <= int(mark[i]) <= math.floor(value + 1e-6), tick
    at = {d: int(mark[int(np.argmin(np.abs(side - d)))]) for d in (2000, 10000, 17500,
                                                                   25000, 32500, 37500)}
    assert at == {2000: 50, 10000: 50, 17500: 500, 25000: 500, 32500: 500, 37500: 50}
    # the amplitude axis really is the CAMBOX profile of the path distance
    assert read(trio, "DPOS AXIS(8)") == 40000 and read(trio, "DPOS AXIS(9)") == 0


def test_example_2_read_every_cycle_of_the_profile_ramp_and_the_second_pass() -> None:
    trio = started(EXAMPLE_2, "EX2")
    trio.advance(ticks=1510)  # at 10000/s from tick 211: path 13000 at tick 1511
    for _ in range(400):  # the profile rises from 0 (path 15000) to 1000 (20000)
        trio.advance(ticks=1)
        path, amplitude = read(trio, "DPOS AXIS(8)"), read(trio, "DPOS AXIS(9)")
        assert path == pytest.approx(10000 * (trio.tick - 11) * DT - 1000, abs=1e-6)
        assert amplitude == pytest.approx(profile_at(path), abs=1e-6)
        value = min(500.0, 10000 * profile_at(path) / 10000 + 50)
        assert math.floor(value - 1e-6) <= read(trio, "PWM_MARK AXIS(4)") <= math.floor(
            value + 1e-6)
    assert trio.machine.axis_idle(9) is False
    # end of the pass: WAIT IDLE, WA(10), DEFPOS(0) AXIS(8), then the loop goes round again
    trio.advance(ticks=4211 - trio.tick)
    assert read(trio, "DPOS AXIS(8)") == 40000 and trio.machine.axis_idle(9)
    trio.advance(ticks=4220 - trio.tick)
    assert read(trio, "DPOS AXIS(8)") == 40000
    trio.advance(ticks=1)
    assert read(trio, "DPOS AXIS(8)") == 0  # DEFPOS(0) AXIS(8) on tick 4221
    trio.advance(ticks=2000)
    assert read(trio, "DPOS AXIS(9)") == pytest.approx(profile_at(read(trio, "DPOS AXIS(8)")))
    assert read(trio, "PWM_MARK AXIS(4)") == 500


# ---- example 3: the gate toggles at the exact ticks the axis passes the positions ---------------
A = 1000 * 16  # ACCEL in counts/s^2 (UNITS=16, ACCEL at its power-up 1000)
HALF = math.sqrt(4800 / A)  # the 300-unit move is a triangle: half its time


def tick_passing(counts: int, start: int, going_out: bool) -> int:
    """The first tick after `start` at which the axis's whole counts have gone past
    `counts` (GT: above it going out, LT: below it coming back)."""
    k = 1
    while True:
        t = k * DT
        travelled = 0.5 * A * t * t if t <= HALF else 4800 - 0.5 * A * (2 * HALF - t) ** 2
        position = int(travelled) if going_out else 4800 - int(travelled)
        if (position > counts) if going_out else (position < counts):
            return start + k
        k += 1


def test_example_3_gate_toggles_at_the_positions_going_out_and_back() -> None:
    trio = started(EXAMPLE_3, "EX3")
    trio.advance(ticks=2200)
    edges = [(e.tick, e.position / 16, e.level) for e in trio.machine.gate_edges]
    out_end = 1 + math.ceil(2 * HALF / DT)  # MOVEABS(300) from tick 1
    expected = [(tick_passing(p * 16, 1, True), p, lvl)
                for p, lvl in ((110, True), (115, False), (195, True), (220, False))]
    expected += [(tick_passing(p * 16, out_end, False), p, lvl)
                 for p, lvl in ((220, True), (195, False), (115, True), (110, False))]
    assert edges[:8] == expected
    assert [t for t, _p, _l in expected] == [471, 481, 639, 697, 1498, 1556, 1713, 1724]


def test_example_3_gate_and_duty_every_cycle_match_the_encoder() -> None:
    trio = started(EXAMPLE_3, "EX3")
    trace = trio.trace(pwm_axes=(0,), xy=(0, 1))
    trio.advance(ticks=1)
    rows = []
    for _ in range(1100):
        trio.advance(ticks=1)
        rows.append((trio.tick, int(read(trio, "PWM_ENCODER AXIS(0)")),
                     trio.machine.duty(0)))
    on = [(t, enc) for t, enc, duty in rows if duty == 0.4]
    # going out the output is on from past 110 up to 115, and from past 195 up to 220
    assert all(1760 < enc <= 1840 or 3120 < enc <= 3520 for _t, enc in on)
    assert {t for t, _e in on} == set(range(471, 481)) | set(range(639, 697))
    duty = trace.column("duty0")
    assert [trace.column("tick")[i] for i in np.flatnonzero(duty == 0.4)][:3] == [471, 472,
                                                                                 473]
    assert int(trace.column("gate0")[list(trace.column("tick")).index(481)]) == 0


def test_example_3_defpos_leaves_pwm_encoder_and_control_6_clears_it() -> None:
    trio = started(EXAMPLE_3, "EX3")
    trio.advance(ticks=500)
    before = read(trio, "PWM_ENCODER AXIS(0)")
    assert before == int(read(trio, "MPOS AXIS(0)") * 16)
    trio.send("DEFPOS(1000) AXIS(0)")
    assert read(trio, "PWM_ENCODER AXIS(0)") == before
    assert read(trio, "DPOS AXIS(0)") == 1000
    trio.send("PWM_CONTROL(6) AXIS(0)")
    assert read(trio, "PWM_ENCODER AXIS(0)") == 0
