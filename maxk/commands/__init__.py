"""The MAX command language: lexer, command table, handlers and interpreter."""

from .interpreter import Interpreter
from .lexer import Lexer, LexError, ParsedCommand
from .table import COMMANDS, CommandSpec, lookup

__all__ = ["COMMANDS", "CommandSpec", "Interpreter", "LexError", "Lexer", "ParsedCommand",
           "lookup"]
