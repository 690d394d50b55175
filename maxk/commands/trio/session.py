"""The Trio command line over telnet, byte for byte as atrio needs it.

For ``?1+1`` CR LF the controller sends: the echo of each character as it arrives, CR LF
for the CR, the output lines (each CR LF), the prompt ``>>`` (no trailing space); then
for the LF: the LF itself, ``Control char : 0x10000000A`` CR LF and ``>>`` again. An
error is one ``%[COMMAND LINE] - <text>`` line (D: atrio needs ``%[COMMAND`` and CR LF;
the rest of the text is ours), followed by the prompt as usual. Telnet negotiation
(IAC ...) and NUL bytes are dropped from the input. The LF answer is the controller's:
atrio sends CR LF and its reply pattern requires ``>>`` LF ``Control char : ...`` CR LF
``>>`` (C, atrio's trio.py). An LF that follows no CR ends a line as CR does (D: a
terminal or ``nc`` that sends LF alone gets its command run, not a control-char report).

A command that waits (``WA(100)``, ``WAIT IDLE``) holds the command line: its output and
prompt come when it ends, and bytes received meanwhile are kept and handled after it, at
most `RESUME_SLICE` of them a servo cycle (a host that queued a megabyte behind a WA must
not freeze the engine when the wait ends). While the session `holding` input, a door
feeds it nothing more: the rest waits in the door, where back-pressure applies. A line is
kept up to `LINE_LIMIT` characters; the rest is echoed but not stored, and the line is
refused when its CR comes.
A fault in the emulator's own code (an unexpected Python exception inside a statement)
answers its line with ``%[COMMAND LINE] - Evaluation error`` (D: RUN_ERROR's page lists
"Evaluation error"; the traceback goes to the ``maxk.commands`` log, never to the host)
and the session takes the next line: no line goes unanswered, no API call waits.
Programs run as processes beside the command line; the door calls
:meth:`TrioCommandLine.servo_cycle` once per servo cycle, after the machine's cycle.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Generator

from maxk.commands.line_session import LineSession, log_fault

from .interpreter import Interpreter, ProcessContext, Wake, due_after
from .lexer import TrioError
from .machine import TrioMachine
from .parser import BLOCK_STATEMENTS, Stmt, parse_line
from .programs import ProgramStore
from .system import ProgramCommands
from .tasks import FAULT_TEXT

PROMPT = b">>"
LINE_LIMIT = 1024  # characters in one command line (D)
RESUME_SLICE = 2048  # held input handled a servo cycle once a wait has ended, to a line end (D)
HEAR_LIMIT = 1 << 20  # unread output past which program PRINTs are not kept for a host (D)
_IAC, _SB, _SE = 0xFF, 0xFA, 0xF0
_EDIT = re.compile(r"!([A-Za-z0-9_]+),(\d+) *([RID]),?(.*)", re.DOTALL)
_EDIT_LIST = re.compile(r"!([A-Za-z0-9_]+),(\d+),(\d+) *L *")
_EDIT_CONTROL = re.compile(r"!([A-Za-z0-9_]+), *([A-Z]) *")
_EX = re.compile(r"\s*EX\s*(\(\s*\d*\s*\))?\s*", re.IGNORECASE)


class TrioCommandLine(LineSession):
    """One telnet command-line session (the Session contract: feed / read). Its bytes
    are echoed one by one as they arrive, so `feed` is its own; the output side and the
    bound on program output nobody asked for are the shared line session's."""

    line_limit = LINE_LIMIT
    unasked_limit = HEAR_LIMIT

    def __init__(self, machine: TrioMachine,
                 programs: ProgramStore | str | os.PathLike[str] | None = None, *,
                 runtime: ProgramCommands | None = None,
                 notify: Callable[[], None] | None = None,
                 on_restart: Callable[[TrioCommandLine], None] | None = None) -> None:
        """`runtime`: the controller's programs and processes, shared by every session
        of one controller (None: this session has its own, as in the language tests);
        `notify`: called when output nobody asked for is waiting (a waiting command
        ended, a program printed); `on_restart`: called after EX."""
        super().__init__(notify)
        self.machine = machine
        self.on_restart = on_restart
        if runtime is None:
            store = programs if isinstance(programs, ProgramStore) else ProgramStore(programs)
            runtime = ProgramCommands(machine, store, self._print)
            self.interpreter = Interpreter(machine, runtime, self._print)
            runtime.interpreter = self.interpreter
        else:
            self.interpreter = Interpreter(machine, runtime, self._print)
        self.system = runtime
        self.context = ProcessContext(process=-1)
        runtime.command_lines.append(self.context)  # its DIMs count in the controller's memory
        runtime.halt_listeners.append(self._halted)
        self.restart_requested = False
        self._input = bytearray()
        self._consumed = 0  # bytes of _input handled by the running pump
        self._telnet = 0  # 0 data, 1 after IAC, 2 option byte, 3 in SB, 4 IAC in SB
        self._after_cr = False  # the last byte was a CR: an LF now is CR LF's LF
        self._busy: Generator[Wake | None, None, None] | None = None
        self.busy_wake: Wake | None = None  # what a waiting command-line statement awaits
        self.busy_due: int | None = None  # scheduler: the tick to resume it
        self.busy_seen = -1  # scheduler: machine revision seen when it last waited

    @property
    def programs(self) -> ProgramStore:
        return self.system.programs

    # ---- the Session contract ---------------------------------------------------------------
    def feed(self, data: bytes) -> None:
        if self.closed or self.restart_requested:
            return  # after EX the controller restarts: what follows goes nowhere (D)
        self._input += data
        self._pump()

    def close(self) -> None:
        """The host went away: its held input goes; `notify` stays, so an EX that closed
        the session still lets its host read what came before (see `resume`)."""
        self.closed = True
        self._input.clear()
        self.system.command_lines[:] = [  # its DIMs go with it
            ctx for ctx in self.system.command_lines if ctx is not self.context]
        if self._halted in self.system.halt_listeners:
            self.system.halt_listeners.remove(self._halted)

    def _halted(self) -> None:
        """A HALT (from any host): a statement waiting here is given up, its prompt sent."""
        busy = self._busy
        running = getattr(busy, "gi_running", False)  # the statement running this HALT
        if busy is not None and not running and not self.closed:
            self.abandon()
            if self.notify is not None:
                self.notify()

    def servo_cycle(self) -> None:
        """One servo cycle of the processes, then of a waiting command-line statement."""
        self.system.run_processes()
        self.resume()

    @property
    def pending(self) -> bool:
        """Output is waiting to be read."""
        return bool(self._out)

    @property
    def waiting(self) -> bool:
        """A command-line statement is waiting (its prompt has not come yet)."""
        return self._busy is not None

    @property
    def backlog(self) -> bool:
        """Input received while a statement waited is still to be handled."""
        return bool(self._input) and not self.restart_requested

    @property
    def holding(self) -> bool:
        """The session holds input it cannot run yet: feed it nothing more until it
        notifies (the door keeps the rest, and stops reading once its inbox is full)."""
        return self._busy is not None or self.backlog

    def abandon(self) -> None:
        """Give up a waiting statement (a console's break): its prompt comes now and the
        bytes received meanwhile are handled."""
        if self._busy is not None:
            self._busy.close()
            self._busy = None
            self._out += PROMPT
            self._pump()

    def resume(self) -> None:
        """Give a waiting command-line statement its servo cycle, then handle up to
        `RESUME_SLICE` of the bytes that arrived meanwhile. The door hears (notify) once
        the session stops holding input, even if that printed nothing."""
        was_holding = self.holding
        if self._busy is not None:
            self._advance()
        if self._busy is None:
            self._pump(RESUME_SLICE)
        if self.notify is not None and (was_holding and not self.holding or self._out):
            self.notify()  # even when an EX held here closed it: its host reads the rest

    def power_up(self) -> None:
        """Start the programs set to run at power up (after a restart of the door)."""
        self.system.start_autorun(announce=False)

    # ---- input bytes --------------------------------------------------------------------------
    def _print(self, text: str) -> None:
        self._out += text.encode("latin-1", "replace")

    def hear(self, text: str) -> None:
        """Output of a running program (every session of the controller hears it). A
        host that has not read `HEAR_LIMIT` of output misses it (D): program output is
        nobody's reply, and a deaf host must not grow the controller."""
        self.unasked(text.encode("latin-1", "replace"), wake=False)

    def _pump(self, limit: int | None = None) -> None:
        """Handle received bytes in order until a statement waits (or `limit` bytes)."""
        data = self._input
        end = len(data)
        if limit is not None and limit < end:  # to the end of the line the limit falls in
            ends = [k for k in (data.find(b"\r", limit - 1), data.find(b"\n", limit - 1))
                    if k >= 0]
            cr = min(ends) if ends else -1
            end = end if cr < 0 else cr + 2 if data[cr:cr + 2] == b"\r\n" else cr + 1
        try:
            self._pump_bytes(data, end)
        finally:  # a fault inside a statement loses that input, not the stream after it
            del data[:self._consumed]

    def _pump_bytes(self, data: bytearray, end: int) -> None:
        i = self._consumed = 0
        while i < end and self._busy is None and not self.restart_requested:
            byte = data[i]
            i += 1
            self._consumed = i
            if self._telnet or byte == _IAC:
                self._telnet_byte(byte)
                continue
            if byte == 0:
                continue
            after_cr, self._after_cr = self._after_cr, byte == 0x0D
            if byte == 0x0D or byte == 0x0A and not after_cr:
                # CR ends a line; so does an LF that follows no CR (D: a terminal that
                # sends LF alone, as nc does, works like one that sends CR)
                self._out += b"\r\n"
                line = self._line.decode("latin-1")
                self._line.clear()
                self._execute(line)
            elif byte < 0x20 or byte == 0x7F:
                # the LF of a CR LF (atrio's framing expects this answer) and any other
                # control character
                self._out.append(byte)
                self._out += f"Control char : 0x1{byte:08X}\r\n".encode() + PROMPT
            else:
                if len(self._line) <= LINE_LIMIT:  # one more than fits marks it too long
                    self._line.append(byte)
                self._out.append(byte)

    def _telnet_byte(self, byte: int) -> None:
        state = self._telnet
        if state == 0:
            self._telnet = 1
        elif state == 1:
            self._telnet = 2 if 0xFB <= byte <= 0xFE else 3 if byte == _SB else 0
        elif state == 2:
            self._telnet = 0
        elif state == 3:
            self._telnet = 4 if byte == _IAC else 3
        else:
            self._telnet = 0 if byte == _SE else 3

    # ---- one command line ---------------------------------------------------------------------
    def _execute(self, line: str) -> None:
        if _EX.fullmatch(line):
            self.system.halt()
            self.restart_requested = True  # no prompt, no trailer: the door restarts
            if self.on_restart is not None:
                self.on_restart(self)
            return
        try:
            if len(line) > LINE_LIMIT:
                raise TrioError("Line too long")
            if line.startswith("!"):
                self._edit(line)
                statements: list[Stmt] = []
            elif line.strip().upper() == "&M":
                statements = []  # Motion Perfect's channel marker: accepted, no effect (D)
            else:
                statements = parse_line(line)
                if any(isinstance(s, BLOCK_STATEMENTS) for s in statements):
                    raise TrioError("Structure error")
        except RecursionError:  # (the parser's limits keep this from happening)
            self._error(TrioError("Expression too complex"))
            return
        except TrioError as exc:
            self._error(exc)
            return
        except Exception:  # a fault of ours: answered, logged, the session goes on
            log_fault("MC405 command line", line)
            self._error(TrioError(FAULT_TEXT))
            return
        self._busy = self._run(statements)
        self._advance()

    def _run(self, statements: list[Stmt]) -> Generator[Wake | None, None, None]:
        for stmt in statements:
            yield from self.interpreter.execute(stmt, self.context)

    def _advance(self) -> None:
        assert self._busy is not None
        self.system.output = self._print  # replies of program commands come here
        try:
            self.busy_wake = next(self._busy)
            self.busy_due = due_after(self.busy_wake, self.machine.servo_tick())
            self.busy_seen = -1
            return  # still waiting
        except StopIteration:
            self._out += PROMPT
        except TrioError as exc:
            self._error(exc)
        except Exception:  # a fault of ours: the statement ends with an error line
            log_fault("MC405 command line", "(a statement)")
            self._error(TrioError(FAULT_TEXT))
        self._busy = None

    def _error(self, exc: TrioError) -> None:
        self._print(f"%[COMMAND LINE] - {exc.message}\r\n")
        self._out += PROMPT

    def _edit(self, line: str) -> None:
        """The line editor's forms (program download and inspection):
        ``!NAME,n R text`` replaces line n (appends at the end), ``!NAME,n I text``
        inserts before line n, ``!NAME,n D`` deletes line n, ``!NAME,N`` prints the line
        count, ``!NAME,a,b L`` lists lines a to b, ``!NAME,M`` / ``!NAME,Z`` end a
        download. atrio sends ``!N,3RPRINT 1``; a vendor uploader sends ``!N,3I,PRINT 1``
        and ``!N,0,10L``: spaces before the letter and one comma after it separate, they
        are not the line's text (I: a BASIC line never starts with a comma)."""
        match = _EDIT.fullmatch(line)
        if match:
            name, number, action, text = match.groups()
            self.system.edit(name, int(number), action, text)
            return
        listing = _EDIT_LIST.fullmatch(line)
        if listing:
            name, first, last = listing.groups()
            for text in self.system.edit_lines(name, int(first), int(last)):
                self._print(text + "\r\n")
            return
        control = _EDIT_CONTROL.fullmatch(line)
        if control is None or control.group(2) not in ("M", "Z", "N"):
            raise TrioError("Syntax error")
        if control.group(2) == "N":
            self._print(f"{self.system.edit_count(control.group(1))}\r\n")
            return
        self.system.edit_control(control.group(1), control.group(2))
