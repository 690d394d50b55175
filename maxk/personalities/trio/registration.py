"""Registration of the MC405: REGIST, MARK/REG_POS and MARKB/REG_POSB, on the world.

REGIST(mode) AXIS(n) arms one capture of the axis's position (MARK reads FALSE until it
comes); the capture latches the count at the edge itself, so REG_POS is the exact
position of the mark, and MARK turns TRUE on the servo tick the axis reaches it:

- modes 1 and 2: the rising / falling edge of the encoder's Z mark, the world's index
  marks of the axis (every `index_period` counts from `index_offset`, `index_width`
  wide), found on the axis's own motion by the shared bisection (`tick_reaching`), on a
  linked axis (CONNECT, CAMBOX, ADDAX ...) by a bisection of its demand up to the next
  motion event;
- modes 3 and 4: the rising / falling edge of the axis's registration input R, which is
  digital input n of the world (D: the MC405 wires its registration inputs to the
  built-in inputs; the axis number picks one), captured on the tick the world changes it,
  at the position the axis has then.

Adding 256 to a mode takes only edges whose position (as DPOS reads it, folded by
REP_DIST) lies inside OPEN_WIN..CLOSE_WIN, 768 only those outside it (I: the manual's
window modes as recalled); an edge the window rejects leaves the capture armed.

Modes 5..9 put the Z mark on channel B (MARKB/REG_POSB) with the R input on A (I: the
MC206 manual's table, from memory); modes outside 1..9 are refused (D). A capture arms
only once (REGIST again to re-arm, C). Links that start on a registration event (CAMBOX
and MOVELINK link options 1 and 256) start from the captured position (`links.py`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from maxk.firmware_model.outputs import next_periodic_marks


@dataclass
class Capture:
    """One armed registration channel of an axis."""

    source: str  # "Z" (index marks) or "R" (the registration input)
    rising: bool
    level: bool = False  # the R input's level when armed (its edges are changes)
    window: int = 0  # 0 none, 1 inside OPEN_WIN..CLOSE_WIN, -1 outside it


@dataclass
class AxisRegistration:
    armed: dict[str, Capture] = field(default_factory=dict)  # channel "A"/"B" -> capture
    mark: bool = False
    markb: bool = False
    reg_pos: float = 0.0  # user units (DEFPOS applied), as MPOS reads
    reg_posb: float = 0.0


WINDOW_SEARCH = 10000
"""Index marks looked at, each way, for the next one a window takes (D: a bound)."""

MODES: dict[int, list[tuple[str, str, bool]]] = {
    1: [("A", "Z", True)], 2: [("A", "Z", False)],
    3: [("A", "R", True)], 4: [("A", "R", False)],
    5: [("A", "R", True), ("B", "Z", True)], 6: [("A", "R", True), ("B", "Z", False)],
    7: [("A", "R", False), ("B", "Z", True)], 8: [("A", "R", False), ("B", "Z", False)],
    9: [("A", "R", True), ("B", "R", False)],
}


class Registration:
    """The machine's registration channels: an event source for Z-mark captures."""

    def __init__(self, machine: Any) -> None:
        self.m = machine
        self._cache: tuple[int, int | None, list[tuple[int, str, float]]] = (-1, None, [])
        self.reset()

    def reset(self) -> None:
        self.axes = [AxisRegistration() for _ in range(self.m.axis_count)]

    # ---- the program's side ------------------------------------------------------------
    def regist(self, axis: int, args: list[float]) -> None:
        mode = args[0] if args else -1
        window = 0
        if mode == int(mode) and int(mode) & 768 in (256, 768):
            window = 1 if int(mode) & 768 == 256 else -1
            mode = int(mode) & 255
        if mode != int(mode) or int(mode) not in MODES or len(args) > 1:
            raise ValueError("Parameter out of range")
        reg = self.axes[axis]
        reg.armed.clear()
        for channel, source, rising in MODES[int(mode)]:
            reg.armed[channel] = Capture(source, rising, self._input(axis), window)
            if channel == "A":
                reg.mark = False
            else:
                reg.markb = False
        self.m.changed()

    def read(self, name: str, axis: int) -> float:
        reg = self.axes[axis]
        if name == "MARK":
            return -1.0 if reg.mark else 0.0
        if name == "MARKB":
            return -1.0 if reg.markb else 0.0
        return reg.reg_pos if name == "REG_POS" else reg.reg_posb

    # ---- the world's side --------------------------------------------------------------
    def _input(self, axis: int) -> bool:
        return self.m.world.digital_level(axis, self.m) if axis in self.m.world.digital \
            else False

    def world_changed(self) -> None:
        """An input changed: an armed R capture whose edge this is latches now."""
        for axis, reg in enumerate(self.axes):
            for channel, cap in list(reg.armed.items()):
                if cap.source != "R":
                    continue
                level = self._input(axis)
                here = self.m.demand(axis)
                if level != cap.level and level == cap.rising and self._in_window(
                        axis, cap, here):
                    self._capture(axis, channel, here)
                else:
                    cap.level = level

    def _in_window(self, axis: int, cap: Capture, counts: float) -> bool:
        """Does an edge at `counts` pass the capture's window?"""
        if cap.window == 0:
            return True
        m = self.m
        a = m.axes[axis]
        position = m.wrapped(axis, (counts + a.datum) / a.units)
        inside = a.params["OPEN_WIN"] <= position <= a.params["CLOSE_WIN"]
        return inside if cap.window == 1 else not inside

    def _z_ticks(self) -> list[tuple[int, str, float]]:
        """(tick, channel, position in counts) of each armed Z capture's next edge."""
        m = self.m
        out = []
        horizon: int | None = -1  # (looked up once, for linked axes)
        for axis, reg in enumerate(self.axes):
            if not any(cap.source == "Z" for cap in reg.armed.values()):
                continue
            a = m.axes[axis]
            own = a.motion is not None and a.link is None and axis not in m.links.addax
            if not own and horizon == -1:
                horizon = m.motion_horizon()
            if not own and (horizon is None or horizon <= m.tick):
                continue
            stage = m.world.axes[axis]
            if stage.index_period <= 0:
                continue
            here = a.steps_now(m) if own else math.floor(m.demand(axis))
            for channel, cap in reg.armed.items():
                if cap.source != "Z":
                    continue
                if cap.rising:
                    up, down = next_periodic_marks(here, stage.index_offset,
                                                   stage.index_period, stage.index_width)
                else:  # the first count past the mark each way
                    up = next_periodic_marks(here, stage.index_offset + stage.index_width,
                                             stage.index_period, 1)[0]
                    down = next_periodic_marks(here, stage.index_offset - 1,
                                               stage.index_period, 1)[1]
                for position, direction in ((up, 1), (down, -1)):
                    for _ in range(WINDOW_SEARCH):  # the next mark the window takes
                        if self._in_window(axis, cap, position):
                            break
                        position += direction * stage.index_period
                    else:
                        continue
                    tick = a.tick_reaching(position, direction, m) if own else \
                        self._linked_tick(axis, position, direction, horizon)
                    if tick is not None:
                        out.append((tick, f"{axis}:{channel}", float(position)))
        return out

    def _linked_tick(self, axis: int, position: float, direction: int,
                     horizon: int | None) -> int | None:
        """The first tick a linked axis's demand reaches `position` travelling
        `direction`, up to the horizon (the next tick the motion changes by itself:
        until then its demand is one closed form, taken as monotonic, D)."""
        m = self.m
        if horizon is None:
            return None

        def reached(tick: int) -> bool:
            here = float(m.demand_counts(axis, np.array([tick]))[0])
            return direction * (here - position) >= 0

        if not reached(horizon):
            return None
        lo, hi = m.tick, horizon
        if reached(lo):
            return lo + 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if reached(mid):
                hi = mid
            else:
                lo = mid
        return hi

    def next_event(self) -> int | None:
        m = self.m
        if self._cache[0] != m.revision:
            found = self._z_ticks()
            best = min((t for t, _c, _p in found), default=None)
            self._cache = (m.revision, best, found)
        return self._cache[1]

    def on_event(self, now: int) -> None:
        m = self.m
        _rev, _best, found = self._cache
        hits: dict[str, tuple[int, float]] = {}
        for tick, key, position in found:
            if tick <= now and (key not in hits or tick < hits[key][0]):
                hits[key] = (tick, position)
        for key, (_tick, position) in hits.items():
            axis, channel = key.split(":")
            self._capture(int(axis), channel, position)
        self._cache = (-1, None, [])
        m.changed()

    def _capture(self, axis: int, channel: str, counts: float) -> None:
        m = self.m
        a = m.axes[axis]
        reg = self.axes[axis]
        reg.armed.pop(channel, None)
        position = (counts + a.datum) / a.units
        if channel == "A":
            reg.mark, reg.reg_pos = True, position
            m.links.registered(axis, "MARK", counts)
        else:
            reg.markb, reg.reg_posb = True, position
            m.links.registered(axis, "MARKB", counts)
        m.changed()


__all__ = ["MODES", "Registration"]
