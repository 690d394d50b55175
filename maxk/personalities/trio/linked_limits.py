"""Limits reached by an axis whose demand comes from a link (TrioBASIC help FWD_IN, REV_IN,
FS_LIMIT, RS_LIMIT, CANCEL, CONNECT, ADDAX, AXIS_MODE).

A limit "issues CANCEL on that axis" (FWD_IN, REV_IN pages), and CANCEL ends a move that is
not speed-profiled at once (CANCEL page): so an axis that a CONNECT, CAMBOX, MOVELINK,
FLEXLINK or CONNPATH drives stops on the servo tick its demand meets the limit, and the
link ends there (the next linked move buffered then starts, as after CANCEL; one that
drives the axis further into the limit ends on its first cycle). The axis keeps its ADDAX
unless AXIS_MODE bit 3 is set (CANCEL page); the ADDAX part itself ignores the limit unless
bit 17 is set, which cancels the current move of the ADDAX's master (ADDAX page) at its
FASTDEC, else DECEL (CANCEL page). An axis with ADDAX has its own run cancelled as any move
at a limit. AXIS_MODE bit 1 keeps a CONNECT running at a limit: its ratio goes to 0 at
CLUTCH_RATE while the limit is active, and back when it is not (CONNECT page).

The demand of such an axis is a closed form of the motion it follows between events; the
first servo tick it stands on a limit and moves on into it is found on an array of ticks
(every tick of a window of up to `WINDOW` cycles, up to the next tick the motion changes by
itself), so a cam that turns back inside a window is seen exactly; a window with no limit
ends in an event that looks at the next one. The software limits compare DPOS here (D:
MPOS on a linked servo axis is not watched cycle by cycle).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import clutch
from .errors import CANCEL_ADDAX
from .link_kinds import Connect

WINDOW = 4096
"""The most servo cycles looked at in one array (D: bounded work per event; about 4 s at
1 ms). The window halves when the motion changed before it was used up (a clutch ramping
every cycle) and doubles when it was, from MIN_WINDOW: work in step with the time run."""
MIN_WINDOW = 16
CONNECT_HOLDS = 1 << 1  # AXIS_MODE bit 1: a CONNECT at a limit runs at ratio 0
CANCEL_MASTER = 1 << 17  # bit 17: the limit cancels the ADDAX master's current move
_FWD, _REV = (1 << 4) | (1 << 9), (1 << 5) | (1 << 10)  # AXISSTATUS limit bits per side


class LinkedLimits:
    """The limit search and actions of the axes a link drives (see the module docstring)."""

    def __init__(self, drive: Any) -> None:
        self.drive = drive
        self.reset()

    def reset(self) -> None:
        self.held: dict[int, tuple[Connect, float, int]] = {}  # axis -> the CONNECT at
        # ratio 0 (AXIS_MODE bit 1), its ratio, the side
        self.tripped: dict[tuple[int, int], tuple[object, object]] = {}  # (axis, side) ->
        # what drove it there: that side does not act again until the axis is back inside
        self._cache: tuple[tuple[int, int], dict[int, tuple[int, int]], int | None] = (
            (-1, -1), {}, None)  # ((revision, tick) scanned at, the limits met, look again)
        self.span = MIN_WINDOW  # the window's length now (see `_scan`)

    # ---- which axes -------------------------------------------------------------------
    def covers(self, axis: int) -> bool:
        """Is the axis's demand made (in part) by a link, ADDAX or what one left?"""
        m = self.drive.m
        links = m.links
        return (m.axes[axis].link is not None or axis in links.addax
                or links.shift[axis] != 0) and not m.framed(axis)

    def _driver(self, axis: int) -> tuple[object, object]:
        m = self.drive.m
        return (m.axes[axis].link, m.links.addax.get(axis))

    # ---- the search --------------------------------------------------------------------
    def _scan(self) -> tuple[dict[int, tuple[int, int]], int | None]:
        """Per covered axis the first tick it meets a limit (and the side), and the tick
        to look again at when none is met in the window."""
        m = self.drive.m
        revision = self._cache[0][0]
        if revision == m.revision and (self._cache[2] is None or m.tick < self._cache[2]):
            return self._cache[1], self._cache[2]
        if self._cache[2] is not None and m.tick < self._cache[2]:
            # the motion changed before the window was used: a shorter one next time
            self.span = max(MIN_WINDOW, self.span // 2)
        elif self._cache[2] is not None:
            self.span = min(WINDOW, self.span * 2)
        found: dict[int, tuple[int, int]] = {}
        again: int | None = None
        now = m.tick
        horizon = m.motion_horizon()
        end = now + self.span if horizon is None or horizon <= now else min(
            now + self.span, horizon)
        end = max(end, now + 1)
        ticks = np.arange(now, end + 1)
        for axis in range(m.axis_count):
            if not self.covers(axis):
                continue
            d = m.demand_counts(axis, ticks)
            steps = np.floor(d + 1e-9)  # (a whole count reached to a float's rounding)
            moving = np.diff(d)
            best: tuple[int, int] | None = None
            for side in (1, -1):
                for edge in self.drive.edges(axis, side, dpos=True):
                    on = steps[:-1] >= edge if side > 0 else steps[:-1] <= edge
                    into = on & (side * moving > 0)
                    if (axis, side) in self.tripped:  # only after it is back inside
                        if not _same(self.tripped[(axis, side)], self._driver(axis)):
                            del self.tripped[(axis, side)]
                        else:
                            inside = ~on
                            if not inside.any():
                                continue
                            into[:int(np.argmax(inside))] = False
                    if into.any():
                        tick = now + int(np.argmax(into))
                        if best is None or tick < best[0]:
                            best = (tick, side)
            if best is not None:
                found[axis] = best
            elif moving.any() and (again is None or end < again):
                again = end  # (looked at to the window's end: look again there)
        self._cache = ((m.revision, now), found, again)
        return found, again

    def next_event(self) -> int | None:
        found, again = self._scan()
        ticks = [tick for tick, _side in found.values()]
        if again is not None:
            ticks.append(again)
        return min(ticks) if ticks else None

    # ---- acting ----------------------------------------------------------------------------
    def look(self, now: int) -> bool:
        """Act on the limits met by now (and on a level limit input on ahead); a CONNECT
        held at ratio 0 runs again once its limit is off. True when something changed."""
        changed = self._release()
        found, _again = self._scan()
        for axis, (tick, side) in sorted(found.items()):
            if tick <= now:
                self._act(axis, side)
                changed = True
        for axis in range(self.drive.m.axis_count):
            if self.covers(axis) and self._level(axis):
                changed = True
        if changed:
            self.drive.m.changed()
        return changed

    def _level(self, axis: int) -> bool:
        """A limit input the world drives as a level (or a stuck switch) that is on ahead
        of the moving axis acts now (drive._level_limit)."""
        m = self.drive.m
        d = m.demand_counts(axis, np.array([m.tick, m.tick + 1]))
        direction = int(np.sign(d[1] - d[0]))
        if direction == 0 or (axis, direction) in self.tripped:
            return False
        if self.drive._level_limit(axis, direction):
            self._act(axis, direction)
            return True
        return False

    def _act(self, axis: int, side: int) -> None:
        m = self.drive.m
        a = m.axes[axis]
        mode = int(a.params["AXIS_MODE"])
        m.outputs.sync_all()
        link = a.link
        if isinstance(link, Connect) and mode & CONNECT_HOLDS:
            if axis not in self.held:
                self.held[axis] = (link, link.ratio, side)
                clutch.change_ratio(m, axis, link, 0.0)
            self.tripped[(axis, side)] = self._driver(axis)
            return
        if link is not None:
            m.cancel(axis)  # the link ends at once; the next buffered one starts
        queue = m.queues[axis]
        if queue and queue[0].started and not queue[0].stopping:
            self.drive._cancel_for_limit(queue[0])  # its own run, at FASTDEC / DECEL
        added = m.links.addax.get(axis)
        if added is not None and mode & CANCEL_MASTER:
            master = m.queues[added.link]
            if master and master[0].started and not master[0].stopping:
                self.drive._cancel_for_limit(master[0])
            elif m.axes[added.link].link is not None:
                m.cancel(added.link)
        if added is not None and mode & CANCEL_ADDAX:
            m.links.set_addax(axis, -1.0)
        self.tripped[(axis, side)] = self._driver(axis)

    def _release(self) -> bool:
        """CONNECTs held at ratio 0 whose limit is no longer active take their ratio back
        (at CLUTCH_RATE)."""
        m = self.drive.m
        changed = False
        for axis, (link, ratio, side) in list(self.held.items()):
            if m.axes[axis].link is not link:
                del self.held[axis]
                continue
            status = self.drive.axis_status(axis)
            if not status & (_FWD if side > 0 else _REV):
                del self.held[axis]
                self.tripped.pop((axis, side), None)
                clutch.change_ratio(m, axis, link, ratio)
                changed = True
        return changed


def _same(a: tuple[object, object], b: tuple[object, object]) -> bool:
    """The same link and ADDAX objects (not equal ones: a new link is a new move)."""
    return a[0] is b[0] and a[1] is b[1]


__all__ = ["CANCEL_MASTER", "CONNECT_HOLDS", "MIN_WINDOW", "LinkedLimits", "WINDOW"]
