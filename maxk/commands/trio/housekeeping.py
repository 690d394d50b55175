"""The command line's housekeeping words and the data functions the runtime answers:
COPY and RENAME of programs, CLEAR and RESET of variables, LIST_GLOBAL, TABLEVALUES,
CRC16, STRTOD, IEEE_IN and IEEE_OUT.

A mixin of the runtime (system.ProgramCommands), so each word is a ``cmd_<name>``
handler like the program words there, in a module of its own concern. Each behaviour is
from the word's TrioBASIC help page; the details a page leaves open are decisions (D) on
the keyword's table entry.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from ...personalities.trio.memory import TABLE_SIZE, VR_COUNT
from .channelwords import channel_read, channel_write
from .datawords import (
    CrcSetup,
    crc_direct,
    crc_legacy,
    crc_setup,
    ieee_in,
    ieee_out,
    letter_codes,
    read_number,
    table_values,
)
from .fifos import FifoFiles
from .interpreter import FILE_CHANNELS, Interpreter, ProcessContext, Value, number_arg
from .lexer import TrioError
from .machine import TrioMachine
from .parser import Expr
from .printformat import Real
from .programs import MAX_PROGRAM_BYTES, ProgramStore
from .tasks import Step, Task

DATA_FUNCTIONS = frozenset({"CRC16", "STRTOD", "IEEE_IN", "IEEE_OUT"})
TABLEVALUES_LIMIT = 10_000  # values one TABLEVALUES lists (D: a bounded reply)
STRTOD_LIMIT = 64  # characters STRTOD reads for one number (D)
_NAME_COLUMN = 33  # LIST_GLOBAL's name column (help page's layout)
_V = TypeVar("_V")


def file_name(name: str) -> str:
    """The program of the store an OPEN names: a location prefix (RAM:, SD:, USB1:, FLASH:)
    and a .TXT or .BAS extension are dropped (D: the store is the one file system and its
    names carry no extension), so the pages' "ram:test.txt" is TEST."""
    name = name.upper()
    if ":" in name and name.split(":", 1)[0] in ("RAM", "SD", "USB1", "USB2", "FLASH"):
        name = name.split(":", 1)[1]
    for extension in (".TXT", ".BAS"):
        if name.endswith(extension):
            name = name[:-len(extension)]
    return name


def _zero(value: Value) -> Value:
    """What RESET leaves in a variable: "" for a string, 0 of the same type (a FLOAT stays
    FLOAT: printformat.Real) for a number."""
    if isinstance(value, str):
        return ""
    return Real(0.0) if isinstance(value, Real) else 0.0


class Definitions(dict[str, _V]):
    """The GLOBAL (or CONSTANT) names: a dict that numbers each name the first time it is
    defined, in one count shared by both kinds (LIST_GLOBAL's order and offsets)."""

    def __init__(self, prefix: str, order: dict[str, int]) -> None:
        super().__init__()
        self.prefix, self.order = prefix, order

    def __setitem__(self, name: str, value: _V) -> None:
        self.order.setdefault(f"{self.prefix} {name}", len(self.order))
        super().__setitem__(name, value)


