"""What an MM4005 run did, for `maxk run --trace/--plot`: the path sampled every N ticks
(two axes for the XY trajectory, every axis for a time-based one), the whole pulse log
streamed through a temporary file (the machine's ring keeps only the newest), the XY path
with the pulses on it or, for a time-based run, every axis against time with the pulses
marked."""

from __future__ import annotations

import shutil
import tempfile
import weakref
from collections.abc import Callable
from pathlib import Path
from typing import IO, Protocol

from maxk.personalities.mm4005.execution import PulseRecord
from maxk.personalities.mm4005.machine import MM4005
from maxk.personalities.mm4005.timed import TracePoint
from maxk.plotting import pyplot, save


class MM4005Controller(Protocol):
    """What a recording reads of the controller (controllers/mm4005/controller.py)."""

    @property
    def machine(self) -> MM4005: ...

    @property
    def pulses(self) -> list[PulseRecord]: ...

    @property
    def trace_points(self) -> list[TracePoint]: ...

    @property
    def timed_log(self) -> bool: ...

    def pulse_header(self) -> tuple[str, ...]: ...

    def stream_pulses(self, stream: IO[str] | None) -> None: ...


class PathTrace:
    """Where two axes were (whole counts) every N ticks while the machine ran: the data
    a path plot draws, with the pulse log as the marks on it."""

    def __init__(self, machine: MM4005, axes: tuple[int, int], every_ticks: int) -> None:
        self.machine = machine
        self.axes = (machine.axis(axes[0]), machine.axis(axes[1]))
        self.every_ticks = every_ticks
        self.samples: list[tuple[int, int, int]] = []  # (tick, x counts, y counts)
        self.positions: list[tuple[float, ...]] = []  # every axis's TP, user units

    def attach(self) -> PathTrace:
        self.machine.add_observer(self.sample, self.every_ticks)
        self.sample(self.machine)
        return self

    def detach(self) -> None:
        self.machine.remove_observer(self.sample)

    def sample(self, machine: MM4005) -> None:
        x, y = self.axes
        self.samples.append((machine.tick, x.counts(machine), y.counts(machine)))
        self.positions.append(tuple(machine.position(n)
                                    for n in range(1, machine.axis_count + 1)))

    def csv(self) -> str:
        return "tick,x_counts,y_counts\n" + "".join(f"{t},{x},{y}\n" for t, x, y in self.samples)


class MM4005Recording:
    """A run's path samples and pulses: CSV (the pulses beside it as NAME.pulses.csv)
    and the XY path with every pulse marked on it."""

    def __init__(self, controller: MM4005Controller, trace: PathTrace) -> None:
        self.controller = controller
        self.trace = trace
        # every pulse of the run streams here as it fires (the ring keeps only the newest)
        self._pulses = tempfile.TemporaryFile("w+", encoding="utf-8", newline="")  # noqa: SIM115
        weakref.finalize(self, self._pulses.close)
        controller.stream_pulses(self._pulses)

    def write_csv(self, path: str) -> None:
        """The samples (XY runs: tick and X/Y counts; time-based runs: tick, time and
        every axis's position) and beside them NAME.pulses.csv, every pulse of the run."""
        c = self.controller
        self.trace.sample(c.machine)
        if c.timed_log:
            names = range(1, c.machine.axis_count + 1)
            rows = ["tick,time_s," + ",".join(f"{n}TP" for n in names)]
            period = c.machine.period
            rows += [f"{t},{t * period:.4f}," + ",".join(f"{v:.6f}" for v in pos)
                     for (t, _x, _y), pos in zip(self.trace.samples, self.trace.positions,
                                                 strict=True)]
            Path(path).write_text("\n".join(rows) + "\n")
        else:
            Path(path).write_text(self.trace.csv())
        self._pulses.flush()
        self._pulses.seek(0)
        with open(Path(path).with_suffix(".pulses.csv"), "w", encoding="utf-8") as out:
            out.write(",".join(c.pulse_header()) + "\n")
            shutil.copyfileobj(self._pulses, out)
        self._pulses.seek(0, 2)

    def plot(self, path: str, title: str, draw: Callable[..., object]) -> None:
        if self.controller.timed_log:
            self._plot_time(path, title)
            return
        self.trace.sample(self.controller.machine)
        samples = self.trace.samples
        x_axis, y_axis = (a.index + 1 for a in self.trace.axes)
        draw(path, [s[1] for s in samples], [s[2] for s in samples],
             marks=[(p.x_counts, p.y_counts) for p in self.controller.pulses],
             marks_label="synchronized pulses",
             axis_names=(f"axis {x_axis}", f"axis {y_axis}"), title=title or "MM4005 path")


    def _plot_time(self, path: str, title: str) -> None:
        """A time-based run: each axis's position against time, the pulses marked."""
        plt = pyplot()
        c = self.controller
        self.trace.sample(c.machine)
        period = c.machine.period
        times = [s[0] * period for s in self.trace.samples]
        moving = sorted(c.machine.timed.axes) or list(range(1, c.machine.axis_count + 1))
        fig, ax = plt.subplots(figsize=(9, 5))
        points = c.trace_points
        for n in moving:
            ax.plot(times, [p[n - 1] for p in self.trace.positions], linewidth=1.0,
                    label=f"axis {n}")
            ax.plot([p.tick * period for p in points], [p.actual[n - 1] for p in points],
                    "x", markersize=6, color="tab:red")
        ax.plot([], [], "x", color="tab:red", label=f"pulses ({len(points)})")
        ax.set_xlabel("time, s")
        ax.set_ylabel("position, units")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best")
        ax.set_title(title or "MM4005 time-based trajectory")
        save(fig, path)
