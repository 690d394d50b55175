"""DAC_OUT (TrioBASIC help DAC_OUT) after a long closed-form stretch of the shared servo
loop: it reads the output of the servo cycle before the one read, not the last cycle the
loop happened to step one by one before a jump.

With ERRORMASK 0 nothing watches the following error, so the loop jumps in closed form
over a long, slow acceleration ramp (ACCEL 50 counts/s^2 to 5000 counts/s: 100 s). On
such a ramp the motor's speed grows by ACCEL x the time, and the output that holds it
grows with it: the plant's steady speed is G (u - friction) / A (the shared motor: see
tests/test_trio_servo_output.py), so 40 s later the output is A x 50 x 40 / G more, in
DAC_OUT's 12-bit counts / 16.
"""

from __future__ import annotations

import math

from maxk.controllers.trio import MC405

TORQUE_PER_COUNT = 0.1 * 3.0 / 2.0 * 10.0 / 32767.0
G = TORQUE_PER_COUNT / 5e-6 * 8000.0 / (2.0 * math.pi)
A = (2e-5 + 0.1 ** 2 / 2.0) / 5e-6
RAMP = "ATYPE=77: P_GAIN=8: D_GAIN=120: SERVO=ON: WDOG=ON: SPEED=5000: ACCEL=50: DECEL=50"


def dac_out_at(ticks: tuple[int, ...], watched: bool) -> list[float]:
    trio = MC405()
    assert trio.send(RAMP + ("" if watched else ": ERRORMASK=0")) == []
    trio.advance(ticks=10)
    trio.send("MOVE(1000000)")
    out = []
    for tick in ticks:
        trio.advance(ticks=tick - trio.machine.tick)
        out.append(float(trio.machine.drive.following.dac_out(0)))
    return out


def test_dac_out_follows_the_ramp_across_a_closed_form_stretch() -> None:
    first, second = dac_out_at((40010, 80010), watched=False)
    assert abs((second - first) - A * 50 * 40 / G / 16) < 1e-3
    # the same as the loop stepped cycle by cycle (FE watched: every cycle looked at)
    stepped = dac_out_at((40010, 80010), watched=True)
    assert abs(first - stepped[0]) < 1e-6 and abs(second - stepped[1]) < 1e-6
