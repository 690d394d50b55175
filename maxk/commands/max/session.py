"""A host's line session with a MAX-family board: the MAXnet framing of replies and flag
notifications (evidence 3.1-3.3), over the board's interpreter.

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
from maxk.personalities.maxk.board import Board

EOLS = {"lfcr": b"\n\r", "lf": b"\n", "crlf": b"\r\n", "cr": b"\r"}
ACK = b"\x06"
NOTIFICATIONS_KEPT = 1024 * 1024  # unread output past which new notifications are lost


@dataclass(frozen=True)
class Framing:
    eol: bytes = EOLS["lfcr"]
    ack: bool = False

    def reply(self, text: str) -> bytes:
        return (ACK if self.ack else b"") + text.encode("latin-1") + self.eol

    def notification(self, word: int) -> bytes:
        return f"%000 {word:08X}".encode() + self.eol

    @classmethod
    def from_options(cls, options: dict[str, str]) -> Framing:
        """`eol=lfcr|lf|crlf|cr` and `ack` (present: lead replies with ACK)."""
        eol = options.get("eol", "lfcr")
        if eol not in EOLS:
            raise ValueError(f"eol is one of {', '.join(sorted(EOLS))}, not {eol!r}")
        return cls(EOLS[eol], "ack" in options)


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
        board.add_flag_listener(self._flags_set)

    def _flags_set(self, word: int) -> None:
        self.unasked(self.framing.notification(word))  # lost by a host that never reads

    def _reply(self, text: str) -> None:
        """A query's reply, in order with the notifications of the commands around it; one
        held by WQ comes when the queue has emptied and wakes the door."""
        self.reply(self.framing.reply(text))
        if not self._feeding and self.notify is not None:
            self.notify()

    def feed(self, data: bytes) -> None:
        self._feeding = True
        try:
            for text in self.interpreter.write(data):
                self.reply(self.framing.reply(text))
        finally:
            self._feeding = False

    def lose_partial_command(self) -> None:
        """A controller reset: a command half received is lost."""
        self.interpreter = Interpreter(self.board)
        self.interpreter.on_reply = self._reply

    def close(self) -> None:
        self.board.remove_flag_listener(self._flags_set)
        super().close()
