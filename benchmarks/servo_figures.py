"""The servo figures' yardstick and the contour figure.

`naive_reference` is what the servo figures are read against: 10 PID axes on the same
discretized motor, stepped tick by tick at 8192 Hz in plain Python floats, with nothing
clever (no closed form, no events, no compiled code). Its rate is measured in the same
process as the figures it divides, so a loaded machine moves both alike.

`circle` is MAXk vector contouring on two servo axes: full circles (VC) at a vector
velocity, where the commanded positions are not polynomials and every tick is stepped.
"""

from __future__ import annotations

import math
import time

from benchmarks.figure import Figure
from maxk import MAXk
from maxk.firmware_model.motor import MotorPlant

NAIVE_AXES = 10
NAIVE_RATE_HZ = 8192


def _naive_run(sim_seconds: float) -> tuple[float, float]:
    """10 axes, each commanded back and forth at its own speed (a triangle wave of
    position), PID with integrator clamp and DAC saturation, the motor's 2x2 update."""
    a11, a12, a21, a22, b1, b2 = MotorPlant().discrete(1.0 / NAIVE_RATE_HZ)
    kp, kd, ki, cap = 100.0, 400.0, 40.0 / 1024.0, 4.0 * 400.0 / (40.0 / 1024.0)
    speeds = [(10_000 + 4_000 * k) / NAIVE_RATE_HZ for k in range(NAIVE_AXES)]
    half = NAIVE_RATE_HZ // 4  # a quarter second each way
    ticks = round(sim_seconds * NAIVE_RATE_HZ)
    ends = []
    start = time.perf_counter()
    for speed in speeds:  # axis by axis: each loop's state in locals, the fastest plain form
        p = w = s = q = r = 0.0
        for tick in range(ticks):
            r += speed if (tick // half) % 2 == 0 else -speed
            e = r - p
            s = max(-cap, min(cap, s + e))
            u = kp * e + kd * (e - q) + ki * s
            u = max(-32767.0, min(32767.0, u))
            q = e
            p, w = a11 * p + a12 * w + b1 * u, a21 * p + a22 * w + b2 * u
        ends.append(p)
    wall = time.perf_counter() - start
    assert all(math.isfinite(x) and abs(x) < 1e6 for x in ends)  # the loops held
    return sim_seconds, wall


def naive_reference(sim_seconds: float = 3.0) -> Figure:
    """The yardstick: best of three runs."""
    best = max(sim / wall for sim, wall in (_naive_run(sim_seconds) for _ in range(3)))
    return Figure("naive_10_pid_axes", best, "simulated s per wall s", None,
                  "10 PID axes stepped tick by tick in plain Python floats at 8192 Hz")


CIRCLE_SETUP = ("AA; PSM,M; LP0,0; KP100,100; KD400,400; KI40,40; KU400,400; KV680,680; "
                "CL1,1;")
CIRCLE_PATH = "AA; VA200000; VV20000,20000; VP0,0; VC0,5000,3600; VC0,5000,-3600; VE;"
"""Ten turns of a 5000-count radius one way and ten back: 31.4 s at 20,000 counts/s."""


def circle(sim_seconds: float = 30.0) -> Figure:
    """Two servo axes of a MAXk-4000 contouring circles (VC) at 20,000 counts/s."""

    def run() -> float:
        board = MAXk("MAXk-4000")
        board.send(CIRCLE_SETUP)
        board.advance(0.01)  # first-use costs (the plant, the closed loop) stay out
        board.send(CIRCLE_PATH)
        start = time.perf_counter()
        board.advance(sim_seconds)
        wall = time.perf_counter() - start
        assert board.query("AA CL?").startswith("on,on")  # no axis tripped
        assert not board.command_error, board.last_error
        return sim_seconds / wall

    best = max(run() for _ in range(3))
    return Figure("servos_2_axes_circle", best, "simulated s per wall s", None,
                  "MAXk-4000, X and Y servo axes contouring 10 turns each way (VC)")
