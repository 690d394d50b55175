"""Motion errors of the MC405 and its disable groups (TrioBASIC help ERRORMASK,
MOTION_ERROR, ERROR_AXIS, DATUM, DISABLE_GROUP, AXIS_ENABLE, WDOG, CANCEL).

- **A motion error**: ERRORMASK's page ANDs it with AXISSTATUS on every servo cycle.
  Each time the machine looks (every event, so on the servo tick a limit or a following
  error acts), an axis not in error whose AXISSTATUS holds a bit of its ERRORMASK goes
  into motion error: its bit sets in MOTION_ERROR, and the bits that caused it stay set
  in AXISSTATUS until DATUM(0), or DATUM(7) on that axis, clears them. ERROR_AXIS is the
  axis that made MOTION_ERROR non-zero (0 again after the clear, as the page says).
- **A clear while the cause stays**: DATUM(0)/(7) clears on its own cycle (MOTION_ERROR
  reads 0 right after it); a bit still on (a limit the axis still stands on) is ANDed
  again on the next servo cycle, so the axis goes back into error there (ERRORMASK's
  page: every cycle; DATUM's: only the flags are reset, I). The machine looks on that
  cycle (`Drive.look_again`) without waiting for another event.
- **Without a disable group** (the axis in error is in none): WDOG goes OFF and every
  axis's motion is cancelled at once (the demand stays where it is); buffered moves are
  dropped and every link ends there (CANCEL's page: moves that are not speed-profiled end
  at once).
- **With a disable group** (DISABLE_GROUP(a, b, ...)): only the axes of the group of the
  axis in error stop; AXIS_ENABLE and SERVO go OFF on each of them and WDOG stays ON; the
  other axes run on. DATUM(7) on an axis clears its error; AXIS_ENABLE = ON and SERVO = ON
  enable it again. DISABLE_GROUP(-1) removes every group; an axis named in a new group
  leaves the one it was in (an axis belongs to one group at most).
- ADDAX stays on an axis whose motion a motion error cancels unless AXIS_MODE bit 3 is set
  (CANCEL's page: it is cancelled like that).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any, Protocol

import numpy as np

from .runs import Run


class ErrorHost(Protocol):
    """What the motion errors need of the drive (drive.Drive)."""

    m: Any  # the machine (drive.DriveHost)
    following: Any  # following.Following: the servo loops open with their drives
    searches: dict[int, tuple[int, Run]]
    look_again: int | None  # the machine looks on this tick (drive.Drive)

    def axis_status(self, axis: int) -> int: ...
    def settable(self, axis: int) -> int: ...

CANCEL_ADDAX = 1 << 3  # AXIS_MODE bit 3: a cancel ends the axis's ADDAX too


class MotionErrors:
    """MOTION_ERROR, ERROR_AXIS, the AXISSTATUS bits an error holds, and the groups."""

    def __init__(self, drive: ErrorHost) -> None:
        self.drive = drive
        self.groups: list[frozenset[int]] = []  # DISABLE_GROUP: survives nothing but -1/EX
        self.reset()

    def reset(self) -> None:
        """Power-up (and EX): no errors, no groups."""
        n = self.drive.m.axis_count
        self.latched = [0] * n  # AXISSTATUS bits held by a motion error until cleared
        self.cleared = [-1] * n  # the tick of the axis's last DATUM(0)/(7), and
        self.held = [0] * n  # the bits still on then: they act again from the next cycle
        self.motion_error = 0  # MOTION_ERROR: a bit per axis in error
        self.error_axis = 0  # ERROR_AXIS (0 with no error: its page)
        self.groups = []

    # ---- DISABLE_GROUP ---------------------------------------------------------------
    def disable_group(self, args: Sequence[float]) -> None:
        """DISABLE_GROUP(-1) removes every group; DISABLE_GROUP(a, b, ...) makes one of
        those axes. Whole axis numbers of the machine, each named once, else 'Parameter out
        of range' with nothing changed (D)."""
        count = self.drive.m.axis_count
        if list(args) == [-1]:
            self.groups = []
            return
        if not args or any(a != int(a) or not 0 <= a < count for a in args) \
                or len(set(args)) != len(args):
            raise ValueError("Parameter out of range")
        group = frozenset(int(a) for a in args)
        kept = [g - group for g in self.groups]  # (D: an axis leaves its old group)
        self.groups = [g for g in kept if g] + [group]

    def group_of(self, axis: int) -> frozenset[int] | None:
        for group in self.groups:
            if axis in group:
                return group
        return None

    # ---- errors --------------------------------------------------------------------------
    def masked(self, axis: int) -> int:
        mask = int(self.drive.m.axes[axis].params["ERRORMASK"])
        if not mask & self.drive.settable(axis) and not self.latched[axis]:
            return 0  # (no bit it holds can be set: FE is 0, no remote drives)
        return self.drive.axis_status(axis) & mask

    def check(self) -> bool:
        """AXISSTATUS AND ERRORMASK, every look: bits on that the axis does not already
        hold put it into motion error (those still on at a clear on this cycle act from
        the next); the axes it stops stop here (see the module docstring)."""
        m = self.drive.m
        new_axes: list[int] = []
        for a in range(m.axis_count):
            masked = self.masked(a)
            new = masked & ~self.latched[a] if self.motion_error >> a & 1 else masked
            if self.cleared[a] >= m.tick:
                new &= ~self.held[a]  # (a bit set since the clear acts at once)
            if new:
                self.latched[a] |= new
                new_axes.append(a)
        if not new_axes:
            return False
        if self.motion_error == 0:
            self.error_axis = new_axes[0]
        for a in new_axes:
            self.motion_error |= 1 << a
        groups = [self.group_of(a) for a in new_axes]
        if any(g is None for g in groups):
            m.system["WDOG"] = 0.0  # the controller's own: every axis stops
            self.halt(range(m.axis_count))
        else:
            stopped = sorted(set().union(*(g for g in groups if g is not None)))
            for a in stopped:
                params = m.axes[a].params
                params["AXIS_ENABLE"] = params["SERVO"] = 0.0
            self.halt(stopped)
        self.drive.following.configure()  # the servo loops open with their drives
        return True

    def clear(self, axis: int | None) -> None:
        """DATUM(0) (every axis) or DATUM(7) (that axis): its error and held bits clear
        now; a cause still on acts again on the next servo cycle (module docstring)."""
        m = self.drive.m
        axes = range(m.axis_count) if axis is None else [axis]
        for a in axes:
            loop = m.axes[a].servo
            if loop is not None and (loop.tripped or loop.trip_tick is not None):
                loop.tripped, loop.trip_tick = False, None  # (Following.rearm, one loop)
                loop.reset_filter(m.motor(a) - loop.p)
            self.latched[a] = 0
            self.motion_error &= ~(1 << a)
            self.cleared[a] = m.tick
        if self.motion_error == 0:
            self.error_axis = 0
        for a in axes:
            self.held[a] = self.masked(a)
        if any(self.held[a] for a in axes):  # (the next cycle's check must run)
            again = self.drive.look_again
            self.drive.look_again = m.tick + 1 if again is None else min(again, m.tick + 1)

    # ---- stopping at once ---------------------------------------------------------------
    def halt(self, axes: Iterable[int]) -> None:
        """Stop the axes at once (the demand stays where it is): their runs (with every
        axis of a path they share), buffered moves and links end here."""
        m = self.drive.m
        m.outputs.sync_all()
        now = m.tick
        chosen = list(axes)
        for i in chosen:
            queue = m.queues[i]
            while queue:
                run = queue[0]
                if run.started:
                    self._halt(run, now)
                else:
                    for a in run.axes:
                        m.queues[a].remove(run)
            axis = m.axes[i]
            if axis.link is not None or axis.pending_link is not None or m.links.chains[i]:
                m.links.chains[i].clear()
                m._unlink(i)
            if i in m.links.addax and int(axis.params["AXIS_MODE"]) & CANCEL_ADDAX:
                m.links.set_addax(i, -1.0)
        searches = self.drive.searches
        for i in chosen:
            searches.pop(i, None)

    def _halt(self, run: Run, now: int) -> None:
        """Stop a running run on this tick where it stands; it leaves the queues."""
        m = self.drive.m
        travelled, _speed = run.distance_speed(np.array([now]), m.period)
        for a in run.axes:
            axis = m.axes[a]
            exact = m.own_demand(a)  # (ADDAX's part stays ADDAX's)
            axis.freeze(m)
            axis.steps = math.floor(exact)
            axis.fraction = exact - axis.steps
            m.queues[a].remove(run)
        m.distance_done[run.base] += float(travelled[0]) / run.units


__all__ = ["CANCEL_ADDAX", "MotionErrors"]
