"""Program handling and processes: DIR, SELECT, LIST, COMPILE, RUN, HALT, the checksums.

What atrio sends (reference section 5) and what it parses back: DIR's table, the
type codes of SELECT and PROG_TYPE, EDPROG's CRC, RUNTYPE and AUTORUN. Programs run as
processes, one task each, stepped once per servo cycle in process order.
"""

from __future__ import annotations

from collections.abc import Callable, Generator

from ...personalities.trio import geometry, splines
from .datawords import CrcSetup
from .debugwords import ProgramTrace
from .errorcodes import PROGRAM_STOPPED
from .fifos import FifoFiles
from .housekeeping import DATA_FUNCTIONS, Definitions, Housekeeping, file_name
from .interpreter import Interpreter, ProcessContext, Value, Wait, Wake, error_code, number_arg
from .keywords import Keyword
from .lexer import Thrown, TrioError
from .machine import TrioMachine
from .network import NetworkWords
from .parser import FunctionDef
from .programs import ProgramStore, crc16
from .tasks import Step, Task, compile_program
from .timers import Scope, TimersAndScope

PROCESS_COUNT = 20  # user processes 0..19 (D: atrio's test autoruns on process 10)
_BASIC_TYPES = frozenset({0, 9, 12})  # .BAS, .MCC and .BAL hold BASIC


