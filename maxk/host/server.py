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
import ctypes
import logging
import os
import struct
import termios
import tty
from collections.abc import Callable

from maxk.controllers.contract import Session
from maxk.host.client import (  # noqa: F401  (the limits, re-exported for the doors' users)
    HARD_LIMIT,
    HIGH_WATER,
    INBOX_LIMIT,
    PIECE,
    SLICE,
    SLICE_SECONDS,
    SYNC_BUDGET,
    UDP_PEERS,
    Client,
    Service,
)
from maxk.host.traffic import Traffic

log = logging.getLogger("maxk.door.serve")


HOSTS_PER_DOOR = 256  # hosts connected at once to one TCP door; more are hung up on (D)
ACCEPT_BACKLOG = 100  # asyncio's listen backlog (a hundred hosts connecting at once)


class _Listener:
    """One TCP door's count of its connected hosts, against its cap."""

    def __init__(self, service: Service, cap: int) -> None:
        self.service = service
        self.cap = cap
        self.open = 0
        self.refused = 0

    def __call__(self) -> asyncio.Protocol:
        if self.open >= self.cap:
            self.refused += 1
            if self.refused in (1, 10, 100) or self.refused % 1000 == 0:
                log.warning("board %d: more than %d hosts at once on one door; %d refused",
                            self.service.number, self.cap, self.refused)
            return _HungUp()
        self.open += 1
        return TcpClient(self.service, self)


class _HungUp(asyncio.Protocol):
    """A connection over a door's cap: closed at once, its descriptor freed (a flood of
    connections never takes the server to EMFILE, nor a door's hosts from it)."""

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        transport.close()


class TcpClient(asyncio.Protocol, Client):
    def __init__(self, service: Service, listener: _Listener | None = None) -> None:
        self.service = service
        self.transport: asyncio.Transport | None = None
        self._listener = listener
        self._client_init()

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self.transport = transport  # type: ignore[assignment]
        self.loop = asyncio.get_running_loop()
        transport.set_write_buffer_limits(high=HIGH_WATER)  # type: ignore[attr-defined]
        info = getattr(transport, "get_extra_info", None)  # (a test's stand-in may lack it)
        self.traffic = self.service.open_traffic("tcp", info("peername") if info else "?")
        self.session = self.service.open_session(self)
        self.service.clients.add(self)

    def connection_lost(self, exc: Exception | None) -> None:
        self.transport = None
        if self._listener is not None:
            self._listener.open -= 1
            self._listener = None
        self._hang_up()

    def data_received(self, data: bytes) -> None:
        self.receive(data)

    def _write(self, data: bytes) -> None:
        transport = self.transport
        if transport is not None and not transport.is_closing():
            transport.write(data)

    def _unsent(self) -> int:
        transport = self.transport
        return 0 if transport is None else transport.get_write_buffer_size()

    def _hold_input(self, hold: bool) -> None:
        transport = self.transport
        if transport is None or transport.is_closing():
            return
        if hold:
            transport.pause_reading()
        else:
            transport.resume_reading()

    # asyncio's flow control: the host stopped reading / read again
    def pause_writing(self) -> None:
        self.output_full()

    def resume_writing(self) -> None:
        self.output_drained()


