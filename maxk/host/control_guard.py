"""The control door's guard (control.py uses it): who may ask (the Host, the token,
another origin, a content type that acts) and how many may connect and how slowly (a cap
on connections, a deadline on a request's headers, streams whose readers stop are let
go). aiohttp's own request handler and parsing underneath; the decision and the figures
are in docs/control.md."""

from __future__ import annotations

import asyncio
import contextlib
import ipaddress
import secrets
import socket
from typing import Any, Protocol

from aiohttp import web
from aiohttp.web_protocol import RequestHandler
from yarl import URL

CONNECTIONS = 64  # connections open at once to the door; more are refused (503) (D)
HEADER_SECONDS = 5.0  # a request's headers must arrive within this (slowloris) (D)
BODY_SECONDS = 5.0  # and its body within this (D)
KEEPALIVE_SECONDS = 10.0  # an idle kept-alive connection is closed after this (D)
WRITE_SECONDS = 5.0  # a stream (events, CSV) whose reader takes none of it this long goes (D)
STREAM_SNDBUF = 64 * 1024  # kernel send buffer of a stream's socket: a reader that stops
# reading is seen within seconds, not after megabytes (D)
SIMPLE_ACTING = frozenset({"POST", "PUT", "PATCH"})  # (DELETE is never a browser's "simple"
# request: a page must ask first, and the door grants no other origin; with a body it too
# must say JSON)


class Counted(Protocol):
    """What a guarded connection needs of its door."""

    header_seconds: float
    open_connections: int


def error_response(status: int, reason: str) -> web.Response:
    return web.json_response({"error": reason, "status": status}, status=status)


def refusal(request: web.Request, token: str | None, hosts: frozenset[str],
            any_address: bool) -> web.Response | None:
    """Why this request is refused (None: it is not): see `ControlDoor._guard`."""
    host = request.headers.get("Host", "")
    if not names_door(host, hosts, any_address):
        return error_response(421, f"this is a control door; the Host {host!r} does not "
                              "name it (loopback names or the --host it listens on)")
    if token is not None:
        given = request.query.get("token") or request.headers.get(
            "Authorization", "").removeprefix("Bearer ").strip()
        if not secrets.compare_digest(given.encode(), token.encode()):
            return error_response(401, "this control door needs its token (printed at "
                                  "start-up): ?token=... or Authorization: Bearer ...")
    origin = request.headers.get("Origin")
    if origin is not None and not same_origin(origin, host):
        return error_response(403, f"a request from the page {origin!r} (another origin) "
                              "is refused: the control door answers its own panel and "
                              "programs")
    site = request.headers.get("Sec-Fetch-Site", "same-origin")
    navigating = request.headers.get("Sec-Fetch-Mode") == "navigate"
    if site not in ("same-origin", "none") and not (navigating and request.method == "GET"):
        return error_response(403, f"a request from another site (Sec-Fetch-Site: {site}) "
                              "is refused")
    acting = request.method in SIMPLE_ACTING or (
        request.method == "DELETE" and request.can_read_body)
    if acting and request.content_type != "application/json":
        return error_response(415, "a request that acts needs Content-Type: "
                              f"application/json (not {request.content_type!r})")
    return None


def names_door(host: str, hosts: frozenset[str], any_address: bool) -> bool:
    """The Host header names this door (its name, any port)."""
    if any(c in host for c in "@/?#\\ "):
        return False  # (no URL's authority: only a name and a port)
    try:
        name = URL(f"http://{host}").raw_host
    except ValueError:
        return False
    if not name:
        return False
    name = name.lower().rstrip(".")
    if name in hosts:
        return True
    if any_address:
        with contextlib.suppress(ValueError):
            ipaddress.ip_address(name.strip("[]"))
            return True  # an address literal is no DNS name a page could rebind
    return False


LOOPBACK_NAMES = frozenset({"localhost", "127.0.0.1", "::1", "[::1]"})


