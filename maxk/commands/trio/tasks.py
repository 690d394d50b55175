"""Compiled programs and the processes that run them.

COMPILE joins ``_``-continued lines, turns a program's lines into a flat list of steps
with the block statements linked into jumps (a one-line IF becomes a block, so a GOTO
or GOSUB inside it jumps), resolves labels (``name:``) for GOTO, GOSUB and ON
BASICERROR GOTO, and checks the structure (every WHILE has its WEND ...). A process runs
the steps as one generator: it yields when a statement waits and once at every loop
back-edge of a pass that has not waited already, so each loop pass takes at least one
servo cycle (decision D: the controller time-slices its processes; one pass per cycle
keeps a busy loop from starving the others and keeps timing deterministic, and a pass
that waited, e.g. in WA(2), loops straight on so WA(2) paces a loop at 2 cycles).

A process also runs at most `STATEMENTS_PER_CYCLE` statements in one servo cycle before it
gives the cycle up, as the controller's process scheduler gives each process a bounded
time slice per servo period (source: the Trio manuals describe processes time-sliced on
the servo interrupt, I; the count of 25 is our decision, D: 25,000 statements a second
at the MC405's 1 ms servo period, which the emulator sustains in real time for a busy
process or two): a ``WHILE 1`` of 500 lines of arithmetic takes 20 servo cycles a pass,
costs virtual time, and a HALT from any host stops it within a cycle.

A runtime error ends the process with its error line, unless ON BASICERROR GOTO named a
handler: then RUN_ERROR and ERROR_LINE are set and the process goes on at the handler
(the handler is cleared, so an error in it ends the process: D).

Long module: COMPILE's block linking and the runner of every block statement (IF, loops,
SELECT_CASE, GOSUB, FUNCTION calls) are one concern, a process's control flow.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Generator
from dataclasses import dataclass, field
from typing import cast

from ..line_session import log_fault
from .interpreter import Argument, Interpreter, Kept, ProcessContext, Value, Wake, error_code
from .lexer import Thrown, TrioError
from .loopjumps import link_loop_jumps, loop_jump
from .parser import (
    Assign,
    Call,
    Case,
    Dim,
    Else,
    ElseIf,
    EndCase,
    EndFunc,
    EndIf,
    Expr,
    For,
    FunctionDef,
    Gosub,
    Goto,
    IfBlock,
    IfLine,
    Label,
    Next,
    Num,
    OnError,
    OnJump,
    Repeat,
    Return,
    SelectCase,
    Stmt,
    Until,
    Wend,
    While,
    parse_line,
)
from .tracing import PAUSED, RUNNING, SLEEP, STEPPING, Trace

# a fault in our own code, as the controller names an error it does not list (RUN_ERROR's
# page has "Evaluation error"; D): the line is answered, the traceback goes to the log
FAULT_TEXT = "Evaluation error"


_NUMBER_TYPES = frozenset({"FLOAT", "INTEGER", "BOOLEAN"})  # AS types a FUNCTION keeps
STATEMENTS_PER_CYCLE = 25
GOSUB_DEPTH = 64  # nested GOSUBs (and FUNCTION calls) before "Stack overflow" (D)
FUNCTION_STATEMENTS = 1000  # statements one FUNCTION call, with every call it makes, may
# run (D: it runs within the statement that calls it, so it is bounded; more is "Function
# too long")


@dataclass(frozen=True)
class Step:
    line: int  # 1-based program line
    stmt: Stmt
    target: int = -1  # jump destination (block statements)
    opener: int = -1  # CASE: the SELECT_CASE step it belongs to
    choices: tuple[int, ...] = ()  # ON ... GOTO/GOSUB: the destinations, in order


@dataclass
class _Open:
    kind: str
    index: int
    line: int
    cond: int = -1  # the condition (or CASE test) step whose false branch is still open
    ends: list[int] = field(default_factory=list)  # jumps to the end of the block


_NAME_CHARS = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_$")


def _code_part(text: str) -> str:
    """The line without its ``'`` comment (a quote inside a string is no comment)."""
    quoted = False
    for i, c in enumerate(text):
        if c == '"':
            quoted = not quoted
        elif c == "'" and not quoted:
            return text[:i]
    return text


