"""BACKLASH and BACKLASH_DIST (TrioBASIC help BACKLASH, BACKLASH_DIST): a compensation move
superimposed on an axis's output after each reversal of its DPOS.

The page: with BACKLASH(ON, distance, speed, accel) an offset move of `distance` is applied
while the demand goes one way and taken back while it goes the other way, at its own speed
and acceleration, on top of the commanded motion; BACKLASH_DIST reads the compensation
applied; MPOS is advanced by it (the page's oscilloscope example: at the start of a
forward MOVE the axis runs at SPEED + the compensation's speed for a moment).

How it is modelled, exact to the servo tick:
- the reversals are the direction changes of the axis's own motions (a move, a path's
  share, a stop), read from the motion plan's monotonic phases when it begins, so each
  compensation move starts at the very instant the demand turns (its time origin is the
  phase's start, not a servo tick);
- a compensation move is a trapezoid (a triangle when short) from rest at the speed and
  acceleration given, from where the compensation is to its new value; a reversal during
  one starts the next from where it has got to, from rest (D);
- the value after a forward reversal is +distance, after a reverse one 0; the first
  motion after BACKLASH(ON) counts as a reversal when it goes forward (the axis is taken
  as having last gone in reverse, D: the page's example shows the move at the start of
  the first forward MOVE);
- the compensation is in the axis's output: a stepper's world motor turns it (limit
  switches and shaft encoders see it, through `stepratio.motor`), MPOS of an axis without
  a servo loop reads DPOS + BACKLASH_DIST; a servo axis's loop takes it in its command
  (`ServoLoop.command_offset`: the loop then steps cycle by cycle), so its MPOS moves by
  it and FE stays the loop's own error; DPOS never includes it.
Decisions (D): BACKLASH(ON) with fewer values keeps the others as last given (power-up 0);
a speed or acceleration of 0 applies the compensation within the servo cycle; OFF takes
the compensation back to 0 at its speed and acceleration; a negative distance compensates
the other way. A distance, speed or acceleration of 2^53 counts or more (the machine's
position range) is refused. Not modelled: reversals of a linked axis (CONNECT, CAMBOX, MOVELINK ...:
their demand has no phases), and the compensation in the search for a limit switch.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from maxk.firmware_model.motion import MotionPlan

MAX_PIECES = 64  # compensation moves kept per axis (older ones are over: dropped)


@dataclass(frozen=True)
class Piece:
    """One compensation move: from `start` to `end` counts, beginning at `t0` seconds."""

    t0: float
    start: float
    end: float
    speed: float  # counts/s (0: at once)
    accel: float  # counts/s^2 (0: at once)
    side: int  # the demand's direction after it (+1 forward, -1 reverse)

    def value(self, t: np.ndarray) -> np.ndarray:
        distance = abs(self.end - self.start)
        tau = np.maximum(t - self.t0, 0.0)
        v, a = self.speed, self.accel
        if distance == 0 or v <= 0 or a <= 0:
            done = np.full(tau.shape, distance)
        else:
            ramp = v / a  # seconds to reach the speed
            if a * ramp * ramp >= distance:  # a triangle: never reaches the speed
                ramp = math.sqrt(distance / a)
                v = a * ramp
            total = 2 * ramp + (distance - a * ramp * ramp) / v
            up = 0.5 * a * np.minimum(tau, ramp) ** 2
            flat = v * np.clip(tau - ramp, 0.0, total - 2 * ramp)
            down_t = np.clip(tau - (total - ramp), 0.0, ramp)
            down = v * down_t - 0.5 * a * down_t ** 2
            done = np.where(tau >= total, distance, np.minimum(up + flat + down, distance))
        return np.where(done >= distance, self.end,  # (exactly there once done)
                        self.start + (1.0 if self.end >= self.start else -1.0) * done)


@dataclass
class AxisBacklash:
    """One axis's settings and the compensation moves it has made."""

    on: bool = False
    distance: float = 0.0  # counts
    speed: float = 0.0  # counts/s
    accel: float = 0.0  # counts/s^2
    side: int = -1  # before any piece: the axis last went in reverse (D)
    pieces: list[Piece] = field(default_factory=list)

    def value(self, t: np.ndarray) -> np.ndarray:
        """The compensation, counts, at times `t` (seconds)."""
        out = np.zeros(t.shape)
        for piece in self.pieces:  # (in order of t0: each later one takes over)
            out = np.where(t >= piece.t0, piece.value(t), out)
        return out

    def value_at(self, t: float) -> float:
        return float(self.value(np.array([t]))[0])

    def move_to(self, t0: float, end: float, side: int) -> None:
        start = self.value_at(t0)
        self.pieces.append(Piece(t0, start, end, self.speed, self.accel, side))
        self.side = side
        if len(self.pieces) > MAX_PIECES:
            del self.pieces[0]

    def forget_after(self, t: float) -> None:
        """A motion replaced at `t`: the reversals planned beyond it did not happen."""
        while self.pieces and self.pieces[-1].t0 > t:
            self.pieces.pop()
        self.side = self.pieces[-1].side if self.pieces else self.side

    def prune(self, t: float) -> None:
        """Drop the pieces a later one, already begun at `t`, has taken over from."""
        while len(self.pieces) > 1 and self.pieces[1].t0 <= t:
            del self.pieces[0]


