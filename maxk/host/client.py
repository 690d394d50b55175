"""A host's share of a door: its session, its input run in turns, back-pressure both
ways. Every stream door (TCP, pty) is a `Client`; the limits here are what keeps one
host from starving another or growing the server.
"""

from __future__ import annotations

import asyncio
import logging
import time
from dataclasses import dataclass, field

from maxk.controllers.contract import Controller, Session
from maxk.host.pacing import Pacer
from maxk.host.traffic import Traffic, TrafficBook, peer_name

log = logging.getLogger("maxk.door")

HIGH_WATER = 256 * 1024  # bytes of unsent replies before a client's input stops being run
HARD_LIMIT = 1024 * 1024  # unread beyond this, unasked output waits in its session (bounded there)
SLICE = 2048  # at most this much of one client's input runs at one turn ...
SLICE_SECONDS = 0.0005  # ... and for at most about this long; then every other client's turn
PIECE = 128  # input is fed in pieces this size while a turn lasts
INBOX_LIMIT = 64 * 1024  # input held unrun before we stop reading that client
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
    _last_fault: str = field(default="", repr=False)
    traffic: TrafficBook | None = None  # each host's recent bytes (made at the first one)

    def open_session(self, client: Client) -> Session:
        return self.controller.open_session(notify=client.flush_session)

    def open_traffic(self, transport: str, peer: object) -> Traffic:
        """A record of one host's bytes, in this controller's book of hosts."""
        if self.traffic is None:
            self.traffic = TrafficBook(self.controller.engine)
        return self.traffic.open(transport, peer_name(peer))

    def handle(self, session: Session, data: bytes) -> bytes:
        """Bring the controller to now, feed the bytes, return what the session says."""
        self.sync()
        self.feed(session, data)
        return session.read()

    def sync(self) -> None:
        """Bring the controller to now; a fault inside its engine is reported like one in
        a feed (below), never out of a door's callback."""
        try:
            self.pacer.sync()
        except Exception as error:  # the server never dies of one controller's fault
            self._report(error, b"")

    def feed(self, session: Session, data: bytes) -> None:
        """Feed a session; a fault inside the controller is reported and that input is
        lost, but the door, the host's connection and every other host go on."""
        try:
            session.feed(data)
        except Exception as error:  # the server never dies of one host's bytes
            self._report(error, data)

    def _report(self, error: Exception, data: bytes) -> None:
        """One line on stderr a fault; the same fault again (an engine that fails at
        every pacing pass) is not repeated."""
        running = f" while running {data[:60]!r}" if data else " advancing time"
        line = (f"maxk serve: board {self.number} ({self.controller.model}): "
                f"{type(error).__name__}: {error}{running}; still serving")
        if line != self._last_fault:
            self._last_fault = line
            log.error("%s", line)


def _holding(session: Session) -> bool:
    """The session holds input it cannot run yet (`HoldsInput`): what the host sends
    waits here. (An attribute read: asked for every piece fed.)"""
    return getattr(session, "holding", False) is True


