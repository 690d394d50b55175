"""A PoKeysLib-shaped host for the I/O functions, written from the library's source
(PoKeysLibIO.c, PoKeysLibEncoders.c, PoKeysLibRTC.c, ...): each method builds the
request the library's function builds and reads the reply the way it reads it, with its
result code. No emulator code is used; `Host` (pokeys_host.py) does the framing and the
library's resend rules.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field

from tests.pokeys_host import PK_ERR_GENERIC, PK_ERR_TRANSFER, PK_OK, Host

PIN_COUNT = 55  # info.iPinCount of the 56 and 57 series


@dataclass
class LibHost:
    host: Host
    pin_function: list[int] = field(default_factory=lambda: [0] * PIN_COUNT)
    counter_options: list[int] = field(default_factory=lambda: [0] * PIN_COUNT)
    digital_set: list[int] = field(default_factory=lambda: [0] * PIN_COUNT)
    digital_get: list[int] = field(default_factory=lambda: [0] * PIN_COUNT)
    analog: list[int] = field(default_factory=lambda: [0] * 7)
    pwm_enabled: list[int] = field(default_factory=lambda: [0] * 6)
    pwm_duty: list[int] = field(default_factory=lambda: [0] * 6)
    pwm_period: int = 0
    encoder_options: list[int] = field(default_factory=lambda: [0] * 25)
    encoder_values: list[int] = field(default_factory=lambda: [0] * 26)
    ultra_fast: tuple[int, int, int] = (0, 0, 0)
    fast: tuple[int, int] = (0, 0)

    def _send(self, cmd: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0,
              payload: bytes = b"") -> bytes | None:
        return self.host.send(self.host.create(cmd, p1, p2, p3, p4, payload))

    # ---- PoKeysLibIO.c ---------------------------------------------------------------
    def PK_PinConfigurationGet(self) -> int:
        r = self._send(0xC0, 0, 0)
        if r is None:
            return PK_ERR_TRANSFER
        self.pin_function = list(r[8:8 + PIN_COUNT])
        r = self._send(0xC0, 0, 1)  # iDigitalCounters
        if r is None:
            return PK_ERR_TRANSFER
        self.counter_options = list(r[8:8 + PIN_COUNT])
        return PK_OK

    def PK_PinConfigurationSet(self) -> int:
        if self._send(0xC0, 1, payload=bytes(self.pin_function)) is None:
            return PK_ERR_TRANSFER
        if self._send(0xC0, 0, 2, payload=bytes(self.counter_options)) is None:
            return PK_ERR_TRANSFER
        return PK_OK

    def _outputs_frame(self) -> bytes:
        frame = bytearray(56)
        for i, v in enumerate(self.digital_set):
            if v:
                frame[i // 8] |= 1 << (i % 8)
        return bytes(frame)

    def PK_DigitalIOSetGet(self) -> int:
        r = self._send(0xCC, 1, payload=self._outputs_frame())
        if r is None:
            return PK_ERR_TRANSFER
        self.digital_get = [r[8 + i // 8] >> (i % 8) & 1 for i in range(PIN_COUNT)]
        return PK_OK

    def PK_DigitalIOSet(self) -> int:
        return PK_OK if self._send(0xCC, 1, payload=self._outputs_frame()) else PK_ERR_TRANSFER

    def PK_DigitalIOGet(self) -> int:
        r = self._send(0xCC, 0)
        if r is None:
            return PK_ERR_TRANSFER
        self.digital_get = [r[8 + i // 8] >> (i % 8) & 1 for i in range(PIN_COUNT)]
        return PK_OK

    def PK_DigitalIOSetSingle(self, pin_id: int, value: int) -> int:
        r = self._send(0x40, pin_id, value)
        if r is None:
            return PK_ERR_TRANSFER
        return PK_ERR_GENERIC if r[2] else PK_OK

    def PK_DigitalIOGetSingle(self, pin_id: int) -> tuple[int, int]:
        r = self._send(0x30, pin_id)
        if r is None:
            return PK_ERR_TRANSFER, 0
        return (PK_ERR_GENERIC if r[2] else PK_OK), r[3]

    def PK_AnalogIOGet(self) -> int:
        r = self._send(0x3A, 1)
        if r is None:
            return PK_ERR_TRANSFER
        self.analog = [(r[8 + 2 * i] << 8) + r[9 + 2 * i] for i in range(7)]
        return PK_OK

    def PK_DigitalCounterGet(self, pin_ids: list[int]) -> dict[int, int] | int:
        r = self._send(0xD8, payload=bytes(pin_ids[:13]))
        if r is None:
            return PK_ERR_TRANSFER
        return {p: struct.unpack_from("<i", r, 8 + 4 * j)[0] for j, p in enumerate(pin_ids)}

    def PK_DigitalCounterClear(self) -> int:
        return PK_OK if self._send(0x1D) else PK_ERR_TRANSFER

    def _pwm_payload(self) -> bytes:
        mask = sum(1 << n for n in range(6) if self.pwm_enabled[n])
        return struct.pack("<B6II", mask, *self.pwm_duty, self.pwm_period)

    def PK_PWMConfigurationSet(self) -> int:
        return PK_OK if self._send(0xCB, 1, payload=self._pwm_payload()) else PK_ERR_TRANSFER

    def PK_PWMUpdate(self) -> int:
        return PK_OK if self._send(0xCB, 1, 1, payload=self._pwm_payload()) else PK_ERR_TRANSFER

    def PK_PWMConfigurationGet(self) -> int:
        r = self._send(0xCB, 0)
        if r is None:
            return PK_ERR_TRANSFER
        self.pwm_enabled = [r[8] >> n & 1 for n in range(6)]
        self.pwm_duty = list(struct.unpack_from("<6I", r, 9))
        self.pwm_period = struct.unpack_from("<I", r, 33)[0]
        return PK_OK

    # ---- PoKeysLibEncoders.c (a network device: no key mapping) -------------------------
    def PK_EncoderConfigurationSet(self) -> int:
        if self._send(0xC4, 1, payload=bytes(self.encoder_options)) is None:
            return PK_ERR_TRANSFER
        if self._send(0xC5, 1) is None:
            return PK_ERR_TRANSFER
        if self._send(0xCE, *self.fast) is None:
            return PK_ERR_TRANSFER
        c, o, f = self.ultra_fast
        if self._send(0x1C, c, o, payload=struct.pack("<I", f)) is None:
            return PK_ERR_TRANSFER
        return PK_OK

    def PK_EncoderConfigurationGet(self) -> int:
        r = self._send(0xC4, 0)
        if r is None or self._send(0xC5, 0) is None:
            return PK_ERR_TRANSFER
        self.encoder_options = list(r[8:33])
        r = self._send(0xCE, 2)
        if r is None:
            return PK_ERR_TRANSFER
        self.fast = (r[2], r[3])
        r = self._send(0x1C, 0xFF)
        if r is None:
            return PK_ERR_TRANSFER
        self.ultra_fast = (r[2], r[3], struct.unpack_from("<I", r, 8)[0])
        return PK_OK

    def PK_EncoderValuesGet(self) -> int:
        """25 basic encoders and the ultra-fast one: 0xCD 0, 0xCD 1, then 0x85 0x37."""
        r = self._send(0xCD, 0)
        if r is None:
            return PK_ERR_TRANSFER
        values = list(struct.unpack_from("<13I", r, 8))
        r = self._send(0xCD, 1)
        if r is None:
            return PK_ERR_TRANSFER
        values += list(struct.unpack_from("<13I", r, 8))
        self.encoder_values = [v - (1 << 32) if v >> 31 else v for v in values]
        self._send(0x85, 0x37)  # the library ignores a failure of this one
        return PK_OK

    def PK_EncoderValuesSet(self) -> int:
        low = [v & 0xFFFFFFFF for v in self.encoder_values]
        if self._send(0xCD, 10, payload=struct.pack("<13I", *low[:13])) is None:
            return PK_ERR_TRANSFER
        if self._send(0xCD, 11, payload=struct.pack("<13I", *low[13:26])) is None:
            return PK_ERR_TRANSFER
        return PK_OK

    # ---- PoKeysLibRTC.c ----------------------------------------------------------------
    def PK_RTCGet(self) -> dict[str, int] | int:
        r = self._send(0x83, 0)
        if r is None:
            return PK_ERR_TRANSFER
        return {"sec": r[8], "min": r[9], "hour": r[10], "dow": r[11], "dom": r[12],
                "month": r[13], "doy": r[14] | r[15] << 8, "year": r[16] | r[17] << 8}

    def PK_RTCSet(self, sec: int, minute: int, hour: int, dom: int, month: int,
                  year: int, dow: int = 0, doy: int = 0) -> int:
        payload = bytes([sec, minute, hour, dow, dom, month]) + struct.pack("<HH", doy, year)
        return PK_OK if self._send(0x83, 0x10, payload=payload) else PK_ERR_TRANSFER