def join_continued(lines: list[str]) -> list[tuple[int, str]]:
    """Logical lines with the number of their first line: a line whose code ends in a
    ``_`` that is not part of a name (``x + _``, ``f(a)_``) goes on on the next one, a
    comment after the ``_`` dropped."""
    out: list[tuple[int, str]] = []
    pending: tuple[int, str] | None = None
    for number, text in enumerate(lines, start=1):
        if pending is not None:
            number, text = pending[0], pending[1] + " " + text
            pending = None
        stripped = _code_part(text).rstrip()
        if stripped.endswith("_") and (len(stripped) == 1 or stripped[-2] not in _NAME_CHARS):
            pending = (number, stripped[:-1])
            continue
        out.append((number, text))
    if pending is not None:
        out.append(pending)
    return out


def _flatten(stmt: Stmt) -> list[Stmt]:
    """A one-line IF as a block, so jumps inside it are steps like any other."""
    if not isinstance(stmt, IfLine):
        return [stmt]
    out: list[Stmt] = [IfBlock(stmt.condition)]
    for inner in stmt.then:
        out += _flatten(inner)
    if stmt.otherwise:
        out.append(Else())
        for inner in stmt.otherwise:
            out += _flatten(inner)
    out.append(EndIf())
    return out


_INCLUDE = re.compile(r'\s*INCLUDE\s*"([^"]*)"\s*(\'.*)?$', re.IGNORECASE)
INCLUDE_DEPTH = 8  # INCLUDEs within INCLUDEs (D)


def _expand(lines: list[str], include: Callable[[str], list[str]] | None,
            depth: int = 0, number: int | None = None) -> list[tuple[int, str]]:
    """The logical lines with each INCLUDE "NAME" replaced by that program's lines (they
    take the INCLUDE's line number: D)."""
    out: list[tuple[int, str]] = []
    for line_number, text in join_continued(lines):
        at = line_number if number is None else number
        match = _INCLUDE.match(text)
        if match is None:
            out.append((at, text))
            continue
        if include is None or depth >= INCLUDE_DEPTH:
            raise TrioError("Structure error", at)
        try:
            included = include(match.group(1).upper())
        except TrioError as exc:
            raise TrioError(exc.message, at) from None
        out += _expand(included, include, depth + 1, at)
    return out


def compile_program(lines: list[str],
                    include: Callable[[str], list[str]] | None = None) -> list[Step]:
    """Parse and link a program; TrioError carries the failing line number. `include`
    gives the lines of a program an INCLUDE names."""
    steps: list[Step] = []
    open_blocks: list[_Open] = []
    targets: dict[int, int] = {}
    openers: dict[int, int] = {}
    labels: dict[str, int] = {}
    for number, text in _expand(lines, include):
        try:
            statements = parse_line(text)
        except TrioError as exc:
            raise TrioError(exc.message, number) from None
        for parsed in statements:
            for stmt in _flatten(parsed):
                try:
                    if isinstance(stmt, ElseIf):  # the end of a branch, then a test
                        _link(Else(), len(steps), number, open_blocks, targets, openers,
                              elseif=True)
                        steps.append(Step(number, Else()))
                        stmt = IfBlock(stmt.condition)
                        steps.append(Step(number, stmt))
                        open_blocks[-1].cond = len(steps) - 1
                        continue
                    if isinstance(stmt, Case):  # the end of a branch, then a test
                        _link(stmt, len(steps), number, open_blocks, targets, openers)
                        steps.append(Step(number, Else()))
                        steps.append(Step(number, stmt))
                        continue
                    if isinstance(stmt, Label):
                        if stmt.name in labels:
                            raise TrioError("Label already defined")
                        labels[stmt.name] = len(steps)
                    _link(stmt, len(steps), number, open_blocks, targets, openers)
                except TrioError as exc:
                    raise TrioError(exc.message, number) from None
                steps.append(Step(number, stmt))
    if open_blocks:
        raise TrioError("Structure error", open_blocks[-1].line)
    link_loop_jumps([(s.line, s.stmt) for s in steps], targets)  # EXIT_LOOP, CONTINUE
    for index, step in enumerate(steps):
        label = None
        if isinstance(step.stmt, (Goto, Gosub, OnError)):
            label = step.stmt.label
        if isinstance(step.stmt, OnJump):
            missing = [name for name in step.stmt.labels if name not in labels]
            if missing:
                raise TrioError("Label not found", step.line)
        if label is not None:
            if label not in labels:
                raise TrioError("Label not found", step.line)
            targets[index] = labels[label]
    jumps = {index: tuple(labels[name] for name in step.stmt.labels)
             for index, step in enumerate(steps) if isinstance(step.stmt, OnJump)}
    return [Step(s.line, s.stmt, targets.get(i, -1), openers.get(i, -1), jumps.get(i, ()))
            for i, s in enumerate(steps)]


