"""The MM4005 on the wire: CR-terminated lines in, CR-terminated replies out.

Framing: a host line ends at CR, LF or CR LF (the EPICS drivers end with CR, the EPICS
trajectory scan with CR CR, StreamDevice and Tcl hosts with LF): CR and LF each end a
line and the empty line between CR and LF is ignored, as every empty line is (D: the
manual's "terminator" accepts either, I). Replies are the reply text and one CR, never
LF (the model 1 driver reads a stray LF into the next reply and breaks).

A line that waits (``1PA5;1WS;1TP``) holds there: the commands after the wait run once
it is over, on the tick it ends (the machine resumes it after that tick's events), and
the host's later lines wait behind it (the session is `holding`: a door feeds it
nothing meanwhile and keeps the bytes itself). Other hosts are answered all along, so a
stop (AB, ST) from a second connection acts at once and ends the wait. Replies that come
after their line's wait reach the host through `notify`, as unasked output does.

Program entry (EP n ... QP): the host's lines are stored as entered, not evaluated
(ESP300 p. 3-3, I), until a line holding QP.
"""

from __future__ import annotations

import re
from collections import deque
from collections.abc import Callable, Mapping
from typing import Final

from maxk.commands.line_session import LineSession, log_fault
from maxk.personalities.mm4005 import ErrorRegister, MM4005Error
from maxk.personalities.mm4005.errors import (
    FOLLOWING_ERROR,
    UNAUTHORIZED,
    UNKNOWN_MESSAGE,
)
from maxk.personalities.mm4005.programs import MEMORY, Wait

from .lexer import MAX_LINE, parse_command, resolve, split_line
from .machine import MM4005Machine
from .spec import Command, CommandSpec, Context, Line, LineOwner
from .table import COMMANDS

CR: Final = b"\r"
HELD_LINES: Final = 256  # lines a host may queue behind a waiting line when fed directly (D)
_SEPARATOR: Final = re.compile(r"([,;])")


class LineRun:
    """One command line under way: its commands, where it stands, what it waits for.
    As a `Task` of the machine's `Tasks` (a host's line) it is resumed when its wait is
    over; inside a program the program is the task."""

    program = False

    def __init__(self, interpreter: Interpreter, commands: list[Command], pieces: list[str],
                 owner: LineOwner | None) -> None:
        self.interpreter = interpreter
        self.commands = commands
        self.pieces = pieces  # each command's text (blanks removed): EP enters the rest
        self.owner = owner
        self.index = 0
        self.wait: Wait | None = None
        self.done = False
        self.failed = False  # a command was refused: the line (and a program) ends
        self.after: Callable[[LineRun], None] | None = None  # told after each resume

    def resume(self) -> None:
        self.interpreter.proceed(self)
        if self.after is not None:
            self.after(self)

    def stop(self) -> None:
        self.done = True
        self.wait = None


class Interpreter:
    """Runs command lines against a machine and keeps the error register."""

    def __init__(self, machine: MM4005Machine,
                 table: Mapping[str, CommandSpec] = COMMANDS) -> None:
        self.context = Context(machine)
        self.context.runner = self
        self.table = table

    @property
    def errors(self) -> ErrorRegister:
        return self.context.errors

    @property
    def machine(self) -> MM4005Machine:
        return self.context.machine

    def start(self, line: str, owner: LineOwner | None) -> LineRun | None:
        """A line parsed whole (a malformed command rejects it: None, error recorded)."""
        if self.machine.take_errors():  # a following error since the last line
            self.context.errors.record(FOLLOWING_ERROR)
        try:
            pieces = split_line(line)
            axes = self.machine.axis_count
            commands = [parse_command(piece, self.table, axes) for piece in pieces]
        except MM4005Error as error:
            self.context.errors.record(error.code)
            return None
        return LineRun(self, commands, pieces, owner)

    def proceed(self, run: Line) -> None:
        """Run on from where the line stands until a wait that is not over yet or its
        end. A refused command ends the line there, the ones before it stay done (D)."""
        assert isinstance(run, LineRun)
        ctx = self.context
        while run.index < len(run.commands) and not run.done:
            command = run.commands[run.index]
            run.index += 1
            ctx.owner, ctx.wait = run.owner, None
            try:
                command = resolve(command, self.machine.variables)
                replies = command.spec.handler(ctx, command)
            except MM4005Error as error:
                ctx.errors.record(error.code)
                run.failed = True
                break
            except Exception:  # a fault of ours: refused as a line it cannot run (D),
                log_fault("MM4005 interpreter", run.pieces[run.index - 1]  # and logged
                          if run.index - 1 < len(run.pieces) else "")
                ctx.errors.record(UNKNOWN_MESSAGE)
                run.failed = True
                break
            finally:
                ctx.owner = None
            if run.owner is not None:
                for reply in replies:
                    run.owner.emit(reply)
            if command.spec.mnemonic == "EP" and run.owner is not None:
                rest = ";".join(run.pieces[run.index:])  # entered, not run
                run.index = len(run.commands)
                if rest:
                    enter = getattr(run.owner, "enter", None)
                    if enter is not None:
                        enter(rest)
                break
            wait, ctx.wait = ctx.wait, None
            if wait is not None and not wait.ready(self.machine.tick):
                run.wait = wait
                return
        run.done = True
        run.wait = None

    def execute_line(self, line: str) -> list[str]:
        """Replies of one line (without CR), for a caller with no session. A line that
        waits goes on later (the machine resumes it); its later replies go nowhere."""
        collector = _Collector()
        run = self.start(line, collector)
        if run is not None:
            self.proceed(run)
            if not run.done:
                self.machine.tasks.add(run)
        collector.closed = True
        return collector.replies


