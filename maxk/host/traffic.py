"""What each host said and was told, for a person debugging it: a bounded record per
connection of bytes in and replies out, stamped with the controller's virtual time, and
the same on the `maxk.door.<transport>` logger at DEBUG (`maxk serve -v`).

One logger per door kind, with the connection carried as a `LoggerAdapter` (a logger per
connection would live for ever in the logging module's table: a server that has seen a
million hosts would keep a million loggers).
"""

from __future__ import annotations

import logging
from collections import deque
from dataclasses import dataclass
from typing import Any

from maxk.firmware_model.engine import Engine

ENTRIES = 200  # what one connection's record keeps (the oldest go first)
HOSTS = 32  # connections a controller remembers, those gone included (the oldest go first)
SHOWN = 120  # bytes of one entry shown in a log line


@dataclass(frozen=True)
class TrafficEntry:
    tick: int
    time: float
    direction: str  # "in" (from the host) or "out" (to the host)
    data: bytes

    def as_dict(self) -> dict[str, Any]:
        return {"tick": self.tick, "time": self.time, "direction": self.direction,
                "text": self.data.decode("latin-1"), "hex": self.data.hex()}


class Traffic:
    """One host's conversation, newest last, at most ENTRIES entries."""

    def __init__(self, transport: str, peer: str, engine: Engine,
                 entries: int = ENTRIES) -> None:
        self.transport = transport
        self.peer = peer
        self.engine = engine
        self.entries: deque[TrafficEntry] = deque(maxlen=entries)
        self.dropped = 0  # entries the record has let go of
        self.bytes_in = 0  # every byte the host sent that reached the door
        self.open = True
        self.log = logging.LoggerAdapter(logging.getLogger(f"maxk.door.{transport}"),
                                         {"peer": peer})

    def _note(self, direction: str, data: bytes) -> None:
        if not data:
            return
        engine = self.engine
        if len(self.entries) == self.entries.maxlen:
            self.dropped += 1
        self.entries.append(TrafficEntry(engine.tick, engine.time, direction, bytes(data)))
        if self.log.isEnabledFor(logging.DEBUG):
            shown = repr(data[:SHOWN]) + ("..." if len(data) > SHOWN else "")
            self.log.debug("%s t=%.6f %s %s", self.peer, engine.time,
                           "<-" if direction == "in" else "->", shown)

    def incoming(self, data: bytes) -> None:
        self.bytes_in += len(data)
        self._note("in", data)

    def outgoing(self, data: bytes) -> None:
        self._note("out", data)

    def closed(self) -> None:
        self.open = False
        self.log.info("%s hung up", self.peer)

    def as_dict(self) -> dict[str, Any]:
        return {"transport": self.transport, "peer": self.peer, "open": self.open,
                "dropped": self.dropped, "entries": [e.as_dict() for e in self.entries]}


class TrafficBook:
    """Every connection a controller has had lately, at most HOSTS (the oldest gone)."""

    def __init__(self, engine: Engine, hosts: int = HOSTS) -> None:
        self.engine = engine
        self.hosts: deque[Traffic] = deque(maxlen=hosts)

    def open(self, transport: str, peer: str) -> Traffic:
        traffic = Traffic(transport, peer, self.engine)
        self.hosts.append(traffic)
        traffic.log.info("%s connected", peer)
        return traffic

    def as_list(self) -> list[dict[str, Any]]:
        return [t.as_dict() for t in self.hosts]


def peer_name(address: object) -> str:
    """`127.0.0.1:5555` for a socket address, the text itself otherwise (a pty's path)."""
    if isinstance(address, tuple) and len(address) >= 2:
        host = address[0]
        return f"[{host}]:{address[1]}" if ":" in str(host) else f"{host}:{address[1]}"
    return str(address)