def _link(stmt: Stmt, index: int, line: int, open_blocks: list[_Open],
          targets: dict[int, int], openers: dict[int, int], elseif: bool = False) -> None:
    def top(*kinds: str) -> _Open:
        if not open_blocks or open_blocks[-1].kind not in kinds:
            raise TrioError("Structure error")
        return open_blocks[-1]

    def close(kind: str) -> int:
        return open_blocks.pop(-1).index if top(kind) else -1

    if isinstance(stmt, IfBlock):
        open_blocks.append(_Open("IF", index, line, cond=index))
    elif isinstance(stmt, Else):
        block = top("IF")
        targets[block.cond] = index + 1  # a false condition goes on after the jump
        block.ends.append(index)
        block.cond = -1
        if not elseif:
            block.kind = "ELSE"
    elif isinstance(stmt, EndIf):
        block = top("IF", "ELSE")
        open_blocks.pop()
        if block.cond >= 0:
            targets[block.cond] = index + 1
        for end in block.ends:
            targets[end] = index + 1
    elif isinstance(stmt, SelectCase):
        open_blocks.append(_Open("CASE", index, line))
    elif isinstance(stmt, Case):  # steps: a jump at index, the test at index + 1
        block = top("CASE")
        if block.cond >= 0:
            targets[block.cond] = index + 1  # the test before fails: try this one
        elif not block.ends:
            targets[block.index] = index + 1  # SELECT_CASE goes to the first test
        if block.ends and block.cond < 0:
            raise TrioError("Structure error")  # a CASE after CASE ELSE
        targets[index] = -1
        block.ends.append(index)
        block.cond = index + 1 if stmt.choices else -1
        openers[index + 1] = block.index
    elif isinstance(stmt, EndCase):
        block = top("CASE")
        open_blocks.pop()
        if block.cond >= 0:
            targets[block.cond] = index + 1
        if not block.ends:
            targets[block.index] = index + 1
        for end in block.ends:
            targets[end] = index + 1
    elif isinstance(stmt, While):
        open_blocks.append(_Open("WHILE", index, line))
    elif isinstance(stmt, Wend):
        opener = close("WHILE")
        targets[index] = opener
        targets[opener] = index + 1
    elif isinstance(stmt, Repeat):
        open_blocks.append(_Open("REPEAT", index, line))
    elif isinstance(stmt, Until):
        targets[index] = close("REPEAT") + 1
    elif isinstance(stmt, FunctionDef):
        if open_blocks:
            raise TrioError("Structure error")  # a FUNCTION inside a block
        open_blocks.append(_Open("FUNCTION", index, line))
    elif isinstance(stmt, EndFunc):
        targets[close("FUNCTION")] = index + 1  # running into a FUNCTION skips it
    elif isinstance(stmt, For):
        open_blocks.append(_Open("FOR", index, line))
    elif isinstance(stmt, Next):
        opener = close("FOR")
        targets[index] = opener + 1
        targets[opener] = index + 1


