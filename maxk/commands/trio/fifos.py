"""FIFO files: a RAM file kept as a circular buffer, written on one channel and read on
another (TrioBASIC help OPEN, FIFO_WRITE, FIFO_READ).

``OPEN #n AS "name" FOR FIFO_WRITE(size[, mode[, terminator]])`` makes the FIFO, ``size``
bytes and at least 256 (page), or clears one that exists (its size kept); PRINT #n puts
characters in. Mode bit 1 (non-blocking) lets a full FIFO overwrite its oldest characters,
in line mode (bit 0) whole oldest lines up to the terminator (default 13); without it a
PRINT that does not fit waits until a reader has made room (page: "blocking"; the
statement waits a servo cycle at a time, D). ``OPEN #n AS "name" FOR FIFO_READ[(mode[,
terminator])]`` reads it: GET #n takes the oldest character, KEY #n gives how many
characters (mode 0) or lines, terminators counted (mode 1) are in it (page).

A FIFO lives in RAM apart from the program store: DIR does not list it, and FIFO_READ of
one never opened for writing is 'Program not found' as INPUT of a missing file (D); a
"RAM:" prefix names the same FIFO (D). Their sizes together are at most `TOTAL_SIZE`: a
new FIFO past it is 'Not enough memory', none made (D: RAM is finite; a program that
opens FIFOs under new names in a loop must not take the host's memory). A reader that
waits in GET looks again every servo cycle, as a writer may be another process (D).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

from .lexer import TrioError

MIN_SIZE = 256  # bytes (page)
MAX_SIZE = 1 << 20  # (D: a bound on what one FIFO may hold)
TOTAL_SIZE = 2 * MAX_SIZE  # (D: what all of them may hold; a new one past it is refused)


@dataclass
class Fifo:
    size: int
    chars: list[int] = field(default_factory=list)  # the oldest character last
    line_mode: bool = False
    overwrite: bool = False
    terminator: int = 13


@dataclass
class _Reader:
    fifo: Fifo
    lines: bool  # KEY counts lines (mode 1), else characters
    terminator: int


class FifoFiles:
    """The controller's FIFOs and the channels open on them."""

    def __init__(self) -> None:
        self.fifos: dict[str, Fifo] = {}
        self.writers: dict[int, Fifo] = {}
        self.pending: dict[int, list[int]] = {}  # a blocking writer's characters to go in
        self.readers: dict[int, _Reader] = {}

    def open(self, channel: int, name: str, mode: str, options: list[float]) -> list[int]:
        """OPEN ... FOR FIFO_WRITE / FIFO_READ: the characters the channel reads (the
        FIFO's own list for a reader, nothing for a writer)."""
        name = _fifo_name(name)
        if any(o != int(o) for o in options):
            raise TrioError("Parameter out of range")
        numbers = [int(o) for o in options]
        if mode == "FIFO_WRITE":
            if len(numbers) > 3:
                raise TrioError("Syntax error")
            size = numbers[0] if numbers else MIN_SIZE
            mode_bits = numbers[1] if len(numbers) > 1 else 0
            terminator = numbers[2] if len(numbers) > 2 else 13
            if not 0 < size <= MAX_SIZE or not 0 <= mode_bits <= 3 or \
                    not 0 <= terminator <= 255:
                raise TrioError("Parameter out of range")
            fifo = self.fifos.get(name)
            if fifo is None:
                size = max(size, MIN_SIZE)
                if sum(f.size for f in self.fifos.values()) + size > TOTAL_SIZE:
                    raise TrioError("Not enough memory")
                fifo = self.fifos[name] = Fifo(size)
            fifo.chars.clear()  # (an existing one: cleared, its size kept)
            fifo.line_mode, fifo.overwrite = bool(mode_bits & 1), bool(mode_bits & 2)
            fifo.terminator = terminator
            self.writers[channel] = fifo
            return []
        if len(numbers) > 2:
            raise TrioError("Syntax error")
        key_mode = numbers[0] if numbers else 0
        terminator = numbers[1] if len(numbers) > 1 else 13
        if key_mode not in (0, 1) or not 0 <= terminator <= 255:
            raise TrioError("Parameter out of range")
        if name not in self.fifos:
            raise TrioError("Program not found")
        fifo = self.fifos[name]
        self.readers[channel] = _Reader(fifo, key_mode == 1, terminator)
        return fifo.chars

    def close(self, channel: int) -> None:
        self.writers.pop(channel, None)
        self.pending.pop(channel, None)
        self.readers.pop(channel, None)

    def write(self, channel: int, text: str) -> bool:
        """PRINT #n to a FIFO writer (False: not one)."""
        fifo = self.writers.get(channel)
        if fifo is None:
            return False
        codes = [ord(c) & 0xFF for c in text]
        if fifo.overwrite:  # (one insertion a PRINT: a character at a time was quadratic)
            fresh: deque[int] = deque()  # this PRINT's characters in, the oldest first
            for code in codes:
                if len(fifo.chars) + len(fresh) >= fifo.size:
                    _drop_oldest(fifo, fresh)
                fresh.append(code)
            fifo.chars[0:0] = reversed(fresh)
            return True
        self.pending.setdefault(channel, []).extend(codes)
        self.flush(channel)
        return True

    def flush(self, channel: int) -> bool:
        """Move a blocking writer's waiting characters in as room allows; True while some
        still wait (the PRINT goes on waiting)."""
        waiting = self.pending.get(channel)
        fifo = self.writers.get(channel)
        if not waiting or fifo is None:
            self.pending.pop(channel, None)
            return False
        room = fifo.size - len(fifo.chars)
        moving, waiting[:] = waiting[:room], waiting[room:]
        fifo.chars[0:0] = moving[::-1]
        if waiting:
            return True
        del self.pending[channel]
        return False

    def key(self, channel: int) -> float | None:
        """KEY #n of a FIFO reader: characters, or lines, in it (None: not a reader)."""
        reader = self.readers.get(channel)
        if reader is None:
            return None
        if reader.lines:
            return float(reader.fifo.chars.count(reader.terminator))
        return float(len(reader.fifo.chars))

    def is_reader(self, channel: int) -> bool:
        return channel in self.readers


def _drop_oldest(fifo: Fifo, fresh: deque[int]) -> None:
    """Room for one more: the oldest character, or in line mode the oldest whole line,
    of the FIFO followed by the characters of the PRINT going in (`fresh`)."""
    while fifo.chars or fresh:
        code = fifo.chars.pop() if fifo.chars else fresh.popleft()
        if not fifo.line_mode or code == fifo.terminator:
            return


def _fifo_name(name: str) -> str:
    name = name.strip().upper()
    return name[4:] if name.startswith("RAM:") else name
