"""Running programs beside the command line on an event engine.

The processes (and any command line whose statement waits) are one event source of the
controller's engine. A process is stepped at the servo cycles it can make progress on,
with exactly the results of stepping every process every cycle (`servo_cycle`), but
without the cost:

- a loop pass or WAIT UNTIL (``yield None``): the next servo cycle;
- WA(ms) (`Wake(tick)`): that exact tick;
- WAIT IDLE or a full move buffer (`ON_CHANGE`): at every event tick of the engine (a
  move ends, a gate fires ...) and the cycle after anything changed the machine
  (`revision`), since only a change can end such a wait.

Output a process prints goes to every session of the controller; a session with output
nobody asked for (a program's PRINT, the prompt after a WA typed on the command line) is
told through its `notify`.
"""

from __future__ import annotations

from typing import Protocol

from .interpreter import due_after
from .session import TrioCommandLine
from .system import ProgramCommands

# A process that waits on a change is stepped again at the same tick when another source's
# event there changes the machine (a WAIT IDLE may end mid-cycle). A statement that itself
# makes such an event at once (MOVEABS to where the axis is: a zero move ending on the
# tick it loads) would wake it again and again and the tick would never end: after this
# many steps in one tick the process goes on at the next servo cycle (D; a loop pass takes
# a servo cycle anyway, tasks.py).
RESTEPS_PER_TICK = 8


class ProcessClock(Protocol):
    """What the scheduler needs of the machine: its servo tick and change counter."""

    def servo_tick(self) -> int: ...

    @property
    def revision(self) -> int: ...


class ProcessScheduler:
    """The engine's event source for TrioBASIC processes and waiting command lines."""

    every_event = True  # a WAIT IDLE may end at any other source's event

    def __init__(self, clock: ProcessClock, runtime: ProgramCommands) -> None:
        self.clock = clock
        self.runtime = runtime
        self.sessions: list[TrioCommandLine] = []

    def add(self, session: TrioCommandLine) -> None:
        self.sessions.append(session)

    def remove(self, session: TrioCommandLine) -> None:
        self.sessions = [s for s in self.sessions if s is not session]

    def _when(self, due: int | None, seen: int, now: int) -> int | None:
        """The next tick a waiter is ready (a fresh or changed ON_CHANGE waiter: next cycle)."""
        if due is None:
            return now + 1 if seen != self.clock.revision else None
        return max(due, now + 1)

    def _ready(self, due: int | None, seen: int, now: int) -> bool:
        if due is not None:
            return due <= now
        return seen != self.clock.revision

    # ---- EventSource ---------------------------------------------------------------------
    def next_event(self) -> int | None:
        now = self.clock.servo_tick()
        ticks = [self._when(t.due, t.seen, now) for t in self.runtime.tasks.values()
                 if not t.paused]  # (a paused one waits for STEPLINE or TROFF)
        ticks += [self._when(s.busy_due, s.busy_seen, now) for s in self.sessions if s.waiting]
        ticks += [now + 1 for s in self.sessions if s.backlog and not s.waiting]
        ticks.append(self.runtime.next_timer())  # a TIMER's outputs change on its tick
        found = [t for t in ticks if t is not None]
        return min(found) if found else None

    def on_event(self, now: int) -> None:
        self.sessions = [s for s in self.sessions if not s.closed]
        runtime = self.runtime
        runtime.run_timers()
        for process, task in sorted(runtime.tasks.items()):
            if runtime.tasks.get(process) is not task:
                continue  # stopped by a process before it this cycle
            if task.paused or not self._ready(task.due, task.seen, now):
                continue
            if task.stepped == (now, RESTEPS_PER_TICK):
                continue  # it woke at this tick often enough: on next cycle (see RESTEPS)
            count = task.stepped[1] + 1 if task.stepped[0] == now else 1
            task.stepped = (now, count)
            runtime.step_task(process, task)
            task.due = due_after(task.wake, now)
            task.seen = self.clock.revision
        if runtime.reset_requested:  # EX in a program: the restart, after this cycle
            runtime.reset_requested = False
            runtime.restart()
        for session in list(self.sessions):
            if session.waiting and self._ready(session.busy_due, session.busy_seen, now):
                session.resume()
                session.busy_seen = self.clock.revision
            elif session.backlog and not session.waiting and not session.closed:
                session.resume()  # the input held while a statement waited, a slice a cycle
        self.flush()

    def flush(self) -> None:
        """Tell every session holding output nobody asked for."""
        for session in self.sessions:
            if session.pending and session.notify is not None and not session.closed:
                session.notify()
