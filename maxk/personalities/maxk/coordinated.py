"""MT/ML linear interpolation: several axes on a straight line, arriving together.

The manual (Appendix C): "The controller would calculate the relative velocities
required to perform a straight line move from the current position to the desired
absolute position so that all axes arrive at their destinations at the same time."

One reference profile is planned for the longest distance; each axis follows it scaled
by its own distance, so every point of the path lies on the line. The reference's
speed, acceleration and deceleration are the largest that keep every axis within its
own VL, AC and DC (and VB), so each axis's limits are honoured; the ramp shape is the
one of the first axis in the move (X before Y before ...).

Limits (D, the evidence does not say): if any axis of the move would start into a
pressed limit the whole move is refused; if a limit trips on one axis during the move,
every axis of it stops the same way (at once or decelerating) and their queues are
flushed, so the others never finish a path that is no longer straight.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from maxk.firmware_model.profiles import Motion, Phase, plan_move

if TYPE_CHECKING:
    from maxk.personalities.maxk.axis import Axis, StartGroup
    from maxk.personalities.maxk.board import Board


class LinearMove:
    """The axes and targets of one MT/ML command; its start group waits for their GOs."""

    def __init__(self, group: StartGroup) -> None:
        self.group = group
        self.targets: dict[int, int] = {}

    def set_target(self, axis: Axis, target: int) -> None:
        self.targets[axis.index] = target
        axis.pending_target = None
        axis.pending_linear = self

    def withdraw(self, axis: Axis, board: Board) -> None:
        self.targets.pop(axis.index, None)
        self.group.withdraw(axis, board)

    def start(self, board: Board) -> None:
        axes = [board.axes[i] for i in sorted(self.targets)]
        for axis in axes:
            axis.pending_linear = None
        distances = {a.index: self.targets[a.index] - a.motor_position(board) for a in axes}
        moving = [a for a in axes if distances[a.index] != 0]
        self.targets.clear()
        if not moving:
            return
        reference = max(abs(distances[a.index]) for a in moving)
        # Scale each axis's limits up to the reference distance; the tightest one wins.
        scale = {a.index: reference / abs(distances[a.index]) for a in moving}
        peak = min(a.config.velocity * scale[a.index] for a in moving)
        base = min(a.config.base_velocity * scale[a.index] for a in moving)
        accel = min(a.config.acceleration * scale[a.index] for a in moving)
        decel = min(a.config.deceleration * scale[a.index] for a in moving)
        motion = plan_move(reference, min(base, peak), peak, accel, decel, moving[0].config.ramp)
        # One axis blocked by a pressed limit refuses the whole move: moving the others
        # alone would leave the line (D).
        blocked = [a for a in moving
                   if board.limit_blocks(a, 1 if distances[a.index] > 0 else -1)]
        if blocked:
            for axis in blocked:
                board.refuse_into_limit(axis)
            return
        for axis in moving:
            axis.start_motion(scaled(motion, distances[axis.index], reference), board)
            axis.linked = [a for a in moving if a is not axis]


def scaled(reference: Motion, distance: int, reference_distance: int) -> Motion:
    """The reference profile scaled to one axis's signed distance, ending exactly on it."""
    f = distance / reference_distance
    sign = 1 if f >= 0 else -1
    g = abs(f)
    phases = [
        Phase(p.t0, p.duration, p.s0 * f, p.v1 * g, p.v2 * g, p.direction * sign, p.shape,
              p.mirrored)
        for p in reference.phases
    ]
    return Motion(phases, reference.end_time, distance, reference.ramp_end_time,
                  direction=sign, peak_speed=reference.peak_speed * g)
