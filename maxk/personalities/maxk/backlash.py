"""Mechanical backlash between a stepper and its stage, and the board's compensation (BC).

The world gives a stage N steps of play (`AxisWorld.backlash`): after the motor reverses,
the stage does not follow its first N steps. BC# makes the board give # extra steps in
the new direction at every reversal, which the motor counter does not count (our reading
of the manual's "Backlash compensation", recorded in the command table). So with BC equal
to the play the stage stands where the motor counter says; with BC0 it lags by the play
after each reversal, which an encoder on the stage (RE) shows.

The state is a function of the motor's path, kept at the origin of each motion and walked
along its monotonic stretches in closed form (each phase of a motion travels one way):

- ``direction``: the way the board last stepped (its memory for BC; power-up: positive,
  so the first move down is a reversal and the first move up is not);
- ``extra``: the net extra steps BC has given (the drive is this far from the counter);
- ``play``: how far the stage stands ahead of the drive, 0..N (0 after travelling up,
  N after travelling down: the stage stays behind while the drive crosses the gap).

The stage stands at ``motor steps + extra + play``. The extra steps are given at once
when a reversal starts (D). Switches, index marks and position maintenance see the motor
counter's steps, not the stage (D: as for missed steps).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from maxk.firmware_model.motion import MotionPlan
from maxk.firmware_model.profiles import Motion


class Backlash(NamedTuple):
    """Where the drive and the stage stand relative to the motor's counted steps."""

    direction: int = 1
    extra: int = 0
    play: int = 0

    @property
    def offset(self) -> int:
        """Steps the stage stands ahead of the motor's counted position."""
        return self.extra + self.play

    def turned(self) -> Backlash:
        """The state after a reversal with no play and no BC: only the direction changes
        (every back-and-forth move of a plain stepper: the plain states are shared)."""
        if not (self.extra or self.play):
            return PLAIN_DOWN if self.direction > 0 else PLAIN_UP
        return Backlash(-self.direction, self.extra, 0)

    def leg(self, moved: int, play: int, compensation: int) -> Backlash:
        """After the motor travels `moved` steps one way (stage play `play`, BC
        `compensation`)."""
        if moved == 0:
            return self if self.play <= play else self._replace(play=play)
        d = 1 if moved > 0 else -1
        extra, drive = self.extra, moved
        if d != self.direction:  # a reversal: BC's extra steps, in the new direction
            extra += d * compensation
            drive += d * compensation
        # up: the stage waits until the drive reaches it; down: until the drive is the
        # whole play below it
        ahead = max(0, min(self.play, play) - drive) if d > 0 else min(play, self.play - drive)
        return Backlash(d, extra, ahead)


PLAIN_UP = Backlash(1, 0, 0)
PLAIN_DOWN = Backlash(-1, 0, 0)


def walk(state: Backlash, origin: int, motion: MotionPlan, until: float | None, end: int,
         play: int, compensation: int) -> Backlash:
    """The state after `motion` (started at motor step `origin` in `state`) has run to
    `until` seconds (None: to its end) where the motor stands on step `end`: every
    change of direction inside the motion is a turning point. With no play and no BC
    only the direction is remembered: a contour's is the way its net travel went (D: its
    turning points would make the whole lazy plan at every VO, for a direction that
    matters only once BC is set); a one-way move's is its own."""
    if play == 0 and compensation == 0 and state.play == 0 and (
            not isinstance(motion, Motion) or motion.monotonic):  # one leg, or taken as one
        moved = end - origin
        if moved == 0 or (moved > 0) == (state.direction > 0):
            return state
        return Backlash(1 if moved > 0 else -1, state.extra, 0)
    position = origin
    phases = motion.phases
    i = 0
    while i < len(phases):
        direction = phases[i].direction
        j = i
        while j + 1 < len(phases) and phases[j + 1].direction == direction:
            j += 1
        last = phases[j]
        turn = last.t0 + last.duration
        if j + 1 >= len(phases) or math.isinf(turn) or (until is not None and turn >= until):
            break
        here = origin + int(motion.offset(turn))
        state = state.leg(here - position, play, compensation)
        position = here
        i = j + 1
    return state.leg(end - position, play, compensation)
