"""The MM4005 on the wire: CR-terminated lines in, CR-terminated replies out.

Framing: a host line ends at CR, LF or CR LF (the EPICS drivers end with CR, the EPICS
trajectory scan with CR CR, StreamDevice and Tcl hosts with LF): CR and LF each end a
line and the empty line between CR and LF is ignored, as every empty line is (D: the
manual's "terminator" accepts either, I). Replies are the reply text and one CR, never
LF (the model 1 driver reads a stray LF into the next reply and breaks).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Final

from maxk.personalities.mm4005 import ErrorRegister, MM4005Error
from maxk.personalities.mm4005.errors import UNKNOWN_MESSAGE

from .lexer import MAX_LINE, parse_line
from .machine import MM4005Machine
from .spec import CommandSpec, Context
from .table import COMMANDS

CR: Final = b"\r"
LF: Final = b"\n"


class Interpreter:
    """Runs command lines against a machine and keeps the error register."""

    def __init__(self, machine: MM4005Machine,
                 table: Mapping[str, CommandSpec] = COMMANDS) -> None:
        self.context = Context(machine)
        self.table = table

    @property
    def errors(self) -> ErrorRegister:
        return self.context.errors

    def execute_line(self, line: str) -> list[str]:
        """Replies of one line (without CR). A malformed command rejects the whole line;
        a refused command stops the line there, the ones before it stay done (D)."""
        try:
            commands = parse_line(line, self.table, self.context.machine.axis_count)
        except MM4005Error as error:
            self.context.errors.record(error.code)
            return []
        replies: list[str] = []
        for command in commands:
            try:
                replies.extend(command.spec.handler(self.context, command))
            except MM4005Error as error:
                self.context.errors.record(error.code)
                break
        return replies


class MM4005Session:
    """The door-facing session: ``feed`` host bytes in any split, ``read`` the replies."""

    def __init__(self, machine: MM4005Machine, interpreter: Interpreter | None = None) -> None:
        self.interpreter = interpreter or Interpreter(machine)
        self._line = bytearray()
        self._overflow = False
        self._out = bytearray()
        self.closed = False

    def close(self) -> None:
        """The host went away: the MM4005 never speaks unasked, so only forget its line."""
        self.closed = True
        self.discard_partial_line()

    def discard_partial_line(self) -> None:
        """A reset loses a line half received."""
        self._line.clear()
        self._overflow = False

    def feed(self, data: bytes) -> None:
        for byte in data:
            if byte == CR[0] or byte == LF[0]:
                self._end_line()
            else:
                if len(self._line) <= MAX_LINE:
                    self._line.append(byte)
                else:
                    self._overflow = True  # bounded memory; the line is refused anyway

    def read(self) -> bytes:
        out, self._out = bytes(self._out), bytearray()
        return out

    def _end_line(self) -> None:
        text = self._line.decode("latin-1")
        self._line.clear()
        if self._overflow:  # longer than 110 characters: refused like parse_line does
            self._overflow = False
            self.interpreter.errors.record(UNKNOWN_MESSAGE)
            return
        if not text.strip(" \t"):
            return
        for reply in self.interpreter.execute_line(text):
            self._out += reply.encode("latin-1") + CR
