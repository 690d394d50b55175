"""What a MAXk axis queue can be blocked on: small types, one per kind of wait.

A queued command's action returns None when it is finished, or one of these; the queue
then stands until the wait is over (`Axis.run_queue`). Start groups (AA-mode GO) and
contour anchors are waits too (`StartGroup`, `ContourWait`), with a `ready(board)` test.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import Any, Protocol, TypeAlias


class RestWait(Enum):
    """Waits for the running motion to end."""

    MOTION = "motion"  # then the entry is finished and the queue goes on (GO, ID after GO)
    RETRY = "rest-retry"  # then the same entry runs again (anything behind ST or a jog)


WAIT_MOTION = RestWait.MOTION
WAIT_REST_RETRY = RestWait.RETRY


@dataclass(frozen=True, slots=True)
class TickWait:
    """Until a tick (WT, MO, a JG ramp, an LE pass). `retry`: then the same entry runs
    (the update's share of queue work was spent before it: `QUEUE_COMMANDS_PER_UPDATE`);
    otherwise the entry that waited is finished."""

    tick: int
    retry: bool = False


@dataclass(frozen=True, slots=True)
class InputWait:
    """SW: until a general purpose input reads high (BW: low)."""

    bit: int
    low: bool = False


class SyncWait(Protocol):
    """A wait on other axes: an AA-mode GO's start group, a contour's anchor."""

    def ready(self, board: Any) -> bool:  # board: the MAXk Board (kept below it here)
        ...


Wait: TypeAlias = RestWait | TickWait | InputWait | SyncWait
"""What a queue can stand on (None: nothing)."""
