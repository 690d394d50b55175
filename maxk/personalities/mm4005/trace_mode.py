"""The trace modes: positions sampled at a fixed period into the controller's memory.

The trace mode (manual 3.140 TT, C): one axis's theoretical and actual position, 'enabled
by TM command and defined by SP and TM commands', read back sample by sample with TT
('9TT, TH1.002, TP1.001'), counted by XN. The page's example gives the rest (I): 'SP0.002'
sets the trace period to 2 ms, '2TM500' the trace mode for axis 2 and 500 data points.
Ours (D): sampling starts on the tick TM runs (the first sample there), the period is
rounded to whole servo cycles.

The global trace mode:

Manual 3.137 TQ (C): 'the global trace mode is enabled by GQ command and defined by SQ
and GQ commands'; TQ's sample number runs from 1 to 'the number of samples set by GQ';
each sample holds axes 1-4's TH and TP (and the analog inputs at that moment). NQ is
'read global acquisition nr'. The GQ and SQ pages themselves were not found, so their
syntax is our decision (D, on the table entries): `GQnn` acquires nn samples starting at
the tick it runs (the first sample there), one every SQ servo cycles; `GQ0` ends an
acquisition early, keeping what it took. The buffer is the one the time-based
trajectory's pulses fill (the EPICS trajectory scan reads those with the same NQ/TQ):
an acquisition starts it afresh, and a trajectory run started meanwhile takes it over
(the acquisition ends there, D).

An event source on the shared engine: each sample is taken on its own tick, exact.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Final

from maxk.firmware_model.engine import Engine

from .timed import TRACE_CAPACITY, PulseTrace, TracePoint

MAX_SAMPLES: Final = TRACE_CAPACITY  # the buffer the ring keeps (D)
MAX_PERIOD: Final = 10_000  # servo cycles between samples: 5 s at 0.5 ms (D)

Positions = Callable[[], tuple[tuple[float, ...], tuple[float, ...]]]


class _Sampler:
    """Samples ``requested`` times, one every ``period`` ticks from the tick it starts
    on: an event source, each sample taken on its own tick."""

    def __init__(self, engine: Engine, positions: Positions) -> None:
        self.engine = engine
        self.positions = positions
        self.requested = 0  # GQ's / TM's nn (their '?' reads it)
        self.period = 1  # ticks (servo cycles) between samples
        self.taken = 0
        self.next_tick: int | None = None  # None: not acquiring
        self.first_tick: int | None = None

    @property
    def acquiring(self) -> bool:
        return self.next_tick is not None

    def start(self, count: int) -> None:
        """A fresh acquisition of ``count`` samples, the first on this tick."""
        if not 0 < count <= MAX_SAMPLES:
            raise ValueError(f"1..{MAX_SAMPLES} samples")
        self.requested = count
        self.taken = 0
        self._clear()
        self.first_tick = self.next_tick = self.engine.tick
        self._sample()

    def stop(self) -> None:
        """Ended early (xx0), at power-up or by another run: no more samples."""
        self.next_tick = None

    def reset(self) -> None:
        """Power-up: no acquisition, nothing recorded, the period back to one cycle."""
        self.stop()
        self.requested, self.period, self.taken, self.first_tick = 0, 1, 0, None
        self._clear()

    def next_event(self) -> int | None:
        return self.next_tick if self.acquiring else None

    def on_event(self, now: int) -> None:
        while self.acquiring and self.next_tick is not None and self.next_tick <= now:
            self._sample()

    def _sample(self) -> None:
        """Every axis's TH and TP on this tick (the engine stands on ``next_tick``)."""
        assert self.next_tick is not None
        theoretical, actual = self.positions()
        self.taken += 1
        self._record(self.next_tick, theoretical, actual)
        if self.taken >= self.requested:
            self.stop()
        else:
            self.next_tick += self.period

    def _clear(self) -> None:  # pragma: no cover - each kind clears its own memory
        raise NotImplementedError

    def _record(self, tick: int, theoretical: tuple[float, ...],
                actual: tuple[float, ...]) -> None:  # pragma: no cover
        raise NotImplementedError


class GlobalTrace(_Sampler):
    """GQ/SQ's acquisition: every axis, into the buffer NQ/TQ read (the pulse ring)."""

    def __init__(self, engine: Engine, trace: PulseTrace, positions: Positions,
                 element: Callable[[], int]) -> None:
        super().__init__(engine, positions)
        self.trace = trace
        self.element = element
        self._last: TracePoint | None = None  # the newest sample this acquisition added

    @property
    def acquiring(self) -> bool:
        """Still sampling: not ended, and the buffer still ends with its own sample (a
        trajectory run that began the buffer anew has ended it)."""
        if self.next_tick is not None and not self._owns_buffer():
            self.stop()
        return self.next_tick is not None

    def _owns_buffer(self) -> bool:
        records = self.trace.records
        return bool(records) and records[-1] is self._last

    def reset(self) -> None:
        super().reset()
        self._last = None

    def _clear(self) -> None:
        self.trace.begin()
        self._last = None

    def _record(self, tick: int, theoretical: tuple[float, ...],
                actual: tuple[float, ...]) -> None:
        self._last = TracePoint(self.taken, tick, self.element(), theoretical, actual)
        self.trace.add(self._last)


class AxisTrace(_Sampler):
    """TM/SP's acquisition: one axis's TH and TP into the trace memory TT and XN read."""

    def __init__(self, engine: Engine, positions: Positions) -> None:
        super().__init__(engine, positions)
        self.axis = 1
        self.samples: list[tuple[int, float, float]] = []  # (tick, TH, TP)

    def start_axis(self, axis: int, count: int) -> None:
        self.axis = axis
        self.start(count)

    def _clear(self) -> None:
        self.samples = []

    def _record(self, tick: int, theoretical: tuple[float, ...],
                actual: tuple[float, ...]) -> None:
        self.samples.append((tick, theoretical[self.axis - 1], actual[self.axis - 1]))
