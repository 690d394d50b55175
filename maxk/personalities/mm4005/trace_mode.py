"""The global trace mode: every installed axis's theoretical and actual position sampled
at a fixed period into the controller's trace buffer, read back with NQ and TQ.

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


class GlobalTrace:
    """GQ/SQ's acquisition: ``requested`` samples, one every ``period`` ticks."""

    def __init__(self, engine: Engine, trace: PulseTrace, positions: Positions,
                 element: Callable[[], int]) -> None:
        self.engine = engine
        self.trace = trace
        self.positions = positions
        self.element = element
        self.requested = 0  # GQ's nn (GQ? reads it)
        self.period = 1  # SQ: servo cycles between samples
        self.taken = 0
        self.next_tick: int | None = None  # None: not acquiring
        self.first_tick: int | None = None
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

    def start(self, count: int) -> None:
        """GQnn: a fresh buffer, the first sample on this tick."""
        if not 0 < count <= MAX_SAMPLES:
            raise ValueError(f"GQ takes 1..{MAX_SAMPLES} samples")
        self.requested = count
        self.trace.begin()
        self.taken = 0
        self._last = None
        self.first_tick = self.next_tick = self.engine.tick
        self._sample()  # the sample of this tick, taken now

    def stop(self) -> None:
        """GQ0, a power-up or another run taking the buffer: no more samples."""
        self.next_tick = None

    def tick_of(self, sample: int) -> int | None:
        """The tick sample ``sample`` (1 first) is or was taken on."""
        if self.first_tick is None:
            return None
        return self.first_tick + (sample - 1) * self.period

    # ---- event source ----------------------------------------------------------------
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
        self._last = TracePoint(self.taken, self.next_tick, self.element(), theoretical,
                                actual)
        self.trace.add(self._last)
        if self.taken >= self.requested:
            self.stop()
        else:
            self.next_tick += self.period
