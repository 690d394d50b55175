"""Incremental lexer: bytes in, commands out, greedy by known mnemonic.

Hosts run operand-less commands together (`AXMA1000;GDID`, `AXHEHM0;ID`), so commands
are split by the mnemonics the table knows, not by separators. An operand ends at a
space, tab, CR, LF or `;`, or at the first character that cannot belong to it.

The lexer is a state machine over the byte stream: it emits a command only once no
further byte could change it (`LP` might still become `LPE`, `MA10` might become
`MA100`), so a command split across writes at any byte gives the same result as one
write. Garbage is reported once, as soon as it is known to be garbage, and skipped up
to the next separator; the rest of the stream still runs.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from maxk.commands.max.table import COMMANDS, CommandSpec, Operand

CONTROL_CHARACTERS = frozenset(chr(c) for c in range(0x20)) - frozenset("\t\r\n\0") | {"\x7f"}
"""Control characters the older boards' hosts write (^X 0x18 after an error, ^D 0x04): each
stands on its own, ends whatever command precedes it and is never part of a mnemonic."""
CLEAR_ERROR = "\x18"  # ^X: clears the command error (VME8 driver's CMD_CLEAR)
SEPARATORS = frozenset(" \t\r\n;\0") | CONTROL_CHARACTERS
MAX_OPERAND_LENGTH = 256
"""An operand longer than this is malformed; the lexer stops buffering it."""

_M3 = {m for m in COMMANDS if len(m) == 3}
_M2 = {m for m in COMMANDS if len(m) == 2}
_PREFIX_OF_M3 = {m[:2] for m in _M3}
_PREFIXES = {m[:k] for m in COMMANDS for k in range(1, len(m) + 1)}
_NUMBER_RUN = re.compile(r"[-+0-9.,]*")
_BLANKS = re.compile(r"[ \t]*")
_NUMBER_START = frozenset("+-0123456789.,")
_HOLD = "hold"
_SPLITS: dict[str, tuple[tuple[ParsedCommand | LexError | ControlCharacter, ...],
                         str, bool, str | None, int]] = {}
"""Lines split from a clean start (the items are immutable: shared between lexers)."""
_CACHED_LINES = 4096
_CACHED_LENGTH = 512


def _run_end(pattern: re.Pattern[str], buf: str, start: int) -> int:
    """Where a run of `pattern` (which may be empty, so it always matches) ends."""
    match = pattern.match(buf, start)
    assert match is not None
    return match.end()


def _mnemonic_at(buf: str, i: int, n: int) -> str | None:
    """The mnemonic starting at i (greedy), None if none can, _HOLD if more input decides."""
    rem = n - i
    head3 = buf[i : i + 3].upper()
    if rem >= 3 and head3 in _M3:
        return head3
    if rem >= 2 and head3[:2] in _M2:
        if rem == 2 and head3 in _PREFIX_OF_M3:
            return _HOLD  # could still become a three-letter mnemonic
        return head3[:2]
    if rem < 3 and head3 in _PREFIXES:
        return _HOLD
    return None
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)\Z")
_HEX_RUN = re.compile(r"[0-9A-Fa-f]*")
_HEX_LIST_RUN = re.compile(r"[0-9A-Fa-f,]*")
_HEX_SLOT = re.compile(r"[0-9A-Fa-f]{1,8}\Z")
_TASK_INDEX = re.compile(r"\[(\d{1,3})\]")


@dataclass(frozen=True, slots=True)
class ParsedCommand:
    """One command as the host wrote it: operand slots are raw text (None = empty slot)."""

    spec: CommandSpec
    slots: tuple[str | None, ...]
    query: bool
    text: str
    task: int | None = None  # vector commands: the [n] task index, if given
    form: str = ""  # vector commands: VP's A/R letter, VO's '='

    @property
    def mnemonic(self) -> str:
        return self.spec.mnemonic


@dataclass(frozen=True, slots=True)
class ControlCharacter:
    """A control character the host wrote (`^X`); the interpreter acts on it at once."""

    char: str

    @property
    def text(self) -> str:
        return f"^{chr(ord(self.char) + 64)}" if self.char != "\x7f" else "DEL"


@dataclass(frozen=True, slots=True)
class LexError:
    """Text that is not a command; the interpreter turns it into a command error."""

    text: str
    reason: str


class Lexer:
    """Feed it text as it arrives; it returns what is complete and keeps the rest."""

    __slots__ = ("_buf", "_skipping", "_bad", "_bad_count")

    def __init__(self) -> None:
        self._buf = ""
        self._skipping = False
        self._bad: str | None = None  # an unknown token being skipped, reported at its end
        self._bad_count = 0

    @property
    def pending(self) -> str:
        """Text held back because more bytes could still change its meaning."""
        return self._buf

    def reset(self) -> None:
        self._buf = ""
        self._skipping = False
        self._bad = None
        self._bad_count = 0

    def _report_bad(self, out: list[ParsedCommand | LexError | ControlCharacter]) -> None:
        bad = self._bad or ""
        shown = bad if self._bad_count <= len(bad) else bad + "..."
        out.append(LexError(shown, f"unknown command {shown!r}"))
        self._bad = None

    def feed(self, data: str | bytes) -> list[ParsedCommand | LexError | ControlCharacter]:
        if isinstance(data, bytes | bytearray):
            data = data.decode("latin-1")
        buf = self._buf + data if self._buf else data
        if self._skipping or self._bad is not None or len(buf) > _CACHED_LENGTH:
            return self._split(buf)
        # Hosts send the same lines over and over (polls, moves): a line's split is a
        # function of the text alone when the lexer starts clean, so it is kept.
        known = _SPLITS.get(buf)
        if known is None:
            out = self._split(buf)
            if len(_SPLITS) >= _CACHED_LINES:
                _SPLITS.clear()
            _SPLITS[buf] = self._state(out)
            return out
        items, self._buf, self._skipping, self._bad, self._bad_count = known
        return list(items)

    def _state(self, out: list[ParsedCommand | LexError | ControlCharacter]) -> tuple[
            tuple[ParsedCommand | LexError | ControlCharacter, ...], str, bool, str | None,
            int]:
        """A split and the state it leaves, to remember. (A method of its own: in `feed`
        mypy has narrowed `_bad` to None, which a compiled build would enforce.)"""
        return tuple(out), self._buf, self._skipping, self._bad, self._bad_count

    def _split(self, buf: str) -> list[ParsedCommand | LexError | ControlCharacter]:
        """The state machine proper, over the held text and what arrived."""
        out: list[ParsedCommand | LexError | ControlCharacter] = []
        n = len(buf)
        i = 0
        while i < n:
            c = buf[i]
            if self._skipping:
                if c in SEPARATORS:
                    self._skipping = False
                    if self._bad is not None:
                        self._report_bad(out)
                    if c in CONTROL_CHARACTERS:
                        out.append(ControlCharacter(c))
                elif self._bad is not None:
                    self._bad_count += 1
                    if len(self._bad) < 32:
                        self._bad += c
                    if self._bad_count >= MAX_OPERAND_LENGTH:
                        self._report_bad(out)  # do not wait forever for a separator
                i += 1
                continue
            if c in SEPARATORS:
                if c in CONTROL_CHARACTERS:
                    out.append(ControlCharacter(c))
                i += 1
                continue
            # ---- mnemonic, greedy: three characters before two ----------------------
            mnemonic = _mnemonic_at(buf, i, n)
            if mnemonic is _HOLD:
                break  # a partial mnemonic: wait for more
            if mnemonic is None:
                # Unknown: skip to the next separator, then report the whole token.
                self._skipping = True
                self._bad = ""
                self._bad_count = 0
                continue
            spec = COMMANDS[mnemonic]
            j = i + len(mnemonic)
            # ---- operand --------------------------------------------------------------
            kind = spec.operand
            if kind is Operand.NONE:
                out.append(ParsedCommand(spec, (), False, buf[i:j]))
                i = j
                continue
            if j >= n:
                break  # the operand (or a query mark) may still come
            if spec.query and buf[j] == "?":
                out.append(ParsedCommand(spec, (), True, buf[i : j + 1]))
                i = j + 1
                continue
            if kind is Operand.NUMBER:
                blanks = 0
                if not spec.operand_optional and buf[j] in " \t":
                    # `LP 10,20,30` (evidence 1.4): blanks may stand before an operand.
                    k = _run_end(_BLANKS, buf, j)
                    if k >= n:
                        break
                    if buf[k] in _NUMBER_START:
                        blanks = k - j
                        j = k
                end = _run_end(_NUMBER_RUN, buf, j)
                if end - j > MAX_OPERAND_LENGTH:
                    out.append(LexError(buf[i : i + 16] + "...", f"{mnemonic}: operand too long"))
                    self._skipping = True
                    i = end
                    continue
                if end >= n:
                    break  # more digits may follow
                run = buf[j:end]
                if run and buf[end] not in SEPARATORS:
                    # What follows the number must start a command (`MA1000GO`);
                    # anything else makes the whole token malformed (`MA1e5`, `VL5000abc`).
                    follower = _mnemonic_at(buf, end, n)
                    if follower is _HOLD:
                        break
                    if follower is None:
                        out.append(LexError(buf[i : end + 1],
                                            f"{mnemonic}: malformed operand {buf[j : end + 1]!r}"))
                        self._skipping = True
                        i = end
                        continue
                text = buf[i:end]
                i = end
                if not run:
                    if spec.operand_optional:
                        out.append(ParsedCommand(spec, (), False, text))
                    else:
                        out.append(LexError(text.rstrip(), f"{mnemonic} needs an operand"))
                        # `VLabc` is one bad token, not two; `MA RP` runs RP.
                        self._skipping = blanks == 0 and buf[j] not in SEPARATORS
                    continue
                slots = tuple(s if s else None for s in run.split(","))
                bad_slot = next((s for s in slots if s is not None and not _NUMBER.match(s)),
                                None)
                if bad_slot is not None:
                    out.append(LexError(text, f"{mnemonic}: malformed number {bad_slot!r}"))
                    continue
                out.append(ParsedCommand(spec, slots, False, text))
                continue
            if kind is Operand.HEX:
                end = _run_end(_HEX_RUN, buf, j)
                if end >= n and end - j <= 8:
                    break  # more hex digits may follow
                text = buf[i:end]
                if end == j or end - j > 8 or (buf[end] not in SEPARATORS
                                               and _mnemonic_at(buf, end, n) is None):
                    out.append(LexError(buf[i : end + 1],
                                        f"{mnemonic} needs a hexadecimal word"))
                    self._skipping = True
                    i = end
                    continue
                if buf[end] not in SEPARATORS and _mnemonic_at(buf, end, n) is _HOLD:
                    break
                out.append(ParsedCommand(spec, (buf[j:end],), False, text))
                i = end
                continue
            if kind is Operand.VECTOR:
                parsed = _vector(spec, buf, i, j, n)
                if parsed is None:
                    break  # more bytes decide
                item, i, skip = parsed
                out.append(item)
                self._skipping = skip
                continue
            if kind is Operand.PATTERN:
                k = j
                while k < n and k - j < 4 and buf[k].upper() in spec.letters:
                    k += 1
                if k >= n and k - j < 4:
                    break  # the rest of the pattern may follow
                text = buf[i:k]
                if k - j < 4:
                    out.append(LexError(buf[i : k + 1],
                                        f"{mnemonic} needs four of {'/'.join(spec.letters)}"))
                    self._skipping = True
                    i = k
                    continue
                out.append(ParsedCommand(spec, (buf[j:k].upper(),), False, text))
                i = k
                continue
            # Operand.LETTER: one letter per axis, comma separated in AA/AM.
            letters = spec.letters
            k = j
            slots_list: list[str | None] = []
            complete = True
            while True:
                if k < n and buf[k].upper() in letters:
                    slots_list.append(buf[k].upper())
                    k += 1
                else:
                    slots_list.append(None)
                if k >= n:
                    complete = False  # a comma and another slot may follow
                    break
                if buf[k] != ",":
                    break
                k += 1
                if k - j > MAX_OPERAND_LENGTH:
                    break
            if not complete:
                if k - j > MAX_OPERAND_LENGTH:
                    out.append(LexError(buf[i : i + 16] + "...", f"{mnemonic}: operand too long"))
                    self._skipping = True
                    i = k
                    continue
                break
            text = buf[i:k]
            i = k
            if all(s is None for s in slots_list):
                choices = "/".join(letters) + ("/?" if spec.query else "")
                out.append(LexError(text or mnemonic, f"{mnemonic} needs one of {choices}"))
                self._skipping = True
                continue
            out.append(ParsedCommand(spec, tuple(slots_list), False, text))
        self._buf = buf[i:] if i < n else ""
        if len(self._buf) > MAX_OPERAND_LENGTH + 8:
            # Defensive bound: nothing legitimate is held this long.
            out.append(LexError(self._buf[:16] + "...", "command too long"))
            self._buf = ""
            self._skipping = True
        return out



def _vector(spec: CommandSpec, buf: str, i: int, j: int, n: int
            ) -> tuple[ParsedCommand | LexError, int, bool] | None:
    """A vector-task command from j on: `[n]`, then VP's A/R or VO's '=', then a comma
    list (hex for VIO). None while more bytes could change it; else (item, next index,
    skip to the next separator)."""
    mnemonic = spec.mnemonic
    k = j
    task = None
    if k >= n:
        return None  # '[', a form letter or an operand may follow
    if buf[k] == "[":
        match = _TASK_INDEX.match(buf, k)
        if match is None:
            if "]" not in buf[k : k + 5] and n - k < 5:
                return None
            return LexError(buf[i : k + 1], f"{mnemonic}: malformed task index"), k, True
        task = int(match.group(1))
        k = match.end()
    form = ""
    if k < n and spec.letters and buf[k].upper() in spec.letters:
        form = buf[k].upper()
        k += 1
    elif k < n and spec.assign_form and buf[k] == "=":
        form = "="
        k += 1
    if spec.arity == 0:
        if k >= n and task is None:
            return None
        return ParsedCommand(spec, (), False, buf[i:k], task, form), k, False
    hex_operand = spec.hex_operands
    end = _run_end(_HEX_LIST_RUN if hex_operand else _NUMBER_RUN, buf, k)
    if end - k > MAX_OPERAND_LENGTH:
        return LexError(buf[i : i + 16] + "...", f"{mnemonic}: operand too long"), end, True
    if end >= n:
        return None  # more digits may follow
    run = buf[k:end]
    if run and buf[end] not in SEPARATORS:
        follower = _mnemonic_at(buf, end, n)
        if follower is _HOLD:
            return None
        if follower is None:
            return (LexError(buf[i : end + 1], f"{mnemonic}: malformed operand "
                                               f"{buf[k : end + 1]!r}"), end, True)
    text = buf[i:end]
    if not run:
        if buf[end] not in SEPARATORS and _mnemonic_at(buf, end, n) is None:
            return (LexError(buf[i : end + 1], f"{mnemonic}: malformed operand "
                                               f"{buf[end]!r}"), end, True)
        return ParsedCommand(spec, (), False, text, task, form), end, False
    slots = tuple(s if s else None for s in run.split(","))
    check = _HEX_SLOT if hex_operand else _NUMBER
    bad = next((s for s in slots if s is not None and not check.match(s)), None)
    if bad is not None:
        kind = "hexadecimal word" if hex_operand else "number"
        return LexError(text, f"{mnemonic}: malformed {kind} {bad!r}"), end, False
    return ParsedCommand(spec, slots, False, text, task, form), end, False
