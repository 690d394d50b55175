"""What a MAXk axis queue can be blocked on: small types, one per kind of wait.

A queued command's action returns None when it is finished, or one of these; the queue
then stands until the wait is over (`Axis.run_queue`). Start groups (AA-mode GO) and
contour anchors are waits too (`StartGroup`, `ContourWait`), with a `ready(board)` test.
"""

from __future__ import annotations

from enum import Enum
from typing import Any, Final, Protocol, TypeAlias, final


class RestWait(Enum):
    """Waits for the running motion to end."""

    MOTION = "motion"  # then the entry is finished and the queue goes on (GO, ID after GO)
    RETRY = "rest-retry"  # then the same entry runs again (anything behind ST or a jog)


WAIT_MOTION: Final = RestWait.MOTION
WAIT_REST_RETRY: Final = RestWait.RETRY


@final
class TickWait:
    """Until a tick (WT, MO, a JG ramp, an LE pass). `retry`: then the same entry runs
    (the update's share of queue work was spent before it: `QUEUE_COMMANDS_PER_UPDATE`);
    otherwise the entry that waited is finished.

    A plain class, not a dataclass: compiled (maxk/compiled.py), it is made natively at
    every LE pass and WT; a dataclass's generated __init__ would run as Python."""

    __slots__ = ("tick", "retry")

    def __init__(self, tick: int, retry: bool = False) -> None:
        self.tick: Final = tick
        self.retry: Final = retry

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, TickWait) and self.tick == other.tick
                and self.retry == other.retry)

    def __hash__(self) -> int:
        return hash((self.tick, self.retry))

    def __repr__(self) -> str:
        return f"TickWait(tick={self.tick!r}, retry={self.retry!r})"


@final
class InputWait:
    """SW: until a general purpose input reads high (BW: low)."""

    __slots__ = ("bit", "low")

    def __init__(self, bit: int, low: bool = False) -> None:
        self.bit: Final = bit
        self.low: Final = low

    def __eq__(self, other: object) -> bool:
        return isinstance(other, InputWait) and self.bit == other.bit and self.low == other.low

    def __hash__(self) -> int:
        return hash((self.bit, self.low))

    def __repr__(self) -> str:
        return f"InputWait(bit={self.bit!r}, low={self.low!r})"


class SyncWait(Protocol):
    """A wait on other axes: an AA-mode GO's start group, a contour's anchor."""

    def ready(self, board: Any) -> bool:  # board: the MAXk Board (kept below it here)
        ...


Wait: TypeAlias = RestWait | TickWait | InputWait | SyncWait
"""What a queue can stand on (None: nothing)."""
