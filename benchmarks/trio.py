"""The Trio MC405 benchmark: the PWM application note's example 2 (a laser's power from
the path speed times a CAMBOX profile along a 40000-long box path) run for ten simulated
minutes with the mark of every servo cycle (1 ms) recorded in a trace.

    PYTHONPATH=$PWD python3 -m benchmarks.trio     (or: python3 -m benchmarks trio)
"""

from __future__ import annotations

import time

from maxk.controllers.trio.controller import MC405
from tests.trio_helpers import EXAMPLE_2

TARGET = 200.0  # simulated seconds per wall second


def example_2(sim_seconds: float = 600.0, poll_hz: float | None = None) -> tuple[float, int]:
    """Run example 2 (the loop never ends) for `sim_seconds`, tracing every servo cycle's
    mark, gate and duty; optionally a host reads PWM_MARK at `poll_hz`. Returns
    (simulated seconds per wall second, servo cycles traced)."""
    trio = MC405()
    assert trio.load("EX2", EXAMPLE_2) == []
    assert trio.send('RUN "EX2"') == []
    trace = trio.trace(pwm_axes=(4,), xy=(0, 1))
    end = trio.tick + trio.ticks(sim_seconds)
    start = time.perf_counter()
    if poll_hz is None:
        trio.machine.advance_to(end)
    else:
        step = trio.ticks(1.0 / poll_hz)
        while trio.tick < end:
            trio.machine.advance_to(min(end, trio.tick + step))
            trio.query("?PWM_MARK AXIS(4)")
    wall = time.perf_counter() - start
    marks = trace.column("mark4")
    assert len(marks) == end + 1 and marks.max() == 500 and 50 in marks  # really computed
    return sim_seconds / wall, len(marks)


def main() -> int:
    for label, poll in (("free", None), ("host polling PWM_MARK at 10 Hz", 10.0)):
        ratio, cycles = example_2(poll_hz=poll)
        print(f"trio_example_2 ({label}): {ratio:,.0f} simulated s per wall s "
              f"({cycles:,} servo cycles traced; target >= {TARGET:.0f})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
