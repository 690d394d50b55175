"""A process under trace (TRON, STEPLINE, STEPINTO, SETLINE): where it pauses next.

A traced process stops before a statement when it has not been told to step, or when the
statement begins a line other than the one it was told to step (TrioBASIC help TRON,
STEPLINE, STEPINTO). STEPLINE steps over a GOSUB routine: it stops again only back at the
depth it stepped from; STEPINTO stops at the routine's first line too. A FUNCTION runs
inside the statement that calls it (tasks.py), so both step over it (D).

The process's PROC_STATUS (help PROC_STATUS) follows: 3 PAUSED while it waits to be
stepped, 2 STEPPING while it runs a stepped line (D: the page names both states, not which
the trace words use), 1 RUNNING once TROFF releases it; untraced, 8 SLEEP while one of
its statements waits (tasks.py).
"""

from __future__ import annotations

from dataclasses import dataclass

RUNNING = 1  # PROC_STATUS values (help PROC_STATUS)
STEPPING = 2
PAUSED = 3
SLEEP = 8  # while a statement waits: WA, WAIT IDLE/UNTIL/LOADED, a full move buffer (tasks.py)


@dataclass
class Trace:
    """What a traced process does at its next statement."""

    into: bool = False  # STEPINTO: stop at a GOSUB routine's lines too
    line: int = -1  # the line being stepped (-1: stop before the next statement)
    depth: int = 0  # the GOSUB depth the step began at
    paused_line: int = 0  # where it stands paused (the line PROC_LINE and STEPLINE see)
    paused_depth: int = 0

    def stops_before(self, line: int, depth: int) -> bool:
        """Whether a statement of `line`, at GOSUB `depth`, waits for a step."""
        if self.line < 0:
            return True
        return line != self.line and (self.into or depth <= self.depth)

    def pause_at(self, line: int, depth: int) -> None:
        self.line = -1
        self.paused_line, self.paused_depth = line, depth

    def step(self, into: bool) -> None:
        """STEPLINE / STEPINTO: run the line it is paused at, then stop again."""
        self.into = into
        self.line, self.depth = self.paused_line, self.paused_depth
