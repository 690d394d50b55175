"""The 64-byte PoKeys frame, both ways (reference sections 1-2).

Request: [0]=0xBB [1]=command [2..5]=param1..4 [6]=request ID [7]=sum([0..6]) & 0xFF,
[8..63] payload. Reply: [0]=0xAA, the same ID in [6] and the header checksum in [7];
the host checks nothing else of the header. There is no payload checksum over Ethernet.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Final

FRAME: Final = 64
REQUEST_HEADER: Final = 0xBB
REPLY_HEADER: Final = 0xAA


def checksum(frame: bytes | bytearray) -> int:
    return sum(frame[0:7]) & 0xFF


@dataclass(frozen=True)
class Request:
    """One valid request frame (or the last frame of a multi-part request, with the
    parts' payloads joined in `data`)."""

    raw: bytes
    data: bytes | None = None

    @property
    def command(self) -> int:
        return self.raw[1]

    @property
    def sub(self) -> int:
        return self.raw[2]

    def param(self, n: int) -> int:
        """param1..param4 = bytes [2]..[5]."""
        return self.raw[1 + n]

    @property
    def request_id(self) -> int:
        return self.raw[6]

    @property
    def payload(self) -> bytes:
        return self.data if self.data is not None else self.raw[8:]

    def u8(self, offset: int) -> int:
        return self.raw[offset]

    def i32(self, offset: int) -> int:
        return int(struct.unpack_from("<i", self.raw, offset)[0])

    def i32s(self, offset: int, count: int) -> list[int]:
        return list(struct.unpack_from(f"<{count}i", self.raw, offset))

    def f32(self, offset: int) -> float:
        return float(struct.unpack_from("<f", self.raw, offset)[0])


def parse_request(frame: bytes | bytearray) -> Request | None:
    """A Request, or None for a frame the device ignores (wrong length, header, checksum)."""
    if len(frame) != FRAME or frame[0] != REQUEST_HEADER or frame[7] != checksum(frame):
        return None
    return Request(bytes(frame))


def make_request(command: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0,
                 request_id: int = 0, payload: bytes = b"") -> bytes:
    """A request frame as PoKeysLib's CreateRequest + SendEthRequest build it."""
    frame = bytearray(FRAME)
    frame[0:7] = bytes([REQUEST_HEADER, command, p1, p2, p3, p4, request_id & 0xFF])
    frame[7] = checksum(frame)
    frame[8:8 + len(payload)] = payload[:FRAME - 8]
    return bytes(frame)


def wrap32(value: int) -> int:
    """A count as a signed 32-bit register holds it."""
    return (value + 0x8000_0000) % 0x1_0000_0000 - 0x8000_0000


REFUSED: Final = 0x01
"""[2] of a refusal: a parameter out of range or a pin without that capability (D: the
status byte and value the single-pin requests 0x10/0x15/0x30/0x35/0x40 use)."""
UNKNOWN: Final = 0xFF
"""[2] of a refusal: no such command or sub-command on this device (D)."""


class Reply:
    """A reply under construction: [1..5] start as the request's, payload zeroed."""

    def __init__(self, request: Request) -> None:
        self.frame = bytearray(FRAME)
        self.frame[1:6] = request.raw[1:6]
        self.request_id = request.request_id
        self.refused = False  # refuse() made it the device's refusal

    def __setitem__(self, offset: int, value: int) -> None:
        self.frame[offset] = value & 0xFF

    def put(self, offset: int, data: bytes) -> None:
        self.frame[offset:offset + len(data)] = data

    def i32(self, offset: int, value: int) -> None:
        struct.pack_into("<i", self.frame, offset, value)

    def counters(self, offset: int, values: Sequence[int]) -> None:
        """Position counters: the device's are 32-bit and wrap (D), as a stage run for
        hours at 125 kHz passes 2^31 pulses; the motion itself keeps every pulse."""
        struct.pack_into(f"<{len(values)}i", self.frame, offset, *map(wrap32, values))

    def f32(self, offset: int, value: float) -> None:
        struct.pack_into("<f", self.frame, offset, value)

    def refuse(self, status: int) -> Reply:
        """Make this the device's refusal: the error status in [2], the payload zero."""
        self.frame[8:] = bytes(FRAME - 8)
        self.frame[2] = status & 0xFF
        self.refused = True
        return self

    def finish(self) -> bytes:
        self.frame[0] = REPLY_HEADER
        self.frame[6] = self.request_id
        self.frame[7] = checksum(self.frame)
        return bytes(self.frame)
