"""MOVE_PA / MOVE_PB: values carried through the move buffer and acted on as each move
becomes active (TrioBASIC help MOVE_PA, MOVE_PB, MOVE_PA_CONT, MOVE_PB_CONT, MOVE_PA_IDLE,
MOVE_PB_IDLE).

Every move loaded copies its axes' MOVE_PA and MOVE_PB (C). At the servo tick a move
becomes active (its run starts, or the merged move before it ends: the tick the move
buffer frees a slot, runs.Run.moves_left) each of its axes acts on its copy by that
axis's MOVE_PA_CONT / MOVE_PB_CONT read then (D: the page says the control applies
"when the move becomes active"):
- 1 and 3: bits 0..11 an output's number, bit 12 its level (C); mode 3 as mode 1 (D:
  its extra "VP_SPEED = 0" case is the idle action at rest points; a merged path at rest
  between moves has the next move active at that same tick);
- 4: bits 0..11 the first output, bits 12..19 how many, bits 20.. their pattern, lowest
  bit to the first output (C);
- 2: the value is copied into AXIS_DEBUG_A (MOVE_PB: AXIS_DEBUG_B) (C);
- 5 and 6 (analogue outputs): nothing (D: the MC405 here has no analogue outputs).
When the axis's last move ends (MTYPE 0) it acts on MOVE_PA_IDLE / MOVE_PB_IDLE the same
way, read then (C).
"""

from __future__ import annotations

from collections.abc import Mapping, MutableMapping
from typing import Protocol

from .runs import Run

PAIRS = (("MOVE_PA", "MOVE_PA_CONT", "MOVE_PA_IDLE"),
         ("MOVE_PB", "MOVE_PB_CONT", "MOVE_PB_IDLE"))
DEBUG = ("AXIS_DEBUG_A", "AXIS_DEBUG_B")  # mode 2's copy of MOVE_PA, MOVE_PB (C)
OUTPUT_BITS = 12  # bits 0..11: an output's number (C)
MAX_PATTERN = 32  # mode 4: bits 20..51 hold the pattern (C)


class Host(Protocol):
    queues: list
    tick: int
    period: float

    def set_output(self, number: int, on: bool) -> None: ...
    def params_of(self, axis: int) -> MutableMapping[str, float]: ...


def copies(params: Mapping[str, float]) -> tuple[float, float]:
    """What a move loaded now carries for one axis: (MOVE_PA, MOVE_PB)."""
    return (params.get("MOVE_PA", 0.0), params.get("MOVE_PB", 0.0))


def act(m: Host, mode: float, value: float, axis: int, k: int) -> None:
    """One MOVE_PA (k 0) / MOVE_PB (k 1) value, or its idle one, acted on by its mode
    (a fraction written to the control parameter is cut, as an integer parameter's: D)."""
    code, mode = int(value), int(mode)
    if mode == 2:
        m.params_of(axis)[DEBUG[k]] = value
    elif mode in (1, 3):
        m.set_output(code & ((1 << OUTPUT_BITS) - 1), bool(code >> OUTPUT_BITS & 1))
    elif mode == 4:
        first = code & ((1 << OUTPUT_BITS) - 1)
        count = min(code >> 12 & 0xFF, MAX_PATTERN)
        pattern = code >> 20
        for i in range(count):
            m.set_output(first + i, bool(pattern >> i & 1))


class MovePa:
    """The move each axis has active, so that each one acts once, at its tick."""

    def __init__(self, machine: Host) -> None:
        self.machine = machine
        self.active: dict[int, tuple[Run, int]] = {}  # axis -> (its run, the move's index)

    def reset(self) -> None:
        self.active.clear()

    def update(self) -> None:
        """Act for every axis whose active move changed since the last look."""
        m = self.machine
        for a, queue in enumerate(m.queues):
            run: Run | None = queue[0] if queue else None
            was = self.active.get(a)
            if run is None or not run.started:
                if was is not None:
                    del self.active[a]
                    params = m.params_of(a)
                    for k, (_value, control, idle) in enumerate(PAIRS):
                        act(m, params.get(control, 0.0), params.get(idle, 0.0), a, k)
                continue
            index = len(run.deltas) - run.moves_left(m.tick, m.period)
            if was is not None and was[0] is run and was[1] == index:
                continue
            self.active[a] = (run, index)
            carried = run.carried.get(index, {}).get(a)
            if carried is None:
                continue
            params = m.params_of(a)
            for k, (_value, control, _idle) in enumerate(PAIRS):
                act(m, params.get(control, 0.0), carried[k], a, k)
