"""The corner state machine of CORNER_MODE bit 2: the move loader's handshake with a
program at sharp corners (TrioBASIC help CORNER_STATE, RAISE_ANGLE, CORNER_MODE), so a
program can lift and turn a cutting knife before the path goes on.

With CORNER_MODE bit 2 set and RAISE_ANGLE above 0 on the base axis, a move of a group of
two or more axes whose start turns away from the end of the move loaded before it by more
than RAISE_ANGLE (C: the change of direction of CHANGE_DIR_LAST, first two axes), while
the group still has moves buffered or running (D: a move from rest has no corner), is
held out of the motion generator: the path before it ends at rest there, and the moves
loaded after it merge behind it. Then (C: the CORNER_STATE page's sequence):
1. when it is the next move to load (the moves before it are on their last one) the
   system sets CORNER_STATE 1;
2. the program sets CORNER_STATE 3 (bit 1): once the moves before it are done, the system
   loads it at zero speed (MTYPE reads it, TANG_DIRECTION gives its direction) and sets
   CORNER_STATE 7;
3. the program sets CORNER_STATE 0: the path ramps up and runs on (MERGE as usual).
One corner at a time per base axis (D); other writes are only stored (D).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Protocol

from maxk.firmware_model.path import PathPlan

from .profiles_sp import change_of_direction, direction, heading
from .runs import CORNER_HELD, CORNER_LOADED, Run

STATE = "CORNER_STATE"
READY, LOAD, LOADED = 1, 2, 4  # CORNER_STATE bits: system, program, system (C)


class Host(Protocol):
    queues: list
    tick: int
    period: float

    def params_of(self, axis: int) -> Mapping[str, float]: ...
    def set_corner_state(self, axis: int, value: float) -> None: ...
    def _apply_plan(self, run: Run, plan: PathPlan) -> None: ...
    def _start_ready(self) -> None: ...


def machine_on(params: Mapping[str, float]) -> bool:
    """CORNER_MODE bit 2 with a RAISE_ANGLE above 0 (C: RAISE_ANGLE 0, no interaction)."""
    return bool(int(params.get("CORNER_MODE", 0.0)) & 4) and params.get("RAISE_ANGLE",
                                                                         0.0) > 0


def _corner_run(queue: Sequence[Run], base: int) -> tuple[int, Run] | None:
    for i, run in enumerate(queue):
        if run.base == base and run.corner:
            return i, run
    return None


class CornerState:
    """Each base axis's last move direction and its corner handshake."""

    def __init__(self, machine: Host) -> None:
        self.m = machine
        self.last_end: dict[int, float] = {}  # base axis -> the end heading of its last move

    def reset(self) -> None:
        self.last_end.clear()

    def holds(self, axes: Sequence[int], delta: Sequence[float],
              arc: tuple[float, ...] | None) -> bool:
        """Whether the move being loaded is held behind a corner (and remember where it
        ends)."""
        base = axes[0]
        vector = tuple(float(d) for d in delta)
        start = heading(direction(vector, arc, False))
        before = self.last_end.get(base)
        self.last_end[base] = heading(direction(vector, arc, True))
        params = self.m.params_of(base)
        if len(axes) < 2 or not machine_on(params) or before is None \
                or not self.m.queues[base]:
            return False
        return change_of_direction(before, start) > params["RAISE_ANGLE"]

    def update(self) -> None:
        """The system's side: CORNER_STATE 1 when a held move is next, 7 once loaded."""
        m = self.m
        for base, queue in enumerate(m.queues):
            found = _corner_run(queue, base)
            if found is None:
                continue
            i, run = found
            state = int(m.params_of(base).get(STATE, 0.0))
            if run.corner == CORNER_HELD and state == 0:
                ahead = queue[i - 1] if i > 0 else None
                if ahead is None or (i == 1 and ahead.started
                                     and ahead.moves_left(m.tick, m.period) <= 1):
                    m.set_corner_state(base, READY)
            elif run.corner == CORNER_LOADED and run.started and state & LOAD \
                    and not state & LOADED:
                m.set_corner_state(base, state | READY | LOADED)

    def write(self, axis: int, value: float) -> None:
        """The program's side: bit 1 lets the held move in at zero speed; 0 ramps it up."""
        m = self.m
        m.set_corner_state(axis, value)
        found = _corner_run(m.queues[axis], axis)
        if found is not None:
            run = found[1]
            if run.corner == CORNER_HELD and int(value) & LOAD:
                run.corner = CORNER_LOADED
            elif run.corner == CORNER_LOADED and int(value) == 0:
                run.corner = 0
                if run.started and not run.stopping:
                    m._apply_plan(run, run.plan_new(m.tick, period=m.period))
        m._start_ready()
