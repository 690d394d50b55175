"""The PoKeys as an I/O device: pins, digital and analog I/O, counters, PWM, encoders,
the real-time clock, PoExtBus, the matrix keyboard, the LCD, a PoNET kbd48CNC, failsafe
and the pulse engine's extra settings (backlash, synced PWM, PoStep).

Pins are numbered 1..55 as the device's documentation and its configuration software
name them; PoKeysLib's arrays are 0-based (pin p is `Pins[p - 1]`). Inputs come from the
shared `World` (world digital input p = pin p, analog channel p = pin p in volts) through
`PoKeysIOWorld` (world.py); outputs are kept here and shown in the world, the status and
the trace. Every setter validates first and changes nothing when it refuses (`IOError`).
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import json
import os
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Final

PINS: Final = 55

# PinFunction bits (PoKeysLib.h ePK_PinCap)
DIGITAL_INPUT: Final = 0x02
DIGITAL_OUTPUT: Final = 0x04
ANALOG_INPUT: Final = 0x08
ANALOG_OUTPUT: Final = 0x10
TRIGGERED_INPUT: Final = 0x20
DIGITAL_COUNTER: Final = 0x40
INVERT: Final = 0x80

FUNCTION_NAMES: Final = {DIGITAL_INPUT: "input", DIGITAL_OUTPUT: "output",
                         ANALOG_INPUT: "analog", ANALOG_OUTPUT: "analog-out",
                         TRIGGERED_INPUT: "triggered", 0: "inactive"}

PWM_CHANNELS: Final = 6
PWM_PINS: Final = (22, 21, 20, 19, 18, 17)  # channel n drives this pin (PK_FillPWMPinNumbers)
PWM_CLOCK_HZ: Final = 25_000_000  # PWMinternalFrequency of the 56 and 57 series
ENCODERS: Final = 26  # 25 basic (0..24) + the ultra-fast encoder (25)
ULTRA_FAST: Final = 25
ANALOG_PINS: Final = range(41, 48)  # AnalogIOGet reads Pins[40..46]
ANALOG_FULL_SCALE: Final = 3.3  # volts at code 4095 (D)
POEXTBUS: Final = 10
LCD_COLUMNS: Final = 20
LCD_ROWS: Final = 4
KBD48_KEYS: Final = 48
MATRIX_KEYS: Final = 128


class IOError(ValueError):  # noqa: A001 - the device's word for a refused set-up
    """A set-up or value the device refuses; nothing was changed."""


# ---- each model's pins (PoKeysLibDeviceData.c) -------------------------------------------
DI: Final = DIGITAL_INPUT | TRIGGERED_INPUT
DIO: Final = DIGITAL_INPUT | DIGITAL_OUTPUT | TRIGGERED_INPUT
CNT: Final = DIGITAL_COUNTER


def _cnc57_pins() -> dict[int, int]:
    """The 57CNC's pin descriptor: pins not listed are restricted (used by the board)."""
    caps: dict[int, int] = {}
    for p in (1, 2):
        caps[p] = DIO | CNT
    for p in (3, 4, 5, 6, 9, 10, 11, 15, 16, 19):
        caps[p] = DI | CNT
    for p in (8, 12, 13, 23, 24, 25, 26, 28, 29, 30, 31, 32):
        caps[p] = DIO
    for p in (14, 52):
        caps[p] = DI
    for p in (17, 21, 22):
        caps[p] = DIGITAL_OUTPUT
    for p in (18, 20):
        caps[p] = DIO
    for p in range(33, 39):
        caps[p] = DIO | CNT
    for p in range(41, 45):
        caps[p] = DIO | CNT | ANALOG_INPUT
    caps[45] = DIO | ANALOG_INPUT
    return caps


# counterSupported[] of PoKeysLibIO.c (56 and 57 series but the 57CNC), pins 1..55
_COUNTERS_56_57: Final = (
    1, 1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 0, 1, 0, 1, 1, 0, 0, 0, 0, 0, 0)