class _Collector:
    """The owner of a line run without a session: keeps the replies until it returns."""

    in_program = False

    def __init__(self) -> None:
        self.replies: list[str] = []
        self.closed = False

    def begin_entry(self, number: int) -> None:
        raise MM4005Error(UNAUTHORIZED, "program entry needs a host's session")

    def emit(self, text: str) -> None:
        if not self.closed:
            self.replies.append(text)


class MM4005Session(LineSession):
    """The door-facing session: ``feed`` host bytes in any split, ``read`` the replies."""

    terminators = b"\r\n"  # CR, LF or CR LF (the empty line between is ignored)
    line_limit = MAX_LINE  # manual 3.3.1.3: 110 characters
    in_program = False

    def __init__(self, machine: MM4005Machine, interpreter: Interpreter | None = None,
                 notify: Callable[[], None] | None = None) -> None:
        super().__init__(notify)
        self.machine = machine
        self.interpreter = interpreter or Interpreter(machine)
        self._run: LineRun | None = None  # this host's line held by a wait
        self._held: deque[str] = deque()  # the host's lines received meanwhile
        self._entry: tuple[int, list[str]] | None = None  # EP n: (n, lines so far)
        self._quiet = False  # feeding or resuming: notify once at the end, not per reply

    # ---- the Session contract ------------------------------------------------------------
    def feed(self, data: bytes) -> None:
        self._quiet = True
        try:
            super().feed(data)
        finally:
            self._quiet = False
        self.machine.tasks.poll()  # a stop from this line may end another host's wait

    @property
    def holding(self) -> bool:
        """A line of this host waits (`HoldsInput`): feed it nothing more until it
        notifies; the door keeps the host's bytes meanwhile."""
        return self._run is not None or bool(self._held)

    @property
    def waiting(self) -> bool:
        return self._run is not None

    @property
    def entering(self) -> int | None:
        """The program number being entered (EP), or None."""
        return None if self._entry is None else self._entry[0]

    def close(self) -> None:
        super().close()
        self.abandon()

    def abandon(self) -> None:
        """Give up the waiting line and the lines behind it (a power-up, a hang-up, a
        console's patience)."""
        if self._run is not None:
            self._run.stop()
            self._run = None
        self._held.clear()

    def power_up(self, interpreter: Interpreter) -> None:
        """The controller powered up: a waiting line, held lines and a program being
        entered are lost (D), as is a line half received."""
        self.abandon()
        self._entry = None
        self.interpreter = interpreter
        self.discard_partial_line()

    # ---- lines ---------------------------------------------------------------------------
    def line_too_long(self) -> None:
        """Longer than 110 characters: refused whole with A, as parse_line does."""
        self.interpreter.errors.record(UNKNOWN_MESSAGE)

    def line_fault(self, text: str) -> None:
        """A fault of ours running the line: TE reads A, unknown message, as for a line
        it cannot run (D)."""
        self.interpreter.errors.record(UNKNOWN_MESSAGE)

    def run_line(self, text: str) -> None:
        if not text.strip(" \t"):
            return
        if self.holding:
            if len(self._held) < HELD_LINES:
                self._held.append(text)
            return  # beyond: lost (a door never feeds a holding session)
        self._run_text(text)

    def _run_text(self, text: str) -> None:
        if self._entry is not None:
            text = self._enter_line(text)
            if not text:
                return
        run = self.interpreter.start(text, self)
        if run is None:
            return
        self.interpreter.proceed(run)
        if not run.done:
            self._run = run
            run.after = self._resumed
            self.machine.tasks.add(run)

    def _resumed(self, run: LineRun) -> None:
        """The held line went on (the machine resumed it): once it has ended, the lines
        received meanwhile run, until one waits; the door is told once."""
        if run.done:
            self._run = None
            quiet, self._quiet = self._quiet, True
            try:
                while self._held and self._run is None:
                    self._run_text(self._held.popleft())
            finally:
                self._quiet = quiet
        if self.notify is not None and not self._quiet and (self._out or not self.holding):
            self.notify()

    # ---- what a line's commands ask of their host -----------------------------------------
    def emit(self, text: str) -> None:
        if self.closed:
            return
        self.reply(text.encode("latin-1", "replace") + CR)
        if self.notify is not None and not self._quiet and self._run is None:
            self.notify()  # a program's reply (a held line's are told once it goes on)

    def begin_entry(self, number: int) -> None:
        """EP n: the next lines go into program n."""
        if self._entry is not None:
            raise MM4005Error(UNAUTHORIZED, f"program {self._entry[0]} is being entered")
        self._entry = (number, [])

    def enter(self, text: str) -> None:
        """The rest of the EP line: the program's first line."""
        self._enter_line(text)

    def _enter_line(self, text: str) -> str:
        """Store a line of the program being entered; a QP in it ends the entry and what
        follows QP on the line runs as usual (returned)."""
        assert self._entry is not None
        number, lines = self._entry
        tokens = _SEPARATOR.split(text)
        quit_at = next((i for i, token in enumerate(tokens)
                        if "".join(token.split()).upper() == "QP"), None)
        body = text if quit_at is None else "".join(tokens[:quit_at]).rstrip(",; \t")
        rest = "" if quit_at is None else "".join(tokens[quit_at + 1:]).lstrip(",; \t")
        if body.strip(" \t"):
            store = self.machine.programs
            if store.used() + sum(len(x) + 1 for x in lines) + len(body) + 1 > MEMORY:
                self.interpreter.errors.record(UNAUTHORIZED)  # memory full (D)
            else:
                lines.append(body)
        if quit_at is not None:
            self._entry = None
            self.machine.programs.put(number, lines)
        return rest