class Housekeeping:
    """cmd_ handlers and data functions; the attributes are the runtime's own."""

    machine: TrioMachine
    programs: ProgramStore
    output: Callable[[str], None]
    tasks: dict[int, Task]
    compiled: dict[str, list[Step]]
    broken: set[str]
    selected: str | None
    constants: dict[str, Value]
    globals: dict[str, int]
    files: dict[int, list[int]]
    sources: dict[int, list[int]]  # OPEN ... FOR INPUT: every character, last first
    writing: dict[int, tuple[str, str]]  # OPEN ... FOR OUTPUT: channel -> file, partial line
    fifo_files: FifoFiles  # OPEN ... FOR FIFO_WRITE (fifos.py)
    crc: CrcSetup | None
    defined: dict[str, int]  # "C name" / "G name" -> when it was first defined
    spellings: dict[str, str]  # ... and its name as first typed

    # ---- programs ----------------------------------------------------------------------
    def _names(self, args: list[Value]) -> tuple[str, str]:
        if len(args) != 2 or not all(isinstance(a, str) for a in args):
            raise TrioError("Syntax error")
        return str(args[0]).upper(), str(args[1]).upper()

    def _idle(self, name: str) -> None:
        if any(t.ctx.program == name for t in self.tasks.values()):
            raise TrioError("Program is running")

    def cmd_copy(self, args: list[Value]) -> None:
        """COPY "program" "newprogram": a copy under a new name, of the same type; a name
        already in use is refused (D), the original is untouched."""
        source, target = self._names(args)
        info = self.programs.get(source)
        if self.programs.exists(target):
            raise TrioError("Program already exists")
        self.programs.create(target, info.type)
        for number, line in enumerate(self.programs.lines[info.name]):
            try:
                self.programs.edit(target, number, "R", line)
            except TrioError:
                self.programs.delete(target)  # out of memory: no half copy (D)
                raise

    def cmd_rename(self, args: list[Value]) -> None:
        """RENAME oldname newname: the program keeps its lines, type and run settings under
        the new name; a running program or a name in use is refused (D)."""
        source, target = self._names(args)
        info = self.programs.get(source)
        self._idle(info.name)
        if self.programs.exists(target):
            raise TrioError("Program already exists")
        autorun, process = info.autorun, info.process
        self.cmd_copy([info.name, target])
        if autorun:
            self.programs.set_runtype(target, True, process)
        self.programs.delete(info.name)
        self.compiled.pop(info.name, None)
        self.broken.discard(info.name)
        if self.selected == info.name:
            self.selected = target.upper()

    # ---- variables ---------------------------------------------------------------------
    def ctx_clear(self, args: list[Value], ctx: ProcessContext) -> None:
        """CLEAR: every VR to 0 and the local variables of the process that runs it (help
        page CLEAR); TABLE is not a global variable and stays (I)."""
        for index in range(VR_COUNT):
            if self.machine.vr_read(index) != 0:
                self.machine.vr_write(index, 0.0)
        self.ctx_reset(args, ctx)

    def ctx_reset(self, args: list[Value], ctx: ProcessContext) -> None:
        """RESET: the local named variables of this process to 0 (help page RESET); a
        DIM'd name keeps its type, numbers become 0 and strings empty (D)."""
        for name, value in ctx.variables.items():
            ctx.variables[name] = _zero(value)
        for array in ctx.arrays.values():
            for k, value in enumerate(array):
                array[k] = _zero(value)

    def cmd_list_global(self, args: list[Value]) -> None:
        """LIST_GLOBAL [offset[, length]]: the GLOBAL and CONSTANT definitions numbered in
        the order they were made, from offset, length of them (-1 or none: all); the
        GLOBALs' table, then the CONSTANTs' (help page's example)."""
        offset = _whole(args[0]) if args else 0
        length = _whole(args[1]) if len(args) > 1 else -1
        if offset < 0 or length < -1:
            raise TrioError("Parameter out of range")
        live = [key for key in sorted(self.defined, key=self.defined.__getitem__)
                if (key[2:] in self.globals if key[0] == "G" else key[2:] in self.constants)]
        chosen = live[offset:] if length == -1 else live[offset:offset + length]
        globals_ = [key[2:] for key in chosen if key[0] == "G"]
        constants = [key[2:] for key in chosen if key[0] == "C"]
        lines: list[str] = []
        if globals_:
            lines += [f"{'Global':<{_NAME_COLUMN}}VR", f"{'-' * 16:<{_NAME_COLUMN}}----"]
            lines += [f"{self._typed('G', name):<{_NAME_COLUMN}}{self.globals[name]}"
                      for name in globals_]
        if constants:
            lines += [f"{'Constant':<{_NAME_COLUMN}}Value",
                      f"{'-' * 16:<{_NAME_COLUMN}}-------"]
            for name in constants:
                value = self.constants[name]
                shown = f'"{value}"' if isinstance(value, str) else f"{value:.5f}"
                lines.append(f"{self._typed('C', name):<{_NAME_COLUMN}}{shown}")
        for line in lines:
            self.output(line + "\r\n")

    def _typed(self, kind: str, name: str) -> str:
        """A definition's name as it was first typed (the page lists `conveyor` so); the
        names match whatever their case, so a later definition keeps that first spelling."""
        return self.spellings.get(f"{kind} {name}") or name

    def channel_word(self, name: str, args: tuple[Expr, ...], ctx: ProcessContext,
                     interp: Interpreter) -> float:
        """CHANNEL_READ / CHANNEL_WRITE (channelwords.py): their buffers go by reference."""
        word = channel_read if name == "CHANNEL_READ" else channel_write
        return word(interp, args, ctx)

    # ---- files written by a program ---------------------------------------------------
    def open_output(self, channel: int, name: str, append: bool) -> None:
        """OPEN #n AS "name" FOR OUTPUT[(mode)]: the program of that name, created as a
        text file (type 3) when missing, else cleared; FOR APPEND: it must exist, and what
        is printed goes after its lines (help page OPEN). Every mode of OUTPUT writes the
        store (D: the emulator has one file system, no RAM or SD card apart)."""
        name = file_name(name)
        if append:
            name = self.programs.get(name).name
        elif self.programs.exists(name):
            name = self.programs.get(name).name
            self._idle(name)
            self.programs.clear(name)
            self.compiled.pop(name, None)
        else:
            self.programs.create(name, 3)
        self.writing[channel] = (name, "")

    def write_file(self, channel: int, text: str) -> bool:
        """PRINT #n to a file opened for output: each finished line (CR LF or LF) becomes
        a line of the file at once; the rest waits for its end or CLOSE. False: the
        channel is no such file (its text goes to the terminal)."""
        if self.fifo_files.write(channel, text):  # a FIFO (fifos.py)
            return True
        if channel not in self.writing:
            return False
        name, pending = self.writing[channel]
        if not self.programs.exists(name):  # DEL or RENAME from a host while open (D)
            raise TrioError("Program not found")
        if len(pending) + len(text) > MAX_PROGRAM_BYTES:  # a line no file could hold
            raise TrioError("Program too large")
        if "\n" not in text:  # no line ends: the unfinished line only grows
            self.writing[channel] = (name, pending + text)
            return True
        lines = (pending + text).replace("\r\n", "\n").split("\n")
        for line in lines[:-1]:
            self.programs.edit(name, len(self.programs.lines[name]), "R", line)
        self.writing[channel] = (name, lines[-1])
        self.compiled.pop(name, None)
        return True

    def close_file(self, channel: int) -> None:
        """CLOSE #n: an unfinished last line is written."""
        name, pending = self.writing.pop(channel, ("", ""))
        if pending and self.programs.exists(name):  # gone (DEL, RENAME): nothing to keep
            self.programs.edit(name, len(self.programs.lines[name]), "R", pending)

    def cmd_seek(self, args: list[Value]) -> None:
        """SEEK #n, from, position: the next character read is `position` bytes from the
        start (from 0) or from where reading is (from 1) of a file open FOR INPUT (help
        page SEEK). Outside the file: 'Parameter out of range' (D), nothing moves."""
        channel, origin, offset = (_whole(a) for a in args)
        if channel not in self.sources:
            raise TrioError("Channel not open")
        whole, waiting = self.sources[channel], self.files[channel]
        at = (len(whole) - len(waiting) if origin == 1 else 0) + offset
        if origin not in (0, 1) or not 0 <= at <= len(whole):
            raise TrioError("Parameter out of range")
        waiting[:] = whole[:len(whole) - at]

    # ---- TABLE -------------------------------------------------------------------------
    def cmd_tablevalues(self, args: list[Value]) -> None:
        """TABLEVALUES(first, last[, format]): the values first..last on one line, comma
        separated, four decimals; format 1 compresses runs (help page's example)."""
        if len(args) not in (2, 3):
            raise TrioError("Syntax error")
        first, last = _whole(args[0]), _whole(args[1])
        compressed = _whole(args[2]) if len(args) == 3 else 0
        if compressed not in (0, 1) or not 0 <= first <= last < TABLE_SIZE \
                or last - first >= TABLEVALUES_LIMIT:
            raise TrioError("Parameter out of range")
        values = [self.machine.table_read(k) for k in range(first, last + 1)]
        self.output(table_values(values, compressed == 1) + "\r\n")

    # ---- data functions ----------------------------------------------------------------
    def cmd_crc16(self, args: list[Value]) -> None:
        self.data_function("CRC16", args)

    def data_function(self, name: str, args: list[Value]) -> float:
        numbers = [number_arg(a) for a in args]
        if name == "IEEE_IN":
            return ieee_in(numbers)
        if name == "IEEE_OUT":
            return ieee_out(numbers)
        if name == "STRTOD":
            return self.strtod(numbers)
        return self.crc16(numbers)

    def crc16(self, args: list[float]) -> float:
        """CRC16(0, poly ...) sets the polynomial and returns -1; CRC16(1|2, source, start,
        end, initial) computes over TABLE (source 0) or VR (1) values start..end, each taken
        as a byte (its low 8 bits, D); not initialised: 0 (help page CRC16)."""
        if not args:
            raise TrioError("Syntax error")
        mode = args[0]
        if mode == 0:
            self.crc = crc_setup(args[1:])
            return -1.0
        if mode not in (1, 2):
            raise TrioError("Parameter out of range")
        if len(args) != 5:
            raise TrioError("Syntax error")
        source, start, end, initial = (_whole(a) for a in args[1:])
        size = TABLE_SIZE if source == 0 else VR_COUNT
        if source not in (0, 1) or not 0 <= start <= end < size or initial < 0:
            raise TrioError("Parameter out of range")
        if self.crc is None:
            return 0.0
        read = self.machine.table_read if source == 0 else self.machine.vr_read
        data = [int(read(k)) & 0xFF for k in range(start, end + 1)]
        compute = crc_legacy if mode == 1 else crc_direct
        return float(compute(self.crc, data, initial))

    def strtod(self, args: list[float]) -> float:
        """STRTOD(format, ...): a number read from the VR array (one character a VR) or
        from an I/O channel's waiting characters, which it takes (help page STRTOD)."""
        if not args:
            raise TrioError("Syntax error")
        fmt = _whole(args[0])
        if not 0 <= fmt <= 7:
            raise TrioError("Parameter out of range")
        from_channel, number_format = fmt & 1, fmt >> 1
        if not from_channel:
            if number_format == 3 or len(args) != 3:
                raise TrioError("Syntax error")
            start, vr_index = _whole(args[1]), _whole(args[2])
            if not 0 <= start < VR_COUNT or not 0 <= vr_index < VR_COUNT:
                raise TrioError("Parameter out of range")
            text = self._vr_text(start)
            value, used = read_number(text, number_format)
            self.machine.vr_write(vr_index, float(start + used))
            return value
        if len(args) != (5 if number_format == 3 else 4):
            raise TrioError("Syntax error")
        channel = _whole(args[1])
        targets = [_whole(a) for a in args[2:]]
        if not 0 <= channel <= 255 or not all(0 <= t < VR_COUNT - 26 for t in targets):
            raise TrioError("Parameter out of range")
        if channel >= FILE_CHANNELS and channel not in self.files:
            raise TrioError("Channel not open")
        waiting = self.files.get(channel, [])  # (its next character last)
        text = "".join(chr(c) for c in reversed(waiting[-STRTOD_LIMIT:]))
        if number_format == 3:
            codes, used = letter_codes(text)
        else:
            value, used = read_number(text, number_format)
        terminator = float(ord(text[used])) if used < len(text) else 0.0
        taken = used + (1 if used < len(text) else 0)  # the terminator is read too (I)
        del waiting[len(waiting) - taken:]
        self.machine.vr_write(targets[0], float(used))
        if number_format != 3:
            self.machine.vr_write(targets[1], terminator)
            return value
        self.machine.vr_write(targets[1], terminator)
        for letter, code_value in codes.items():
            self.machine.vr_write(targets[2] + letter, code_value)
        return float(sum(1 << letter for letter in codes))

    def _vr_text(self, start: int) -> str:
        out: list[str] = []
        for index in range(start, min(start + STRTOD_LIMIT, VR_COUNT)):
            code = int(self.machine.vr_read(index))
            if not 0 < code < 256:
                break
            out.append(chr(code))
        return "".join(out)




def _whole(value: Value) -> int:
    number = number_arg(value)
    if number != int(number):
        raise TrioError("Parameter out of range")
    return int(number)
