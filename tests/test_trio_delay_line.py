"""POSI_SEQ_MODE and POSI_SEQ_DELAY (TrioBASIC help POSI_SEQ_MODE, POSI_SEQ_DELAY): the
demand put out through a delay line of POSI_SEQ_DELAY servo cycles, seen in DPOS, in MPOS
and by the world's motor of a stepper (the encoder on its shaft, one count a step).

The move: SPEED 1000 counts/s at ACCEL = DECEL 100000 counts/s^2, so 10 cycles of ramp
(5 counts: k^2 / 20 counts k cycles in), then one count a cycle; MOVE(100) ends 110
cycles after it starts (95 counts at cycle 100).
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405

FAST = "SPEED=1000: ACCEL=100000: DECEL=100000"


def stepper(*lines: str) -> MC405:
    trio = MC405()
    for line in ("ATYPE AXIS(0) = 76", "BASE(4)", FAST, *lines):
        assert trio.send(line) == [], line
    trio.world_view().set_shaft_encoder("0", "4", 1.0)
    return trio


def demand(k: float) -> float:
    """MOVE(100)'s demand k cycles after it starts (by hand, from the profile)."""
    if k <= 0:
        return 0.0
    if k <= 10:
        return k * k / 20
    if k <= 100:
        return 5 + (k - 10)
    if k <= 110:
        return 100 - (110 - k) ** 2 / 20
    return 100.0


def read(trio: MC405) -> tuple[float, float, float]:
    return (float(trio.query("?DPOS")), float(trio.query("?MPOS")),
            float(trio.query("?ENCODER AXIS(0)")))


@pytest.mark.parametrize("k", [0, 5, 10, 11, 15, 30, 105, 110, 115, 120, 130])
def test_mode_1_puts_out_the_demand_of_delay_cycles_ago(k: int) -> None:
    trio = stepper("POSI_SEQ_DELAY=10", "POSI_SEQ_MODE=1")
    trio.advance(ticks=20)  # the buffer full: the delay acts from the move's start
    trio.send("MOVE(100)")
    start = trio.machine.tick
    trio.advance(ticks=k)
    dpos, mpos, steps = read(trio)
    assert abs(dpos - demand(k - 10)) < 1e-9 and abs(mpos - dpos) < 1e-9
    assert steps == int(demand(k - 10) + 0.5)  # the motor itself runs late (whole steps)
    assert trio.machine.tick == start + k


def test_mode_2_is_the_mean_and_nothing_is_delayed_until_the_buffer_is_full() -> None:
    trio = stepper("POSI_SEQ_DELAY=10")
    trio.send("POSI_SEQ_MODE=2: MOVE(100)")  # the buffer starts filling with the move
    start = trio.machine.tick
    for k in (5, 9):  # not full yet: the demand as it is
        trio.advance(ticks=start + k - trio.machine.tick)
        assert abs(read(trio)[0] - demand(k)) < 1e-9, k
    for k in (10, 15, 60, 115, 125):
        trio.advance(ticks=start + k - trio.machine.tick)
        assert abs(read(trio)[0] - (demand(k) + demand(k - 10)) / 2) < 1e-9, k
    trio.send("POSI_SEQ_MODE=0")  # off: the demand again at once
    assert read(trio)[0] == 100.0


def test_bad_settings_are_refused() -> None:
    trio = stepper()
    assert trio.send("POSI_SEQ_MODE=3") == ["! Parameter out of range"]
    assert trio.send("POSI_SEQ_DELAY=-1") == ["! Parameter out of range"]
    assert trio.send("POSI_SEQ_DELAY=10001") == ["! Parameter out of range"]
    assert (trio.query("?POSI_SEQ_MODE"), trio.query("?POSI_SEQ_DELAY")) == ("0", "0")


def test_a_servo_axis_s_loop_follows_the_delayed_demand() -> None:
    """Each cycle's output is P e + D (e - e_prev) with e = the demand of 10 cycles ago
    (by hand, `demand`) - measured: the loop closes on the delayed output; DPOS reads it."""
    p_gain, d_gain = 8.0, 120.0
    trio = MC405()
    for line in (f"ATYPE=77: P_GAIN={p_gain}: D_GAIN={d_gain}: SERVO=ON: WDOG=ON", FAST,
                 "POSI_SEQ_DELAY=10: POSI_SEQ_MODE=1"):
        assert trio.send(line) == [], line
    trio.advance(ticks=20)
    trio.send("MOVE(100)")
    m = trio.machine
    loop = m.axes[0].servo
    assert loop is not None
    start = m.tick
    e_prev = demand(-10) - loop.p
    for k in range(0, 200):
        e = demand(k - 10) - loop.p
        assert abs(float(trio.query("?DPOS")) - demand(k - 10)) < 1e-9, k
        trio.advance(ticks=1)
        expected = (p_gain * e + d_gain * (e - e_prev)) / 16.0
        assert abs(m.drive.following.dac_out(0) - expected) < 1e-6, k
        e_prev = e
    assert m.tick == start + 200
