"""The servo figures' yardstick and the contour figure.

`naive_reference` is what every speed figure is read against: the shared naive loop (10
PID axes stepped tick by tick at 8192 Hz in plain Python floats, nothing clever), run in
the same process as the figures it divides, so a loaded machine moves both alike.

`circle` is MAXk vector contouring on two servo axes: full circles (VC) at a vector
velocity, where the commanded positions are not polynomials and every tick is stepped.
"""

from __future__ import annotations

import time

from benchmarks import naive_servo
from benchmarks.figure import Figure
from maxk import MAXk


def naive_reference(sim_seconds: float = 1.0) -> Figure:
    """The yardstick: the shared naive loop (benchmarks/naive_servo.py), best of three
    runs of one simulated second, as the shared file's own main measures it."""
    run, which = naive_servo.loop()
    best = max(run(sim_seconds) for _ in range(3))
    return Figure("naive_10_pid_axes", best, "simulated s per wall s", None,
                  f"10 PID axes stepped tick by tick at 8192 Hz: {which}")


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
