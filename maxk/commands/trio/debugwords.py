"""TRON, TROFF, STEPLINE, STEPINTO and SETLINE: pausing a program and stepping it line by
line (TrioBASIC help pages of each; the paused state is tracing.py's).

- ``TRON ["prog"]`` pauses the program (the SELECTed one from the command line, the program
  itself inside a program) before its next statement; a program not running is started
  paused at its first statement (I: the page's example 2 starts STARTUP so).
- ``STEPLINE ["prog"[, process]]`` / ``STEPINTO``: a paused program runs one line and
  pauses again; one running untraced is paused (D); one not running is started paused on
  the process given or the highest free one (page). Alone in a program they pause it.
- ``TROFF ["prog"]`` releases it: it runs on at full speed. So does RUN of a program under
  trace (D: the emulator runs one copy of a program, and a debugger's Run goes on).
- ``SETLINE "prog", process, line[, base[, robot]]`` moves the program pointer of a paused
  program to a line (one not running is started paused there, its BASE set when base is
  not -1; a base that is no axis is 'Invalid axis number', nothing started, D); a running
  program is paused there (D).

- ``BREAK_ADD "prog" line`` / ``BREAK_DELETE``: a breakpoint; a running program pauses
  before a breakpoint's line each time it comes to it from another line, as TRON pauses
  it. A line with no code moves the breakpoint to the next line with code; past the last
  line with code, 'Parameter out of range' (page: "an error"). ``BREAK_LIST "prog"``
  prints ``Program: NAME`` and ``Line n: code`` for each, ``BREAK_RESET`` clears them
  (their pages). They are kept by line number across edits (D).

Each pause is reported to every host as the controller's line
``%[Process n:Line l] - Paused`` followed by the text of that line (TRON's page: "the line
that is stepped to is displayed"); a release as ``%[Process n:Program NAME] - Released``.
"""

from __future__ import annotations

from collections.abc import Callable

from .interpreter import ProcessContext, Value, number_arg
from .lexer import TrioError
from .machine import TrioMachine
from .programs import ProgramStore
from .tasks import Step, Task
from .tracing import RUNNING, Trace