LIMIT = 2.0 ** 53
"""Counts (counts/s, counts/s^2) a compensation may reach: the machine's position range
(`machine.MAX_COUNTS`); beyond it the trapezoid's arithmetic overflows."""


class Backlash:
    """Every axis's compensation (see the module docstring)."""

    def __init__(self, axis_count: int) -> None:
        self.axes = [AxisBacklash() for _ in range(axis_count)]

    def reset(self) -> None:
        self.axes = [AxisBacklash() for _ in self.axes]

    def command(self, axis: int, args: Sequence[float], units: float, now: float) -> None:
        """BACKLASH(enable[, distance, speed, accel]) in user units (checked whole before
        anything changes)."""
        if not 1 <= len(args) <= 4:
            raise ValueError("Syntax error")
        if not all(math.isfinite(a) for a in args):
            raise ValueError("Parameter out of range")
        if any(a < 0 for a in args[2:]):
            raise ValueError("Parameter out of range")
        b = self.axes[axis]
        scale = abs(units)
        values = [b.distance, b.speed, b.accel]
        for k, value in enumerate(args[1:]):
            values[k] = value * (units if k == 0 else scale)
        if not all(abs(v) < LIMIT for v in values):  # (a position the machine can hold)
            raise ValueError("Parameter out of range")
        b.distance, b.speed, b.accel = values
        b.prune(now)
        if args[0] != 0:
            if not b.on:
                b.on, b.side = True, -1
        else:
            b.on = False
            if b.value_at(now) != 0.0:
                b.move_to(now, 0.0, b.side)

    def began(self, axis: int, motion: MotionPlan, start: float) -> None:
        """An axis's own motion began at `start` seconds: its reversals from the plan."""
        b = self.axes[axis]
        if not b.on:
            return
        b.forget_after(start)
        b.prune(start)
        for phase in motion.phases:
            if phase.duration <= 0 or (phase.v1 <= 0 and phase.v2 <= 0):
                continue  # (no travel: no direction)
            if math.isinf(phase.t0):
                break
            side = 1 if phase.direction > 0 else -1
            if side != b.side:
                b.move_to(start + phase.t0, b.distance if side > 0 else 0.0, side)

    def offset(self, axis: int, period: float) -> Callable[[int], float] | None:
        """The compensation as a servo loop's command offset (counts at a tick); None
        when the axis has never had any (the loop then runs compiled, in closed form)."""
        b = self.axes[axis]
        if not b.pieces:
            return None
        return lambda tick: b.value_at(tick * period)

    def at(self, axis: int, tick: int, period: float) -> float:
        """The compensation at one tick, counts."""
        b = self.axes[axis]
        return b.value_at(tick * period) if b.pieces else 0.0

    def counts(self, axis: int, ticks: np.ndarray, period: float) -> np.ndarray | None:
        """The compensation at `ticks`, counts; None when the axis has never had any."""
        b = self.axes[axis]
        if not b.pieces:
            return None
        return b.value(ticks * period)


__all__ = ["Backlash"]
