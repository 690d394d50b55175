"""SYNC: an axis (and up to two more of its BASE array) synchronised with a point on a
moving axis, added on top of the axes' own moves.

From the SYNC, SYNC_CONTROL, SYNC_TIMER, SYNC_PAUSE and SYNC_DWELL pages of the
TrioBASIC help (C unless marked):
- SYNC(1, sync time, sync pos, sync axis, pos1[, pos2[, pos3]]): over `sync time` servo
  cycles the base axes move to follow the point captured at `sync pos` on `sync axis`:
  once synchronised, the first axis is at pos1 plus the sync axis's travel since sync
  pos (the conveyor's movement), the second and third at pos2 and pos3. Both in the same
  user units. SYNC(10, ...) re-synchronises to another point or axis over its time,
  SYNC(4, time) stops following. SYNC is not a buffered move: the axes go on making
  their own moves while synchronised (they add), CANCEL and RAPIDSTOP leave it.
- SYNC_CONTROL reads 0 none, 2 performing the synchronisation, 3 synchronised, 4
  stopping, 11 performing a re-synchronisation (1 and 10, "starting", take no servo
  cycle here, D); SYNC_TIMER the milliseconds of the (re)synchronisation so far, its
  whole time once complete.
- SYNC_PAUSE and SYNC_DWELL (per axis, ms) say when in the sync time the axis's motion
  happens: it waits the pause, and is done the dwell before the end (I: the pages'
  words; their graphs are not in the text).

Decided here (D), as the pages give the profile only as a graph: the axis's share of
the change is the cycloid s(z) = z - sin(2 pi z) / 2 pi of the fraction z of its motion
window done (no jump in speed or acceleration at either end), blending from what it
followed before (nothing, for SYNC(1)) to the new target, both moving; SYNC(4) lets the
conveyor's pull fade as 1 - s(z) cycle by cycle (each servo cycle moves the axis that
share of the conveyor's change: folded at every tick while it stops), so the axis
comes to rest without going back, and what it moved stays (a constant shift). The
conveyor's movement goes on the first axis only (no USER_FRAME: the frame's x is along
the conveyor). SYNC follows the sync axis's demand (the machine's link convention).
Not modelled: SYNC_WITHDRAW (its page gives no shape or timing), SYNC(20) (USER_FRAMEB,
the robot frames), a limit ending a SYNC at once.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from .runs import TrioAxis

STATES = {"sync": 2, "resync": 11, "synced": 3, "stopping": 4}


class Host(Protocol):
    axes: list[TrioAxis]
    tick: int
    period: float

    def changed(self) -> None: ...
    def dpos_at(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...


def share(z: np.ndarray) -> np.ndarray:
    """The cycloid: the share of a SYNC motion done after the fraction z of it (D)."""
    z = np.clip(z, 0.0, 1.0)
    return z - np.sin(2.0 * np.pi * z) / (2.0 * np.pi)


@dataclass(frozen=True)
class Target:
    """What a SYNC follows: the point `at` on `axis`, at `pos` on the base axes."""

    axis: int
    at: float
    pos: tuple[float, ...]


@dataclass
class Sync:
    """One SYNC on a base array (axes[0] its base axis)."""

    axes: tuple[int, ...]
    reference: tuple[float, ...]  # each axis's own DPOS when SYNC(1) began (user units)
    old: Target | None  # what it followed before this phase
    new: Target | None  # what it follows (None: stopping)
    start: int  # the tick this phase began
    ticks: int  # its time, servo cycles
    kind: str  # "sync", "resync", "stopping"
    windows: tuple[tuple[float, float], ...]  # per axis: its motion's first and last tick
    # stopping: the offsets at `since`, summed cycle by cycle from there
    base: list[float] = field(default_factory=list)
    since: int = 0


class Syncs:
    """The machine's SYNCs: their offsets on the axes' demand, their states, and the
    folds of a SYNC(4) (an event source)."""

    def __init__(self, machine: Host, keep: Callable[[int, float], None]) -> None:
        self.machine = machine
        self.running: dict[int, Sync] = {}  # base axis -> its SYNC
        self.keep = keep  # what a SYNC moved stays on the axis: a shift (counts) of it

    def reset(self) -> None:
        self.running.clear()

    def _end(self, base: int, now: int) -> None:
        """The SYNC on `base` ends now: where it put each axis stays (a constant shift,
        which MOVEABS and the rest see as the ADDAX shifts)."""
        sync = self.running.pop(base)
        tick = np.array([now])
        for k, a in enumerate(sync.axes):
            self.keep(a, float(self.offset_of(sync, k, tick)[0]) * self.machine.axes[a].units)

    def of(self, axis: int) -> tuple[Sync, int] | None:
        for sync in self.running.values():
            if axis in sync.axes:
                return sync, sync.axes.index(axis)
        return None

    # ---- the command ------------------------------------------------------------------
    def command(self, axes: list[int], args: list[float],
                depends: Callable[[int, int], bool]) -> None:
        """SYNC(control, time[, sync pos, sync axis, pos1[, pos2[, pos3]]]) on the base
        array `axes`; 'Parameter out of range' for what the page does not allow (D)."""
        m = self.machine
        if len(args) < 2:
            raise ValueError("Syntax error")
        control, time = args[0], args[1]
        if time != int(time) or not 1 <= time < 2 ** 31:
            raise ValueError("Parameter out of range")
        base = axes[0]
        current = self.running.get(base)
        if control == 4:
            if len(args) != 2:
                raise ValueError("Parameter out of range")
            if current is not None and current.kind != "stopping":
                offsets = [self.offset_of(current, k, np.array([m.tick]))[0]
                           for k in range(len(current.axes))]
                self.running[base] = Sync(current.axes, current.reference, current.new,
                                          None, m.tick, int(time), "stopping",
                                          self._windows(current.axes, int(time)),
                                          [float(v) for v in offsets], m.tick)
                m.changed()
            return
        if control not in (1, 10):
            raise ValueError("Parameter out of range")  # 20: USER_FRAMEB, not modelled
        if not 5 <= len(args) <= 7:
            raise ValueError("Syntax error")
        link = args[3]
        count = len(args) - 4
        group = tuple(axes[:count])
        if link != int(link) or not 0 <= link < len(m.axes) or int(link) in group \
                or len(group) < count or any(depends(int(link), a) for a in group):
            raise ValueError("Invalid axis number" if link != int(link) or not
                             0 <= link < len(m.axes) else "Parameter out of range")
        target = Target(int(link), args[2], tuple(args[4:]))
        now = np.array([m.tick])
        if control == 10 and current is not None and current.kind != "stopping" \
                and current.axes == group:
            old = current.new
            if current.kind != "synced" and not self._complete(current, m.tick):
                raise ValueError("Parameter out of range")  # (mid-blend: D)
            self.running[base] = Sync(group, current.reference, old, target, m.tick,
                                      int(time), "resync", self._windows(group, int(time)))
        else:
            if current is not None and current.kind == "stopping":
                self._end(base, m.tick)  # a new SYNC while one stops: it ends here (D)
                current = None
            if current is not None or any(self.of(a) is not None for a in group):
                raise ValueError("Parameter out of range")  # one SYNC an axis (D)
            reference = tuple(float(m.dpos_at(a, now)[0]) for a in group)
            self.running[base] = Sync(group, reference, None, target, m.tick, int(time),
                                      "sync", self._windows(group, int(time)))
        m.changed()

    def _windows(self, axes: tuple[int, ...], time: int) -> tuple[tuple[float, float], ...]:
        """Each axis's motion window in the phase (SYNC_PAUSE, SYNC_DWELL: ms)."""
        m = self.machine
        per_ms = 1e-3 / m.period
        out = []
        for a in axes:
            params = m.axes[a].params
            pause = params.get("SYNC_PAUSE", 0.0) * per_ms
            dwell = params.get("SYNC_DWELL", 0.0) * per_ms
            if pause < 0 or dwell < 0 or pause + dwell >= time:
                raise ValueError("Parameter out of range")  # no time left to move (D)
            out.append((pause, time - dwell))
        return tuple(out)

    def _complete(self, sync: Sync, tick: int) -> bool:
        return tick - sync.start >= sync.ticks

    # ---- positions --------------------------------------------------------------------
    def follow(self, target: Target | None, sync: Sync, k: int,
               ticks: np.ndarray) -> np.ndarray:
        """The offset (user units) that puts axis k on the target at `ticks`."""
        if target is None:
            return np.zeros(np.shape(ticks))
        where = target.pos[k] - sync.reference[k]
        if k != 0:
            return np.full(np.shape(ticks), where)
        conveyor = self.machine.dpos_at(target.axis, ticks) - target.at
        return where + conveyor

    def weight(self, sync: Sync, k: int, ticks: np.ndarray) -> np.ndarray:
        first, last = sync.windows[k]
        return share((ticks - sync.start - first) / (last - first))

    def offset_of(self, sync: Sync, k: int, ticks: np.ndarray) -> np.ndarray:
        """Axis k's SYNC offset (user units) at ticks from now to the next event."""
        if sync.kind != "stopping":
            new = self.follow(sync.new, sync, k, ticks)
            if sync.old is None and sync.kind == "sync":
                return self.weight(sync, k, ticks) * new
            old = self.follow(sync.old, sync, k, ticks)
            return old + self.weight(sync, k, ticks) * (new - old)
        # stopping: each servo cycle after `since` adds (1 - s) of the conveyor's change
        ticks = np.asarray(ticks)
        low = min(int(np.min(ticks)), sync.since)
        # past the stop's time the pull is gone: the offset stays (a search far ahead
        # sums only the stop's cycles)
        high = min(max(int(np.max(ticks)), sync.since), max(sync.start + sync.ticks,
                                                              sync.since))
        ticks = np.minimum(ticks, high)
        span = np.arange(low, high + 1)
        pull = self.follow(sync.old, sync, k, span)
        fold = sync.since - low
        steps = np.diff(pull[fold:])
        fade = 1.0 - self.weight(sync, k, span[fold + 1:])
        ahead = np.concatenate(([0.0], np.cumsum(fade * steps)))
        behind = (pull[:fold] - pull[fold]) * (1.0 - float(self.weight(
            sync, k, np.array([sync.since]))[0]))
        moved = np.concatenate((behind, ahead))
        return sync.base[k] + moved[ticks - low]

    def counts(self, axis: int, ticks: np.ndarray) -> np.ndarray | float:
        """The running SYNC's part of the axis's demand (counts)."""
        found = self.of(axis)
        if found is None:
            return 0.0
        sync, k = found
        return self.offset_of(sync, k, ticks) * self.machine.axes[axis].units

    # ---- reading ----------------------------------------------------------------------
    def read(self, name: str, axis: int) -> float:
        """SYNC_CONTROL and SYNC_TIMER of the axis."""
        found = self.of(axis)
        if found is None:
            return 0.0
        sync, _k = found
        m = self.machine
        done = self._complete(sync, m.tick)
        if name == "SYNC_TIMER":
            if sync.kind == "stopping":
                return 0.0
            elapsed = min(m.tick - sync.start, sync.ticks)
            return elapsed * m.period * 1000.0
        if sync.kind == "stopping":
            return float(STATES["stopping"])
        return float(STATES["synced"] if done else STATES[sync.kind])

    # ---- the engine's events: SYNC(4) folds each tick until it ends ---------------------
    def next_event(self) -> int | None:
        due = [s.since + 1 for s in self.running.values() if s.kind == "stopping"]
        return max(min(due), self.machine.tick) if due else None

    def on_event(self, now: int) -> None:
        m = self.machine
        ended: list[int] = []
        for base, sync in self.running.items():
            if sync.kind != "stopping" or sync.since >= now:
                continue
            tick = np.array([now])
            sync.base = [float(self.offset_of(sync, k, tick)[0])
                         for k in range(len(sync.axes))]
            sync.since = now
            if self._complete(sync, now):
                ended.append(base)
        for base in ended:  # what it moved stays, a constant shift of each axis
            self._end(base, now)
        if ended:
            m.changed()


__all__ = ["STATES", "Sync", "Syncs", "Target", "share"]
