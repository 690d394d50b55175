"""The console's words for the PoKeys as an I/O device: pins, digital I/O, analog
inputs, counters, PWM, encoders, the LCD, keys and the clock (a mixin of
`PoKeysConsole`, which gives `dev` and `_axis`). Each word is real requests through the
Python API, or a change of the world (`analog`, `key`, `kbd48`, `encoder N on X`)."""

from __future__ import annotations

from maxk.controllers.pokeys.status import ConsoleError, PoKeysControls, on_off
from maxk.personalities.pokeys import AXIS_LETTERS
from maxk.personalities.pokeys.io import (
    ANALOG_FULL_SCALE,
    ANALOG_INPUT,
    DIGITAL_COUNTER,
    DIGITAL_INPUT,
    DIGITAL_OUTPUT,
    ENCODERS,
    INVERT,
    PINS,
    PWM_CHANNELS,
    PWM_CLOCK_HZ,
    PWM_PINS,
    TRIGGERED_INPUT,
    ULTRA_FAST,
)

PIN_FUNCTIONS = {"input": DIGITAL_INPUT, "output": DIGITAL_OUTPUT, "analog": ANALOG_INPUT,
                 "counter": DIGITAL_INPUT | DIGITAL_COUNTER, "triggered": TRIGGERED_INPUT,
                 "inactive": 0}
PIN_WORDS = {DIGITAL_INPUT: "input", DIGITAL_OUTPUT: "output", ANALOG_INPUT: "analog",
             DIGITAL_COUNTER: "counter", TRIGGERED_INPUT: "triggered"}


def _pin_line(pin: int, function: int) -> str:
    names = [n for bit, n in PIN_WORDS.items() if function & bit and bit != DIGITAL_INPUT
             or (bit == DIGITAL_INPUT and function & bit and not function & DIGITAL_COUNTER)]
    return f"pin {pin}: {' '.join(names) or 'inactive'}" + (" inverted" if function & INVERT
                                                             else "")


IO_WORDS: dict[str, tuple[str, str]] = {
    "pin": ("pin [N [input|output|analog|counter|triggered|inactive [invert]]]",
            "pin functions (PinConfigurationGet/Set); pin alone lists the pins in use"),
    "out": ("out N on|off", "drive a digital output pin (DigitalIOSetSingle)"),
    "io": ("io", "every pin in use with its level (DigitalIOGet)"),
    "analog": ("analog [N VOLTS]", "AnalogIOGet codes, or set pin N's voltage in the world"),
    "counter": ("counter N [M ...] | counter clear", "digital counters (DigitalCounterGet)"),
    "pwm": ("pwm | pwm period CLOCKS | pwm N DUTY|P%|off",
            "PWM channels 0..5 (pins 22..17), 25 MHz clocks"),
    "encoder": ("encoder | encoder N on X [reverse] | encoder N off | "
                "encoder N enable|disable | encoder N set V",
                "encoder values; wire an encoder to an axis's stage in the world"),
    "lcd": ("lcd", "the text on the LCD as the host wrote it"),
    "key": ("key ROW COL on|off", "press a matrix keyboard key in the world"),
    "kbd48": ("kbd48 K on|off", "press key K (0..47) of the PoNET kbd48CNC in the world"),
    "rtc": ("rtc", "the real-time clock (RTCGet)"),
    "save": ("save", "SaveConfiguration: the set-up survives a reset"),
}


