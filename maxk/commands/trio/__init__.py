"""TrioBASIC for the Trio MC405: lexer, keyword table, interpreter and command line.

The language turns the bytes atrio (or a person over telnet) sends into actions on a
:class:`TrioMachine` and replies back; the PWM firmware it drives lives in
``maxk.personalities.trio``.
"""

from .fake import FakeTrioMachine
from .interpreter import Interpreter, ProcessContext, format_number
from .keywords import KEYWORDS, Keyword, Kind, lookup
from .lexer import TrioError, tokenize
from .machine import TrioMachine
from .parser import parse_expression, parse_line
from .programs import ProgramStore, program_checksum
from .session import TrioCommandLine
from .tasks import Task, compile_program

__all__ = [
    "KEYWORDS",
    "FakeTrioMachine",
    "Interpreter",
    "Keyword",
    "Kind",
    "ProcessContext",
    "ProgramStore",
    "Task",
    "TrioCommandLine",
    "TrioError",
    "TrioMachine",
    "compile_program",
    "format_number",
    "lookup",
    "parse_expression",
    "parse_line",
    "program_checksum",
    "tokenize",
]
