"""A PoKeys device behind the controller contract, and its Python API in virtual time.

    >>> from maxk.controllers.pokeys import PoKeys
    >>> dev = PoKeys("PoKeys57CNC")
    >>> dev.setup(3)
    >>> dev.configure_axis(0, internal=True, max_speed=10, accel=0.05)
    >>> dev.set_state("running")
    >>> dev.move({0: 1000})
    >>> dev.run_until_idle()
    True
    >>> dev.status().positions[0]
    1000

Every API call is a real 64-byte request through the device's own session (the bytes a
PoKeysLib host sends), so the API, the console, the doors and the tests all exercise the
same language; nothing here reads the wall clock: time moves when you advance it.
"""

from __future__ import annotations

import math
import struct
from collections.abc import Mapping, Sequence

from maxk.commands.pokeys import PoKeysSession, make_request
from maxk.commands.pokeys.device_commands import discovery_reply
from maxk.commands.pokeys.session import DISCOVERY_HOST_IP, is_discovery
from maxk.controllers.contract import BuildOptions, Notify, Transport
from maxk.controllers.pokeys.console import PoKeysConsole
from maxk.controllers.pokeys.io_api import PoKeysIOApi
from maxk.controllers.pokeys.status import (
    V1_STATES,
    V2_STATES,
    EngineStatus,
    PoKeysError,
    axis_index,
)
from maxk.controllers.pokeys.world_view import PoKeysWorldView
from maxk.firmware_model.world import AxisWorld, World
from maxk.personalities.pokeys import (
    MODELS,
    AxisConfigBits,
    PoKeysDevice,
    SharedWorld,
    SlotEngine,
    SwitchBits,
    pokeys_world,
)
from maxk.personalities.pokeys.constants import SLOT_SECONDS
from maxk.personalities.pokeys.engine import PulseEngine
from maxk.personalities.pokeys.world import PoKeysIOWorld


