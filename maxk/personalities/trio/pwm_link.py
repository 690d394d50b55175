"""The MC405's PWM outputs tied to the motion, on the shared outputs mechanism.

- Modes 2 and 8: the mark is a `ComputedOutput` of the link axis's VP_SPEED (and the
  amplitude axis's DPOS), evaluated at whatever servo tick it is read; `marks_at` gives
  every servo cycle of a stretch at once (traces, plots).
- The gating FIFO: its head entry is a `PositionTrigger` on its axis; `trigger_ticks`
  finds the exact tick the axis passes it (bisection over the motion's phases), and this
  event source syncs PWM_ENCODER there, so the gate toggles on that very tick.
- PWM_ENCODER follows the axis's whole counts (not DEFPOS) whenever it is looked at.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from maxk.firmware_model.outputs import ComputedOutput, PositionTrigger, trigger_ticks

from .memory import TableMemory
from .pwm import PWM_ATYPES, GateEntry, PwmBank, PwmMode, PwmOutput
from .runs import TrioAxis


@dataclass(frozen=True)
class GateEdge:
    """The gate of a PWM output toggled: at this servo tick, to this level."""

    tick: int
    axis: int
    level: bool
    position: int  # the FIFO entry (PWM_ENCODER counts)


class MotionView(Protocol):
    """What the PWM outputs read of the machine."""

    @property
    def tick(self) -> int: ...
    @property
    def period(self) -> float: ...
    @property
    def revision(self) -> int: ...
    @property
    def axes(self) -> Sequence[TrioAxis]: ...
    @property
    def system(self) -> dict[str, float]: ...
    @property
    def table(self) -> TableMemory: ...
    @property
    def axis_count(self) -> int: ...

    def vp_speed_at(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...
    def dpos_at(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...
    def counts_at(self, axis: int, tick: int) -> int: ...
    def changed(self) -> None: ...


GATE_LOG = 1024
"""Gate edges kept for a look (`:gates`), the newest (D: an endless program of gated moves
must not grow the controller for ever; the PWM trace records every edge when asked)."""


class PwmLinks:
    """The PWM bank of axes 0-4 and what ties it to the motion (an event source: the
    ticks gate positions are passed)."""

    def __init__(self, machine: MotionView) -> None:
        self.machine = machine
        self.edges: deque[GateEdge] = deque(maxlen=GATE_LOG)
        self.bank = PwmBank(machine.axis_count)
        self.computed: dict[int, ComputedOutput] = {}
        self._encoder_counts: dict[int, int] = {}
        self._cache: tuple[int, int | None] = (-1, None)
        self.reset()

    def reset(self) -> None:
        """Power-up: every output off, encoders at 0 (the edge log is kept)."""
        self.bank = PwmBank(self.machine.axis_count)
        self.computed = {}
        self._encoder_counts = {a: self.machine.counts_at(a, self.machine.tick)
                                for a in self.bank.outputs}
        for output in self.bank.outputs.values():
            output.on_gate = self._gate_fired
        self._cache = (-1, None)

    # ---- PWM_CONTROL ---------------------------------------------------------------------
    def control(self, axis: int, args: Sequence[float]) -> None:
        m = self.machine
        output = self.bank[axis]
        self.sync_encoder(axis)
        if output.computed:
            output.load_mark(self.mark(axis))  # the last loaded mark stays when the mode goes
        output.control(args, m.table, m.axes[axis].units, m.axis_count)
        self._link_mark(axis, output)

    def _link_mark(self, axis: int, output: PwmOutput) -> None:
        """Modes 2 and 8: the mark is a computed output of VP_SPEED (x DPOS)."""
        if not output.computed:
            self.computed.pop(axis, None)
            return
        m = self.machine
        speed_axis, amplitude_axis = output.links
        assert speed_axis is not None

        def speed(tick: int) -> float:
            return float(m.vp_speed_at(speed_axis, np.array([tick]))[0])

        def amplitude(tick: int) -> float:
            if amplitude_axis is None:
                return 1.0
            return float(m.dpos_at(amplitude_axis, np.array([tick]))[0])

        self.computed[axis] = ComputedOutput(output.computed_mark, speed, amplitude)

    # ---- the mark and the output -----------------------------------------------------------
    def mark(self, axis: int) -> int:
        """PWM_MARK now: the register, or in modes 2/8 the mark this servo cycle loaded."""
        output = self.bank[axis]
        computed = self.computed.get(axis)
        if computed is not None:
            output.load_mark(int(computed.value_at(self.machine.tick)))
        return output.mark

    def marks_at(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """The mark of every servo cycle in `ticks` (between now and the next event)."""
        m = self.machine
        output = self.bank[axis]
        if axis not in self.computed:
            return np.full(ticks.shape, output.mark, dtype=np.int64)
        speed_axis, amplitude_axis = output.links
        assert speed_axis is not None
        speed = m.vp_speed_at(speed_axis, ticks)
        if output.mode is PwmMode.SPEED_PROFILE and amplitude_axis is not None:
            value = speed * m.dpos_at(amplitude_axis, ticks) * output.multiplier \
                + output.offset
        else:
            value = speed * output.multiplier + output.offset
        value = np.minimum(value, output.limit)
        value = np.where(np.isfinite(value), np.clip(value, 0.0, 65535.0), 0.0)
        return value.astype(np.int64)

    def enabled(self, axis: int) -> bool:
        """WDOG ON and an ATYPE whose Z channel is the PWM output (35, 36)."""
        atype = int(self.machine.axes[axis].params["ATYPE"])
        return self.machine.system.get("WDOG", 0) != 0 and atype in PWM_ATYPES

    def duty(self, axis: int) -> float:
        """The fraction of each period the combined (PWM AND gate) output is on, now."""
        output = self.bank[axis]
        self.mark(axis)
        self.sync_encoder(axis)
        return output.duty(self.machine.system.get("WDOG", 0) != 0,
                           int(self.machine.axes[axis].params["ATYPE"]))

    # ---- PWM_ENCODER and the gating FIFO ---------------------------------------------------
    def sync_encoder(self, axis: int) -> None:
        """PWM_ENCODER follows the whole counts the axis made since the last look."""
        output = self.bank.outputs.get(axis)
        if output is None:
            return
        counts = self.machine.counts_at(axis, self.machine.tick)
        moved = counts - self._encoder_counts[axis]
        self._encoder_counts[axis] = counts
        output.move_encoder(moved)  # (0 too: an entry made passed by PWM_CONTROL(6) fires)

    def sync_all(self) -> None:
        for axis in self.bank.outputs:
            self.sync_encoder(axis)

    def _gate_fired(self, axis: int, entry: GateEntry) -> None:
        self.edges.append(GateEdge(self.machine.tick, axis, entry.level, entry.position))
        self.machine.changed()

    def next_gate_tick(self, axis: int) -> int | None:
        """The tick the axis passes the FIFO head (None: not with the present motion)."""
        m = self.machine
        output = self.bank[axis]
        head = output.next_gate()
        a = m.axes[axis]
        if head is None or a.motion is None or a.link is not None:
            return None  # (a linked axis's gates are compared when it is looked at: D)
        self.sync_encoder(axis)
        need = head.counts_to_pass(output.encoder)
        if need == 0:
            return m.tick
        here = a.steps_at_tick(m.tick, m.period)
        trigger = PositionTrigger(here + need, 1 if need > 0 else -1, head)
        found = trigger_ticks(a, m, [trigger])  # type: ignore[arg-type]
        return found[0][0] if found else None

    # ---- EventSource: the gate toggles ----------------------------------------------------
    def next_event(self) -> int | None:
        m = self.machine
        if self._cache[0] == m.revision:
            return self._cache[1]
        best: int | None = None
        for a, output in self.bank.outputs.items():
            if output.fifo:
                tick = self.next_gate_tick(a)
                if tick is not None and (best is None or tick < best):
                    best = tick
        self._cache = (m.revision, best)
        return best

    def on_event(self, now: int) -> None:
        for a, output in self.bank.outputs.items():
            if output.fifo:
                self.sync_encoder(a)
        self.machine.changed()
