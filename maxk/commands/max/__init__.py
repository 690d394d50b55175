"""The MAX command language: lexer, command table, handlers and interpreter."""

from maxk.commands.max.interpreter import Interpreter
from maxk.commands.max.lexer import Lexer, LexError, ParsedCommand
from maxk.commands.max.table import COMMANDS, CommandSpec, lookup

__all__ = ["COMMANDS", "CommandSpec", "Interpreter", "LexError", "Lexer", "ParsedCommand",
           "lookup"]
