"""Compiled programs and the processes that run them.

COMPILE turns a program's lines into a flat list of steps with the block statements
linked into jumps, checking the structure (every WHILE has its WEND ...). A process runs
the steps as one generator: it yields when a statement waits and once at every loop
back-edge of a pass that has not waited already, so each loop pass takes at least one
servo cycle (decision D: the controller time-slices its processes; one pass per cycle
keeps a busy loop from starving the others and keeps timing deterministic, and a pass
that waited, e.g. in WA(2), loops straight on so WA(2) paces a loop at 2 cycles).

A process also runs at most `STATEMENTS_PER_CYCLE` statements in one servo cycle before it
gives the cycle up, as the controller's process scheduler gives each process a bounded
time slice per servo period (source: the Trio manuals describe processes time-sliced on
the servo interrupt, I; the count of 100 is our decision, D): a ``WHILE 1`` of 500 lines
of arithmetic takes 5 servo cycles a pass, costs virtual time, and a HALT from any host
stops it within a cycle.
"""

from __future__ import annotations

from collections.abc import Generator
from dataclasses import dataclass

from .interpreter import Interpreter, ProcessContext, Wake
from .lexer import TrioError
from .parser import (
    Else,
    EndIf,
    Expr,
    For,
    IfBlock,
    Next,
    Repeat,
    Stmt,
    Until,
    Wend,
    While,
    parse_line,
)


@dataclass(frozen=True)
class Step:
    line: int  # 1-based program line
    stmt: Stmt
    target: int = -1  # jump destination (block statements)


def compile_program(lines: list[str]) -> list[Step]:
    """Parse and link a program; TrioError carries the failing line number."""
    steps: list[Step] = []
    open_blocks: list[tuple[str, int, int]] = []  # (kind, step index, line)
    targets: dict[int, int] = {}
    for number, text in enumerate(lines, start=1):
        try:
            statements = parse_line(text)
        except TrioError as exc:
            raise TrioError(exc.message, number) from None
        for stmt in statements:
            index = len(steps)
            steps.append(Step(number, stmt))
            try:
                _link(stmt, index, number, open_blocks, targets)
            except TrioError as exc:
                raise TrioError(exc.message, number) from None
    if open_blocks:
        raise TrioError("Structure error", open_blocks[-1][2])
    return [Step(s.line, s.stmt, targets.get(i, -1)) for i, s in enumerate(steps)]


def _link(stmt: Stmt, index: int, line: int, open_blocks: list[tuple[str, int, int]],
          targets: dict[int, int]) -> None:
    def close(kind: str) -> int:
        if not open_blocks or open_blocks[-1][0] != kind:
            raise TrioError("Structure error")
        return open_blocks.pop()[1]

    if isinstance(stmt, IfBlock):
        open_blocks.append(("IF", index, line))
    elif isinstance(stmt, Else):
        opener = close("IF")
        targets[opener] = index + 1  # a false condition continues after ELSE
        open_blocks.append(("ELSE", index, line))
    elif isinstance(stmt, EndIf):
        if open_blocks and open_blocks[-1][0] == "ELSE":
            targets[close("ELSE")] = index + 1  # the end of the THEN part jumps here
        else:
            targets[close("IF")] = index + 1
    elif isinstance(stmt, While):
        open_blocks.append(("WHILE", index, line))
    elif isinstance(stmt, Wend):
        opener = close("WHILE")
        targets[index] = opener
        targets[opener] = index + 1
    elif isinstance(stmt, Repeat):
        open_blocks.append(("REPEAT", index, line))
    elif isinstance(stmt, Until):
        targets[index] = close("REPEAT") + 1
    elif isinstance(stmt, For):
        open_blocks.append(("FOR", index, line))
    elif isinstance(stmt, Next):
        opener = close("FOR")
        targets[index] = opener + 1
        targets[opener] = index + 1


STATEMENTS_PER_CYCLE = 100


class Task:
    """One running process: a compiled program and its context."""

    def __init__(self, interpreter: Interpreter, steps: list[Step], ctx: ProcessContext) -> None:
        self.interpreter = interpreter
        self.steps = steps
        self.ctx = ctx
        self._run = self._program()
        self.finished = False
        self.wake: Wake | None = None  # what the last step waits for (None: next cycle)
        self.due: int | None = None  # scheduler: the tick to run next (None: on a change)
        self.seen = -1  # scheduler: the machine revision its last step saw (-1: fresh)

    def step(self) -> Wake | None:
        """Run until the program waits, ends a loop pass or finishes (one servo cycle);
        return what it waits for (None: the next servo cycle).

        A TrioError carries the line it happened on; the task is finished after it.
        """
        if self.finished:
            return None
        try:
            self.wake = next(self._run)
        except StopIteration:
            self.finished = True
            self.wake = None
        except TrioError as exc:
            self.finished = True
            exc.line = self.ctx.line
            raise
        return self.wake

    def _program(self) -> Generator[Wake | None, None, None]:
        interp, ctx, steps = self.interpreter, self.ctx, self.steps
        pc = 0
        waited = False  # this loop pass already gave up a servo cycle
        budget = STATEMENTS_PER_CYCLE
        while pc < len(steps):
            budget -= 1
            if budget < 0:  # this cycle's slice is used: go on next cycle
                yield None
                waited = True
                budget = STATEMENTS_PER_CYCLE - 1
            step = steps[pc]
            ctx.line = step.line
            stmt = step.stmt
            if isinstance(stmt, (IfBlock, While)):
                pc = pc + 1 if self._true(stmt.condition) else step.target
            elif isinstance(stmt, Else):
                pc = step.target  # end of the THEN part: skip the ELSE part
            elif isinstance(stmt, (EndIf, Repeat)):
                pc += 1
            elif isinstance(stmt, Wend):
                if not waited:
                    yield None
                    budget = STATEMENTS_PER_CYCLE
                waited = False
                pc = step.target
            elif isinstance(stmt, Until):
                if self._true(stmt.condition):
                    pc += 1
                else:
                    if not waited:
                        yield None
                        budget = STATEMENTS_PER_CYCLE
                    waited = False
                    pc = step.target
            elif isinstance(stmt, For):
                start = interp.number(stmt.start, ctx)
                end = interp.number(stmt.end, ctx)
                increment = 1.0 if stmt.step is None else interp.number(stmt.step, ctx)
                ctx.variables[stmt.variable] = start
                ctx.loops[pc] = (end, increment)
                pc = pc + 1 if _in_range(start, end, increment) else step.target
            elif isinstance(stmt, Next):
                opener = step.target - 1
                loop = steps[opener].stmt
                assert isinstance(loop, For)
                if stmt.variable is not None and stmt.variable != loop.variable:
                    raise TrioError("Structure error")
                end, increment = ctx.loops[opener]
                value = ctx.variables.get(loop.variable, 0.0) + increment
                ctx.variables[loop.variable] = value
                if _in_range(value, end, increment):
                    if not waited:
                        yield None
                        budget = STATEMENTS_PER_CYCLE
                    waited = False
                    pc = step.target
                else:
                    pc += 1
            else:
                for wake in interp.execute(stmt, ctx):
                    waited = True
                    yield wake
                    budget = STATEMENTS_PER_CYCLE
                pc += 1

    def _true(self, condition: Expr) -> bool:
        return self.interpreter.number(condition, self.ctx) != 0


def _in_range(value: float, end: float, increment: float) -> bool:
    return value <= end if increment >= 0 else value >= end
