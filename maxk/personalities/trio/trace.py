"""What the PWM outputs did, servo cycle by servo cycle: a trace, a CSV and a path plot.

A `PwmTrace` attached to the machine records every servo cycle while the engine runs:
the demand positions of two axes (the XY path) and, per PWM axis, the mark, the gate and
the duty (the fraction of each PWM period the combined output is on). Between events the
machine is closed form, so each stretch is one array evaluation (`marks_at`,
`dpos_at`); the tick of an event is recorded again after the event acted (a gate that
toggles there shows its new level from that tick).
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from pathlib import Path
from typing import Protocol

import numpy as np

from maxk.plotting import pyplot, save

from .pwm import PWM_ATYPES, PwmBank, PwmMode


class _Params(Protocol):
    @property
    def params(self) -> dict[str, float]: ...


class Traced(Protocol):
    """What a trace reads of the machine (the MC405 machine, by its own methods)."""

    @property
    def pwm(self) -> PwmBank: ...
    @property
    def axes(self) -> Sequence[_Params]: ...
    @property
    def system(self) -> dict[str, float]: ...
    @property
    def period(self) -> float: ...

    def dpos_at(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...
    def marks_at(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...


class PwmTrace:
    """Every servo cycle's XY position and PWM mark, gate and duty."""

    def __init__(self, machine: Traced, pwm_axes: tuple[int, ...] = (4,),
                 xy: tuple[int, int] = (0, 1)) -> None:
        for axis in pwm_axes:
            machine.pwm[axis]  # refuses an axis without a PWM output
        self.machine = machine
        self.pwm_axes = pwm_axes
        self.xy = xy
        self._chunks: list[dict[str, np.ndarray]] = []

    # ---- recording (called by the machine) --------------------------------------------
    def stretch(self, first: int, last: int) -> None:
        """Ticks first..last, with the motion and outputs as they are now."""
        if last < first:
            return
        self._append(self._sample(np.arange(first, last + 1)))

    def at_event(self, now: int) -> None:
        """The tick `now` again, after its events acted."""
        row = self._sample(np.array([now]))
        if self._chunks and self._chunks[-1]["tick"][-1] == now:
            last = self._chunks[-1]
            for name, values in row.items():
                last[name][-1] = values[0]
        else:
            self._append(row)

    def _append(self, chunk: dict[str, np.ndarray]) -> None:
        self._chunks.append({k: v.copy() for k, v in chunk.items()})

    def _sample(self, ticks: np.ndarray) -> dict[str, np.ndarray]:
        m = self.machine
        out: dict[str, np.ndarray] = {"tick": ticks.astype(np.int64),
                                      "x": m.dpos_at(self.xy[0], ticks),
                                      "y": m.dpos_at(self.xy[1], ticks)}
        wdog = m.system.get("WDOG", 0) != 0
        for axis in self.pwm_axes:
            output = m.pwm[axis]
            marks = m.marks_at(axis, ticks)
            gate = np.full(ticks.shape, output.gate_open)
            enabled = (wdog and int(m.axes[axis].params["ATYPE"]) in PWM_ATYPES
                       and output.mode is not PwmMode.OFF)
            duty = np.minimum(marks / output.cycle, 1.0)
            duty = np.where(gate & (marks > 0) & enabled, duty, 0.0)
            out[f"mark{axis}"] = marks
            out[f"gate{axis}"] = gate.astype(np.int64)
            out[f"duty{axis}"] = duty
        return out

    # ---- reading -------------------------------------------------------------------------
    def column(self, name: str) -> np.ndarray:
        if not self._chunks:
            return np.array([])
        return np.concatenate([c[name] for c in self._chunks])

    def columns(self) -> list[str]:
        names = ["tick", "x", "y"]
        for axis in self.pwm_axes:
            names += [f"mark{axis}", f"gate{axis}", f"duty{axis}"]
        return names

    def __len__(self) -> int:
        return sum(len(c["tick"]) for c in self._chunks)

    def write_csv(self, path: str | Path) -> Path:
        """tick, time (s), x, y, then mark/gate/duty per PWM axis; one row a servo cycle."""
        path = Path(path)
        names = self.columns()
        data = {n: self.column(n) for n in names}
        period = self.machine.period
        with path.open("w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow([names[0], "time", *names[1:]])
            for i in range(len(data["tick"])):
                tick = int(data["tick"][i])
                row: list[object] = [tick, f"{tick * period:.6f}"]
                for n in names[1:]:
                    value = data[n][i]
                    row.append(int(value) if n.startswith(("mark", "gate")) else
                               f"{float(value):.6f}")
                writer.writerow(row)
        return path

    def plot(self, path: str | Path, axis: int | None = None, title: str = "") -> Path:
        """The XY path with the PWM duty of `axis` drawn along it (the laser power on the
        path). Needs matplotlib."""
        plt = pyplot()
        from matplotlib.collections import LineCollection

        axis = self.pwm_axes[0] if axis is None else axis
        x, y = self.column("x"), self.column("y")
        duty = self.column(f"duty{axis}")
        fig, ax = plt.subplots(figsize=(7, 7))
        ax.plot(x, y, color="0.8", linewidth=1.0, label="path")
        if len(x) > 1:
            points = np.column_stack([x, y]).reshape(-1, 1, 2)
            segments = np.concatenate([points[:-1], points[1:]], axis=1)
            lines = LineCollection(list(segments), cmap="inferno_r", linewidths=3.0)
            lines.set_array(duty[1:])
            lines.set_clim(0.0, 1.0)
            ax.add_collection(lines)
            fig.colorbar(lines, ax=ax, label=f"PWM duty, axis {axis}")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(f"axis {self.xy[0]} DPOS")
        ax.set_ylabel(f"axis {self.xy[1]} DPOS")
        ax.grid(True, alpha=0.3)
        ax.set_title(title or "MC405 PWM along the path")
        return save(fig, path)
