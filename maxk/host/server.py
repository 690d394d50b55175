"""`maxk serve`: boards in real time behind MAXnet-style TCP ports, serial ptys and
shared-memory files, all on one asyncio loop.

Framing (evidence 3.1-3.3): commands end at `;`, CR or LF (the lexer's job); a query's
reply is its text followed by the line ending (LF CR by default: the EPICS MAXnet
driver's input terminator), optionally led by ACK 0x06; commands without a reply send
nothing. When a done, overtravel, slip or command-error flag sets, every client of that
board receives `%000 SSSSSSSS` (the MAXnet flag word in 8 hex digits). Each connection
has its own lexer, so half a command from one client never mixes with another's; the
command mode (AX/AA/AM) belongs to the board, as on the real controller.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import sys
import termios
import tty
from dataclasses import dataclass, field

from maxk.commands.max.interpreter import Interpreter
from maxk.controllers.maxk import MAXk
from maxk.host.pacing import Pacer

EOLS = {"lfcr": b"\n\r", "lf": b"\n", "crlf": b"\r\n", "cr": b"\r"}
ACK = b"\x06"
HIGH_WATER = 256 * 1024  # bytes of unsent replies before we stop reading a client
HARD_LIMIT = 1024 * 1024  # beyond this, notifications to a client that never reads are lost


@dataclass
class Framing:
    eol: bytes = EOLS["lfcr"]
    ack: bool = False

    def reply(self, text: str) -> bytes:
        return (ACK if self.ack else b"") + text.encode("latin-1") + self.eol

    def notification(self, word: int) -> bytes:
        return f"%000 {word:08X}".encode() + self.eol


@dataclass
class BoardService:
    """One board with its clock and everything attached to it."""

    number: int
    maxk: MAXk
    pacer: Pacer
    framing: Framing
    clients: set[Client] = field(default_factory=set)
    ports: list[tuple[str, int]] = field(default_factory=list)
    ptys: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.maxk.board.add_flag_listener(self._flags_set)

    def _flags_set(self, word: int) -> None:
        message = self.framing.notification(word)
        for client in list(self.clients):
            client.send(message)

    def handle(self, interpreter: Interpreter, data: bytes) -> list[bytes]:
        """Bring the board to now, feed the bytes, frame the replies."""
        self.pacer.sync()
        return [self.framing.reply(r) for r in interpreter.write(data)]


class Client:
    """Anything that receives a board's output: a TCP connection or a pty."""

    def send(self, data: bytes) -> None:  # pragma: no cover - interface
        raise NotImplementedError


class TcpClient(asyncio.Protocol, Client):
    def __init__(self, service: BoardService) -> None:
        self.service = service
        self.interpreter = Interpreter(service.maxk.board)
        self.transport: asyncio.Transport | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self.transport = transport  # type: ignore[assignment]
        transport.set_write_buffer_limits(high=HIGH_WATER)  # type: ignore[attr-defined]
        self.service.clients.add(self)

    def connection_lost(self, exc: Exception | None) -> None:
        self.service.clients.discard(self)
        self.transport = None

    def data_received(self, data: bytes) -> None:
        for reply in self.service.handle(self.interpreter, data):
            self.send(reply)

    def send(self, data: bytes) -> None:
        transport = self.transport
        if transport is None or transport.is_closing():
            return
        if transport.get_write_buffer_size() > HARD_LIMIT:
            return  # a client that never reads loses output, as on a line; memory is bounded
        transport.write(data)

    # Flow control: a client that never reads its replies stops being read, so the
    # server's memory stays bounded while everyone else is served.
    def pause_writing(self) -> None:
        if self.transport is not None:
            self.transport.pause_reading()

    def resume_writing(self) -> None:
        if self.transport is not None:
            self.transport.resume_reading()


