"""A PoKeys slot trace: one CSV row per 1 ms slot, and a plot of it (position and pulse
rate per axis over time, the buffer's fill level).

`maxk/trace.py` and `maxk/pathplot.py` are written around a MAXk board (its axis letters,
status strings, doorbell and output bits), so the pulse engine's trace lives here: it
hangs on the pulse engine's per-slot `trace` hook (which makes the engine emit slot by
slot while it is attached) and reads positions and the buffer after each slot.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import TextIO

from maxk.personalities.pokeys import AXIS_LETTERS, EngineState, SlotRecord
from maxk.personalities.pokeys.constants import SLOT_SECONDS
from maxk.personalities.pokeys.device import PoKeysDevice
from maxk.personalities.pokeys.engine import PulseEngine
from maxk.plotting import pyplot, save


class SlotRecorder:
    """Writes each slot to CSV (if given a stream) and keeps it for a plot."""

    def __init__(self, engine: PulseEngine, stream: TextIO | None = None,
                 axes: int | None = None, device: PoKeysDevice | None = None) -> None:
        self.engine = engine
        self.device = device  # with a device: its pins, PWM and encoders too
        self.encoders = [] if device is None else [
            i for i, e in enumerate(device.io.encoders) if e.axis is not None]
        self.pwm: list[list[float]] = [[] for _ in range(6)]
        self.axes = axes if axes is not None else len(engine.axes)
        self.stream = stream
        self._writer = None if stream is None else csv.writer(stream, lineterminator="\n")
        self.time: list[float] = []
        self.positions: list[list[int]] = [[] for _ in range(self.axes)]
        self.pulses: list[list[int]] = [[] for _ in range(self.axes)]
        self.fill: list[int] = []
        self.slots = 0
        if self._writer is not None:
            header = ["slot", "time_s", "engine_state", "buffer_fill"]
            for x in AXIS_LETTERS[:self.axes]:
                header += [f"{x}_pulses", f"{x}_dir", f"{x}_position", f"{x}_state"]
            if device is not None:
                header += ["outputs", "inputs"] + [f"pwm{n}_duty" for n in range(6)]
                header += [f"encoder{i}" for i in self.encoders]
            self._writer.writerow(header)

    def attach(self) -> None:
        self._before = self.engine.trace
        self.engine.trace = self

    def detach(self) -> None:
        if self.engine.trace is self:
            self.engine.trace = self._before
        if self.stream is not None:
            self.stream.close()
            self.stream = None
            self._writer = None

    def __call__(self, record: SlotRecord) -> None:
        e = self.engine
        fill = e.buffer.count
        self.slots += 1
        self.time.append((record.slot + 1) * SLOT_SECONDS)
        self.fill.append(fill)
        for i in range(self.axes):
            self.positions[i].append(e.axes[i].position)
            self.pulses[i].append(record.pulses[i])
        io_row: list[object] = []
        if self.device is not None:
            io_row = self._io_columns(self.device)
        if self._writer is not None:
            row: list[object] = [record.slot, f"{record.slot * SLOT_SECONDS:.3f}",
                                 EngineState(record.engine_state).name, fill]
            for i in range(self.axes):
                row += [record.pulses[i], int(record.directions[i]), e.axes[i].position,
                        record.axis_states[i]]
            self._writer.writerow(row + io_row)

    def _io_columns(self, device: PoKeysDevice) -> list[object]:
        """Output and input pins as bit masks (bit p-1 = pin p, hex), each PWM channel's
        duty in percent as the pin puts it out, the attached encoders' counts."""
        io, pins = device.io, device.pins
        outputs = sum(1 << (p - 1) for p, level in pins.output_levels().items() if level)
        inputs = sum(1 << (p - 1) for p in range(1, 56)
                     if not io.is_output(p) and io.functions[p - 1] and pins.input_level(p))
        duties = [device.pwm_output(n) * 100 for n in range(6)]
        for n, duty in enumerate(duties):
            self.pwm[n].append(duty)
        return [f"{outputs:014x}", f"{inputs:014x}", *(f"{d:.2f}" for d in duties),
                *(pins.encoder_value(i) for i in self.encoders)]

    def plot(self, path: str | Path, title: str = "") -> Path:
        """Three panels over time: positions, pulse rates (pulses/s), buffer fill.
        ImportError with advice when matplotlib is not installed."""
        plt = pyplot()
        path = Path(path)
        moving = [i for i in range(self.axes) if any(self.pulses[i])] or [0]
        pwm = [n for n in range(6) if any(self.pwm[n])]
        panels = 4 if pwm else 3
        fig, axes = plt.subplots(panels, 1, sharex=True, figsize=(9, 2.7 * panels))
        pos, rate, fill = axes[0], axes[1], axes[2]
        if pwm:
            duty = axes[3]
            for n in pwm:
                duty.step(self.time, self.pwm[n], where="post", label=f"PWM {n}")
            duty.set_ylabel("PWM duty, %")
            duty.set_ylim(-2, 102)
            duty.legend(loc="best")
            duty.grid(True, alpha=0.3)
        for i in moving:
            x = AXIS_LETTERS[i]
            pos.step(self.time, self.positions[i], where="post", label=x)
            rate.step(self.time, [p / SLOT_SECONDS for p in self.pulses[i]], where="post",
                      label=x)
        fill.step(self.time, self.fill, where="post", color="tab:gray")
        pos.set_ylabel("position, pulses")
        rate.set_ylabel("pulse rate, pulses/s")
        fill.set_ylabel("buffer fill, slots")
        fill.set_ylim(0, self.engine.buffer.depth + 4)
        axes[-1].set_xlabel("time, s")
        for ax in (pos, rate, fill):
            ax.grid(True, alpha=0.3)
        pos.legend(loc="best")
        pos.set_title(title or "PoKeys slot trace")
        return save(fig, path)
