"""A host connection: TCP stream (or UDP datagrams) cut into 64-byte frames, one
64-byte reply per valid request, never anything unsolicited (reference 1-3)."""

from __future__ import annotations

from ...personalities.pokeys.device import PoKeysDevice
from .device_commands import discovery_reply
from .packet import FRAME, Request, parse_request
from .table import MULTIPART, dispatch

FIRST_PART = 0x08
LAST_PART = 0x10
PARTS = 8


DISCOVERY_HOST_IP = (127, 0, 0, 1)
"""The host address a discovery answer names when the door does not say (D)."""


class PoKeysSession:
    """feed() the host's bytes in any split; read() what the device sends back.

    The door advances the device's time (``device.run_to``) before feeding; replies are
    computed at the device's present slot. An empty feed is a zero-length UDP datagram,
    i.e. discovery (reference 5): it is answered with the discovery form (19 bytes on the
    57 series, 14 on the 56E). A TCP stream never delivers an empty feed.

    ``datagrams=True``: every feed is one whole datagram (UDP): a datagram that is not
    64 or 8 x 64 bytes is ignored whole, so a stray short one cannot misalign the next.
    """

    def __init__(self, device: PoKeysDevice, datagrams: bool = False,
                 host_ip: tuple[int, int, int, int] = DISCOVERY_HOST_IP) -> None:
        self.device = device
        self.datagrams = datagrams
        self.host_ip = host_ip
        self._pending = bytearray()
        self._out = bytearray()
        self._parts: list[Request] = []
        self.silenced = 0  # frames that got no reply (for tests and doors' logs)
        self.closed = False

    def feed(self, data: bytes) -> None:
        if self.closed:
            return
        if not data:
            self._out += self.discovery(self.host_ip)
            return
        if self.datagrams:
            if len(data) not in (FRAME, FRAME * PARTS):
                self.silenced += 1
                return
            self._pending.clear()
        self._pending += data
        while len(self._pending) >= FRAME:
            frame = bytes(self._pending[:FRAME])
            del self._pending[:FRAME]
            self._frame(frame)

    def close(self) -> None:
        """The host went away; nothing more is answered."""
        self.closed = True
        self._pending.clear()
        self._out.clear()

    def read(self) -> bytes:
        out = bytes(self._out)
        self._out.clear()
        return out

    def discovery(self, host_ip: tuple[int, int, int, int]) -> bytes:
        """The answer to a zero-length discovery datagram from host_ip."""
        return discovery_reply(self.device, host_ip)

    def _frame(self, frame: bytes) -> None:
        request = parse_request(frame)
        if request is None:
            self._parts.clear()
            self.silenced += 1
            return
        if request.command == MULTIPART:
            request = self._multipart(request)
            if request is None:
                return
        reply = dispatch(self.device, request)
        if reply is None:
            self.silenced += 1
        else:
            self._out += reply

    def _multipart(self, part: Request) -> Request | None:
        """Collect the 8 frames of a 0xB0 request; the whole answers once, to the last."""
        flags, index = part.sub & 0x18, part.sub & 0x07
        if flags & FIRST_PART:
            self._parts = []
        if index != len(self._parts) or (self._parts and
                                         part.raw[3:6] != self._parts[0].raw[3:6]):
            self._parts.clear()
            self.silenced += 1
            return None
        self._parts.append(part)
        if not flags & LAST_PART:
            return None
        parts, self._parts = self._parts, []
        if len(parts) != PARTS or not parts[0].sub & FIRST_PART:
            self.silenced += 1
            return None
        return Request(part.raw, data=b"".join(p.raw[8:] for p in parts))
