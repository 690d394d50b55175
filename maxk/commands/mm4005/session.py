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

from maxk.commands.line_session import LineSession
from maxk.personalities.mm4005 import ErrorRegister, MM4005Error
from maxk.personalities.mm4005.errors import FOLLOWING_ERROR, UNKNOWN_MESSAGE

from .lexer import MAX_LINE, parse_line
from .machine import MM4005Machine
from .spec import CommandSpec, Context
from .table import COMMANDS

CR: Final = b"\r"


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
        if self.context.machine.take_errors():  # a following error since the last line
            self.context.errors.record(FOLLOWING_ERROR)
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


class MM4005Session(LineSession):
    """The door-facing session: ``feed`` host bytes in any split, ``read`` the replies."""

    terminators = b"\r\n"  # CR, LF or CR LF (the empty line between is ignored)
    line_limit = MAX_LINE  # manual 3.3.1.3: 110 characters

    def __init__(self, machine: MM4005Machine, interpreter: Interpreter | None = None) -> None:
        super().__init__()
        self.interpreter = interpreter or Interpreter(machine)

    def line_too_long(self) -> None:
        """Longer than 110 characters: refused whole with A, as parse_line does."""
        self.interpreter.errors.record(UNKNOWN_MESSAGE)

    def run_line(self, text: str) -> None:
        if not text.strip(" \t"):
            return
        for reply in self.interpreter.execute_line(text):
            self.reply(reply.encode("latin-1") + CR)
