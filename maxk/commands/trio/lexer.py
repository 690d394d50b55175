"""TrioBASIC tokens: one program line (or command line) at a time.

Names are upper-cased (TrioBASIC is case-insensitive: atrio sends ``?version``);
string literals keep their case and double a quote to include one (``"a""b"``). A
``'`` outside a string starts a comment that runs to the end of the line, so
``PWM_CYCLE=1000' sets 20khz`` is a statement and a comment.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


class TrioError(Exception):
    """A TrioBASIC error: the text after ``] - `` in the controller's error line."""

    def __init__(self, message: str, line: int | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.line = line  # program line number (1-based) when known


class Thrown(TrioError):
    """THROW_ERROR(message): the program's own error text, RUN_ERROR 268 (THROW_ERROR's
    page; the RUN_ERROR page lists 268 as the user's error string)."""

    CODE = 268


class Tok(Enum):
    NUMBER = "number"
    STRING = "string"
    NAME = "name"
    OP = "op"
    END = "end"


@dataclass(frozen=True)
class Token:
    kind: Tok
    text: str  # upper-cased for names; the operator; the string's contents
    value: float = 0.0
    column: int = 0


_DIGITS = frozenset("0123456789")
# Blanks between tokens: a CR (a line from a Windows file or a terminal's CR LF) and a
# form feed are blanks like space and tab (D: Motion Perfect files are CR LF).
_BLANK = " \t\r\f\v"
_LETTERS = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_")
_TWO_CHAR_OPS = ("<<", ">>", "<=", ">=", "<>")
_ONE_CHAR_OPS = "+-*/^=<>(),;:?#[]"


def tokenize(line: str) -> list[Token]:
    """Split a line into tokens, ending with an END token."""
    tokens: list[Token] = []
    i, n = 0, len(line)
    while i < n:
        c = line[i]
        if c in _BLANK:
            i += 1
        elif c == "'":
            break
        elif c == '"':
            j, text = i + 1, []
            while True:
                if j >= n:
                    raise TrioError("Syntax error")  # unterminated string
                if line[j] == '"':
                    if j + 1 < n and line[j + 1] == '"':
                        text.append('"')
                        j += 2
                        continue
                    break
                text.append(line[j])
                j += 1
            tokens.append(Token(Tok.STRING, "".join(text), column=i))
            i = j + 1
        elif c in _DIGITS or (c == "." and i + 1 < n and line[i + 1] in _DIGITS):
            j = i
            while j < n and line[j] in _DIGITS:
                j += 1
            if j < n and line[j] == ".":
                j += 1
                while j < n and line[j] in _DIGITS:
                    j += 1
            if j < n and line[j] in "eE" and j + 1 < n and (
                line[j + 1] in _DIGITS
                or (line[j + 1] in "+-" and j + 2 < n and line[j + 2] in _DIGITS)
            ):
                j += 2
                while j < n and line[j] in _DIGITS:
                    j += 1
            value = float(line[i:j])
            if value == float("inf"):
                raise TrioError("Arithmetic error")  # a literal beyond the float range (D)
            tokens.append(Token(Tok.NUMBER, line[i:j], value, column=i))
            i = j
        elif c == "$":
            j = i + 1
            while j < n and line[j] in "0123456789abcdefABCDEF":
                j += 1
            if j == i + 1:
                raise TrioError("Syntax error")
            if j - i > 17:
                raise TrioError("Arithmetic error")  # more than 64 bits of hex (D)
            tokens.append(Token(Tok.NUMBER, line[i:j], float(int(line[i + 1:j], 16)), column=i))
            i = j
        elif c in _LETTERS:
            j = i
            while j < n and (line[j] in _LETTERS or line[j] in _DIGITS or line[j] == "$"):
                j += 1
            word = line[i:j].upper()
            if word == "REM":
                break
            tokens.append(Token(Tok.NAME, word, column=i))
            i = j
        elif c == "." and i + 1 < n and line[i + 1] in _LETTERS and tokens and \
                tokens[-1].column + len(tokens[-1].text) == i and \
                (tokens[-1].kind is Tok.NAME or tokens[-1].text == ")"):
            tokens.append(Token(Tok.OP, ".", column=i))  # value.name: the bit operator
            i += 1  # with its bit number in a variable (MOTION_ERROR.a, its page)
        elif line.startswith(_TWO_CHAR_OPS, i):
            tokens.append(Token(Tok.OP, line[i:i + 2], column=i))
            i += 2
        elif c in _ONE_CHAR_OPS:
            tokens.append(Token(Tok.OP, c, column=i))
            i += 1
        else:
            raise TrioError("Syntax error")
    tokens.append(Token(Tok.END, "", column=n))
    return tokens
