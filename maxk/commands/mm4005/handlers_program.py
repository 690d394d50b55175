"""Stored programs: EP enters one, QP ends the entry, EX runs it, XX erases it, XM reads
the memory.

Evidence: the manual's XM page (3.175: programs 1 to 127, 'Out of range: Error F',
30720 bytes of non-volatile memory, one byte a character; C); the sibling ESP300's manual
p. 3-3 (program execution mode: ``EP``, the lines, ``QP``, then ``1EX``; lines stored,
not evaluated; the controller answers the host while a program runs) and a public ESP301
driver (``nXX`` then ``nEP`` ... ``QP``, ``nEX``): I. What none says is ours (D, on each
table entry).

A program runs beside the hosts' command lines (a `Task` of the machine): its lines one
after another at the tick EX was sent, until a wait (WS) holds it; its replies go to the
host that started it. AB ends it (D). A refused command or a malformed line ends it
there, with the error in the register (D); `ProgramRun.line` says where it stood.
"""

from __future__ import annotations

from maxk.personalities.mm4005.errors import (
    PARAMETER,
    PROGRAM_NUMBER,
    UNAUTHORIZED,
    MM4005Error,
)
from maxk.personalities.mm4005.programs import MAX_PROGRAMS, MEMORY, Wait

from .spec import Command, Context, Line, LineOwner, LineRunner


def program_number(cmd: Command) -> int:
    """xx of EP/EX/XX: 1..127, else F (as XM's, 3.175)."""
    value = cmd.axis
    if value is None or not 1 <= value <= MAX_PROGRAMS:
        raise MM4005Error(PROGRAM_NUMBER, f"program number 1..{MAX_PROGRAMS}")
    return value


def _not_in_program(ctx: Context, mnemonic: str) -> LineOwner:
    owner = ctx.owner
    if owner is None or owner.in_program:
        raise MM4005Error(UNAUTHORIZED, f"{mnemonic} inside a program")  # (D)
    return owner


class ProgramRun:
    """Program n running: a `Task` of the machine's `Tasks`."""

    program = True
    in_program = True

    def __init__(self, runner: LineRunner, number: int, lines: list[str],
                 listener: LineOwner | None) -> None:
        self.runner = runner
        self.number = number
        self.lines = list(lines)
        self.listener = listener
        self.line = 0  # the line running (1-based; 0 before the first)
        self.current: Line | None = None
        self.wait: Wait | None = None
        self.done = False
        self.failed = False

    # ---- as a line's owner -----------------------------------------------------------------
    def emit(self, text: str) -> None:
        if self.listener is not None:
            self.listener.emit(text)

    def begin_entry(self, number: int) -> None:
        raise MM4005Error(UNAUTHORIZED, "EP inside a program")

    # ---- as a task ---------------------------------------------------------------------------
    def resume(self) -> None:
        """Go on until a wait or the last line."""
        runner = self.runner
        while not self.done:
            current = self.current
            if current is None:
                if self.line >= len(self.lines):
                    self.done = True
                    return
                self.line += 1
                current = self.current = runner.start(self.lines[self.line - 1], self)
                if current is None:  # a malformed line: the program ends (D)
                    self.failed = self.done = True
                    return
            runner.proceed(current)
            if current.failed:
                self.failed = self.done = True
                return
            if not current.done:
                self.wait, current.wait = current.wait, None
                return
            self.current = None

    def stop(self) -> None:
        if self.current is not None:
            self.current.stop()
        self.done = True
        self.wait = None


def enter_program(ctx: Context, cmd: Command) -> list[str]:
    """EP: enter program xx: the host's next lines are stored, not run, up to QP."""
    number = program_number(cmd)
    owner = _not_in_program(ctx, "EP")
    if ctx.machine.programs.get(number) is not None:
        raise MM4005Error(UNAUTHORIZED, f"program {number} exists (erase it with XX)")  # D
    owner.begin_entry(number)
    return []


def quit_program(ctx: Context, cmd: Command) -> list[str]:
    """QP: quit program entry (outside an entry it is refused)."""
    raise MM4005Error(UNAUTHORIZED, "QP outside program entry")  # an entry takes it itself


def execute_program(ctx: Context, cmd: Command) -> list[str]:
    """EX: run program xx beside the command lines."""
    number = program_number(cmd)
    owner = _not_in_program(ctx, "EX")
    machine = ctx.machine
    lines = machine.programs.get(number)
    if lines is None:
        raise MM4005Error(PARAMETER, f"no program {number}")
    if machine.tasks.program is not None:
        raise MM4005Error(UNAUTHORIZED, "a program is running")  # one at a time (D)
    assert ctx.runner is not None
    run = ProgramRun(ctx.runner, number, lines, owner)
    machine.tasks.add(run)
    run.resume()
    return []


def erase_program(ctx: Context, cmd: Command) -> list[str]:
    """XX: erase program xx (none stored: nothing to do)."""
    number = program_number(cmd)
    _not_in_program(ctx, "XX")
    machine = ctx.machine
    running = machine.tasks.program
    if isinstance(running, ProgramRun) and running.number == number:
        raise MM4005Error(UNAUTHORIZED, f"program {number} is running")  # (D)
    machine.programs.erase(number)
    return []


def read_memory(ctx: Context, cmd: Command) -> list[str]:
    """XM: the program memory unused (xx missing or 0) or program xx's length in bytes."""
    store = ctx.machine.programs
    number = cmd.axis
    if number is None:
        return [f"XM{MEMORY - store.used()}"]
    if not 1 <= number <= MAX_PROGRAMS:
        raise MM4005Error(PROGRAM_NUMBER, f"program number 0..{MAX_PROGRAMS}")
    return [f"{number}XM{store.length(number)}"]
