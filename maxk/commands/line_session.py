"""What every line controller's session shares (the MAX family, the MM4005, the Trio
command line): the `Session` contract's output side, bounded unasked output, closing,
and a line assembler with declared terminators and a line-length limit.

A language declares its framing as class attributes and says what a line does:

    class MM4005Session(LineSession):
        terminators = b"\\r\\n"     # a line ends at CR, LF or CR LF
        line_limit = 110           # longer lines are refused when they end
        def run_line(self, text): ...   # its replies through self.reply(...)

A stream language (the MAX lexer splits at `;` as well) overrides `feed` and keeps the
rest. Limits: a line longer than `line_limit` is not stored (bounded memory) and is
refused when its terminator comes (`line_too_long`); unasked output (flag notifications,
program PRINTs) is kept only while the host has read all but `unasked_limit` bytes;
replies are never dropped (the door's back-pressure bounds them: host/client.py).
A fault in the emulator's own code while a line runs (an unexpected Python exception) is
logged with its traceback (``maxk.commands``, never to the host), the language answers it
as its controller answers a refused line (`line_fault`), and the lines after it run: one
bad line never takes the rest of the host's bytes with it.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import ClassVar

log = logging.getLogger("maxk.commands")


def log_fault(where: str, text: str) -> None:
    """Log the exception being handled, a fault of ours while `text` ran, with its
    traceback (every language's guard uses it): for the operator, never for the host."""
    log.exception("%s: internal fault running %r", where, text[:80])


class LineSession:
    """The shared half of a line session (see the module docstring)."""

    terminators: ClassVar[bytes] = b"\r"  # bytes that end a line
    dropped: ClassVar[bytes] = b""  # bytes never stored (telnet NULs, a stray LF)
    line_limit: ClassVar[int] = 1024  # characters kept of one line
    unasked_limit: ClassVar[int] = 1 << 20  # unread output past which unasked output is lost

    def __init__(self, notify: Callable[[], None] | None = None) -> None:
        self.notify = notify
        self.closed = False
        self._out = bytearray()
        self._line = bytearray()
        self._overflow = False

    # ---- the Session contract ------------------------------------------------------------
    def feed(self, data: bytes) -> None:
        """Bytes from the host, split anywhere: each complete line runs."""
        if self.closed:
            return
        terminators, dropped, limit = self.terminators, self.dropped, self.line_limit
        line = self._line
        for byte in data:
            if byte in terminators:
                self._end_line()
            elif byte in dropped:
                continue
            elif len(line) < limit:
                line.append(byte)
            else:
                self._overflow = True  # bounded memory; refused when the line ends

    def read(self) -> bytes:
        out = bytes(self._out)
        self._out.clear()
        return out

    def close(self) -> None:
        """The host went away: forget its half line, tell it nothing more."""
        self.closed = True
        self.notify = None
        self.discard_partial_line()

    # ---- for the language ------------------------------------------------------------------
    def run_line(self, text: str) -> None:  # pragma: no cover - each language has its own
        raise NotImplementedError

    def line_too_long(self) -> None:
        """A line longer than `line_limit` ended: refused (nothing of it runs)."""

    def line_fault(self, text: str) -> None:
        """A fault of ours while `text` ran (already logged): the language answers it as
        its controller answers a line it refuses (default: nothing more)."""

    def reply(self, data: bytes) -> None:
        """Output the host asked for: always kept, in order."""
        self._out += data

    def unasked(self, data: bytes, *, wake: bool = True) -> bool:
        """Output nobody asked for (a notification, a program's PRINT): kept while the host
        reads, lost past `unasked_limit` unread (never a reply); the door is told."""
        if self.closed or len(self._out) > self.unasked_limit:
            return False
        self._out += data
        if wake and self.notify is not None:
            self.notify()
        return True

    def discard_partial_line(self) -> None:
        """A reset (or a hang-up) loses a line half received."""
        self._line.clear()
        self._overflow = False

    def _end_line(self) -> None:
        text = self._line.decode("latin-1")
        self._line.clear()
        if self._overflow:
            self._overflow = False
            self.line_too_long()
            return
        try:
            self.run_line(text)
        except Exception:  # a fault of ours: logged, answered, the next line runs
            log_fault(type(self).__name__, text)
            self.line_fault(text)
