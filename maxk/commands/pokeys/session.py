"""A host connection: TCP stream (or UDP datagrams) cut into 64-byte frames, one
64-byte reply per valid request, never anything unsolicited (reference 1-3)."""

from __future__ import annotations

from ...personalities.pokeys.device import PoKeysDevice
from .device_commands import discovery_reply
from .packet import FRAME, Reply, Request, parse_request
from .table import MULTIPART, answer

FIRST_PART = 0x08
LAST_PART = 0x10
PARTS = 8


DISCOVERY_TEXT = b"Discovery request"
"""The 17-byte text form of discovery that hosts of their own send to port 20055 (a
home-automation plugin's only way to find its device); the empty datagram is PoKeysLib's.
Both get the same answer (reference 5)."""


def is_discovery(datagram: bytes) -> bool:
    """A discovery datagram: empty, or the text form (a trailing NUL, CR or LF allowed)."""
    return not datagram or datagram.rstrip(b"\0\r\n") == DISCOVERY_TEXT


DISCOVERY_HOST_IP = (127, 0, 0, 1)
"""The host address a discovery answer names when the door does not say (D)."""


class PoKeysSession:
    """feed() the host's bytes in any split; read() what the device sends back.

    The door advances the device's time (``device.run_to``) before feeding; replies are
    computed at the device's present slot. An empty feed is a zero-length UDP datagram,
    i.e. discovery (reference 5): it is answered with the discovery form (19 bytes on the
    57 series, 14 on the 56E); so is the text form `Discovery request`, as a datagram or
    on a TCP stream (between frames). A TCP stream never delivers an empty feed.

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
        self._broken = False  # a 0xB0 group lost a frame: refused at its last
        self.silenced = 0  # frames the device could not take: no reply (tests, logs)
        self.refused = 0  # requests answered with the device's refusal
        self.closed = False

    def feed(self, data: bytes) -> None:
        if self.closed:
            return
        if not data or (self.datagrams and is_discovery(data)):
            self._out += self.discovery(self.host_ip)
            return
        if self.datagrams:
            if len(data) not in (FRAME, FRAME * PARTS):
                self.silenced += 1
                return
            self._pending.clear()
        self._pending += data
        while self._pending[:1] == DISCOVERY_TEXT[:1]:
            # the text form on a stream: answered once whole (a frame starts with 0xBB)
            if not DISCOVERY_TEXT.startswith(bytes(self._pending[:len(DISCOVERY_TEXT)])):
                self._pending.clear()  # not a request at all: dropped, no reply
                self.silenced += 1
                return
            if len(self._pending) < len(DISCOVERY_TEXT):
                return
            del self._pending[:len(DISCOVERY_TEXT)]
            while self._pending[:1] in (b"\0", b"\r", b"\n"):
                del self._pending[:1]
            self._out += self.discovery(self.host_ip)
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
            self._broken = bool(self._parts)  # a 0xB0 group under way lost this frame
            self._parts.clear()
            self.silenced += 1  # the device cannot take it as a request: no reply
            return
        self.device.failsafe.contact()  # a host spoke: the failsafe timeout starts again
        if request.command == MULTIPART:
            whole = self._multipart(request)
            if whole is None:
                return
            request = whole
        reply, refused = answer(self.device, request)
        self.refused += refused
        self._out += reply

    def _multipart(self, part: Request) -> Request | None:
        """Collect the 8 frames of a 0xB0 request; the whole answers once, to the last.
        A group that arrives incomplete or out of order is refused at its last frame
        (a reply with that frame's ID, 0 accepted, D); a frame before the last waits."""
        flags, index = part.sub & 0x18, part.sub & 0x07
        if flags & FIRST_PART:
            self._parts = []
            self._broken = False
        if index != len(self._parts) or (self._parts and
                                         part.raw[3:6] != self._parts[0].raw[3:6]):
            self._broken = True
        elif not self._broken:
            self._parts.append(part)
        if not flags & LAST_PART:
            return None
        parts, self._parts = self._parts, []
        broken, self._broken = self._broken, False
        if broken or len(parts) != PARTS or not parts[0].sub & FIRST_PART:
            self._out += Reply(part).refuse(0).finish()  # 0 accepted
            self.refused += 1
            return None
        return Request(part.raw, data=b"".join(p.raw[8:] for p in parts))