class Task:
    """One running process: a compiled program and its context."""

    def __init__(self, interpreter: Interpreter, steps: list[Step], ctx: ProcessContext,
                 library: Callable[[str], tuple[list[Step], int] | None] | None = None
                 ) -> None:
        """`library` finds a FUNCTION of the store's BASIC libraries (.BAL) by name: its
        library's steps and where it starts (None: no such function)."""
        self.interpreter = interpreter
        self.library = library
        self.steps = steps
        self.ctx = ctx
        self._run = self._program()
        self.finished = False
        self.wake: Wake | None = None  # what the last step waits for (None: next cycle)
        self.due: int | None = None  # scheduler: the tick to run next (None: on a change)
        self.seen = -1  # scheduler: the machine revision its last step saw (-1: fresh)
        self.stepped = (-1, 0)  # scheduler: the tick it last stepped at, and how often then
        self.functions = {s.stmt.name: i for i, s in enumerate(steps)
                          if isinstance(s.stmt, FunctionDef)}
        self.frames: list[ProcessContext] = []  # FUNCTION calls running: depth, memory
        # a STATIC's calls running (a recursive FUNCTION): the innermost holds its names
        self.static_holders: dict[tuple[int, int], list[ProcessContext]] = {}
        self.budget = FUNCTION_STATEMENTS
        ctx.functions = self.call_function
        self.trace: Trace | None = None  # TRON / STEPLINE: where it pauses (tracing.py)
        self.paused = False  # waiting for STEPLINE or TROFF: not stepped
        self.jump: int | None = None  # SETLINE: the step it goes on at
        self.breaks: set[int] = set()  # BREAK_ADD: lines it pauses before (debugwords.py)
        self.last_line = 0  # the line of the statement it ran last (a breakpoint's entry)
        self.on_pause: Callable[[Task], None] | None = None  # says where it paused

    def call_function(self, name: str, args: list[Argument]) -> Value:
        """Run a FUNCTION of the program, or of a BASIC library of the store (I: a
        library's FUNCTIONs are seen by every program), to its RETURN value (or ENDFUNC:
        0), with its parameters as its own variables, inside the statement that calls it:
        it may not wait (D). A DIM array passed alone goes by reference."""
        start = self.functions.get(name)
        steps = self.steps
        if start is None and self.library is not None:
            found = self.library(name)
            if found is not None:
                steps, start = found
        if start is None:
            raise TrioError("Variable not defined")
        define = steps[start].stmt
        assert isinstance(define, FunctionDef)
        if len(args) != len(define.params):
            raise TrioError("Syntax error")
        if len(self.frames) >= GOSUB_DEPTH:
            raise TrioError("Stack overflow")
        outer = self.ctx
        caller = self.frames[-1] if self.frames else outer
        ctx = ProcessContext(process=outer.process, program=outer.program, base=outer.base,
                             functions=self.call_function, ticks=outer.ticks)
        for param, kind, arg in zip(define.params, define.types, args, strict=True):
            if kind in _NUMBER_TYPES:
                ctx.types[param] = kind  # its AS type: what an element or it holds
            if isinstance(arg, list):
                ctx.arrays[param] = arg
                shape = next((caller.shapes[n] for n, a in caller.arrays.items()
                              if a is arg and n in caller.shapes), None)
                if shape is not None:  # the array keeps its dimensions (.dims, .dimsize)
                    ctx.shapes[param] = shape
            else:  # a number is a FLOAT unless its AS type says otherwise (help DIM)
                ctx.variables[param] = self.interpreter._typed(param, arg, ctx)
        if not self.frames:
            self.budget = FUNCTION_STATEMENTS  # shared by the whole tree of calls
        self.frames.append(ctx)
        kept: list[tuple[int, int]] = []  # the STATIC steps this call went through
        try:
            pc = start + 1
            while True:
                self.budget -= 1
                if self.budget < 0:
                    raise TrioError("Function too long")
                step = steps[pc]
                ctx.line = step.line
                stmt = step.stmt
                if isinstance(stmt, Dim) and stmt.static:
                    key = (id(steps), pc)
                    kept.append(key)
                    holders = self.static_holders.setdefault(key, [])
                    holders.append(ctx)
                    if len(holders) > 1:  # a call of a call: one storage, as VB's STATIC
                        self._restore(ctx, self._kept(holders[-2], stmt))
                        pc += 1
                        continue
                    if key in self.interpreter.statics:  # set up by an earlier call
                        self._restore(ctx, self.interpreter.statics[key])
                        pc += 1
                        continue
                if isinstance(stmt, EndFunc):
                    return 0.0
                if isinstance(stmt, Return) and not ctx.stack:
                    if stmt.value is None:
                        return 0.0
                    value = self.interpreter.evaluate(stmt.value, ctx)
                    return self.interpreter.as_type(define.returns, value) \
                        if define.returns in _NUMBER_TYPES else value
                for wake in self._step(ctx, pc, step, True, steps):
                    if wake is not _PASS and wake is not _LOOPED:
                        raise TrioError("Function cannot wait")
                pc = ctx.pc
        finally:
            self.frames.pop()
            outer.base = ctx.base  # BASE set inside a FUNCTION holds for the process (D)
            for key in kept:  # the STATIC names keep what this call left in them
                names = steps[key[1]].stmt
                assert isinstance(names, Dim)
                left = self.interpreter.statics[key] = self._kept(ctx, names)
                holders = self.static_holders[key]
                holders.pop()
                if holders:  # the call it returns to goes on with them
                    self._restore(holders[-1], left)
                else:
                    del self.static_holders[key]

    @staticmethod
    def _kept(ctx: ProcessContext, names: Dim) -> dict[str, Kept]:
        return {name: (ctx.variables.get(name), ctx.arrays.get(name), ctx.shapes.get(name),
                       ctx.types.get(name)) for name in names.names}

    @staticmethod
    def _restore(ctx: ProcessContext, kept: dict[str, Kept]) -> None:
        """A STATIC's names as the last call left them."""
        for name, (value, array, shape, kind) in kept.items():
            if value is not None:
                ctx.variables[name] = value
            if array is not None and shape is not None:
                ctx.arrays[name], ctx.shapes[name] = array, shape
            if kind is not None:
                ctx.types[name] = kind

    def step(self) -> Wake | None:
        """Run until the program waits, ends a loop pass, uses its slice or finishes (one
        servo cycle); return what it waits for (None: the next servo cycle).

        A TrioError carries the line it happened on; the task is finished after it.
        """
        if self.finished or self.paused:
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
        except RecursionError:  # (bounded nesting keeps this from happening)
            self.finished = True
            raise TrioError("Stack overflow", self.ctx.line) from None
        except Exception:  # a fault of ours: the program stops as at a run-time error
            self.finished = True
            log_fault(f"MC405 program {self.ctx.program} line {self.ctx.line}", "")
            raise TrioError(FAULT_TEXT, self.ctx.line) from None
        return self.wake

    def _program(self) -> Generator[Wake | None, None, None]:
        ctx, steps = self.ctx, self.steps
        pc = 0
        waited = False  # this loop pass already gave up a servo cycle
        budget = STATEMENTS_PER_CYCLE
        while pc < len(steps) and not ctx.stopped:
            budget -= 1
            if budget < 0:  # this cycle's slice is used: go on next cycle
                yield None
                waited = True
                budget = STATEMENTS_PER_CYCLE - 1
            step = steps[pc]
            ctx.line = step.line
            if self.breaks and step.line in self.breaks and step.line != self.last_line:
                self.trace = self.trace or Trace()  # a breakpoint: pause before its line
                self.trace.line = -1
            while self.trace is not None or self.jump is not None:  # TRON, STEPLINE,
                # SETLINE: go on elsewhere, pause before this statement (a label is none)?
                if self.jump is not None:  # SETLINE moved the program pointer
                    pc, self.jump = self.jump, None
                    step = steps[pc]
                    ctx.line = step.line
                if self.trace is None or isinstance(step.stmt, Label) or \
                        not self.trace.stops_before(step.line, len(ctx.stack)):
                    ctx.status = RUNNING if self.trace is None else STEPPING
                    break
                self.trace.pause_at(step.line, len(ctx.stack))
                self.paused, ctx.status = True, PAUSED
                if self.on_pause is not None:
                    self.on_pause(self)
                yield None  # (resumed by STEPLINE, STEPINTO or TROFF)
                waited, budget = True, STATEMENTS_PER_CYCLE
            self.last_line = step.line
            try:
                for wake in self._step(ctx, pc, step, waited):
                    if wake is _LOOPED:
                        waited = False
                        continue
                    if wake is not _PASS:
                        waited = True
                        if ctx.status == RUNNING:  # a statement waiting: PROC_STATUS 8
                            ctx.status = SLEEP  # (help PROC_STATUS: "during WA, WAIT IDLE")
                    yield None if wake is _PASS else cast("Wake | None", wake)
                    if ctx.status == SLEEP:
                        ctx.status = RUNNING
                    budget = STATEMENTS_PER_CYCLE
                pc = ctx.pc
            except TrioError as exc:
                if ctx.on_error is None:
                    raise
                ctx.run_error = Thrown.CODE if isinstance(exc, Thrown) else \
                    error_code(exc.message)
                ctx.error_line = step.line
                pc, ctx.on_error = ctx.on_error, None

    def _step(self, ctx: ProcessContext, pc: int, step: Step, waited: bool,
              steps: list[Step] | None = None) -> Generator[Wake | None | object, None, None]:
        """Run one step, setting ctx.pc to the next; yields _PASS to end a loop pass
        (a servo cycle unless one was already given up) and _LOOPED after a back-edge."""
        interp, stmt = self.interpreter, step.stmt
        ctx.pc = pc + 1
        if isinstance(stmt, (IfBlock, While)):
            ctx.pc = pc + 1 if interp.number(stmt.condition, ctx) != 0 else step.target
        elif isinstance(stmt, (Else, Goto, FunctionDef)) or loop_jump(stmt) is not None:
            ctx.pc = step.target  # a branch's end / GOTO / past a FUNCTION / out of a loop
        elif isinstance(stmt, EndFunc):
            raise TrioError("Structure error")  # reached only by a jump into a FUNCTION
        elif isinstance(stmt, (EndIf, Repeat, Label, EndCase)):
            pass
        elif isinstance(stmt, Gosub):
            if len(ctx.stack) >= GOSUB_DEPTH:
                raise TrioError("Stack overflow")
            ctx.stack.append(pc + 1)
            ctx.pc = step.target
        elif isinstance(stmt, Return):
            if not ctx.stack:
                raise TrioError("RETURN without GOSUB")
            ctx.pc = ctx.stack.pop()
        elif isinstance(stmt, OnJump):
            choice = interp.number(stmt.value, ctx)
            if choice == int(choice) and 1 <= choice <= len(step.choices):
                if stmt.gosub:  # (out of range: on to the next statement, I)
                    if len(ctx.stack) >= GOSUB_DEPTH:
                        raise TrioError("Stack overflow")
                    ctx.stack.append(pc + 1)
                ctx.pc = step.choices[int(choice) - 1]
        elif isinstance(stmt, OnError):
            ctx.on_error = step.target if stmt.label is not None else None
        elif isinstance(stmt, SelectCase):
            ctx.cases[pc] = interp.evaluate(stmt.value, ctx)
            ctx.pc = step.target
        elif isinstance(stmt, Case):
            if not self._matches(ctx, stmt, ctx.cases.get(step.opener, 0.0)):
                ctx.pc = step.target
        elif isinstance(stmt, Wend):
            if not waited:
                yield _PASS
            yield _LOOPED
            ctx.pc = step.target
        elif isinstance(stmt, Until):
            if interp.number(stmt.condition, ctx) == 0:
                if not waited:
                    yield _PASS
                yield _LOOPED
                ctx.pc = step.target
        elif isinstance(stmt, For):
            start = interp.number(stmt.start, ctx)
            end = interp.number(stmt.end, ctx)
            increment = 1.0 if stmt.step is None else interp.number(stmt.step, ctx)
            if stmt.vr is not None:
                interp.assign(Assign(Call("VR", (stmt.vr,)), Num(start)), ctx)
            else:
                ctx.variables[stmt.variable] = interp._typed(stmt.variable, start, ctx)
            ctx.loops[pc] = (end, increment)
            ctx.pc = pc + 1 if _in_range(start, end, increment) else step.target
        elif isinstance(stmt, Next):
            opener = step.target - 1
            loop = (steps or self.steps)[opener].stmt
            assert isinstance(loop, For)
            if stmt.variable is not None and stmt.variable != loop.variable:
                raise TrioError("Structure error")
            if opener not in ctx.loops:  # (SETLINE into a FOR loop's body)
                raise TrioError("Structure error")
            end, increment = ctx.loops[opener]
            if loop.vr is not None:  # the counter is VR(n), read and written as the program would
                counter = Call("VR", (loop.vr,))
                value = interp.number(counter, ctx) + increment
                interp.assign(Assign(counter, Num(value)), ctx)
            else:
                value = interp.number_value(ctx.variables.get(loop.variable, 0.0)) + increment
                ctx.variables[loop.variable] = interp._typed(loop.variable, value, ctx)
            if _in_range(value, end, increment):
                if not waited:
                    yield _PASS
                yield _LOOPED
                ctx.pc = step.target
        else:
            yield from interp.execute(stmt, ctx)

    def _matches(self, ctx: ProcessContext, stmt: Case, value: object) -> bool:
        if not stmt.choices:
            return True  # CASE ELSE
        interp = self.interpreter
        for low, high in stmt.choices:
            first = interp.evaluate(low, ctx)
            if high is None:
                if first == value:
                    return True
            elif isinstance(value, float) and isinstance(first, float) \
                    and first <= value <= interp.number(high, ctx):
                return True
        return False

    def _true(self, condition: Expr) -> bool:
        return self.interpreter.number(condition, self.ctx) != 0


_PASS = object()  # the end of a loop pass: give up the servo cycle
_LOOPED = object()  # a loop back-edge was taken (the next pass starts fresh)


def _in_range(value: float, end: float, increment: float) -> bool:
    return value <= end if increment >= 0 else value >= end
