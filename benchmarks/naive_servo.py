"""The one yardstick every speed figure is divided by: the project's shared naive loop.

`run` is, line for line, the computation of the shared bench's `naive_servo.py` (10 PID
axes on a stable second-order plant, stepped tick by tick in plain Python floats at 8192
Hz); `tests/test_benchmarks_yardstick.py` holds the two equal, statement for statement.
Where the shared file is beside the checkout (`../shared/bench/naive_servo.py`, as on the
project's machines and in CI) the benchmarks run that file itself; elsewhere this copy.
Either way it runs in the same process, in the same minute, as the figures it divides.
"""

from __future__ import annotations

import importlib.util
import time
from collections.abc import Callable
from pathlib import Path

RATE = 8192
AXES = 10

SHARED_LOOP = Path(__file__).resolve().parent.parent.parent / "shared" / "bench" / \
    "naive_servo.py"
"""Where the shared loop lives relative to a checkout (the repo's parent's shared/)."""


def run(seconds: float) -> float:
    a1, a2, b1, b2 = 1.9, -0.9, 0.0004, 0.00039  # a stable second-order plant
    kp, ki, kd = 10.0, 1.0 / 1024, 160.0
    y = [0.0] * AXES; y1 = [0.0] * AXES; u1 = [0.0] * AXES; u2 = [0.0] * AXES  # noqa: E702
    e1 = [0.0] * AXES; acc = [0.0] * AXES  # noqa: E702
    n = int(seconds * RATE)
    t0 = time.perf_counter()
    for k in range(n):
        target = 1000.0 * (k / n)
        for i in range(AXES):
            e = target - y[i]
            acc[i] += e
            u = kp * e + kd * (e - e1[i]) + ki * acc[i]
            if u > 32767.0:
                u = 32767.0
            elif u < -32767.0:
                u = -32767.0
            yn = a1 * y[i] + a2 * y1[i] + b1 * u1[i] + b2 * u2[i]
            y1[i] = y[i]; y[i] = yn; u2[i] = u1[i]; u1[i] = u; e1[i] = e  # noqa: E702
    return seconds / (time.perf_counter() - t0)


def loop() -> tuple[Callable[[float], float], str]:
    """The shared file's `run` when it is there, else this module's; and which it is."""
    if SHARED_LOOP.is_file():
        spec = importlib.util.spec_from_file_location("_shared_naive_servo", SHARED_LOOP)
        if spec is not None and spec.loader is not None:
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
            shared_run: Callable[[float], float] = module.run
            return shared_run, "the shared naive_servo.py"
    return run, "benchmarks/naive_servo.py (the shared loop's copy)"