def _generic_pins() -> dict[int, int]:
    """56E / 57E: the library's pin-capability ranges (digital I/O on 1..55, analog
    inputs 41..47, counters per its table; triggered inputs are the USB models' only)."""
    caps = {}
    for p in range(1, PINS + 1):
        c = DIGITAL_INPUT | DIGITAL_OUTPUT
        if p in ANALOG_PINS:
            c |= ANALOG_INPUT
        if _COUNTERS_56_57[p - 1]:
            c |= CNT
        caps[p] = c
    return caps


def pin_capabilities(model: str) -> dict[int, int]:
    """pin (1..55) -> the PinFunction bits it can take (0: restricted)."""
    caps = _cnc57_pins() if model == "PoKeys57CNC" else _generic_pins()
    return {p: caps.get(p, 0) for p in range(1, PINS + 1)}


def check_function(pin: int, function: int, caps: int) -> str | None:
    """Why `function` cannot be set on `pin` (None: it can). One main function; invert
    goes with digital in/out and triggered inputs, the counter with a digital input."""
    if function == 0:
        return None
    if not 0 <= function <= 0xFF:
        return f"pin {pin}: a function is one byte, not {function}"
    main = function & (DIGITAL_INPUT | DIGITAL_OUTPUT | ANALOG_INPUT | ANALOG_OUTPUT
                       | TRIGGERED_INPUT)
    if main == 0 or main & (main - 1):
        return f"pin {pin}: one function at a time (0x{function:02x})"
    if function & 0x01:
        return f"pin {pin}: bit 0 is reserved"
    if not caps & main:
        return f"pin {pin} cannot be {FUNCTION_NAMES[main]}"
    if function & INVERT and main not in (DIGITAL_INPUT, DIGITAL_OUTPUT, TRIGGERED_INPUT):
        return f"pin {pin}: only a digital pin can be inverted"
    if function & DIGITAL_COUNTER and (main != DIGITAL_INPUT or not caps & DIGITAL_COUNTER):
        return f"pin {pin} cannot count"
    return None


# ---- the state -----------------------------------------------------------------------------
@dataclass
class Encoder:
    options: int = 0  # bit 0 enabled, 1 4x sampling, 2 2x sampling (library's encoderOptions)
    pin_a: int = 0
    pin_b: int = 0
    base: int = 0  # value when last loaded or detached
    axis: int | None = None  # the pulse-engine axis whose stage it reads
    axis_from: int = 0  # the stage when the count started
    direction: int = 1


@dataclass
class Lcd:
    configuration: int = 0  # 0 disabled, 1 enabled on the primary pins
    rows: int = 0
    columns: int = 0
    text: list[bytearray] = field(
        default_factory=lambda: [bytearray(b" " * LCD_COLUMNS) for _ in range(LCD_ROWS)])
    cursor: tuple[int, int] = (0, 0)  # row, column
    mode: int = 0
    display: tuple[int, int, int] = (1, 0, 0)
    entry: tuple[int, int] = (1, 0)
    custom: dict[int, bytes] = field(default_factory=dict)

    def clear(self) -> None:
        for row in self.text:
            row[:] = b" " * LCD_COLUMNS
        self.cursor = (0, 0)

    def lines(self) -> list[str]:
        rows = self.rows or LCD_ROWS
        cols = self.columns or LCD_COLUMNS
        return [bytes(r[:cols]).decode("latin-1") for r in self.text[:rows]]


@dataclass
class Kbd48:
    """A PoNET kbd48CNC on module ID 0: 48 keys the world presses, 48 LEDs the host sets."""

    keys: set[int] = field(default_factory=set)
    leds: bytes = bytes(16)
    pwm: int = 0
    light: int = 128  # light sensor reading (D)
    status_requested: bool = False
    light_requested: bool = False


