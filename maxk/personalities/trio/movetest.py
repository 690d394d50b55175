"""MOVETEST(start/stop, dist0, accel0, speed0, dwell0, dist1, accel1, speed1, dwell1): a
test cycle of two moves on the axis, forward and back (TrioBASIC help MOVETEST; newer than
the MC405's token table, helpwords.NEWER_WORDS).

MOVETEST(1, ...) starts it: a MOVE of dist0 at speed0 with accel0 (its deceleration too: D),
a dwell of dwell0 ms, a MOVE of -dist1 (dist1 is the distance back: D) at speed1 and
accel1, dwell1 ms, and again (C: its page). The moves are the axis's own buffered moves
(MTYPE 1), loaded when the axis is idle, with the axis's VP_MODE, JERK and SRAMP (D); the
axis's SPEED, ACCEL and DECEL are left as they were (D). A dwell ends on the first servo
tick at or after it (D). MOVETEST(0) stops the cycle at the end of the second move (C);
CANCEL and RAPIDSTOP stop the move running and the cycle (C). A move refused (a limit, a
disabled drive) ends the cycle (D).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

_RATES = ("SPEED", "ACCEL", "DECEL")


@dataclass
class _Cycle:
    legs: tuple[tuple[float, float, float, float], tuple[float, float, float, float]]
    # (distance, accel, speed, dwell ms) of the move forward and of the move back
    leg: int = 0  # the move running, or the one whose dwell runs
    phase: str = "wait"  # "wait" to load, "move" running, "dwell" after it
    until: int = 0  # the dwell's end tick
    stopping: bool = False  # MOVETEST(0): stop after the second move


class MoveTests:
    """The test cycles of every axis: an every-event watcher of the machine."""

    every_event = True

    def __init__(self, machine: Any) -> None:
        self.m = machine
        self.cycles: dict[int, _Cycle] = {}

    def reset(self) -> None:
        self.cycles.clear()

    def next_event(self) -> int | None:
        ends = [c.until for c in self.cycles.values() if c.phase == "dwell"]
        return max(min(ends), self.m.tick) if ends else None

    def on_event(self, now: int) -> None:
        self.look()

    def movetest(self, axis: int, args: list[float]) -> None:
        """MOVETEST(0) or MOVETEST(1, eight values); bad values: refused, nothing set."""
        if not args or args[0] not in (0, 1):
            raise ValueError("Parameter out of range")
        if args[0] == 0:
            if axis in self.cycles:
                self.cycles[axis].stopping = True
                self.look()
            return
        if len(args) != 9 or any(v <= 0 for v in (args[2], args[3], args[6], args[7])) \
                or args[4] < 0 or args[8] < 0:
            raise ValueError("Parameter out of range")
        self.cycles[axis] = _Cycle(((args[1], args[2], args[3], args[4]),
                                    (-args[5], args[6], args[7], args[8])))
        self.look()

    def cancel(self, axis: int | None = None) -> None:
        """CANCEL (one axis) or RAPIDSTOP (None: every axis) ends the cycle."""
        if axis is None:
            self.cycles.clear()
        else:
            self.cycles.pop(axis, None)

    def look(self) -> None:
        m = self.m
        for axis, cycle in list(self.cycles.items()):
            for _step in range(4):  # (zero dwells: a move may end and the next load now)
                if cycle.phase == "move" and m.axis_idle(axis):
                    if cycle.stopping and cycle.leg == 1:
                        del self.cycles[axis]
                        break
                    dwell = cycle.legs[cycle.leg][3] / 1000.0
                    cycle.until = m.tick + math.ceil(dwell / m.period - 1e-9)
                    cycle.phase = "dwell"
                if cycle.phase == "dwell" and m.tick >= cycle.until:
                    if cycle.stopping and cycle.leg == 1:
                        del self.cycles[axis]
                        break
                    cycle.leg, cycle.phase = 1 - cycle.leg, "wait"
                if cycle.phase == "wait" and m.axis_idle(axis):
                    if not self._load(axis, cycle.legs[cycle.leg]):
                        del self.cycles[axis]
                        break
                    cycle.phase = "move"
                    continue
                break

    def _load(self, axis: int, leg: tuple[float, float, float, float]) -> bool:
        m = self.m
        params = m.axes[axis].params
        saved = {name: params[name] for name in _RATES}
        distance, accel, speed, _dwell = leg
        params.update(SPEED=speed, ACCEL=accel, DECEL=accel)
        try:
            m._load((axis,), [round(distance * m.axes[axis].units)])
        except ValueError:
            return False
        finally:
            params.update(saved)
        return True


__all__ = ["MoveTests"]