class IOWords:
    """The I/O words; `PoKeysConsole` mixes them in."""

    dev: PoKeysControls

    def _axis(self, name: str) -> int:  # pragma: no cover - PoKeysConsole gives it
        raise NotImplementedError

    def _io_status(self) -> list[str]:
        """`status`'s I/O lines: the output pins' levels and the PWM channels' duty (only
        when some are set up)."""
        device = self.dev.device
        lines = []
        outputs = device.pins.output_levels()
        if outputs:
            lines.append("outputs " + " ".join(f"{p}:{int(v)}" for p, v in outputs.items()))
        pwm = [f"{n}:{device.pwm_output(n) * 100:.1f}%" for n in range(PWM_CHANNELS)
               if device.io.pwm_enabled >> n & 1]
        if pwm:
            lines.append("pwm " + " ".join(pwm))
        return lines

    # ---- pins and I/O --------------------------------------------------------------------
    def _pin(self, word: str) -> int:
        pin = int(word)
        if not 1 <= pin <= PINS:
            shown = word if len(word) <= 12 else word[:12] + "..."
            raise ConsoleError(f"no pin {shown} (pins 1..{PINS})")
        return pin

    def _do_pin(self, args: list[str]) -> list[str]:
        functions = self.dev.pin_functions()
        if not args:
            used = [p for p in range(1, PINS + 1) if functions[p - 1]]
            return [_pin_line(p, functions[p - 1]) for p in used] or ["no pin in use"]
        pin = self._pin(args[0])
        if len(args) == 1:
            caps = self.dev.device.io.capabilities[pin]
            can = ", ".join(n for bit, n in PIN_WORDS.items() if bit and caps & bit) or "nothing"
            return [_pin_line(pin, functions[pin - 1]), f"  can be: {can}"]
        words = [a.lower() for a in args[1:]]
        invert = "invert" in words
        words = [w for w in words if w != "invert"]
        if len(words) != 1 or words[0] not in PIN_FUNCTIONS:
            raise ConsoleError(f"pin: say {IO_WORDS['pin'][0]}")
        self.dev.set_pin_function(pin, PIN_FUNCTIONS[words[0]] | (INVERT if invert else 0))
        return []

    def _do_out(self, args: list[str]) -> list[str]:
        pin, level = args
        self.dev.set_output(self._pin(pin), on_off(level))
        return []

    def _do_io(self, args: list[str]) -> list[str]:
        functions = self.dev.pin_functions()
        levels = self.dev.digital_inputs()
        used = [p for p in range(1, PINS + 1)
                if functions[p - 1] & (DIGITAL_INPUT | DIGITAL_OUTPUT | TRIGGERED_INPUT)]
        if not used:
            return ["no digital pin in use (pin N input|output)"]
        ins = [f"{p}:{int(levels[p - 1])}" for p in used if not functions[p - 1] & DIGITAL_OUTPUT]
        outs = [f"{p}:{int(levels[p - 1])}" for p in used if functions[p - 1] & DIGITAL_OUTPUT]
        return [f"inputs {' '.join(ins) or '-'}", f"outputs {' '.join(outs) or '-'}"]

    def _do_analog(self, args: list[str]) -> list[str]:
        if args:
            pin, volts = args
            self.dev.device.pins.analog(self._pin(pin), float(volts))
            return []
        codes = self.dev.analog_inputs()
        functions = self.dev.pin_functions()
        used = [p for p in codes if functions[p - 1] & ANALOG_INPUT]
        if not used:
            return ["no analog pin in use (pin 41 analog)"]
        return [" ".join(f"{p}:{codes[p]} ({codes[p] * ANALOG_FULL_SCALE / 4095:.3f} V)"
                         for p in used)]

    def _do_counter(self, args: list[str]) -> list[str]:
        if args and args[0].lower() == "clear":
            self.dev.clear_counters()
            return []
        if not args:
            raise ConsoleError(f"counter: say {IO_WORDS['counter'][0]}")
        counts = self.dev.counters([self._pin(a) for a in args])
        return [" ".join(f"{p}:{v}" for p, v in counts.items())]

    def _do_pwm(self, args: list[str]) -> list[str]:
        enabled, duties, period = self.dev.pwm()
        if not args:
            head = f"period {period} clocks ({PWM_CLOCK_HZ / period:g} Hz)" if period else \
                "period 0"
            chans = [f"{n} (pin {PWM_PINS[n]}) {duties[n]} = "
                     f"{self.dev.device.pwm_output(n) * 100:.1f}%"
                     for n in range(PWM_CHANNELS) if enabled >> n & 1]
            return [head] + (chans or ["no channel enabled (pwm N DUTY)"])
        if args[0].lower() == "period":
            (value,) = args[1:]
            self.dev.set_pwm(enabled, duties, int(value))
            return []
        channel, value = int(args[0]), args[1].lower()
        if not 0 <= channel < PWM_CHANNELS:
            raise ConsoleError(f"PWM channels are 0..{PWM_CHANNELS - 1}")
        if value == "off":
            enabled &= ~(1 << channel)
        else:
            if value.endswith("%"):
                fraction = float(value[:-1]) / 100
                if not 0 <= fraction <= 1:
                    raise ConsoleError("a duty in percent is 0..100%")
                duties[channel] = round(fraction * period)
            else:
                duties[channel] = int(value)
            enabled |= 1 << channel
        self.dev.set_pwm(enabled, duties, period)
        return []

    def _do_encoder(self, args: list[str]) -> list[str]:
        pins = self.dev.device.pins
        if not args:
            values = self.dev.encoder_values()
            io = self.dev.device.io
            shown = [i for i, e in enumerate(io.encoders)
                     if values[i] or e.axis is not None or pins.encoder_counting(i)]
            if not shown:
                return ["no encoder counting (encoder N on X, encoder N enable)"]
            lines = []
            for i in shown:
                axis = io.encoders[i].axis
                lines.append(f"{i}: {values[i]}" + ("" if axis is None else
                                                    f" on {AXIS_LETTERS[axis]}")
                             + ("" if pins.encoder_counting(i) else " (disabled)"))
            return lines
        n = int(args[0])
        if not 0 <= n < ENCODERS:
            raise ConsoleError(f"encoders are 0..{ENCODERS - 1}")
        what = [a.lower() for a in args[1:]]
        if what[:1] == ["on"] and len(what) in (2, 3):
            reverse = what[2:] == ["reverse"]
            if len(what) == 3 and not reverse:
                raise ConsoleError(f"encoder: say {IO_WORDS['encoder'][0]}")
            pins.attach_encoder(n, self._axis(what[1]), -1 if reverse else 1)
        elif what == ["off"]:
            pins.attach_encoder(n, None)
        elif what in (["enable"], ["disable"]):
            if n == ULTRA_FAST:
                self.dev.set_ultra_fast(1 if what[0] == "enable" else 0)
            else:
                self.dev.set_encoder_options(n, 1 if what[0] == "enable" else 0)
        elif what[:1] == ["set"] and len(what) == 2:
            self.dev.set_encoder(n, int(what[1]))
        else:
            raise ConsoleError(f"encoder: say {IO_WORDS['encoder'][0]}")
        return []

    def _do_lcd(self, args: list[str]) -> list[str]:
        return [f"|{line}|" for line in self.dev.device.io.lcd.lines()]

    def _do_key(self, args: list[str]) -> list[str]:
        row, col, level = args
        r, c = int(row), int(col)
        if not (0 <= r < 16 and 0 <= c < 8):
            raise ConsoleError("matrix keys are rows 0..15, columns 0..7")
        self.dev.device.pins.press_key(r * 8 + c, on_off(level))
        return []

    def _do_kbd48(self, args: list[str]) -> list[str]:
        key, level = args
        self.dev.device.pins.press_kbd48(int(key), on_off(level))
        return []

    def _do_rtc(self, args: list[str]) -> list[str]:
        return [self.dev.rtc()]

    def _do_save(self, args: list[str]) -> list[str]:
        self.dev.save_configuration()
        return []

