"""A PoKeys host written from shared/reference/pokeys-protocol.md alone (no emulator
code): the frames PoKeysLib builds and the rules it holds a reply to, over a Session
(feed/read). Between calls the test advances the device's time, as a door would.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from dataclasses import dataclass, field

PK_OK = 0
PK_ERR_GENERIC = -1
PK_ERR_TRANSFER = -10
PK_ERR_PARAMETER = -20


class Session:  # the door's contract, restated
    def feed(self, data: bytes) -> None: ...
    def read(self) -> bytes: ...


def header_sum(frame: bytes | bytearray) -> int:
    return sum(frame[0:7]) & 0xFF


@dataclass
class Host:
    session: Session
    request_id: int = 0  # the library starts wherever malloc left it; 0 here
    sent: list[bytes] = field(default_factory=list)
    tick: Callable[[], None] = lambda: None  # advances the device between frames

    # ---- SendEthRequest -------------------------------------------------------------
    def create(self, cmd: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0,
               payload: bytes = b"") -> bytearray:
        frame = bytearray(64)
        frame[1:6] = bytes([cmd, p1, p2, p3, p4])
        frame[8:8 + len(payload)] = payload
        return frame

    def send(self, frame: bytearray, sends: int = 5) -> bytes | None:
        """One request, resent with a new ID up to 5 times; the accepted reply or None."""
        for _ in range(sends):
            self.request_id = (self.request_id + 1) & 0xFF
            frame[0] = 0xBB
            frame[6] = self.request_id
            frame[7] = header_sum(frame)
            self.sent.append(bytes(frame))
            self.session.feed(bytes(frame))
            self.tick()
            reply = self.session.read()
            if not reply:
                continue  # silence: select() times out, the library resends
            assert len(reply) == 64, f"one 64-byte reply per request, got {len(reply)}"
            if reply[0] != 0xAA or reply[6] != self.request_id:
                continue
            assert reply[7] == header_sum(reply), "a reply with a bad checksum"
            return reply
        return None

    def send_multipart(self, header: bytearray, data: bytes) -> bytes | None:
        """PK_PEv2_BufferFillLarge: 8 frames in one send, each with a new ID; one reply."""
        frames = bytearray()
        for i in range(8):
            part = bytearray(header[:8]) + bytearray(56)
            part[0] = 0xBB
            part[2] = i | (0x08 if i == 0 else 0x10 if i == 7 else 0)
            self.request_id = (self.request_id + 1) & 0xFF
            part[6] = self.request_id
            part[7] = header_sum(part)
            part[8:64] = data[i * 56:(i + 1) * 56].ljust(56, b"\0")
            self.sent.append(bytes(part))
            frames += part
        self.session.feed(bytes(frames))
        self.tick()
        reply = self.session.read()
        if len(reply) != 64 or reply[0] != 0xAA or reply[6] != self.request_id:
            return None
        return reply

    # ---- PK_DeviceDataGet --------------------------------------------------------------
    def device_data_get(self) -> dict[str, object]:
        r = self.send(self.create(0x00))
        assert r is not None
        data: dict[str, object] = {"fw": (r[4], r[5])}
        extended = r[8:12] in (b"PKEx", b"PK58")
        if extended:
            data["serial"] = struct.unpack_from("<I", r, 12)[0]
            data["hw_type"] = r[18]
            data["build_date"] = r[20:31].rstrip(b"\0").decode()
            data["name_0x00"] = r[31:41].rstrip(b"\0").decode()
        else:
            data["serial"] = r[2] * 256 + r[3]
        r = self.send(self.create(0x03))
        assert r is not None
        data["user_id"], data["lock"] = r[2], r[3]
        network = extended and data["hw_type"] in (31, 32) or (
            not extended and 20000 <= int(data["serial"]) < 65536)  # type: ignore[call-overload]
        if network:
            r = self.send(self.create(0xE0))
            assert r is not None
            data["dhcp"], data["ip"] = r[8], tuple(r[13:17])
            data["tcp_timeout"] = r[17] | r[18] << 8
            data["options"] = r[27] if r[27] & 0xA0 == 0xA0 else 0
        r = self.send(self.create(0x06))
        assert r is not None
        long_name = r[8:18] == r[35:45]
        data["name"] = (r[35:55] if long_name else r[8:18]).rstrip(b"\0").decode()
        if not extended:
            date = b""
            for part in range(3):
                r = self.send(self.create(0x04, part))
                assert r is not None
                date += r[2:6] if part < 2 else r[2:5]
            data["build_date"] = date.decode()
        r = self.send(self.create(0x8F))
        assert r is not None
        data["options_8f"] = r[8]
        return data

    # ---- pulse engine v2 ----------------------------------------------------------------
    def pev2_status(self) -> dict[str, object] | int:
        test = (0x10 + self.request_id) % 199
        r = self.send(self.create(0x85, 0x00, test))
        if r is None:
            return PK_ERR_TRANSFER
        if r[63] != (test + 0x5A) & 0xFF:
            return PK_ERR_GENERIC
        return decode_status(r)

    def pev2(self, sub: int, p2: int = 0, p3: int = 0, p4: int = 0, payload: bytes = b""
             ) -> bytes | None:
        return self.send(self.create(0x85, sub, p2, p3, p4, payload))

    def buffer_fill(self, entries: list[list[int]], axes: int, wide: bool = False
                    ) -> tuple[int, dict[str, object]] | None:
        """PK_PEv2_BufferFill(_16): as many entries as fit in 56 bytes; (accepted, status)."""
        per = 56 // (axes * (2 if wide else 1))
        chunk = entries[:per]
        r = self.pev2(0xFE if wide else 0xFF, len(chunk), axes,
                      payload=encode_entries(chunk, wide))
        return None if r is None else (r[2], decode_status(r))

    def buffer_fill_large(self, entries: list[list[int]], axes: int, wide: bool = False
                          ) -> tuple[int, dict[str, object]] | None:
        per = 448 // (axes * (2 if wide else 1))
        chunk = entries[:per]
        header = self.create(0xB0, 0, 0xFE if wide else 0xFF, len(chunk), axes)
        r = self.send_multipart(header, encode_entries(chunk, wide))
        return None if r is None else (r[2], decode_status(r))


def encode_entries(entries: list[list[int]], wide: bool) -> bytes:
    out = bytearray()
    for entry in entries:
        for v in entry:
            if wide:
                out += struct.pack("<H", abs(v) | (0x8000 if v < 0 else 0))
            else:
                out.append(abs(v) | (0x80 if v < 0 else 0))
    return bytes(out)


def decode_status(r: bytes) -> dict[str, object]:
    """PK_PEv2_DecodeStatus."""
    return {
        "soft_limit": r[3], "axis_enabled_states": r[4], "limit_override": r[5],
        "enabled": r[8], "activated": r[9], "state": r[10], "charge_pump": r[11],
        "lim_p": r[12], "lim_n": r[13], "home": r[14], "generator": r[15],
        "axis_states": list(r[16:24]), "positions": list(struct.unpack_from("<8i", r, 24)),
        "info": (r[56], r[57], r[58], r[59]), "estop_polarity": r[60],
    }


def axis_config_payload(config: int, switches: int, homing: int = 50, back: int = 50,
                        max_speed: float = 10.0, accel: float = 0.05, decel: float = 0.05,
                        soft_min: int = -100000, soft_max: int = 100000) -> bytes:
    """Bytes [8..52] of AxisConfigurationSet ([44] always 0)."""
    raw = bytearray(45)
    raw[0], raw[1] = config, switches
    raw[5], raw[6] = homing, back
    struct.pack_into("<fffii", raw, 8, max_speed, accel, decel, soft_min, soft_max)
    return bytes(raw)