class PoKeys(PoKeysIOApi):
    """A PoKeys56E (pulse engine v1) or PoKeys57E / 57CNC (v2): the door contract and a
    Python API speaking the device's requests in virtual time."""

    kind = "PoKeys"
    transports: tuple[Transport, ...] = ("tcp", "udp")
    packet_size = 64

    def __init__(self, model: str = "PoKeys57CNC", world: World | None = None,
                 serial: int | None = None) -> None:
        if model not in MODELS:
            raise ValueError(f"unknown PoKeys model {model!r} (models: {', '.join(MODELS)})")
        self.device = PoKeysDevice.create(model, None if world is None else SharedWorld(world),
                                          serial)
        self._session = PoKeysSession(self.device)
        self.last_refused = False  # the last request() got the device's refusal
        self._request_id = 0
        self._console: PoKeysConsole | None = None

    # ---- the door contract ---------------------------------------------------------
    @property
    def model(self) -> str:
        return self.device.identity.model

    @property
    def engine(self) -> SlotEngine:
        return self.device.machine

    def open_session(self, notify: Notify | None = None) -> PoKeysSession:
        """A host's session: 64-byte requests in, one 64-byte reply each, silence on
        invalid ones; a PoKeys never speaks unasked, so `notify` is never called."""
        return PoKeysSession(self.device)

    def open_datagram_session(self) -> PoKeysSession:
        """A UDP peer's session: each feed is one datagram (odd sizes ignored whole)."""
        return PoKeysSession(self.device, datagrams=True)

    def is_discovery(self, datagram: bytes) -> bool:
        """Whether a datagram asks who is there (empty, or the text "Discovery request"):
        the UDP door then lets every served device that answers discovery answer, as
        every PoKeys on a network answers a broadcast."""
        return is_discovery(datagram)

    def discovery_answer(self, datagram: bytes, peer: object) -> bytes | None:
        """This device's answer to a discovery datagram from `peer` (an (ip, port)
        pair): the 19-byte form (14 on the 56E) naming the peer as the host."""
        if not is_discovery(datagram):
            return None
        return discovery_reply(self.device, _ipv4(peer))

    def console(self) -> PoKeysConsole:
        """A person's view (the REPL, command scripts): a small command language. One
        per device, so the stops it reports are not heard twice."""
        if self._console is None:
            self._console = PoKeysConsole(self)
        return self._console

    def reset(self) -> None:
        """Power the device up again: the pulse engine stops with an empty buffer, its
        counters at 0 and its configuration lost; name and network setup are kept."""
        self.device.power_up()

    # ---- what is inside -----------------------------------------------------------
    @property
    def pulse_engine(self) -> PulseEngine:
        return self.device.engine

    @property
    def version(self) -> int:
        return self.device.engine.spec.version

    @property
    def axes(self) -> int:
        return self.device.engine.spec.axes

    @property
    def world(self) -> World:
        world = self.device.machine.world
        if world is None:
            raise ValueError("this device runs on a bench world of its own")
        return world

    # ---- requests -----------------------------------------------------------------
    def request(self, command: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0,
                payload: bytes = b"") -> bytes | None:
        """One request frame with the next ID; the 64-byte reply, or None (silence)."""
        self._request_id = (self._request_id + 1) & 0xFF
        refused = self._session.refused
        self._session.feed(make_request(command, p1, p2, p3, p4, self._request_id, payload))
        reply = self._session.read()
        self.last_refused = self._session.refused != refused
        return reply or None

    def _ask(self, what: str, command: int, p1: int = 0, p2: int = 0, p3: int = 0,
             p4: int = 0, payload: bytes = b"") -> bytes:
        reply = self.request(command, p1, p2, p3, p4, payload)
        if reply is None:
            raise PoKeysError(f"no reply to {what} (the device ignores it)")
        if self.last_refused:
            raise PoKeysError(f"{what} refused (status {reply[2]} in the reply)")
        return reply

    def _pev2(self, what: str, sub: int, p2: int = 0, p3: int = 0, p4: int = 0,
              payload: bytes = b"") -> bytes:
        if self.version != 2:
            raise PoKeysError(f"{what}: the {self.model} has pulse engine v1")
        return self._ask(what, 0x85, sub, p2, p3, p4, payload)

    def _pev1(self, what: str, sub: int, p2: int = 0, p3: int = 0, payload: bytes = b""
              ) -> bytes:
        return self._ask(what, 0x80, sub, p2, p3, 0, payload)

    # ---- time ---------------------------------------------------------------------
    @property
    def slot(self) -> int:
        return self.device.machine.tick

    @property
    def time(self) -> float:
        return self.device.machine.time

    def advance(self, seconds: float = 0.0, *, slots: int = 0) -> None:
        self.device.machine.advance(math.ceil(seconds / SLOT_SECONDS - 1e-9) + slots)

    def is_idle(self) -> bool:
        return self.device.engine.idle()

    def run_until_idle(self, timeout: float = 60.0) -> bool:
        """Advance until nothing moves (the buffer drained, moves, homing and probing
        over); False on timeout."""
        ticks = math.ceil(timeout / SLOT_SECONDS)
        return self.device.machine.run_until(lambda _e: self.is_idle(), ticks)

    # ---- the pulse engine, both versions ------------------------------------------
    def status(self) -> EngineStatus:
        if self.version == 1:
            r = self._pev1("PEStatusGet", 0x00)
            return EngineStatus(r[23], tuple(r[24:27]), struct.unpack_from("<3i", r, 8),
                                r[20], r[21], r[22])
        test = (0x10 + self._request_id) % 199
        r = self._pev2("PEv2_StatusGet", 0x00, test)
        if r[63] != (test + 0x5A) & 0xFF:
            raise PoKeysError("status reply with a wrong test byte")
        return EngineStatus(r[10], tuple(r[16:24]), struct.unpack_from("<8i", r, 24),
                            r[12], r[13], r[14], r[3], r[8])

    def setup(self, axes: int, charge_pump: int = 0, generator: int = 1, buffer_size: int = 0,
              estop_polarity: int = 0) -> None:
        """v2 PulseEngineSetup: axes 0..axes-1 take part."""
        self._pev2("PEv2_PulseEngineSetup", 0x01,
                   payload=bytes([axes, charge_pump, generator, buffer_size, estop_polarity, 0]))

    def set_state(self, state: str | int, limit_override: int = 0) -> None:
        names = V1_STATES if self.version == 1 else V2_STATES
        value = names[state.lower()] if isinstance(state, str) else state
        if self.version == 1:
            self._pev1("PEStateSet", 0x02, payload=bytes([value]))
        else:
            self._pev2("PEv2_PulseEngineStateSet", 0x02, value, limit_override)

    def configure_axis(self, axis: int, *, enabled: bool = True, internal: bool = False,
                       position_mode: bool = True, max_speed: float | None = None,
                       accel: float | None = None, decel: float | None = None,
                       switches: int | None = None, invert: bool | None = None,
                       invert_home: bool | None = None, soft_limits: tuple[int, int] | None = None,
                       homing: tuple[int, int] | None = None) -> None:
        """Change an axis's configuration: v2 reads it (0x85/0x10) and sets it (0x11);
        v1 sets the shared parameters (0x80/0x11) and axis bits (0x13). Speeds pulses/ms,
        accelerations pulses/ms^2; None leaves a field as it is."""
        if self.version == 1:
            self._configure_v1(axis, max_speed, accel, decel, switches, invert, invert_home)
            return
        raw = bytearray(self._pev2("PEv2_AxisConfigurationGet", 0x10, axis)[8:53])
        config = raw[0] & ~0x0D & 0xFF
        config |= (AxisConfigBits.ENABLED if enabled else 0)
        config |= (AxisConfigBits.INTERNAL_PLANNER if internal else 0)
        config |= (AxisConfigBits.POSITION_MODE if position_mode else 0)
        for flag, on in ((AxisConfigBits.INVERTED, invert),
                         (AxisConfigBits.INVERTED_HOME, invert_home),
                         (AxisConfigBits.SOFT_LIMIT_ENABLED,
                          None if soft_limits is None else True)):
            if on is not None:
                config = config | flag if on else config & ~flag
        raw[0] = int(config)
        if switches is not None:
            raw[1] = switches
        if homing is not None:
            raw[5], raw[6] = homing
        speed, acc, dec = struct.unpack_from("<fff", raw, 8)
        struct.pack_into("<fff", raw, 8, speed if max_speed is None else max_speed,
                         acc if accel is None else accel, dec if decel is None else decel)
        if soft_limits is not None:
            struct.pack_into("<ii", raw, 20, *soft_limits)
        raw[36] = 0  # [44] is always 0 as the library sends it
        self._pev2("PEv2_AxisConfigurationSet", 0x11, axis, payload=bytes(raw))

    def _configure_v1(self, axis: int, max_speed: float | None, accel: float | None,
                      decel: float | None, switches: int | None, invert: bool | None,
                      invert_home: bool | None) -> None:
        params = bytearray(self._pev1("PEParametersGet", 0x10)[8:47])
        values = list(struct.unpack_from("<9f", params, 0))
        for block, value in ((0, max_speed), (3, accel), (6, decel)):
            if value is not None:
                values[block + axis] = value
        struct.pack_into("<9f", params, 0, *values)
        self._pev1("PEParametersSet", 0x11, payload=bytes(params))
        bits = bytearray(self._pev1("PEAxisConfigurationGet", 0x12)[8:13])
        wanted: list[bool | None] = [None] * 5
        if switches is not None:
            wanted[0] = bool(switches & SwitchBits.LIMIT_P)
            wanted[1] = bool(switches & SwitchBits.LIMIT_N)
            wanted[2] = bool(switches & SwitchBits.HOME)
        wanted[3], wanted[4] = invert, invert_home
        for i, on in enumerate(wanted):
            if on is not None:
                bits[i] = bits[i] | 1 << axis if on else bits[i] & ~(1 << axis)
        self._pev1("PEAxisConfigurationSet", 0x13, payload=bytes(bits))

    def move(self, targets: Mapping[int, int | float], fraction: float = 1.0) -> None:
        """Internal-controller axes to positions (speeds on speed-mode axes, pulses/s).
        v2: PulseEngineMovePV, only the named axes; v1: PEMove, the others keep their
        targets."""
        if self.version == 1:
            e = self.device.engine
            values = [int(targets.get(a.index, a.target if a.target is not None
                                      else a.position)) for a in e.axes]
            self._pev1("PEMove", 0x05, payload=struct.pack("<3i", *values))
            return
        values = [int(targets.get(i, 0)) for i in range(8)]
        mask = sum(1 << i for i in targets)
        speed = max(1, min(65535, round(fraction * 65535)))
        payload = struct.pack("<8i", *values) + struct.pack(
            "<8H", *(speed if mask >> i & 1 else 0 for i in range(8)))
        self._pev2("PEv2_PulseEngineMovePV", 0x25, mask, payload=payload)

    def set_positions(self, positions: Mapping[int, int]) -> None:
        """Load position counters (the stage does not move)."""
        if self.version == 1:
            current = list(self.status().positions)
            for i, v in positions.items():
                current[i] = v
            self._pev1("PECurrentPositionSet", 0x01, payload=struct.pack("<3i", *current))
            return
        values = [int(positions.get(i, 0)) for i in range(8)]
        mask = sum(1 << i for i in positions)
        self._pev2("PEv2_PositionSet", 0x03, mask, payload=struct.pack("<8i", *values))

    def fill(self, entries: Sequence[Sequence[int]], *, wide: bool | None = None,
             large: bool = False) -> int:
        """Offer slots of pulses (one row per slot, one column per axis 0..AX-1) until
        the device takes no more; the number of slots it accepted. v2: 8-bit (0xFF),
        16-bit (0xFE) or multi-part (0xB0) fills; v1: PEBufferFill (0x35)."""
        rows = entries  # sliced a chunk at a time: a long offer costs what the device takes
        if not rows:
            return 0
        width = len(rows[0])
        if wide is None:
            wide = any(abs(v) > 127 for r in rows for v in r)
        size = 2 if wide else 1
        taken = 0
        while taken < len(rows):
            if self.version == 1:
                chunk = [list(r) for r in rows[taken:taken + 18]]
                r = self._pev1("PEBufferFill", 0x35, len(chunk),
                               payload=_encode(chunk, False, 3))
                accepted = r[8]
            elif large:
                chunk = [list(r) for r in rows[taken:taken + 448 // (width * size)]]
                accepted = self._fill_large(chunk, wide, width)
            else:
                chunk = [list(r) for r in rows[taken:taken + 56 // (width * size)]]
                r = self._pev2("PEv2_BufferFill", 0xFE if wide else 0xFF, len(chunk), width,
                               payload=_encode(chunk, wide, width))
                accepted = r[2]
            taken += accepted
            if accepted < len(chunk):
                break
        return taken

    def _fill_large(self, rows: list[list[int]], wide: bool, width: int) -> int:
        data = _encode(rows, wide, width).ljust(448, b"\0")
        frames = bytearray()
        for i in range(8):
            self._request_id = (self._request_id + 1) & 0xFF
            part = i | (0x08 if i == 0 else 0x10 if i == 7 else 0)
            frames += make_request(0xB0, part, 0xFE if wide else 0xFF, len(rows), width,
                                   self._request_id, data[i * 56:(i + 1) * 56])
        refused = self._session.refused
        self._session.feed(bytes(frames))
        reply = self._session.read()
        if not reply:
            raise PoKeysError("no reply to PEv2_BufferFillLarge")
        if self._session.refused != refused:
            raise PoKeysError("PEv2_BufferFillLarge refused (0 accepted)")
        return reply[2]

    def clear_buffer(self) -> None:
        if self.version == 1:
            self._pev1("PEBufferFlush", 0x36)
        else:
            self._pev2("PEv2_BufferClear", 0xF0)

    def free_slots(self) -> int:
        """Free slots of the buffer (v1 asks 0x37; v2 has no such request: the API
        counts what the engine holds, as a host counts accepted slots)."""
        if self.version == 1:
            return self._pev1("PEBufferFreeSizeGet", 0x37)[8]
        return self.device.engine.buffer.free

    def reboot(self) -> None:
        """v2 PulseEngineReboot: stopped, buffer empty, counters 0, configuration kept."""
        self._pev2("PEv2_PulseEngineReboot", 0x05)

    def home(self, axes: Sequence[int], offsets: Mapping[int, int] | None = None) -> None:
        if self.version == 1:
            flags = bytes(1 if i in axes else 0 for i in range(3))
            self._pev1("PEHomingStart", 0x20, payload=flags)
            return
        values = [int((offsets or {}).get(i, 0)) for i in range(8)]
        self._pev2("PEv2_HomingStart", 0x21, sum(1 << i for i in axes),
                   payload=struct.pack("<8i", *values))

    def homing_finish(self, state: str | int = "stopped") -> None:
        value = V2_STATES[state.lower()] if isinstance(state, str) else state
        self._pev2("PEv2_HomingFinish", 0x22, value, 1)

    def probe(self, targets: Mapping[int, int], speed: float = 0.5, probe_input: int = 1,
              polarity: int = 1) -> None:
        """v2 ProbingStart: the axes run toward `targets` (their max positions) at
        `speed` x max speed until probe input `probe_input` reads `polarity`."""
        values = [int(targets.get(i, 0)) for i in range(8)]
        payload = struct.pack("<8if", *values, speed) + bytes([probe_input, polarity])
        self._pev2("PEv2_ProbingStart", 0x23, sum(1 << i for i in targets), payload=payload)

    def probing_finish(self) -> tuple[tuple[int, ...], int]:
        """(positions saved at the probe's edge, status 0 none / 1 probed / 2 missed)."""
        r = self._pev2("PEv2_ProbingFinish", 0x24, 1)
        return struct.unpack_from("<8i", r, 8), r[40]

    # ---- the world around the device ----------------------------------------------
    @property
    def pins(self) -> PoKeysIOWorld:
        """The pins' side of the world: set_input, analog, press_key, press_kbd48,
        attach_encoder, output_levels."""
        return self.device.pins

    def stage(self, axis: int) -> AxisWorld:
        return self.world.axes[axis]

    def world_view(self) -> PoKeysWorldView:
        """The world contract (controllers/world_view.py): axes X..V (or 1..8)."""
        return PoKeysWorldView(self)

    def set_limits(self, axis: int, *, plus: float | None | str = "keep",
                   minus: float | None | str = "keep") -> None:
        """Place the limit switches in physical pulses (None: no switch on that side)."""
        stage = self.stage(axis)
        if plus != "keep":
            stage.set_plus_limit(plus)  # type: ignore[arg-type]
        if minus != "keep":
            stage.set_minus_limit(minus)  # type: ignore[arg-type]

    def set_home(self, axis: int, low: float | None, high: float | None) -> None:
        self.stage(axis).set_home(low, high)

    def set_input(self, number: int, level: object) -> None:
        """A digital input (0: the e-stop, n: pin n and probe input n): a level or a
        function of the engine (e.g. `axis_position_source("Z", lambda p: p <= -1234)`);
        edges on a counter pin count."""
        self.device.pins.set_input(number, level)

    def press_estop(self, pressed: bool = True) -> None:
        world = self.device.engine.world
        number = world.estop_input if isinstance(world, SharedWorld) else 0
        self.world.digital[number] = pressed


def _encode(rows: Sequence[Sequence[int]], wide: bool, width: int) -> bytes:
    out = bytearray()
    for row in rows:
        for v in list(row)[:width] + [0] * (width - len(row)):
            if wide:
                out += struct.pack("<H", min(abs(v), 0x7FFF) | (0x8000 if v < 0 else 0))
            else:
                out.append(min(abs(v), 0x7F) | (0x80 if v < 0 else 0))
    return bytes(out)


def build(model: str, options: BuildOptions | None = None) -> PoKeys:
    """The registry's builder: an archive file keeps what PK_SaveConfiguration saved
    (pins, PWM, encoders, ...) across runs, as the device's flash does; its own 1 ms slot."""
    dev = PoKeys(model)
    if options is not None and options.archive:
        dev.device.io.archive = str(options.archive)
        dev.device.io.load_archive()
    return dev


__all__ = ["MODELS", "EngineStatus", "PoKeys", "PoKeysError", "axis_index", "build",
           "pokeys_world"]


def _ipv4(peer: object) -> tuple[int, int, int, int]:
    """The host's IPv4 address as four numbers (127.0.0.1 when it is not one, D)."""
    try:
        parts = tuple(int(x) for x in str(peer[0]).split("."))  # type: ignore[index]
    except (TypeError, ValueError, IndexError):
        return DISCOVERY_HOST_IP
    if len(parts) != 4 or not all(0 <= x <= 255 for x in parts):
        return DISCOVERY_HOST_IP
    return (parts[0], parts[1], parts[2], parts[3])