class UdpDoor(asyncio.DatagramProtocol):
    """Datagrams for a packet controller: each datagram is one request, answered by one
    datagram to the address it came from (a session per host address)."""

    def __init__(self, service: Service) -> None:
        self.service = service
        self.transport: asyncio.DatagramTransport | None = None
        self.sessions: dict[object, Session] = {}
        self.traffic: dict[object, Traffic] = {}  # per host address, as the sessions
        self.neighbours: list[UdpDoor] = []  # the server's UDP doors (discovery)

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self.transport = transport  # type: ignore[assignment]

    def datagram_received(self, data: bytes, addr: tuple[str, int]) -> None:
        session = self.sessions.pop(addr, None)
        if session is None:
            controller = self.service.controller
            # a packet controller may frame datagrams itself (each feed one datagram:
            # a stray size is ignored whole instead of misaligning the next request)
            opener = getattr(controller, "open_datagram_session", controller.open_session)
            session = opener()
            if len(self.sessions) >= UDP_PEERS:
                oldest = next(iter(self.sessions))
                self.sessions.pop(oldest).close()
                self.traffic.pop(oldest).closed()
            self.traffic[addr] = self.service.open_traffic("udp", addr)
        self.sessions[addr] = session  # most recent last
        traffic = self.traffic[addr]
        traffic.incoming(data)
        finds = getattr(self.service.controller, "is_discovery", None)
        discovery = finds is not None and finds(data)
        answer = getattr(self.service.controller, "discovery_answer", None)
        if discovery and answer is not None:
            out = answer(data, addr) or b""  # naming the asking host, as the others do
        else:
            out = self.service.handle(session, data)
        traffic.outgoing(out)
        size = self.service.controller.packet_size or len(out) or 1
        if self.transport is not None:
            for i in range(0, len(out), size):
                self.transport.sendto(out[i:i + size], addr)
        if discovery:
            # who is there: every other served controller that answers discovery answers
            # from its own door, as every device on a network answers a broadcast
            for door in self.neighbours:
                if door is not self:
                    door.answer_discovery(data, addr)

    def answer_discovery(self, data: bytes, addr: tuple[str, int]) -> None:
        """Another door's host asked who is there: this controller's answer, if it has one."""
        answer = getattr(self.service.controller, "discovery_answer", None)
        reply = None if answer is None else answer(data, addr)
        if reply and self.transport is not None:
            traffic = self.traffic.get(addr)
            if traffic is not None:
                traffic.incoming(data)
                traffic.outgoing(reply)
            self.transport.sendto(reply, addr)

    def close(self) -> None:
        for session in self.sessions.values():
            session.close()
        self.sessions.clear()
        if self.transport is not None:
            self.transport.close()


class _OpenWatch:
    """Who has a device file open, from the kernel's inotify open/close events (Linux):
    a pty's host opening and closing the port. None where inotify is not available."""

    IN_OPEN, IN_CLOSE_WRITE, IN_CLOSE_NOWRITE = 0x20, 0x08, 0x10

    def __init__(self, fd: int) -> None:
        self.fd = fd

    @classmethod
    def on(cls, path: str) -> _OpenWatch | None:
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            fd = libc.inotify_init1(os.O_NONBLOCK | os.O_CLOEXEC)
            if fd < 0:
                return None
            mask = cls.IN_OPEN | cls.IN_CLOSE_WRITE | cls.IN_CLOSE_NOWRITE
            if libc.inotify_add_watch(fd, path.encode(), mask) < 0:
                os.close(fd)
                return None
        except (OSError, AttributeError):
            return None
        return cls(fd)

    def changes(self) -> int:
        """Opens minus closes since the last look."""
        delta = 0
        while True:
            try:
                data = os.read(self.fd, 4096)
            except (BlockingIOError, InterruptedError):
                return delta
            except OSError:
                return delta
            offset = 0
            while offset + 16 <= len(data):
                _wd, mask, _cookie, length = struct.unpack_from("iIII", data, offset)
                offset += 16 + length
                if mask & self.IN_OPEN:
                    delta += 1
                if mask & (self.IN_CLOSE_WRITE | self.IN_CLOSE_NOWRITE):
                    delta -= 1

    def close(self) -> None:
        with contextlib.suppress(OSError):
            os.close(self.fd)


class PtyClient(Client):
    """A pseudo-terminal: legacy serial code opens the slave side like a real port.

    As on a real serial line, nothing from before the host opened the port reaches it:
    while no host has the port open, notifications are not sent, and when a host opens
    it whatever was left unread (by a host that went away) is discarded. Who has the
    port open is known from the kernel's open/close events on the slave (Linux inotify);
    without them the pty behaves as a line that is always listened to."""

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
        self._client_init()
        self.traffic = service.open_traffic("pty", self.path)
        self.session = service.open_session(self)
        self._reading = True
        self._watch = _OpenWatch.on(self.path)
        self._hosts = 0  # hosts that have the port open (when known)
        if self._watch is not None:
            loop.add_reader(self._watch.fd, self._opens_changed)
        loop.add_reader(self.master, self._readable)
        service.clients.add(self)

    def _opens_changed(self) -> None:
        if self._watch is None:
            return
        before = self._hosts
        self._hosts = max(0, self._hosts + self._watch.changes())
        if before == 0 and self._hosts > 0:
            # a host opened the port: it starts clean, as a real serial line does
            with contextlib.suppress(OSError, termios.error):
                termios.tcflush(self.slave_fd, termios.TCIFLUSH)
            self._out.clear()

    def flush_session(self) -> None:
        """Notifications reach a host that has the port open; with nobody listening
        they are lost, as bytes on an unplugged line are."""
        self._opens_changed()  # open/close events the loop has not handled yet
        if self._watch is not None and self._hosts == 0 and self.session is not None:
            self.session.read()
            return
        super().flush_session()

    def _readable(self) -> None:
        self._opens_changed()  # a host that opened and wrote at once: flush before replying
        try:
            data = os.read(self.master, 65536)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:
            return  # EIO while no client has the slave open
        self.receive(data)

    def _write(self, data: bytes) -> None:
        """Queue output and write what the pty takes now; the rest when it can."""
        was_empty = not self._out
        self._out += data
        self._flush()
        if was_empty and self._out:
            self.loop.add_writer(self.master, self._flush)
        if len(self._out) > HIGH_WATER:
            self.output_full()

    def _unsent(self) -> int:
        return len(self._out)

    def _hold_input(self, hold: bool) -> None:
        if hold and self._reading:
            self.loop.remove_reader(self.master)
        elif not hold and not self._reading:
            self.loop.add_reader(self.master, self._readable)
        self._reading = not hold

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
        self.output_drained()

    def close(self) -> None:
        self.loop.remove_reader(self.master)
        self.loop.remove_writer(self.master)
        if self._watch is not None:
            self.loop.remove_reader(self._watch.fd)
            self._watch.close()
        self._drop_session()
        for fd in (self.master, self.slave_fd):
            with contextlib.suppress(OSError):
                os.close(fd)
        if self.link:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(self.link)