class PtyClient(Client):
    """A pseudo-terminal: legacy serial code opens the slave side like a real port."""

    def __init__(self, service: BoardService, loop: asyncio.AbstractEventLoop,
                 link: str | None = None) -> None:
        self.service = service
        self.interpreter = Interpreter(service.maxk.board)
        self.master, slave = os.openpty()
        tty.setraw(slave)  # no echo, no CR/LF translation: bytes as on a real line
        attrs = termios.tcgetattr(slave)
        attrs[3] &= ~termios.ECHO
        termios.tcsetattr(slave, termios.TCSANOW, attrs)
        self.slave_fd = slave  # kept open so the pty survives clients coming and going
        self.path = os.ttyname(slave)
        self.link = link
        if link:
            if os.path.lexists(link):
                if not os.path.islink(link):
                    os.close(self.master)
                    os.close(slave)
                    raise OSError(f"--pty-link {link} exists and is not a symlink")
                os.unlink(link)
            os.symlink(self.path, link)
        self._out = bytearray()  # output the pty could not take yet
        os.set_blocking(self.master, False)
        self.loop = loop
        loop.add_reader(self.master, self._readable)
        service.clients.add(self)

    def _readable(self) -> None:
        try:
            data = os.read(self.master, 65536)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:
            return  # EIO while no client has the slave open
        for reply in self.service.handle(self.interpreter, data):
            self.send(reply)

    def send(self, data: bytes) -> None:
        """Queue output and write what the pty takes; while much waits, stop reading the
        client's input (as TCP does), so replies are not lost to a slow reader."""
        if len(self._out) + len(data) > HARD_LIMIT:
            return  # nobody reads this port: output is lost, memory is bounded
        was_empty = not self._out
        self._out += data
        self._flush()
        if was_empty and self._out:
            self.loop.add_writer(self.master, self._flush)
        if len(self._out) > HIGH_WATER:
            self.loop.remove_reader(self.master)

    def _flush(self) -> None:
        while self._out:
            try:
                n = os.write(self.master, self._out)
            except (BlockingIOError, InterruptedError):
                return
            except OSError:
                self._out.clear()
                break
            del self._out[:n]
        self.loop.remove_writer(self.master)
        self.loop.add_reader(self.master, self._readable)

    def close(self) -> None:
        self.loop.remove_reader(self.master)
        self.loop.remove_writer(self.master)
        self.service.clients.discard(self)
        for fd in (self.master, self.slave_fd):
            with contextlib.suppress(OSError):
                os.close(fd)
        if self.link:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(self.link)


class Server:
    """Every board, its doors and the pacer, on one event loop."""

    def __init__(self, services: list[BoardService], pace_interval: float = 0.001) -> None:
        self.services = services
        self.pace_interval = pace_interval
        self._servers: list[asyncio.base_events.Server] = []
        self._ptys: list[PtyClient] = []
        self._extra_pacing: list = []  # callables run after each pacing pass (shared memory)
        self._stop = asyncio.Event()

    async def open_tcp(self, service: BoardService, host: str, port: int) -> tuple[str, int]:
        loop = asyncio.get_running_loop()
        server = await loop.create_server(lambda: TcpClient(service), host, port)
        self._servers.append(server)
        address = server.sockets[0].getsockname()[:2]
        service.ports.append(address)
        return address

    def open_pty(self, service: BoardService, link: str | None = None) -> str:
        pty = PtyClient(service, asyncio.get_running_loop(), link)
        self._ptys.append(pty)
        service.ptys.append(pty.path)
        return pty.path

    def after_pacing(self, callback) -> None:  # type: ignore[no-untyped-def]
        self._extra_pacing.append(callback)

    async def pace(self) -> None:
        """Keep every board at now; never blocks request handling for long, since the
        engine jumps from event to event."""
        while not self._stop.is_set():
            for step in [*(s.pacer.sync for s in self.services), *self._extra_pacing]:
                try:
                    step()
                except Exception as error:  # one board's failure must not stop the others
                    print(f"maxk serve: {error!r} (in {step!r}); still serving",
                          file=sys.stderr, flush=True)
            await asyncio.sleep(self.pace_interval)

    def stop(self) -> None:
        self._stop.set()

    async def run(self) -> None:
        try:
            await self.pace()
        finally:
            for server in self._servers:
                server.close()
            for pty in self._ptys:
                pty.close()
