"""pyserial URL handler: `serial.serial_for_url("maxk://MAXk-4000")` is an in-process
controller (any model `maxk serve` knows, through the controller contract).

Registered the way pyserial documents for protocol handlers: importing maxk appends
"maxk.host" to `serial.protocol_handler_packages`, and pyserial then finds this module,
`maxk.host.protocol_maxk`, for the `maxk://` scheme. Legacy code that already opens its
port with `serial_for_url` changes only its port string (and imports maxk once, or runs
under `python -m maxk.host.pyserial_run script.py`).

URL: `maxk://[MODEL][?speed=K][&eol=lfcr|lf|crlf|cr][&ack][&framing=maxnet|pc68]`. The
board runs in real time (K times faster with speed), with the same framing as the TCP and
serial doors: replies end with LF CR by default and flag notifications arrive as
`%000 SSSSSSSS`; `framing=pc68` frames them as the older boards' hosts read them
(docs/doors.md), each `write()` being whole commands.
"""

from __future__ import annotations

import math
import threading
import time
import urllib.parse

import serial
from serial.serialutil import PortNotOpenError, SerialBase, SerialException

from maxk.commands.max.session import EOLS, FRAMINGS
from maxk.controllers.contract import BuildOptions, Controller, Session
from maxk.controllers.registry import DEFAULT_MODEL, build, canonical_model
from maxk.host.pacing import Pacer

POLL = 0.0005  # seconds between looks while a read waits (the wall clock is the door's)
MAX_INCOMING = 1 << 20  # unread bytes kept; beyond this the oldest are lost, as on a line


class Serial(SerialBase):
    """A serial port whose other end is an emulated MAXk."""

    is_open: bool
    _line_options: dict[str, str]

    def open(self) -> None:
        if self._port is None:
            raise SerialException("port must be configured before it can be used")
        if self.is_open:
            raise SerialException("port already open")
        model, speed, line_options = self._parse(self._port)
        if getattr(self, "controller", None) is None or self.controller.model != model:
            # The controller is powered as long as this object lives: closing and
            # reopening the port keeps its state, as unplugging a cable would.
            self.controller: Controller = build(model, BuildOptions(line_options=line_options))
            self.pacer = Pacer(self.controller, speed)
            self._incoming = bytearray()
            self._lock = threading.RLock()  # a reader thread and a writer may share it
            self.session: Session | None = None
        if self.session is None or line_options != self._line_options:
            if self.session is not None:
                self.session.close()
            framing = getattr(self.controller, "framing", None)
            if framing is not None:  # a MAXk: the URL's eol/ack frame its replies
                self.controller.framing = type(framing).from_options(  # type: ignore[attr-defined]
                    line_options)
            self.session = self.controller.open_session(notify=self._drain)
            self._line_options = line_options
        self.is_open = True

    def _drain(self) -> None:
        """The session has output (replies, notifications): keep it for read()."""
        if self.session is not None:
            self._receive(self.session.read())

    def _receive(self, data: bytes) -> None:
        self._incoming.extend(data)
        if len(self._incoming) > MAX_INCOMING:
            del self._incoming[: len(self._incoming) - MAX_INCOMING]

    @staticmethod
    def _parse(url: str) -> tuple[str, float, dict[str, str]]:
        parts = urllib.parse.urlsplit(url)
        if parts.scheme != "maxk":
            raise SerialException(f"expected a maxk:// URL, got {url!r}")
        name = (parts.netloc + parts.path).strip("/") or DEFAULT_MODEL
        try:
            model = canonical_model(name)
        except ValueError as error:
            raise SerialException(str(error)) from None
        options = urllib.parse.parse_qs(parts.query, keep_blank_values=True)
        unknown = set(options) - {"speed", "eol", "ack", "framing"}
        if unknown:
            raise SerialException(f"unknown maxk:// option {sorted(unknown)[0]!r} "
                                  "(speed, eol, ack, framing)")
        try:
            speed = float(options.get("speed", ["1"])[0])
        except ValueError:
            raise SerialException("speed must be a number") from None
        if not math.isfinite(speed) or speed <= 0:
            raise SerialException("speed must be a positive number")
        eol = options.get("eol", ["lfcr"])[0]
        if eol not in EOLS:
            raise SerialException(f"eol is one of {', '.join(sorted(EOLS))}")
        framing = options.get("framing", ["maxnet"])[0]
        if framing not in FRAMINGS:
            raise SerialException(f"framing is one of {', '.join(FRAMINGS)}")
        if framing != "maxnet" and "ack" in options:
            raise SerialException("ack is the MAXnet framing's")
        return model, speed, {"eol": eol, **({"ack": ""} if "ack" in options else {}),
                              **({"framing": framing} if framing != "maxnet" else {})}

    def close(self) -> None:
        self.is_open = False

    def _reconfigure_port(self) -> None:
        """Baud rate, parity and the rest mean nothing to an emulated line."""

    @property
    def in_waiting(self) -> int:
        if not self.is_open:
            raise PortNotOpenError()
        with self._lock:
            self.pacer.sync()
            return len(self._incoming)

    @property
    def out_waiting(self) -> int:
        return 0  # writes reach the board at once

    def write(self, data: bytes) -> int:
        if not self.is_open:
            raise PortNotOpenError()
        data = serial.to_bytes(data)
        with self._lock:
            self.pacer.sync()
            assert self.session is not None
            self.session.feed(data)
            self._drain()
        return len(data)

    def read(self, size: int = 1) -> bytes:
        if not self.is_open:
            raise PortNotOpenError()
        deadline = None if self._timeout is None else time.monotonic() + self._timeout
        self._cancel = False
        while True:
            with self._lock:
                self.pacer.sync()
                if len(self._incoming) >= size or self._cancel:
                    break
            if deadline is not None and time.monotonic() >= deadline:
                break
            time.sleep(POLL)
        with self._lock:
            data = bytes(self._incoming[:size])
            del self._incoming[:size]
        return data

    def cancel_read(self) -> None:
        self._cancel = True

    def reset_input_buffer(self) -> None:
        if not self.is_open:
            raise PortNotOpenError()
        with self._lock:
            self._incoming.clear()

    def reset_output_buffer(self) -> None:
        if not self.is_open:
            raise PortNotOpenError()

    def flush(self) -> None:
        """Writes reach the board at once."""

    @property
    def cts(self) -> bool:
        return True

    @property
    def dsr(self) -> bool:
        return True

    @property
    def ri(self) -> bool:
        return False

    @property
    def cd(self) -> bool:
        return True

    def _update_rts_state(self) -> None:
        pass

    def _update_dtr_state(self) -> None:
        pass

    def _update_break_state(self) -> None:
        """A break on the line resets the controller (decision D: the MAXk's reset is a
        DLL call with no ASCII form; a serial break is how a terminal sends one)."""
        if self._break_state and self.is_open:
            with self._lock:
                self.pacer.sync()
                self.controller.reset()

    def send_break(self, duration: float = 0.25) -> None:
        """Reset the board; no wall-clock wait (the emulated line needs none)."""
        if not self.is_open:
            raise PortNotOpenError()
        self.break_condition = True
        self.break_condition = False
