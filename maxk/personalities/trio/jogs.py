"""Jog inputs of the MC405: FWD_JOG, REV_JOG, FAST_JOG and JOGSPEED; FWD_START and
REV_START, a jog asked for by a program where no input is declared (their pages).

An axis whose FWD_JOG (REV_JOG) names an input jogs forward (in reverse) while that
input is low, at JOGSPEED, or at SPEED while the input FAST_JOG names is low too (C: the
MC206 manual's JOGSPEED page: "a slow jog ... when a jog input ... is low"); -1 (the
power-up value) declares none. A jog is a FORWARD/REVERSE-like move at that speed
(MTYPE 14/15, I) started on the servo tick the input goes low, or the jog input is
declared, while the axis is idle (D: a jog does not interrupt a move); when the input
goes high again it ramps down at DECEL, as CANCEL. Both jog inputs low: no jog (D).

The inputs are read as IN(n) reads them, so what the language makes of input polarity
applies here too; they are looked at when the world or a parameter changes, and at
every engine event (an axis that becomes idle with its jog input still low jogs then).
"""

from __future__ import annotations

from typing import Any

FOREVER = 2.0 ** 50  # counts: a jog runs until its input lets go (as FORWARD)
FWD_JOG, REV_JOG = 14, 15  # MTYPE (I: the manual's MTYPE table as recalled)


class Jogs:
    """The jog inputs of every axis: an every-event watcher of the machine."""

    every_event = True

    def __init__(self, machine: Any) -> None:
        self.m = machine
        self.jogging: dict[int, int] = {}  # axis -> direction of the jog it runs

    def reset(self) -> None:
        self.jogging.clear()

    def next_event(self) -> int | None:
        return None

    def on_event(self, now: int) -> None:
        self.look()

    def _low(self, number: float) -> bool:
        return number >= 0 and not self.m.digital_input(int(number))

    def _asked(self, params: Any, jog: str, start: str) -> bool:
        """The jog input is low, or with no input (-1) FWD_START/REV_START is 1 (C: their
        pages' table: 1 jogs, any other value does not; an input set: no function)."""
        number = params.get(jog, -1)
        if number == -1:
            return bool(params.get(start, 0.0) == 1)
        return self._low(number)

    def wanted(self, axis: int) -> int:
        params = self.m.axes[axis].params
        forward = self._asked(params, "FWD_JOG", "FWD_START")
        reverse = self._asked(params, "REV_JOG", "REV_START")
        return 0 if forward == reverse else 1 if forward else -1

    def look(self) -> None:
        m = self.m
        for axis in range(m.axis_count):
            params = m.axes[axis].params
            if params.get("FWD_JOG", -1) < 0 and params.get("REV_JOG", -1) < 0 \
                    and axis not in self.jogging and params.get("FWD_START", 0.0) != 1 \
                    and params.get("REV_START", 0.0) != 1:
                continue
            want = self.wanted(axis)
            running = self.jogging.get(axis, 0)
            if running and want != running:
                queue = m.queues[axis]
                if queue and queue[0].started and not queue[0].stopping:
                    m.cancel(axis)
                del self.jogging[axis]
                running = 0
            if want and not running and m.axis_idle(axis):
                fast = self._low(params.get("FAST_JOG", -1))
                speed = "SPEED" if fast else "JOGSPEED"
                if not params.get(speed, 0.0) > 0:
                    continue
                m._speed_name = speed
                try:
                    m._load((axis,), [int(FOREVER) * want],
                            kind=FWD_JOG if want > 0 else REV_JOG)
                except ValueError:
                    continue  # (a disabled drive, an active limit: no jog)
                finally:
                    m._speed_name = "SPEED"
                self.jogging[axis] = want


__all__ = ["Jogs"]
