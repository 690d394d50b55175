"""The doors for legacy hosts: TCP, UDP and serial ptys, for any controller, on one
asyncio loop.

Written once against the controller contract (controllers/contract.py): a door opens a
session per host, brings the controller to "now" (its pacer) before feeding it the
host's bytes, and sends what the session has to say. A session can also speak unasked
(a MAXk's flag notification, heard by every host of that board): it calls the door back
and the door sends it at once. Line controllers get TCP and a pty; a packet controller
(PoKeys) gets TCP framed in fixed-size packets and UDP with one reply datagram per
request, answered to the sender's address.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import sys
import termios
import tty
from collections.abc import Callable
from dataclasses import dataclass, field

from maxk.controllers.contract import Controller, Session
from maxk.host.pacing import Pacer

HIGH_WATER = 256 * 1024  # bytes of unsent replies before we stop reading a client
HARD_LIMIT = 1024 * 1024  # beyond this, notifications to a client that never reads are lost
UDP_PEERS = 64  # UDP hosts remembered (their sessions) per controller, least recent dropped


@dataclass
class Service:
    """One controller with its clock and everything attached to it."""

    number: int
    controller: Controller
    pacer: Pacer
    clients: set[Client] = field(default_factory=set)
    ports: list[tuple[str, int]] = field(default_factory=list)
    udp_ports: list[tuple[str, int]] = field(default_factory=list)
    ptys: list[str] = field(default_factory=list)

    def open_session(self, client: Client) -> Session:
        return self.controller.open_session(notify=client.flush_session)

    def handle(self, session: Session, data: bytes) -> bytes:
        """Bring the controller to now, feed the bytes, return what the session says."""
        self.pacer.sync()
        session.feed(data)
        return session.read()


class Client:
    """Anything that receives a controller's output: a TCP connection or a pty."""

    session: Session | None = None

    def send(self, data: bytes) -> None:  # pragma: no cover - interface
        raise NotImplementedError

    def flush_session(self) -> None:
        """The session has something to say unasked: send it now."""
        if self.session is not None:
            out = self.session.read()
            if out:
                self.send(out)


class TcpClient(asyncio.Protocol, Client):
    def __init__(self, service: Service) -> None:
        self.service = service
        self.transport: asyncio.Transport | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self.transport = transport  # type: ignore[assignment]
        transport.set_write_buffer_limits(high=HIGH_WATER)  # type: ignore[attr-defined]
        self.session = self.service.open_session(self)
        self.service.clients.add(self)

    def connection_lost(self, exc: Exception | None) -> None:
        self.service.clients.discard(self)
        if self.session is not None:
            self.session.close()
            self.session = None
        self.transport = None

    def data_received(self, data: bytes) -> None:
        if self.session is None:
            return
        out = self.service.handle(self.session, data)
        if out:
            self.send(out)

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


class UdpDoor(asyncio.DatagramProtocol):
    """Datagrams for a packet controller: each datagram is one request, answered by one
    datagram to the address it came from (a session per host address)."""

    def __init__(self, service: Service) -> None:
        self.service = service
        self.transport: asyncio.DatagramTransport | None = None
        self.sessions: dict[object, Session] = {}

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self.transport = transport  # type: ignore[assignment]

    def datagram_received(self, data: bytes, addr: tuple[str, int]) -> None:
        session = self.sessions.pop(addr, None)
        if session is None:
            session = self.service.controller.open_session()
            if len(self.sessions) >= UDP_PEERS:
                oldest = next(iter(self.sessions))
                self.sessions.pop(oldest).close()
        self.sessions[addr] = session  # most recent last
        out = self.service.handle(session, data)
        size = self.service.controller.packet_size or len(out) or 1
        if self.transport is not None:
            for i in range(0, len(out), size):
                self.transport.sendto(out[i:i + size], addr)

    def close(self) -> None:
        for session in self.sessions.values():
            session.close()
        self.sessions.clear()
        if self.transport is not None:
            self.transport.close()


class PtyClient(Client):
    """A pseudo-terminal: legacy serial code opens the slave side like a real port."""

    def __init__(self, service: Service, loop: asyncio.AbstractEventLoop,
                 link: str | None = None) -> None:
        self.service = service
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
        self.session = service.open_session(self)
        loop.add_reader(self.master, self._readable)
        service.clients.add(self)

    def _readable(self) -> None:
        try:
            data = os.read(self.master, 65536)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:
            return  # EIO while no client has the slave open
        if self.session is None:
            return
        out = self.service.handle(self.session, data)
        if out:
            self.send(out)

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
        if self.session is not None:
            self.session.close()
            self.session = None
        for fd in (self.master, self.slave_fd):
            with contextlib.suppress(OSError):
                os.close(fd)
        if self.link:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(self.link)


class Server:
    """Every controller, its doors and the pacer, on one event loop."""

    def __init__(self, services: list[Service], pace_interval: float = 0.001) -> None:
        self.services = services
        self.pace_interval = pace_interval
        self._servers: list[asyncio.base_events.Server] = []
        self._udp: list[UdpDoor] = []
        self._ptys: list[PtyClient] = []
        self._extra_pacing: list[Callable[[], None]] = []  # run after each pacing pass
        self._stop = asyncio.Event()

    async def open_tcp(self, service: Service, host: str, port: int) -> tuple[str, int]:
        loop = asyncio.get_running_loop()
        server = await loop.create_server(lambda: TcpClient(service), host, port)
        self._servers.append(server)
        address = server.sockets[0].getsockname()[:2]
        service.ports.append(address)
        return address

    async def open_udp(self, service: Service, host: str, port: int) -> tuple[str, int]:
        loop = asyncio.get_running_loop()
        transport, door = await loop.create_datagram_endpoint(
            lambda: UdpDoor(service), local_addr=(host, port))
        self._udp.append(door)
        address = transport.get_extra_info("sockname")[:2]
        service.udp_ports.append(address)
        return address

    def open_pty(self, service: Service, link: str | None = None) -> str:
        pty = PtyClient(service, asyncio.get_running_loop(), link)
        self._ptys.append(pty)
        service.ptys.append(pty.path)
        return pty.path

    def after_pacing(self, callback: Callable[[], None]) -> None:
        self._extra_pacing.append(callback)

    async def pace(self) -> None:
        """Keep every controller at now; never blocks request handling for long, since
        the engine jumps from event to event."""
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
            for door in self._udp:
                door.close()
            for pty in self._ptys:
                pty.close()
