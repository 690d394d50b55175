"""The PoKeys's I/O as a Python API (a mixin of `PoKeys`): pins, digital I/O, analog
inputs, counters, PWM, encoders, the clock. Each call is the request PoKeysLib sends,
through the device's own session, so the API exercises the same bytes as a host."""

from __future__ import annotations

import struct
from collections.abc import Sequence

from maxk.controllers.pokeys.status import PoKeysError
from maxk.personalities.pokeys.device import PoKeysDevice
from maxk.personalities.pokeys.io import PINS, check_function


class PoKeysIOApi:
    """The I/O calls; `PoKeys` gives `device` and `_ask`."""

    device: PoKeysDevice

    def _ask(self, what: str, command: int, p1: int = 0, p2: int = 0, p3: int = 0,
             p4: int = 0, payload: bytes = b"") -> bytes:  # pragma: no cover - PoKeys's
        raise NotImplementedError

    # ---- pins and I/O (each a real request) -----------------------------------------
    def pin_functions(self) -> list[int]:
        """PK_PinConfigurationGet: PinFunction bits of pins 1..55 (index 0 = pin 1)."""
        return list(self._ask("PinConfigurationGet", 0xC0)[8:8 + PINS])

    def set_pin_functions(self, functions: Sequence[int]) -> None:
        """PK_PinConfigurationSet: every pin at once (the device refuses the whole set-up
        when a pin cannot take its function)."""
        self._ask("PinConfigurationSet (a pin cannot take that function)", 0xC0, 1,
                  payload=bytes(functions[:PINS]))

    def set_pin_function(self, pin: int, function: int) -> None:
        if not 1 <= pin <= PINS:
            raise PoKeysError(f"no pin {pin} (pins 1..{PINS})")
        functions = self.pin_functions()
        functions[pin - 1] = function
        why = check_function(pin, function, self.device.io.capabilities[pin])
        if why:
            raise PoKeysError(why)
        self.set_pin_functions(functions)

    def digital_inputs(self) -> list[bool]:
        """PK_DigitalIOGet: every pin's level (index 0 = pin 1)."""
        r = self._ask("DigitalIOGet", 0xCC)
        return [bool(r[8 + i // 8] >> (i % 8) & 1) for i in range(PINS)]

    def set_output(self, pin: int, level: bool) -> None:
        """PK_DigitalIOSetSingle."""
        if not 1 <= pin <= PINS:
            raise PoKeysError(f"no pin {pin} (pins 1..{PINS})")
        r = self._ask("DigitalIOSetSingle", 0x40, pin - 1, 1 if level else 0)
        if r[2]:
            raise PoKeysError(f"pin {pin} is not a digital output (pin {pin} output)")

    def analog_inputs(self) -> dict[int, int]:
        """PK_AnalogIOGet: 12-bit codes of pins 41..47."""
        r = self._ask("AnalogIOGet", 0x3A, 1)
        return {41 + i: r[8 + 2 * i] << 8 | r[9 + 2 * i] for i in range(7)}

    def counters(self, pins: Sequence[int]) -> dict[int, int]:
        """PK_DigitalCounterGet for up to 13 pins."""
        pins = list(pins)[:13]
        if any(not 1 <= p <= PINS for p in pins):
            raise PoKeysError(f"pins are 1..{PINS}")
        r = self._ask("DigitalCounterGet", 0xD8, payload=bytes(p - 1 for p in pins))
        return {p: struct.unpack_from("<i", r, 8 + 4 * j)[0] for j, p in enumerate(pins)}

    def clear_counters(self) -> None:
        self._ask("DigitalCounterClear", 0x1D)

    def pwm(self) -> tuple[int, list[int], int]:
        """PK_PWMConfigurationGet: (enabled mask, duties, period) in 25 MHz clocks."""
        r = self._ask("PWMConfigurationGet", 0xCB)
        return r[8], list(struct.unpack_from("<6I", r, 9)), struct.unpack_from("<I", r, 33)[0]

    def set_pwm(self, enabled: int, duties: Sequence[int], period: int) -> None:
        """PK_PWMConfigurationSet."""
        payload = struct.pack("<B6II", enabled, *duties, period)
        self._ask("PWMConfigurationSet (a channel's pin cannot drive)", 0xCB, 1,
                  payload=payload)

    def encoder_values(self) -> list[int]:
        """PK_EncoderValuesGet: encoders 0..25 (25 the ultra-fast one), signed."""
        first = self._ask("EncoderValuesGet", 0xCD, 0)
        second = self._ask("EncoderValuesGet", 0xCD, 1)
        return list(struct.unpack_from("<13i", first, 8) + struct.unpack_from("<13i", second, 8))

    def set_encoder_options(self, encoder: int, options: int) -> None:
        """PK_EncoderConfigurationSet for one basic encoder (the others kept)."""
        if not 0 <= encoder < 25:
            raise PoKeysError("basic encoders are 0..24 (25 is the ultra-fast one)")
        current = bytearray(self._ask("EncoderConfigurationGet", 0xC4)[8:33])
        current[encoder] = options & 0xFF
        self._ask("EncoderConfigurationSet", 0xC4, 1, payload=bytes(current))

    def set_ultra_fast(self, configuration: int, options: int = 0, filter: int = 0) -> None:
        self._ask("EncoderConfigurationSet (ultra-fast)", 0x1C, configuration, options,
                  payload=struct.pack("<I", filter))

    def set_encoder(self, encoder: int, value: int) -> None:
        """PK_EncoderValuesSet for one encoder (the others keep their counts)."""
        values = self.encoder_values()
        values[encoder] = value
        self._ask("EncoderValuesSet", 0xCD, 10, payload=struct.pack("<13i", *values[:13]))
        self._ask("EncoderValuesSet", 0xCD, 11, payload=struct.pack("<13i", *values[13:]))

    def rtc(self) -> str:
        """PK_RTCGet as text: YYYY-MM-DD HH:MM:SS."""
        r = self._ask("RTCGet", 0x83)
        year = r[16] | r[17] << 8
        return f"{year:04d}-{r[13]:02d}-{r[12]:02d} {r[10]:02d}:{r[9]:02d}:{r[8]:02d}"

    def lcd_lines(self) -> list[str]:
        return self.device.io.lcd.lines()

    def save_configuration(self) -> None:
        self._ask("SaveConfiguration", 0x50, 0xAA, 0x55)