CONFIG_FIELDS: Final = ("functions", "counter_options", "pwm_enabled", "pwm_duty",
                        "pwm_period", "encoder_setup", "fast_encoders", "ultra_fast",
                        "analog_filter", "matrix_config", "matrix_decimation", "lcd_setup",
                        "failsafe")


@dataclass
class DeviceIO:
    """Everything but the pulse engine, as one device keeps it."""

    model: str
    capabilities: dict[int, int] = field(init=False)
    functions: list[int] = field(default_factory=lambda: [0] * PINS)
    counter_options: list[int] = field(default_factory=lambda: [0] * PINS)
    outputs: list[bool] = field(default_factory=lambda: [False] * PINS)
    counters: list[int] = field(default_factory=lambda: [0] * PINS)
    pwm_enabled: int = 0
    pwm_duty: list[int] = field(default_factory=lambda: [0] * PWM_CHANNELS)
    pwm_period: int = 0
    synced_pwm: tuple[int, int, int] = (0, 0, 0)  # enabled, source axis, channel
    sync_outputs: bytes = bytes(10)
    encoders: list[Encoder] = field(default_factory=lambda: [Encoder() for _ in range(ENCODERS)])
    fast_encoders: tuple[int, int] = (0, 0)  # configuration, options
    ultra_fast: tuple[int, int, int] = (0, 0, 0)  # configuration, options, filter
    analog_filter: int = 0
    rtc_offset: float = 0.0  # seconds between the clock and 2018-01-10 00:00 at slot 0
    poextbus: bytes = bytes(POEXTBUS)
    matrix_config: bytes = bytes(42)  # CA 01 payload [8..49]
    matrix_decimation: int = 0
    matrix_keys: set[int] = field(default_factory=set)
    matrix_mapping: dict[int, bytes] = field(default_factory=dict)
    lcd: Lcd = field(default_factory=Lcd)
    kbd48: Kbd48 = field(default_factory=Kbd48)
    failsafe: bytes = bytes(25)  # [3], [4], then [8..30] of the 0x81 frame
    backlash: bytes = bytes(34)  # [3], [4], then [8..39]
    postep: bytes = bytes(25)  # enable, then 8 x (type, address, update)
    postep_currents: bytes = bytes(48)
    postep_modes: bytes = bytes(48)
    easy_sensors: dict[int, bytes] = field(default_factory=dict)
    poil_memory: dict[int, bytearray] = field(default_factory=dict)
    matrix_led: bytes = bytes(3)
    internal_drivers: bytes = bytes(8)
    matrix_led_data: dict[int, bytes] = field(default_factory=dict)
    poled: dict[int, int] = field(default_factory=dict)  # 0xE6 channel -> state
    i2c_active: int = 0
    onewire_active: int = 0
    saved: dict[str, Any] | None = None
    archive: str | None = None

    def __post_init__(self) -> None:
        self.capabilities = pin_capabilities(self.model)

    # ---- pins ------------------------------------------------------------------------
    def set_functions(self, functions: Sequence[int]) -> None:
        problems = [why for p, f in enumerate(functions[:PINS], 1)
                    if (why := check_function(p, f, self.capabilities[p]))]
        if problems:
            raise IOError("; ".join(problems))
        for i, f in enumerate(functions[:PINS]):
            if not f & DIGITAL_OUTPUT:
                self.outputs[i] = False
            self.functions[i] = f

    def set_function(self, pin: int, function: int) -> None:
        self._pin(pin)
        functions = list(self.functions)
        functions[pin - 1] = function
        self.set_functions(functions)

    def _pin(self, pin: int) -> None:
        if not 1 <= pin <= PINS:
            raise IOError(f"no pin {pin} (pins 1..{PINS})")

    def is_output(self, pin: int) -> bool:
        return bool(self.functions[pin - 1] & DIGITAL_OUTPUT)

    def output_level(self, pin: int) -> bool:
        """The level the pin drives (an inverted output drives the opposite)."""
        i = pin - 1
        if not self.functions[i] & DIGITAL_OUTPUT:
            return False
        return self.outputs[i] != bool(self.functions[i] & INVERT)

    def set_output(self, pin: int, value: bool) -> None:
        self._pin(pin)
        if not self.is_output(pin):
            raise IOError(f"pin {pin} is not a digital output")
        self.outputs[pin - 1] = bool(value)

    def counter_available(self, pin: int) -> bool:
        return 1 <= pin <= PINS and bool(self.capabilities[pin] & DIGITAL_COUNTER)

    def counts(self, pin: int) -> bool:
        return self.counter_available(pin) and bool(self.functions[pin - 1] & DIGITAL_COUNTER)

    # ---- PWM -------------------------------------------------------------------------
    def set_pwm(self, enabled: int, duties: Sequence[int], period: int,
                duties_only: bool = False) -> None:
        if not duties_only:
            for n in range(PWM_CHANNELS):
                pin = PWM_PINS[n]
                if enabled >> n & 1 and not self.capabilities.get(pin, 0) & DIGITAL_OUTPUT:
                    raise IOError(f"PWM channel {n} (pin {pin}) is not an output here")
            self.pwm_enabled, self.pwm_period = enabled & 0x3F, period & 0xFFFFFFFF
        self.pwm_duty = [d & 0xFFFFFFFF for d in duties[:PWM_CHANNELS]]

    def pwm_fraction(self, channel: int) -> float:
        """The channel's duty as a fraction of its period (0 when disabled)."""
        if not self.pwm_enabled >> channel & 1 or self.pwm_period == 0:
            return 0.0
        return min(1.0, self.pwm_duty[channel] / self.pwm_period)

    # ---- save / restore --------------------------------------------------------------
    def configuration(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for name in CONFIG_FIELDS:
            value: Any
            if name == "encoder_setup":
                value = [[e.options, e.pin_a, e.pin_b] for e in self.encoders]
            elif name == "lcd_setup":
                value = [self.lcd.configuration, self.lcd.rows, self.lcd.columns]
            else:
                value = getattr(self, name)
            if isinstance(value, bytes):
                value = value.hex()
            elif isinstance(value, (tuple, list)):
                value = list(value)
            out[name] = value
        return out

    def apply(self, config: dict[str, Any]) -> None:
        """Load a saved configuration (power-up with the flash's contents)."""
        fresh = DeviceIO(self.model)
        try:
            functions = [int(f) for f in config.get("functions", fresh.functions)][:PINS]
            fresh.set_functions(functions + [0] * (PINS - len(functions)))
            for name, mask in (("counter_options", 0xFF), ("pwm_duty", 0xFFFFFFFF)):
                values = [int(v) & mask for v in config.get(name, [])]
                target = getattr(fresh, name)
                target[:len(values)] = values[:len(target)]
            fresh.pwm_enabled = int(config.get("pwm_enabled", 0)) & 0x3F
            fresh.pwm_period = int(config.get("pwm_period", 0)) & 0xFFFFFFFF
            for e, (opt, a, b) in zip(fresh.encoders, config.get("encoder_setup", []),
                                      strict=False):
                e.options, e.pin_a, e.pin_b = int(opt) & 0xFF, int(a) & 0xFF, int(b) & 0xFF
            fe = config.get("fast_encoders", [0, 0])
            fresh.fast_encoders = (int(fe[0]) & 0xFF, int(fe[1]) & 0xFF)
            uf = config.get("ultra_fast", [0, 0, 0])
            fresh.ultra_fast = (int(uf[0]) & 0xFF, int(uf[1]) & 0xFF, int(uf[2]) & 0xFFFFFFFF)
            fresh.analog_filter = int(config.get("analog_filter", 0)) & 0xFFFFFFFF
            fresh.matrix_config = bytes.fromhex(config.get("matrix_config", ""))[:42].ljust(
                42, b"\0")
            fresh.matrix_decimation = int(config.get("matrix_decimation", 0)) & 0xFF
            lcd = config.get("lcd_setup", [0, 0, 0])
            fresh.lcd.configuration, fresh.lcd.rows, fresh.lcd.columns = (
                int(lcd[0]) & 0xFF, int(lcd[1]) & 0xFF, int(lcd[2]) & 0xFF)
            fresh.failsafe = bytes.fromhex(config.get("failsafe", ""))[:25].ljust(25, b"\0")
        except (TypeError, ValueError, IndexError, IOError):
            return  # a damaged archive: the device starts with factory defaults (D)
        for name in CONFIG_FIELDS:
            if name == "encoder_setup":
                for mine, new in zip(self.encoders, fresh.encoders, strict=True):
                    mine.options, mine.pin_a, mine.pin_b = new.options, new.pin_a, new.pin_b
            elif name == "lcd_setup":
                self.lcd.configuration = fresh.lcd.configuration
                self.lcd.rows, self.lcd.columns = fresh.lcd.rows, fresh.lcd.columns
            else:
                setattr(self, name, getattr(fresh, name))
        self.outputs = [False] * PINS

    def save(self) -> None:
        """PK_SaveConfiguration: the set-up survives a reset (and the run, with an archive
        file, written whole by rename so a crash leaves the old one)."""
        self.saved = self.configuration()
        if self.archive:
            directory = os.path.dirname(self.archive) or "."
            os.makedirs(directory, exist_ok=True)
            # mode 0600, as every file the server writes for its user (issue 34: this one
            # was 0644 beside the MAXk's 0600 archive)
            fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(self.archive)}.",
                                       suffix=".tmp", dir=directory)
            try:
                with os.fdopen(fd, "w", encoding="utf-8") as f:
                    json.dump(self.saved, f)
                os.replace(tmp, self.archive)
            except BaseException:
                with contextlib.suppress(OSError):
                    os.unlink(tmp)
                raise

    def load_archive(self) -> None:
        if not self.archive or not os.path.exists(self.archive):
            return
        try:
            if os.path.getsize(self.archive) > 1_000_000:
                return
            with open(self.archive, encoding="utf-8") as f:
                data = json.load(f)
        except (OSError, ValueError):
            return
        if isinstance(data, dict):
            self.saved = data
            self.apply(data)

    def clear_saved(self) -> None:
        """PK_ClearConfiguration: the flash holds the factory set-up again."""
        self.saved = DeviceIO(self.model).configuration()
        if self.archive and os.path.exists(self.archive):
            os.remove(self.archive)

    def power_up(self) -> None:
        """A reset: the saved set-up (or the factory one); counters and outputs zero."""
        keep = (self.saved, self.archive, self.rtc_offset)
        self.__dict__.update(DeviceIO(self.model).__dict__)
        self.saved, self.archive, self.rtc_offset = keep
        if self.saved is not None:
            self.apply(self.saved)


RTC_EPOCH: Final = _dt.datetime(2018, 1, 10)
"""The clock at power-up of a device nobody set (D: the 57CNC's firmware build date)."""


def rtc_now(io: DeviceIO, seconds: float) -> _dt.datetime:
    try:
        return RTC_EPOCH + _dt.timedelta(seconds=int(seconds + io.rtc_offset))
    except OverflowError:
        return RTC_EPOCH


def rtc_set(io: DeviceIO, seconds: float, when: _dt.datetime) -> None:
    io.rtc_offset = (when - RTC_EPOCH).total_seconds() - int(seconds)


def pressed_bits(keys: set[int], count: int) -> bytes:
    out = bytearray((count + 7) // 8)
    for k in keys:
        if 0 <= k < count:
            out[k // 8] |= 1 << (k % 8)
    return bytes(out)