PACE_BUDGET = 0.003  # seconds of one controller's engine work per pacing turn (D)


class Server:
    """Every controller, its doors and the pacer, on one event loop."""

    def __init__(self, services: list[Service], pace_interval: float = 0.001,
                 hosts_per_door: int = HOSTS_PER_DOOR) -> None:
        self.services = services
        self.pace_interval = pace_interval
        self.hosts_per_door = hosts_per_door
        self.listeners: list[_Listener] = []
        self._servers: list[asyncio.base_events.Server] = []
        self._udp: list[UdpDoor] = []
        self._ptys: list[PtyClient] = []
        self._extra_pacing: list[Callable[[], None]] = []  # run after each pacing pass
        self._stop = asyncio.Event()

    async def open_tcp(self, service: Service, host: str, port: int) -> tuple[str, int]:
        loop = asyncio.get_running_loop()
        listener = _Listener(service, self.hosts_per_door)
        # asyncio accepts up to the backlog in one go and closes a refused connection some
        # turns of the loop later: under a small descriptor limit (a cap fitted to it) the
        # burst stays within the cap, so a flood never reaches EMFILE (D)
        backlog = max(8, min(ACCEPT_BACKLOG, self.hosts_per_door))
        server = await loop.create_server(listener, host, port, backlog=backlog)
        self.listeners.append(listener)
        self._servers.append(server)
        address = server.sockets[0].getsockname()[:2]
        service.ports.append(address)
        return address

    async def open_udp(self, service: Service, host: str, port: int) -> tuple[str, int]:
        loop = asyncio.get_running_loop()
        transport, door = await loop.create_datagram_endpoint(
            lambda: UdpDoor(service), local_addr=(host, port))
        self._udp.append(door)
        door.neighbours = self._udp
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
        """Keep every controller at now. Each controller gets a bounded turn of engine
        work (PACE_BUDGET) and the loop is given back between controllers, so a host's
        request to one controller waits at most one turn of each other controller: one
        whose work takes longer than real time falls behind on its own (its clock runs
        slow and says so, `Service.behind`), never another's door or the server."""
        while not self._stop.is_set():
            for service in self.services:
                service.sync(PACE_BUDGET)
                await asyncio.sleep(0)  # hosts, signals and the other doors between turns
                if self._stop.is_set():
                    return
            for step in self._extra_pacing:
                try:
                    step()
                except Exception as error:  # one board's failure must not stop the others
                    log.error("maxk serve: %r (in %r); still serving", error, step)
            await asyncio.sleep(self.pace_interval)

    def stop(self) -> None:
        self._stop.set()

    async def run(self) -> None:
        try:
            await self.pace()
        finally:
            for server in self._servers:
                server.close()
            for service in self.services:  # the hosts still connected are hung up on
                for client in list(service.clients):
                    if isinstance(client, TcpClient) and client.transport is not None:
                        client.transport.close()
            for door in self._udp:
                door.close()
            for pty in self._ptys:
                pty.close()
            await asyncio.sleep(0)  # (let the transports finish closing their sockets)
