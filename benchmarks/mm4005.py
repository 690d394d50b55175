"""MM4005 benchmark: a 1,000-element trajectory with synchronized pulses.

A raster of 500 lines 10 units long joined by 500 half circles of radius 0.05 (the arcs
slow the path to sqrt(VS R)), run at VV 20 units/s, VS 1000 units/s^2, with pulses every
0.1 unit from element 2 to element 999 (about 50,000 pulses, each at its exact tick).
Figures: simulated seconds per wall second for the run, alone and with a host polling
MS, TP and TE at 10 Hz as the EPICS driver does while moving; and the time to define the
trajectory and pass ET.

    python -m benchmarks mm4005      (or: python -m benchmarks.mm4005)
"""

from __future__ import annotations

import time
from collections.abc import Callable

from benchmarks.figure import Figure
from maxk.controllers.mm4005.controller import MM4005Controller

ROWS = 250  # each row: LX, CA180, LX, CA-180 -> 1,000 elements
WIDTH = 10.0
RADIUS = 0.05
PULSE_STEP = 0.1


def raster_lines() -> list[str]:
    lines = ["NT", "FA0", "VV20", "VS1000", f"CR{RADIUS}"]
    for _ in range(ROWS):
        lines += [f"LX{WIDTH}", "CA180", "LX0", "CA-180"]
    return lines


def _define(mm: MM4005Controller, pulses: int) -> float:
    """Define the raster and start it; the wall seconds that took."""
    start = time.perf_counter()
    for line in raster_lines():
        mm.send(line)
    mm.send(f"NB2;NE{4 * ROWS - 1};NN{pulses};NS;ET")
    wall = time.perf_counter() - start
    assert mm.query("TE") == "TE@", "ET refused"
    assert mm.query("XT") == f"XT{4 * ROWS}"
    return wall


def _pulse_count() -> int:
    """NN for a pulse every PULSE_STEP between the start of 2 and the end of 999."""
    mm = MM4005Controller("MM4005-2")
    for line in raster_lines():
        mm.send(line)
    elements = mm.machine.trajectory.elements[1 : 4 * ROWS - 1]
    return round(sum(e.geometry.length for e in elements) / PULSE_STEP) + 1


def run(poll_hz: float | None) -> tuple[float, float, float, int]:
    """(simulated s, wall s of the run, wall s of the definition, pulses fired)."""
    pulses = _pulse_count()
    mm = MM4005Controller("MM4005-2")
    mm.send("1PA-5;2PA-1")  # stand clear of the travel limits
    mm.run_until_idle()
    define_wall = _define(mm, pulses)
    begin = mm.time
    start = time.perf_counter()
    if poll_hz is None:
        assert mm.run_until_idle(timeout=3600.0)
    else:
        step = mm.ticks(1.0 / poll_hz)
        while not mm.machine.is_idle():
            mm.advance(ticks=step)
            mm.send("MS;")
            mm.send("TP;")
            mm.send("TE;")
    wall = time.perf_counter() - start
    fired = mm.machine.pulse_trace.total  # (the log keeps only the newest 20,000)
    assert fired == pulses, (fired, pulses)
    return mm.time - begin, wall, define_wall, pulses


def _best(runs: int, fn: Callable[[], tuple[float, float, float, int]]
          ) -> tuple[float, float, float, int]:
    results = [fn() for _ in range(runs)]
    return max(results, key=lambda r: r[0] / r[1])


TIMED_ELEMENTS = 1000
TIMED_DT = 0.05  # s per element: 50 s of trajectory


def run_timed() -> tuple[float, float, int]:
    """The EPICS trajectory scan's time-based trajectory: 2 axes on a Lissajous figure,
    1,000 elements of 0.05 s, a pulse per element. (simulated s, wall s, pulses)."""
    import math
    mm = MM4005Controller("MM4005-2")
    lines = ["NC", "1DC1", "2DC1", "UC0.5"]
    point = (0.0, 0.0)
    for i in range(1, TIMED_ELEMENTS + 1):
        nxt = (5 * math.sin(i / 50), 3 * math.sin(i / 35))
        lines.append(f"{i}DT{TIMED_DT:f};1DX{nxt[0] - point[0]:f};2DX{nxt[1] - point[1]:f}")
        point = nxt
    lines.append(f"MB1,ME{TIMED_ELEMENTS},MN{TIMED_ELEMENTS + 1}")
    lines.append("VC")
    for line in lines:
        mm.send(line)
    assert mm.query("TB") == "TB@ No error"
    mm.send("0EC1")
    begin = mm.time
    start = time.perf_counter()
    assert mm.run_until_idle(timeout=3600.0)
    wall = time.perf_counter() - start
    fired = mm.machine.pulse_trace.total
    assert fired == TIMED_ELEMENTS, fired
    return mm.time - begin, wall, fired


def figures() -> list[Figure]:
    timed = max((run_timed() for _ in range(3)), key=lambda r: r[0] / r[1])
    simulated, wall, define_wall, pulses = _best(3, lambda: run(None))
    polled = _best(3, lambda: run(10.0))
    note = f"1,000 elements, {pulses:,} pulses, {simulated:.0f} s of path"
    return [
        Figure("mm4005_timed_trajectory_pulses", timed[0] / timed[1],
               "simulated s per wall s", 500.0,
               f"EPICS scan's time-based trajectory: 1,000 elements x 2 axes, {timed[2]:,} "
               f"pulses, {timed[0]:.0f} s"),
        Figure("mm4005_trajectory_pulses_free", simulated / wall, "simulated s per wall s",
               500.0, note),
        Figure("mm4005_trajectory_pulses_polled", polled[0] / polled[1],
               "simulated s per wall s", 500.0, note + ", MS+TP+TE at 10 Hz"),
        Figure("mm4005_trajectory_define_and_et", define_wall * 1000.0, "ms", None,
               "1,005 command lines and ET (pulse plan included)"),
    ]


def main() -> int:
    for fig in figures():
        target = f">= {fig.target:,.0f}" if fig.target else ""
        print(f"{fig.name:<34} {fig.value:>14,.3f}  {fig.unit:<24} {target:>10}  {fig.note}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
