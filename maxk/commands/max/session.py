"""A host's line session with a MAX-family board: the MAXnet framing of replies and flag
notifications (evidence 3.1-3.3), over the board's interpreter; or the older boards' stream
framing (`framing=pc68`, below).

Commands end at `;`, CR or LF (the lexer's job); a query's reply is its text followed by
the line ending (LF CR by default: the EPICS MAXnet driver's input terminator),
optionally led by ACK 0x06; commands without a reply send nothing. When a done,
overtravel, slip or command-error flag sets, every session of that board receives
`%000 SSSSSSSS` (the MAXnet flag word in 8 hex digits). Each session has its own lexer;
the command mode (AX/AA/AM) belongs to the board, as on the real controller.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from maxk.commands.line_session import LineSession
from maxk.commands.max.interpreter import Interpreter
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.board import Board

EOLS = {"lfcr": b"\n\r", "lf": b"\n", "crlf": b"\r\n", "cr": b"\r"}
FRAMINGS = ("maxnet", "pc68")
"""`maxnet`: replies end in the line ending, flags come as `%000 SSSSSSSS` (the MAXnet
driver's). `pc68`: the VME8/VME58/PC68 stream hosts' (evidence 3.2, drvOmsPC68's
recv_mess): every reply is framed by a run of line-ending bytes before and after it, the
same count on both sides; the status bytes `#` (command error), `$` (slip), `@`
(overtravel) and `!` (done) come in band in a reply's leading run, `#` at once; no `%000`
notifications; and each write is whole commands (its end completes an open operand)."""
COMMAND_ERROR_BYTE = b"#"
_STATUS_BYTES = ((F.SLIP_SHIFT, 0x2000_0000 | 0x4000_0000, "$"),
                 (F.OVERTRAVEL_SHIFT, 0x0800_0000 | 0x1000_0000, "@"),
                 (F.DONE_SHIFT, 0x0200_0000 | 0x0400_0000, "!"))
ACK = b"\x06"
NOTIFICATIONS_KEPT = 1024 * 1024  # unread output past which new notifications are lost


@dataclass(frozen=True)
class Framing:
    eol: bytes = EOLS["lfcr"]
    ack: bool = False
    style: str = "maxnet"

    @property
    def in_band(self) -> bool:
        """The older boards' stream framing: status bytes in band, whole writes."""
        return self.style == "pc68"

    def reply(self, text: str, status: str = "") -> bytes:
        if self.in_band:
            # Leading run: the status bytes, then the line ending; the trailing run is as
            # long (the host counts the leading run and eats as many after the body).
            eol = self.eol
            pad = eol[-1:] * len(status)
            return (status.encode() + eol + text.encode("latin-1") + eol + pad)
        return (ACK if self.ack else b"") + text.encode("latin-1") + self.eol

    def notification(self, word: int) -> bytes:
        return f"%000 {word:08X}".encode() + self.eol

    @classmethod
    def from_options(cls, options: dict[str, str]) -> Framing:
        """`eol=lfcr|lf|crlf|cr`, `ack` (present: lead replies with ACK) and
        `framing=maxnet|pc68`."""
        eol = options.get("eol", "lfcr")
        if eol not in EOLS:
            raise ValueError(f"eol is one of {', '.join(sorted(EOLS))}, not {eol!r}")
        style = options.get("framing", "maxnet")
        if style not in FRAMINGS:
            raise ValueError(f"framing is one of {', '.join(FRAMINGS)}, not {style!r}")
        if style == "pc68" and "ack" in options:
            raise ValueError("ack is the MAXnet framing's; the pc68 framing has none")
        return cls(EOLS[eol], "ack" in options, style)


def status_bytes(word: int) -> str:
    """The in-band status bytes of a MAXnet flag word's event bits, in the order slip,
    overtravel, done (the command error's `#` is sent at once, not here)."""
    out = ""
    for shift, wk, char in _STATUS_BYTES:
        if word & (0xFF << shift) or word & wk:
            out += char
    return out


class MaxSession(LineSession):
    """Bytes in, framed replies and notifications out (the `Session` contract). The MAX
    lexer reads the stream itself (a command ends at `;`, CR or LF), so `feed` is its."""

    unasked_limit = NOTIFICATIONS_KEPT

    def __init__(self, board: Board, framing: Framing,
                 notify: Callable[[], None] | None = None) -> None:
        super().__init__(notify)
        self.board = board
        self.framing = framing
        self.interpreter = Interpreter(board)
        self.interpreter.on_reply = self._reply
        self._feeding = False
        self._status = ""  # pc68 framing: status bytes for the next reply's leading run
        board.add_flag_listener(self._flags_set)

    def _flags_set(self, word: int) -> None:
        if not self.framing.in_band:
            self.unasked(self.framing.notification(word))  # lost by a host that never reads
            return
        if word & F.COMMAND_ERROR:
            # At once: a query refused (`AX EA` without an encoder) has no reply, and the
            # host reading for it must see the `#` in its place.
            self.unasked(COMMAND_ERROR_BYTE)
        for char in status_bytes(word):
            if char not in self._status:
                self._status += char

    def _frame(self, text: str) -> bytes:
        status, self._status = self._status, ""
        return self.framing.reply(text, status)

    def _reply(self, text: str) -> None:
        """A query's reply, in order with the notifications of the commands around it; one
        held by WQ comes when the queue has emptied and wakes the door."""
        self.reply(self._frame(text))
        if not self._feeding and self.notify is not None:
            self.notify()

    def feed(self, data: bytes) -> None:
        if self.interpreter.echo:  # EN: the bytes as received, before what they cause
            self.reply(bytes(data))
        self._feeding = True
        try:
            for text in self.interpreter.write(data, whole=self.framing.in_band):
                self.reply(self._frame(text))
        finally:
            self._feeding = False

    def lose_partial_command(self) -> None:
        """A controller reset: a command half received is lost."""
        self.interpreter = Interpreter(self.board)
        self.interpreter.on_reply = self._reply

    def close(self) -> None:
        self.board.remove_flag_listener(self._flags_set)
        super().close()