def door_names(host: str) -> frozenset[str]:
    """The names a request's Host may give for a door listening on `host`: the loopback
    names, and the address or name it was told to listen on (with this machine's own
    names when that is every address)."""
    names = set(LOOPBACK_NAMES)
    if host and host not in ("0.0.0.0", "::"):
        names.add(host.lower())
        if ":" in host:
            names.add(f"[{host.lower()}]")
    else:
        with contextlib.suppress(OSError):
            names.update({socket.gethostname().lower(), socket.getfqdn().lower()})
    return frozenset(names)


def same_origin(origin: str, host: str) -> bool:
    """A browser's Origin is the door's own when it is http:// and the Host it asked."""
    return origin.lower() == f"http://{host.lower()}"


def small_send_buffer(request: web.Request) -> None:
    transport = request.transport
    sock = transport.get_extra_info("socket") if transport is not None else None
    if sock is not None:
        with contextlib.suppress(OSError):
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, STREAM_SNDBUF)


def abort(handler: RequestHandler) -> None:
    """End a connection now, unsent output dropped (aiohttp's force_close alone waits
    for a reader that never reads to take it)."""
    transport = handler.transport
    if transport is not None:
        transport.abort()
    handler.force_close()


class Refused(asyncio.Protocol):
    """A connection over the door's cap: a 503, its request read and dropped, and closed
    after a moment (a close with its request unread would reset the connection before
    the client read why). More than REFUSING at once are closed at once: a flood never
    takes the server to EMFILE."""

    BODY = b'{"error": "too many connections to the control door", "status": 503}'
    REFUSING = 32
    LINGER = 0.2  # seconds a refused connection is given to read its 503
    refusing = 0

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self.transport = transport
        if Refused.refusing >= self.REFUSING:
            transport.abort()
            return
        Refused.refusing += 1
        self._counted = True
        with contextlib.suppress(Exception):
            transport.write(b"HTTP/1.1 503 Service Unavailable\r\nConnection: close\r\n"
                            b"Content-Type: application/json\r\n"
                            b"Content-Length: %d\r\n\r\n%s" % (len(self.BODY), self.BODY))
            transport.write_eof()
        asyncio.get_running_loop().call_later(self.LINGER, transport.abort)

    def data_received(self, data: bytes) -> None:
        """(Dropped: a refused request is not read.)"""

    def eof_received(self) -> bool:
        return False  # the client is done too: close

    def connection_lost(self, exc: BaseException | None) -> None:
        if getattr(self, "_counted", False):
            self._counted = False
            Refused.refusing -= 1


class GuardedHandler(RequestHandler):
    """aiohttp's own request handler, counted against the door's cap, with a deadline on
    a request's headers: from the connection's start (or from its first byte after a
    finished request) to the request reaching the door, `header_seconds`; a connection
    that sends its headers slower (slowloris) is closed."""

    def __init__(self, door: Counted, manager: web.Server, **kwargs: Any) -> None:
        super().__init__(manager, **kwargs)
        self._door = door
        self._header_since: float | None = None
        self._header_timer: asyncio.TimerHandle | None = None
        self._counted = True

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        super().connection_made(transport)
        self._headers_from_now()

    def connection_lost(self, exc: BaseException | None) -> None:
        if self._counted:
            self._counted = False
            self._door.open_connections -= 1
        if self._header_timer is not None:
            self._header_timer.cancel()
            self._header_timer = None
        super().connection_lost(exc)

    def data_received(self, data: bytes) -> None:
        if self._header_since is None and self._current_request is None and data:
            self._headers_from_now()
        super().data_received(data)

    def request_started(self) -> None:
        """The request's headers are in (the door's middleware says so)."""
        self._header_since = None
        if self._header_timer is not None:
            self._header_timer.cancel()
            self._header_timer = None

    def _headers_from_now(self) -> None:
        loop = asyncio.get_running_loop()
        self._header_since = loop.time()
        if self._header_timer is None:
            self._header_timer = loop.call_later(self._door.header_seconds, self._deadline)

    def _deadline(self) -> None:
        self._header_timer = None
        since = self._header_since
        if since is None or self._current_request is not None:
            return
        left = since + self._door.header_seconds - asyncio.get_running_loop().time()
        if left > 0:
            self._header_timer = asyncio.get_running_loop().call_later(left, self._deadline)
            return
        abort(self)