class Client:
    """A host on a stream (a TCP connection or a pty): its session, and its input run in
    slices that take turns with every other client, so one flooding host never stalls
    another (a fresh host's query waits at most one slice per busy host). Replies are
    never dropped: while the host does not read them (its output above HIGH_WATER), its
    input waits, unrun, and reading from it stops once INBOX_LIMIT is held. Output
    nobody asked for waits with its session while HARD_LIMIT is unread; each session
    bounds what it keeps (the MAXk drops notifications, the MC405 program PRINTs, past a
    megabyte unread), never a reply."""

    session: Session | None = None
    service: Service
    loop: asyncio.AbstractEventLoop
    traffic: Traffic | None = None  # this host's recent bytes, and its log

    def _client_init(self) -> None:
        self._inbox = bytearray()
        self._scheduled = False
        self._closing = False  # the host hung up: its input runs out, then the session goes
        self._output_full = False  # unread replies above HIGH_WATER
        self._input_held = False  # reading paused (inbox full or output full)

    @property
    def held_input(self) -> int:
        """Bytes of this host's input the door holds, not yet run."""
        return len(self._inbox)

    @property
    def input_run(self) -> bool:
        """Everything of this host's input that reached the door has run: none waits here
        and its session holds none (a test knows a command has run without a probe)."""
        return not self._inbox and not self._scheduled and not (
            self.session is not None and _holding(self.session))

    # what a stream provides
    def _write(self, data: bytes) -> None:  # pragma: no cover - interface
        raise NotImplementedError

    def _unsent(self) -> int:  # pragma: no cover - interface
        raise NotImplementedError

    def _hold_input(self, hold: bool) -> None:  # pragma: no cover - interface
        raise NotImplementedError

    # the shared mechanism
    def send(self, data: bytes, *, droppable: bool = False) -> None:
        if droppable and self._unsent() > HARD_LIMIT:
            return  # a notification to a host that never reads: lost, memory bounded
        if self.traffic is not None:
            self.traffic.outgoing(data)
        self._write(data)

    def flush_session(self) -> None:
        """The session has something to say unasked: send it now, unless the host has
        not read its last megabyte: then it stays with the session (which may hold a
        reply that came after a wait: never dropped here) until the host reads. A
        session that held input may take it again now."""
        if self.session is not None and self._unsent() <= HARD_LIMIT:
            out = self.session.read()
            if out:
                self.send(out)
        if self._closing and not self._inbox and not (
                self.session is not None and _holding(self.session)):
            self._drop_session()  # the host hung up and what it sent has run
            return
        self._schedule()

    def receive(self, data: bytes) -> None:
        """Input from the host: held, and run in turns. A host with nothing waiting (a
        poll, a query) is served at once: only a backlog waits for its turn."""
        if self.session is None:
            return
        if self.traffic is not None:
            self.traffic.incoming(data)
        idle = not self._inbox and not self._scheduled
        self._inbox += data
        if idle and not self._output_full:
            self._run_slice()
            return
        self._update_input()
        self._schedule()

    def _schedule(self) -> None:
        if (self._scheduled or not self._inbox or self._output_full or self.session is None
                or _holding(self.session)):
            return  # a holding session notifies when it takes input again
        self._scheduled = True
        self.loop.call_soon(self._run_slice)

    def _run_slice(self) -> None:
        self._scheduled = False
        if self.session is None or self._output_full or not self._inbox:
            return
        service = self.service
        service.sync()
        session = self.session
        taken = 0
        deadline = time.perf_counter() + SLICE_SECONDS
        while taken < SLICE and self._inbox and not _holding(session):
            piece = bytes(self._inbox[:PIECE])
            del self._inbox[:PIECE]
            service.feed(session, piece)
            taken += len(piece)
            if time.perf_counter() >= deadline:
                break
        out = session.read()
        if out:
            self.send(out)
        if self._closing and not self._inbox and not _holding(session):
            self._drop_session()
            return
        self._output_full = self._unsent() > HIGH_WATER
        self._update_input()
        self._schedule()

    def output_drained(self) -> None:
        """The host read its replies: what its session kept may go, its input may run."""
        if self._unsent() <= HARD_LIMIT:
            self.flush_session()
        self._output_full = self._unsent() > HIGH_WATER
        self._update_input()
        self._schedule()

    def output_full(self) -> None:
        self._output_full = True
        self._update_input()

    def _update_input(self) -> None:
        hold = self._output_full or len(self._inbox) >= INBOX_LIMIT
        if hold != self._input_held:
            self._input_held = hold
            self._hold_input(hold)

    def _hang_up(self) -> None:
        """The host went away. What it sent still runs (as the board runs what reached
        it), in turns as before, with nobody left to read the replies; then the session
        goes."""
        if self.session is not None and (self._inbox or _holding(self.session)):
            self._closing = True
            self._output_full = False
            self._schedule()
            return
        self._drop_session()

    def _drop_session(self) -> None:
        if self.traffic is not None:
            self.traffic.closed()
        self.service.clients.discard(self)
        if self.session is not None:
            self.session.close()
            self.session = None
        self._inbox.clear()
