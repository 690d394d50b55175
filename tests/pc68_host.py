"""A PC68/PC78-style stream host, written for the tests from the older boards' rules
(evidence 3.2 and E7): it writes whole commands with no terminator and reads each reply
one byte at a time as a leading run of CR/LF bytes (in which the status bytes `!` done,
`@` overtravel and `$` slip may stand, counted with the run, and `#` means the command
failed), the body up to the next CR or LF, then a trailing run as long as the leading one.

It knows nothing of the emulator: it sees bytes through a `transport` with `write(bytes)`
and `read_byte() -> int | None` (None: nothing came, which for this host is a lost line).
"""

from __future__ import annotations

import socket
from dataclasses import dataclass, field


class CommandFailed(Exception):
    """The board answered `#`."""


class LostLine(Exception):
    """A reply the host waited for never came (its parser is out of step)."""


@dataclass
class PC68Host:
    transport: object
    status_seen: list[str] = field(default_factory=list)  # every status byte, in order
    replies: int = 0

    def write(self, text: str) -> None:
        self.transport.write(text.encode())  # type: ignore[attr-defined]

    def _byte(self) -> str:
        b = self.transport.read_byte()  # type: ignore[attr-defined]
        if b is None:
            raise LostLine("no byte where a reply was due")
        return chr(b)

    def read_reply(self) -> str:
        head = 0
        c = self._byte()
        while c in "\r\n!@$#":
            if c == "#":
                raise CommandFailed
            if c in "!@$":
                self.status_seen.append(c)
            head += 1
            c = self._byte()
        body = ""
        while c not in "\r\n":
            body += c
            c = self._byte()
        tail = 1
        while tail < head:
            self._byte()
            tail += 1
        self.replies += 1
        return body

    def ask(self, text: str, count: int = 1) -> list[str]:
        """Write a line of queries and read one reply for each."""
        self.write(text)
        return [self.read_reply() for _ in range(count)]

    def expect_failure(self, text: str) -> bool:
        """Write a line whose answer may be `#` (AX EA on an axis with no encoder)."""
        self.write(text)
        try:
            self.read_reply()
        except CommandFailed:
            return True
        return False


class SessionTransport:
    """In-process: the session's feed and read."""

    def __init__(self, session) -> None:
        self.session = session
        self.pending = b""

    def write(self, data: bytes) -> None:
        self.session.feed(data)

    def read_byte(self) -> int | None:
        if not self.pending:
            self.pending = self.session.read()
        if not self.pending:
            return None
        b, self.pending = self.pending[0], self.pending[1:]
        return b


class SocketTransport:
    """Over TCP; the socket's timeout is only a liveness bound."""

    def __init__(self, sock: socket.socket) -> None:
        self.sock = sock
        self.pending = b""
        self.sent = 0

    def write(self, data: bytes) -> None:
        self.sock.sendall(data)
        self.sent += len(data)

    def read_byte(self) -> int | None:
        if not self.pending:
            try:
                self.pending = self.sock.recv(4096)
            except TimeoutError:
                return None
        if not self.pending:
            return None
        b, self.pending = self.pending[0], self.pending[1:]
        return b
