"""The tuning assistant: run a move on a servo axis and plot how the motor followed it.

The vendor's Tuning Assistant plots the motor's response so the user can choose gains
(manual 2.12). ``tune()`` does the same against the emulated motor: it samples every
update tick (commanded and actual position and velocity, following error, DAC output)
and ``TuningRun.plot()`` draws them into a PNG with matplotlib (the ``plot`` extra).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from maxk.controllers.maxk.controller import MAXk
from maxk.firmware_model.motor import VOLTS_PER_COUNT
from maxk.plotting import pyplot, save

DEFAULT_MOVE = "AC100000; VL5000; MR6400; GO;"
"""A trapezoid with a flat top, short enough to plot clearly (manual 2.13's method)."""



@dataclass
class TuningRun:
    """Per-tick samples of one tuning move (numpy arrays, counts and seconds)."""

    gains: str
    move: str
    time: np.ndarray
    commanded: np.ndarray
    actual: np.ndarray
    commanded_velocity: np.ndarray  # counts/s
    actual_velocity: np.ndarray  # counts/s
    following_error: np.ndarray  # commanded - actual, counts
    dac_volts: np.ndarray
    tripped: bool

    @property
    def max_following_error(self) -> float:
        return float(np.max(np.abs(self.following_error)))

    @property
    def final_error(self) -> float:
        return float(self.following_error[-1])

    @property
    def overshoot(self) -> float:
        """How far the motor went past the end of the move (counts, >= 0)."""
        target = self.commanded[-1]
        direction = 1.0 if target >= self.commanded[0] else -1.0
        return max(0.0, float(np.max(direction * (self.actual - target))))

    def summary(self) -> str:
        return (f"gains: {self.gains or 'factory'}\nmove: {self.move}\n"
                f"max following error: {self.max_following_error:.2f} counts\n"
                f"overshoot: {self.overshoot:.2f} counts\n"
                f"final error: {self.final_error:.2f} counts\n"
                f"peak DAC: {np.max(np.abs(self.dac_volts)):.2f} V"
                + ("\nfollowing error over 32768: the PID was disabled" if self.tripped else ""))

    def plot(self, path: str | Path) -> Path:
        """Write the four traces to a PNG. Raises ImportError with advice when
        matplotlib is not installed."""
        plt = pyplot()
        path = Path(path)
        fig, axes = plt.subplots(4, 1, sharex=True, figsize=(9, 10))
        t = self.time
        axes[0].plot(t, self.commanded, label="commanded (RP)")
        axes[0].plot(t, self.actual, label="actual (RE)", linestyle="--")
        axes[0].set_ylabel("position, counts")
        axes[1].plot(t, self.commanded_velocity, label="commanded")
        axes[1].plot(t, self.actual_velocity, label="actual", linestyle="--")
        axes[1].set_ylabel("velocity, counts/s")
        axes[2].plot(t, self.following_error, color="tab:red")
        axes[2].set_ylabel("following error, counts")
        axes[3].plot(t, self.dac_volts, color="tab:green")
        axes[3].set_ylabel("DAC, V")
        axes[3].set_xlabel("time, s")
        for ax in axes[:2]:
            ax.legend(loc="best")
        for ax in axes:
            ax.grid(True, alpha=0.3)
        fig.suptitle(f"maxk tune: {self.gains or 'factory gains'} | {self.move}")
        return save(fig, path)


def tune(gains: str = "", move: str = DEFAULT_MOVE, *, seconds: float | None = None,
         axis: str = "X", motor: dict | None = None, model: str = "MAXk-8000") -> TuningRun:
    """Run `move` on a fresh servo axis with `gains` (commands such as "KP100; KD400;")
    and sample every tick until the move has ended and the motor settled (or for
    `seconds`). `motor` sets MotorPlant parameters of the emulated motor."""
    board = MAXk(model)
    if motor:
        board.set_motor(axis, **motor)
    board.send(f"A{axis} PSM; LP0; {gains}")
    if board.command_error:
        raise ValueError(f"bad gains {gains!r}: {board.last_error}")
    board.send(f"A{axis} CL1;")
    loop = board.board.axis(axis).servo
    assert loop is not None
    loop.recorder = []
    board.send(f"A{axis} {move} ID;")
    if board.command_error:
        raise ValueError(f"bad move {move!r}: {board.last_error}")
    if seconds is None:
        board.run_until_done(axis, timeout=120.0)
        board.advance(max(0.25, 0.2 * board.time))  # and the settling after it
    else:
        board.advance(seconds)
    samples = np.array(loop.recorder, dtype=float)
    loop.recorder = None
    rate = board.board.update_rate_hz
    tick, commanded, actual, v, w, error, dac = samples.T
    return TuningRun(gains, move, (tick - tick[0]) / rate, commanded, actual, v * rate, w,
                     error, dac * VOLTS_PER_COUNT, loop.tripped)
