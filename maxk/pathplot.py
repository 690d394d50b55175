"""XY path plots: where two axes went during a run, and where an output was on.

`maxk run SCRIPT --plot PNG` samples the motor positions (RP) of two axes every update
cycle or every N ticks while the script runs, and draws the path into a PNG with
matplotlib (the ``plot`` extra), the stretches where an output bit was high in another
colour: for a contour with VIO, the torch-on part of the cut.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from maxk.controllers.contract import Controller
from maxk.plotting import pyplot, save


class PathRecorder:
    """Samples two axes' positions (and one output bit) as the controller runs."""

    def __init__(self, controller: Controller, axes: tuple[str, str] = ("X", "Y"),
                 every_ticks: int = 8, bit: int | None = None) -> None:
        self.engine = controller.engine
        self.view = controller.world_view()
        self.axes = (self.view.axis_names[self.view.index(axes[0])],
                     self.view.axis_names[self.view.index(axes[1])])
        if bit is not None and self.view.output_level(bit) is None:
            raise ValueError(f"the {controller.kind} has no output {bit}")
        self.every_ticks = every_ticks
        self.bit = bit
        self.time: list[float] = []
        self.x: list[int] = []
        self.y: list[int] = []
        self.on: list[bool] = []

    def attach(self) -> None:
        self.engine.add_observer(self.sample, self.every_ticks)
        self.sample()

    def detach(self) -> None:
        self.engine.remove_observer(self.sample)

    def sample(self, _engine: object = None) -> None:
        view = self.view
        self.time.append(self.engine.time)
        self.x.append(view.reading(self.axes[0]).position)
        self.y.append(view.reading(self.axes[1]).position)
        self.on.append(self.bit is not None and bool(view.output_level(self.bit)))

    def plot(self, path: str | Path, title: str = "") -> Path:
        """Write the path to a PNG. Raises ImportError with advice when matplotlib is not
        installed."""
        return draw_path(path, self.x, self.y,
                         on=self.on if self.bit is not None else None,
                         on_label=f"output {self.bit} high",
                         axis_names=self.axes, title=title)


def draw_path(path: str | Path, x: Sequence[float], y: Sequence[float], *,
              on: Sequence[bool] | None = None, on_label: str = "output high",
              marks: Sequence[tuple[float, float]] = (), marks_label: str = "pulses",
              axis_names: tuple[str, str] = ("X", "Y"), title: str = "") -> Path:
    """An XY path as a PNG: the stretches where an output was on drawn over it, and
    points marked on it (the MM4005's synchronized pulses). Any controller's samples."""
    plt = pyplot()
    path = Path(path)
    fig, ax = plt.subplots(figsize=(7, 7))
    ax.plot(x, y, color="0.6", linewidth=1.0, label="path")
    if on is not None and any(on):
        # the stretches with the output high, drawn over the path
        xs = [a if lit else float("nan") for a, lit in zip(x, on, strict=True)]
        ys = [b if lit else float("nan") for b, lit in zip(y, on, strict=True)]
        ax.plot(xs, ys, color="tab:red", linewidth=2.0, label=on_label)
    if marks:
        ax.plot([m[0] for m in marks], [m[1] for m in marks], "x", color="tab:red",
                markersize=7, label=f"{marks_label} ({len(marks)})")
    if len(x):
        ax.plot(x[0], y[0], "o", color="tab:green", label="start")
        ax.plot(x[-1], y[-1], "s", color="tab:blue", label="end")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"{axis_names[0]} position, counts")
    ax.set_ylabel(f"{axis_names[1]} position, counts")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    ax.set_title(title or "maxk path")
    return save(fig, path)