class ProgramTrace:
    """The trace words' handlers; the attributes are the runtime's own (system.py)."""

    machine: TrioMachine
    programs: ProgramStore
    tasks: dict[int, Task]
    breakpoints: dict[str, set[int]]
    compiled: dict[str, list[Step]]
    compile: Callable[[str], list[Step]]
    selected: str | None
    process_output: Callable[[str], None]
    output: Callable[[str], None]
    start: Callable[..., int]
    _target: Callable[[list[Value]], str]

    # ---- the words --------------------------------------------------------------------------
    def ctx_tron(self, args: list[Value], ctx: ProcessContext) -> None:
        _names_only(args, 1)
        self._pause(self._named(args, ctx), -1)

    def ctx_troff(self, args: list[Value], ctx: ProcessContext) -> None:
        _names_only(args, 1)
        self.release(self._named(args, ctx))

    def release(self, name: str) -> bool:
        """TROFF (and RUN of a program under trace, D): it runs on; whether one was."""
        released = False
        for process, task in self._running(name):
            if task.trace is None:
                continue
            task.trace, task.paused, task.ctx.status = None, False, RUNNING
            self.process_output(f"%[Process {process}:Program {name}] - Released\r\n")
            released = True
        return released

    def ctx_stepline(self, args: list[Value], ctx: ProcessContext) -> None:
        self._step(args, ctx, into=False)

    def ctx_stepinto(self, args: list[Value], ctx: ProcessContext) -> None:
        self._step(args, ctx, into=True)

    def ctx_setline(self, args: list[Value], ctx: ProcessContext) -> None:
        if not 3 <= len(args) <= 5 or not isinstance(args[0], str):
            raise TrioError("Syntax error")
        name = self._target(args[:1])
        process, line = _whole(args[1]), _whole(args[2])
        base = _whole(args[3]) if len(args) > 3 else -1
        if len(args) > 4:
            _whole(args[4])  # the robot index: no kinematic robot is emulated here (D)
        if base != -1 and not 0 <= base < self.machine.axis_count:
            raise TrioError("Invalid axis number")  # as BASE(n) says it (D)
        running = self._running(name)
        if process != -1 and running and running[0][0] != process:
            raise TrioError("Program is running")  # (one copy of a program runs here)
        started = None
        if not running:
            started = self.start(name, process)
            running = [(started, self.tasks[started])]
        task = running[0][1]
        target = next((i for i, s in enumerate(task.steps) if s.line == line), None)
        if target is None:
            if started is not None:
                del self.tasks[started]  # (nothing half done)
            raise TrioError("Parameter out of range")  # no statement on that line
        if started is not None and base != -1:
            task.ctx.base = [base]
        trace = self._traced(task)
        task.jump, trace.line = target, -1
        if task.paused:  # it stands paused: it stands at the new line now
            trace.pause_at(line, 0)
            task.ctx.line = line
            task.ctx.stack.clear()
            self._announce(task)

    def ctx_break_add(self, args: list[Value], ctx: ProcessContext) -> None:
        name, line = self._break_line(args)
        self.breakpoints.setdefault(name, set()).add(line)

    def ctx_break_delete(self, args: list[Value], ctx: ProcessContext) -> None:
        name, line = self._break_line(args)
        self.breakpoints.get(name, set()).discard(line)

    def ctx_break_list(self, args: list[Value], ctx: ProcessContext) -> None:
        _names_only(args, 1)
        name = self._target(args)
        lines = self.programs.lines[name]
        self.output(f"Program: {name}\r\n")
        for line in sorted(self.breakpoints.get(name, ())):
            text = lines[line - 1].strip() if line <= len(lines) else ""
            self.output(f"Line {line}: {text}\r\n")

    def ctx_break_reset(self, args: list[Value], ctx: ProcessContext) -> None:
        _names_only(args, 1)
        self.breakpoints.get(self._target(args), set()).clear()

    def attach_trace(self, task: Task) -> None:
        """A task starting: its program's breakpoints (the same set: later BREAK_ADDs
        act on it at once) and where its pauses are reported."""
        task.breaks = self.breakpoints.setdefault(task.ctx.program, set())
        task.on_pause = self._announce

    # ---- helpers ----------------------------------------------------------------------------
    def _break_line(self, args: list[Value]) -> tuple[str, int]:
        """BREAK_ADD/BREAK_DELETE's program and line: the line itself if it has code,
        else the next one that has (page)."""
        if len(args) != 2 or not isinstance(args[0], str) or isinstance(args[1], str):
            raise TrioError("Syntax error")
        name, line = self._target(args[:1]), _whole(args[1])
        steps = self.compiled.get(name)
        if steps is None:
            steps = self.compile(name)
        lines = sorted({step.line for step in steps if step.line >= line})
        if line < 1 or not lines:
            raise TrioError("Parameter out of range")
        return name, lines[0]

    # ---- helpers (trace) ----------------------------------------------------------------------
    def _named(self, args: list[Value], ctx: ProcessContext) -> str:
        """The program named, or the one asking (in a program), or the SELECTed one."""
        if not args and ctx.program:
            return ctx.program
        return self._target(args)

    def _running(self, name: str) -> list[tuple[int, Task]]:
        return [(p, t) for p, t in sorted(self.tasks.items()) if t.ctx.program == name]

    def _traced(self, task: Task) -> Trace:
        if task.trace is None:
            task.trace = Trace()
            task.on_pause = self._announce
        return task.trace

    def _pause(self, name: str, process: int) -> None:
        """Put the program under trace, paused before its next statement (started if it
        does not run)."""
        running = self._running(name)
        if not running:
            started = self.start(name, process)
            running = [(started, self.tasks[started])]
        for _, task in running:
            trace = self._traced(task)
            if not task.paused:
                trace.line = -1

    def _step(self, args: list[Value], ctx: ProcessContext, into: bool) -> None:
        _names_only(args, 2)
        if len(args) > 1 and (not isinstance(args[0], str) or isinstance(args[1], str)):
            raise TrioError("Syntax error")
        process = _whole(args[1]) if len(args) > 1 else -1
        if not args and ctx.program:  # in a program: it pauses here
            self._pause(ctx.program, -1)
            return
        name = self._target(args[:1])
        running = self._running(name)
        if process != -1:
            if running and all(p != process for p, _ in running):
                raise TrioError("Program is running")  # (one copy of a program runs here)
            running = [(p, t) for p, t in running if p == process]
        if not running:
            self._pause(name, process)
            return
        for _, task in running:
            trace = self._traced(task)
            if task.paused:
                trace.step(into)
                task.paused = False
            else:
                trace.into, trace.line = into, -1

    def _announce(self, task: Task) -> None:
        """The controller's pause line, then the text of the line it stands at."""
        ctx = task.ctx
        lines = self.programs.lines.get(ctx.program, [])
        text = lines[ctx.line - 1].strip() if 0 < ctx.line <= len(lines) else ""
        self.process_output(f"%[Process {ctx.process}:Line {ctx.line}] - Paused\r\n"
                            f"{text}\r\n")


def _names_only(args: list[Value], most: int) -> None:
    if len(args) > most or (args and not isinstance(args[0], str)):
        raise TrioError("Syntax error")


def _whole(value: Value) -> int:
    number = number_arg(value)
    if number != int(number):
        raise TrioError("Parameter out of range")
    return int(number)