class ProgramCommands(Housekeeping, TimersAndScope, ProgramTrace, NetworkWords):
    """The SystemHook of the interpreter: commands that act on programs and processes
    (and, from Housekeeping, COPY/RENAME, CLEAR/RESET, LIST_GLOBAL and the data words)."""

    def __init__(self, machine: TrioMachine, programs: ProgramStore,
                 output: Callable[[str], None]) -> None:
        self.machine = machine
        self.programs = programs
        self.output = output  # replies to the command line that asked
        self.process_output = output  # what running programs report (errors)
        self.interpreter: Interpreter | None = None  # runs the programs (set by the owner)
        self.selected: str | None = None
        self.tasks: dict[int, Task] = {}
        self.ended: dict[int, ProcessContext] = {}  # each idle process's last program
        self.compiled: dict[str, list[Step]] = {}
        self.broken: set[str] = set()  # libraries that failed to compile since their edit
        self.defined: dict[str, int] = {}  # each GLOBAL/CONSTANT's number (LIST_GLOBAL)
        self.constants: dict[str, Value] = Definitions("C", self.defined)  # CONSTANT
        self.globals: dict[str, int] = Definitions("G", self.defined)  # GLOBAL "name", vr
        self.spellings: dict[str, str] = {}  # each one's name as first typed (LIST_GLOBAL)
        self.crc: CrcSetup | None = None  # CRC16(0, poly ...)
        self.breakpoints: dict[str, set[int]] = {}  # BREAK_ADD: each program's lines
        self.flash_pages: dict[int, list[float]] = {}  # FLASHTABLE (network.py)
        self.flash_table: list[float] | None = None  # FLASHVR(-1) (network.py)
        self.ethernet_values: dict[int, float] = {}  # ETHERNET's ports and modes (network.py)
        self.analog_outputs: dict[int, float] = {}  # AOUT(n)
        self.indexed: dict[tuple[str, tuple[float, ...]], float] = {}  # NODE_PROFILE(s, n)
        self.files: dict[int, list[int]] = {}  # OPEN #n: the characters still to read
        self.writing: dict[int, tuple[str, str]] = {}  # OPEN #n FOR OUTPUT: file, rest
        self.sources: dict[int, list[int]] = {}  # OPEN #n FOR INPUT: the whole file
        self.fifo_files = FifoFiles()  # OPEN ... FOR FIFO_WRITE / FIFO_READ (fifos.py)
        self.command_lines: list[ProcessContext] = []  # each open session's own context
        self.halt_listeners: list[Callable[[], None]] = []  # each open command line's: a
        # HALT from any host ends a statement waiting at another's prompt too (D)
        self._halting = False
        self.reset_requested = False  # EX in a program: the scheduler restarts after the cycle
        self.clock_offset = 0.0  # TIME = / DATE =: the real time clock set ahead (s)
        self.scope: Scope | None = None  # SCOPE armed (TRIGGER starts it)
        self.scope_cycles = 0  # SCOPE_CYCLE_COUNT: capture cycles started
        self.scope_trigger_pos = 0  # SCOPE_TRIGGER_POS: where the last trigger fell
        self.timers: dict[int, tuple[int, list[int], bool]] = {}  # TIMER slot -> the tick
        # it ends, its outputs and the level they take then

    def memory_in_use(self, asking: ProcessContext) -> int:
        """What the DIMs of the controller's live contexts hold: its processes, the
        FUNCTION calls running in them, its command lines (and the one asking). A process
        that ended, a call that returned, a session that closed holds nothing."""
        live = {id(asking): asking}
        for task in self.tasks.values():
            for ctx in (task.ctx, *task.frames):
                live[id(ctx)] = ctx
        for ctx in self.command_lines:
            live[id(ctx)] = ctx
        return sum(ctx.held for ctx in live.values())

    def context_of(self, process: int) -> ProcessContext | None:
        task = self.tasks.get(process)
        return task.ctx if task is not None else None

    def ended_context(self, process: int) -> ProcessContext | None:
        return self.ended.get(process)

    def _ended(self, process: int, task: Task, code: float = PROGRAM_STOPPED) -> None:
        """A process's program stopped: RUN_ERROR PROC(n) reads why (help page RUN_ERROR:
        31 a normal stop, STOP or HALT; an error's number), ERROR_LINE its line."""
        ctx = task.ctx  # (only what PROC(n) reads is kept: the DIMs are let go)
        self.ended[process] = ProcessContext(process=process, program=ctx.program,
                                             run_error=code, error_line=ctx.error_line)

    # ---- SystemHook ---------------------------------------------------------------------
    def system_parameter(self, name: str) -> float | None:
        if name in ("MPE", "FLASH_STATUS"):
            return 0.0
        if name[:-1] in ("AIN", "AINBI", "AOUT") and name[-1] in "0123":
            channel = int(name[-1])  # AIN(n), AOUT(n) as parameters (their page)
            if name.startswith("AOUT"):
                return self.analog_outputs.get(channel, 0.0)
            return float(round(self.machine.analog_input(channel) / 10.0 * 2047))
        if name in ("NIN", "NOP", "NIO"):
            return 32.0  # the I/O points IN and OP address here (D: as IN and OP take)
        if name in ("N_ANA_IN", "N_ANA_OUT"):
            return 8.0  # the channels AIN(n) and AOUT(n) take
        if name == "SCOPE_POS":
            return self.scope_position()
        if name == "SCOPE_CYCLE_COUNT":
            return float(self.scope_cycles)
        if name == "SCOPE_TRIGGER_POS":
            return float(self.scope_trigger_pos)
        if name == "CONTROL":
            return 405.0  # the MC405's ID (CONTROL's page); never locked (D)
        if name in ("INPUTS0", "INPUTS1"):  # IN(0..15) / IN(16..31) as a number (page)
            first = 0 if name == "INPUTS0" else 16
            return float(sum(1 << k for k in range(16)
                             if self.machine.digital_input(first + k)))
        if name == "CHECKSUM":
            crc = 0
            for program in self.programs.names():
                crc = crc16(self.programs.checksum(program).to_bytes(2, "big"), crc)
            return float(crc)
        return None

    def file_text(self, name: str) -> str:
        """OPEN #n AS "NAME" FOR INPUT: the text of a program of the store, its lines
        ending in CR LF (D: the store is the controller's file system)."""
        info = self.programs.get(file_name(name))
        return "".join(line + "\r\n" for line in self.programs.lines[info.name])

    def system_function(self, name: str, args: list[Value]) -> float:
        if name in DATA_FUNCTIONS:
            return self.data_function(name, args)
        if name == "FREE":
            return self.free_memory()  # (network.py)
        if name in ("FLASHTABLE", "FLASHVR"):
            return self.flashtable(args) if name == "FLASHTABLE" else self.flashvr(args)
        program = _name(args)
        if name in ("IS_PROG", "IS_FILE"):  # one function under two names (IS_FILE's page)
            return -1.0 if self.programs.exists(program) else 0.0
        return float(self.programs.get(program).type) if self.programs.exists(program) else -1.0

    def system_command(self, keyword: Keyword, args: list[Value],
                       ctx: ProcessContext) -> Wait:
        if keyword.name == "STOP" and not args and ctx.program:
            ctx.stopped = True  # STOP alone in a program: this program ends here
            args = [ctx.program]
        if keyword.name in splines.NAMES or keyword.name in geometry.TABLE_NAMES:
            self.table_spline(keyword.name, args)
            return _done()
        with_context = getattr(self, "ctx_" + keyword.name.lower(), None)
        if with_context is not None:  # CLEAR, RESET: act on the asking process too
            with_context(args, ctx)
            return _done()
        handler = getattr(self, "cmd_" + keyword.name.lower(), None)
        if handler is not None:  # else a token-table word the emulator does not model:
            handler(args)  # accepted with no effect (its table note says so)
        return _done()

    def table_spline(self, name: str, args: list[Value]) -> None:
        """B_SPLINE, C_SPLINE, A_SPLINE: TABLE points expanded into TABLE (splines.py);
        SPHERE_CENTRE, FILLET: TABLE geometry (geometry.py); every value computed before
        one write, so an error changes nothing."""
        if any(isinstance(a, str) for a in args):
            raise TrioError("Syntax error")
        try:
            numbers = [float(a) for a in args]
            read = self.machine.table_read
            out, values = (splines.expand(name, numbers, read) if name in splines.NAMES
                           else geometry.table_function(name, numbers, read))
            self.machine.table_write(out, values)
        except ValueError as exc:
            text = str(exc)  # (a TABLE range error reads as TABLE's own)
            raise TrioError(text[:1].upper() + text[1:]) from None

    # ---- program handling -----------------------------------------------------------------
    def _target(self, args: list[Value]) -> str:
        """The program named by the first argument, else the selected one."""
        if args and isinstance(args[0], str):
            return self.programs.get(args[0]).name
        if args or self.selected is None or not self.programs.exists(self.selected):
            raise TrioError("Program not found")
        return self.selected

    def _not_running(self, name: str) -> None:
        if any(t.ctx.program == name for t in self.tasks.values()):
            raise TrioError("Program is running")

    def cmd_dir(self, args: list[Value]) -> None:
        for line in self.programs.directory_lines():
            self.output(line + "\r\n")

    def cmd_select(self, args: list[Value]) -> None:
        name = _name(args[:1])
        if len(args) == 2:
            program_type = _integer(args[1])
            info = self.programs.create(name, program_type)
        elif self.programs.exists(name):
            info = self.programs.get(name)
        else:  # SELECT of a missing program creates it, a BASIC program (help page)
            info = self.programs.create(name, 0)
        self.selected = info.name

    def cmd_del(self, args: list[Value]) -> None:
        name = self._target(args[:1])
        self._not_running(name)
        self.programs.delete(name)
        self.compiled.pop(name, None)
        self.broken.discard(name)
        if self.selected == name:
            self.selected = None

    def cmd_new(self, args: list[Value]) -> None:
        name = self._target(args)
        self._not_running(name)
        self.programs.clear(name)
        self.compiled.pop(name, None)
        self.broken.discard(name)

    def cmd_list(self, args: list[Value]) -> None:
        name = self._target(args)
        for line in self.programs.lines[name]:
            self.output(line + "\r\n")

    def edit(self, name: str, number: int, action: str, text: str) -> None:
        program = self.programs.get(name).name
        self._not_running(program)
        self.programs.edit(program, number, action, text)
        self.compiled.pop(program, None)
        self.broken.discard(program)

    def edit_count(self, name: str) -> int:
        """``!NAME,N``: how many lines the program has."""
        return len(self.programs.lines[self.programs.get(name).name])

    def edit_lines(self, name: str, first: int, last: int) -> list[str]:
        """``!NAME,a,bL``: lines a to b (from 0, b included, D), those that exist."""
        lines = self.programs.lines[self.programs.get(name).name]
        return lines[first:last + 1]

    def edit_control(self, name: str, action: str) -> None:
        """``!NAME,M`` / ``!NAME,Z``: end of a download; the store is already written (D)."""
        self.programs.get(name)

    def compile(self, name: str) -> list[Step]:
        """Compile one program; its errors carry the line number."""
        steps = compile_program(self.programs.lines[name], self._included)
        self.compiled[name] = steps
        self.programs.set_compiled(name, 4 * len(steps))
        return steps

    def find_function(self, name: str) -> tuple[list[Step], int] | None:
        """A FUNCTION of a BASIC library (.BAL) of the store, compiled when needed: its
        library's steps and its first step (I: a library's FUNCTIONs are called by
        name from every program, as public programs do without naming the library)."""
        for program in self.programs.names():
            if self.programs.info[program].type != 12:
                continue
            steps = self.compiled.get(program)
            if steps is None:
                if program in self.broken:
                    continue
                try:
                    steps = self.compile(program)
                except TrioError:
                    self.broken.add(program)  # offers nothing until it is edited (D)
                    continue
            for index, step in enumerate(steps):
                if isinstance(step.stmt, FunctionDef) and step.stmt.name == name:
                    return steps, index
        return None

    def _included(self, name: str) -> list[str]:
        """INCLUDE "NAME": the lines of a BASIC program in the store."""
        info = self.programs.get(name)
        if info.type not in _BASIC_TYPES:
            raise TrioError("Program cannot be run")
        return self.programs.lines[info.name]

    def _compile_reporting(self, name: str) -> None:
        if self.programs.get(name).type not in _BASIC_TYPES:
            return
        try:
            self.compile(name)
        except TrioError as exc:
            self.output(f"%[Program {name} Line {exc.line}] - {exc.message}\r\n")

    def cmd_compile(self, args: list[Value]) -> None:
        self._compile_reporting(self._target(args))

    def cmd_compile_all(self, args: list[Value]) -> None:
        for name in self.programs.names():
            self._compile_reporting(name)

    def cmd_edprog(self, args: list[Value]) -> None:
        name = self._target(args[:1])
        if len(args) != 2 or _integer(args[1]) != 10:
            raise TrioError("Parameter out of range")
        self.output(f"{self.programs.checksum(name)}\r\n")

    def cmd_runtype(self, args: list[Value]) -> None:
        name = self._target(args[:1])
        autorun = _integer(args[1])
        process = _integer(args[2]) if len(args) > 2 else -1
        if autorun not in (0, 1) or not -1 <= process < PROCESS_COUNT:
            raise TrioError("Parameter out of range")
        self.programs.set_runtype(name, autorun == 1, process if autorun else -1)

    # ---- processes ------------------------------------------------------------------------
    def start(self, name: str, process: int = -1) -> int:
        """RUN: compile when edited, then start on the process given (or the highest free)."""
        info = self.programs.get(name)
        if info.type not in _BASIC_TYPES:
            raise TrioError("Program cannot be run")
        self._not_running(info.name)
        if process == -1:
            free = [p for p in range(PROCESS_COUNT - 1, -1, -1) if p not in self.tasks]
            if not free:
                raise TrioError("No free process")
            process = free[0]
        elif not 0 <= process < PROCESS_COUNT:
            raise TrioError("Parameter out of range")
        elif process in self.tasks:
            raise TrioError("Process is busy")
        steps = self.compiled.get(info.name)
        if steps is None:
            try:
                steps = self.compile(info.name)
            except TrioError as exc:
                raise TrioError(f"Program {info.name} line {exc.line}: {exc.message}") from None
        assert self.interpreter is not None
        ctx = ProcessContext(process=process, program=info.name)
        self.tasks[process] = Task(self.interpreter, steps, ctx, self.find_function)
        self.attach_trace(self.tasks[process])  # its breakpoints (debugwords.py)
        return process

    def cmd_run(self, args: list[Value]) -> None:
        process = _integer(args[1]) if len(args) > 1 else -1
        name = self._target(args[:1])
        if not self.release(name):  # (a paused program: RUN goes on, as TROFF; debugwords.py)
            self.start(name, process)

    def cmd_stop(self, args: list[Value]) -> None:
        name = self._target(args[:1])
        for process, task in list(self.tasks.items()):
            if task.ctx.program == name:
                task.ctx.stopped = True
                self._ended(process, task)
                del self.tasks[process]

    def halt(self) -> None:
        """Every program stops, and every command line's waiting statement is given up
        (its prompt comes now): a paused clock or a long WA never leaves a host's prompt
        dead (D, issue 34: HALT is the controller's stop, from whichever host)."""
        for process, task in self.tasks.items():
            task.ctx.stopped = True
            self._ended(process, task)
        self.tasks.clear()
        if self._halting:
            return
        self._halting = True
        try:
            for listener in list(self.halt_listeners):
                listener()
        finally:
            self._halting = False

    def cmd_halt(self, args: list[Value]) -> None:
        self.halt()

    def cmd_process(self, args: list[Value]) -> None:
        for process in sorted(self.tasks):
            task = self.tasks[process]
            state = "Paused" if task.paused else "Stepping" if task.trace else "Running"
            self.output(f"Process {process}:Program {task.ctx.program} - {state}\r\n")

    def start_autorun(self, announce: bool) -> None:
        """AUTORUN; and power up (announce False), which starts MC_CONFIG first: the program
        of type 9, or the one named MC_CONFIG (help "MC_CONFIG Program": "MC_CONFIG, if
        present, is always run at power-up"; an uploader that sends SELECT MC_CONFIG makes a
        BASIC program of that name, and a power cycle applies it on the real controller)."""
        if not announce:
            self.power_up_table()  # FLASHVR(-1)'s TABLE (network.py)
        infos = [self.programs.info[n] for n in self.programs.names()]
        config = [i for i in infos if i.type == 9 or i.name.upper() == "MC_CONFIG"]
        wanted = [i for i in infos if i.type == 0 and i.autorun and i not in config]
        if not announce:
            wanted = config + wanted
        for info in wanted:
            try:
                process = self.start(info.name, info.process if info.type == 0 else -1)
            except TrioError as exc:
                self.output(f"%[Program {info.name}] - {exc.message}\r\n")
                continue
            if announce:
                self.output(f"%[Process {process}:Program {info.name}] - Running\r\n")

    def cmd_autorun(self, args: list[Value]) -> None:
        self.start_autorun(announce=True)

    def ctx_ex(self, args: list[Value], ctx: ProcessContext) -> None:
        """EX in a program (its page: "EX may be included in a program"): the program ends
        here and the controller restarts at the end of this servo cycle, as EX typed on the
        command line (programs stop, the machine powers up, the autorun programs start; see
        docs/trio.md for what a restart keeps). The command lines stay open (D). On the
        command line EX restarts only when alone on its line (the session handles it; here
        a 'Syntax error', D)."""
        if not ctx.program or len(args) > 1:
            raise TrioError("Syntax error")
        ctx.stopped = True
        self.reset_requested = True

    def restart(self) -> None:
        """The controller's restart (EX): every program stops, the machine powers up, the
        autorun programs start (a machine with no power-up restarts its programs only)."""
        self.halt()
        power_up = getattr(self.machine, "restart", None)
        if power_up is not None:
            power_up()
        self.start_autorun(announce=False)

    def cmd_disable_group(self, args: list[Value]) -> None:
        """DISABLE_GROUP(-1) / DISABLE_GROUP(a, b, ...) (personality errors.py)."""
        numbers = [number_arg(a) for a in args]
        try:
            self.machine.disable_group(numbers)
        except ValueError as exc:
            raise TrioError(str(exc)) from None

    def cmd_initialise(self, args: list[Value]) -> None:
        """INITIALISE: every axis parameter to its power-up value (personality)."""
        self.machine.initialise()

    def cmd_ethercat(self, args: list[Value]) -> None:
        numbers = [number_arg(a) for a in args]
        if numbers[0] == 0x22 and len(numbers) >= 3 and numbers[2] == -1:
            self.output("0\r\n")  # no EtherCAT network: state 0 (D)

    def run_processes(self) -> None:
        """One servo cycle of every process, lowest number first."""
        self.run_timers()
        for process in sorted(self.tasks):
            task = self.tasks.get(process)
            if task is None:
                continue  # stopped by an earlier process this cycle
            self.step_task(process, task)

    def step_task(self, process: int, task: Task) -> None:
        """One servo cycle of one process; an error ends it with a message."""
        try:
            task.step()
        except TrioError as exc:
            self.process_output(f"%[Process {process}:Program {task.ctx.program} "
                                f"Line {exc.line}] - {exc.message}\r\n")
            task.ctx.error_line = float(exc.line or 0)
            self._ended(process, task, Thrown.CODE if isinstance(exc, Thrown)
                        else error_code(exc.message))
        else:
            if task.finished:
                self._ended(process, task)
        if task.finished and self.tasks.get(process) is task:
            del self.tasks[process]


def _done() -> Generator[Wake | None, None, None]:
    return
    yield  # a generator that finishes at once


def _name(args: list[Value]) -> str:
    if len(args) != 1 or not isinstance(args[0], str):
        raise TrioError("Syntax error")
    return args[0].upper()




def _integer(value: Value) -> int:
    number = number_arg(value)
    if number != int(number):
        raise TrioError("Parameter out of range")
    return int(number)
