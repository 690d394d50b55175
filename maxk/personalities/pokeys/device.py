"""A PoKeys device as the host sees it at connect time: identity, network setup, name,
activated options, and its pulse engine (v1 on the PoKeys56E, v2 on the 57 series)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Final

from ...firmware_model.world import World
from .failsafe import FailsafeWatch
from .io import DeviceIO
from .machine import SlotEngine
from .pev1 import PulseEngineV1
from .pev2 import PulseEngineV2
from .world import CounterSampler, PoKeysIOWorld, PulseEngineWorld, SharedWorld, pokeys_world


@dataclass(frozen=True)
class Identity:
    """What a model reports about itself (reference section 4)."""

    model: str
    serial: int
    firmware: tuple[int, int]  # (major, minor) bytes [4]/[5]: 0x33,6 reads "4.3.6"
    hw_type: int  # DeviceType byte [18] of an extended-ID reply (0 for old-ID devices)
    extended_id: bool  # 'PKEx' layout of the 0x00 reply
    build_date: str  # 11 characters, "Mmm dd yyyy"
    engine_version: int
    activated_options: int  # 0x8F [8]; bit 0 = pulse engine (reference section 10)
    product_id: int = 0


MODELS: Final[dict[str, Identity]] = {
    # Old-ID device: serial in 20000-65535, FW major 32 = "3.0.x", >= 3.0.59 has the
    # pulse engine without activation (reference 10): the library reads PEv1.
    "PoKeys56E": Identity("PoKeys56E", 27431, (32, 61), 11, False, "Mar 14 2014", 1, 0x01),
    "PoKeys57E": Identity("PoKeys57E", 31877, (0x33, 5), 31, True, "Nov 03 2017", 2, 0x01),
    "PoKeys57CNC": Identity("PoKeys57CNC", 32123, (0x33, 6), 32, True, "Jan 10 2018", 2, 0x01),
}


@dataclass
class NetworkConfig:
    """The 0xE0 reply: addresses as the four bytes the wire carries."""

    dhcp: int = 0
    ip_setup: tuple[int, int, int, int] = (127, 0, 0, 1)
    ip_current: tuple[int, int, int, int] = (127, 0, 0, 1)
    tcp_timeout: int = 1000  # ms
    gateway: tuple[int, int, int, int] = (127, 0, 0, 1)
    subnet_mask: tuple[int, int, int, int] = (255, 0, 0, 0)
    options: int = 0xA0  # kept by the library only if (options & 0xA0) == 0xA0


@dataclass
class PoKeysDevice:
    identity: Identity
    engine: PulseEngineV1 | PulseEngineV2
    network: NetworkConfig = field(default_factory=NetworkConfig)
    name: str = ""
    user_id: int = 0
    lock_status: int = 0
    machine: SlotEngine = field(init=False)
    io: DeviceIO = field(init=False)
    pins: PoKeysIOWorld = field(init=False)
    failsafe: FailsafeWatch = field(init=False)

    def __post_init__(self) -> None:
        self.machine = SlotEngine(self.engine)
        self.io = DeviceIO(self.identity.model)
        world = self.machine.world or World.default(len(self.engine.axes))
        self.pins = PoKeysIOWorld(self.io, world, self._stage, lambda: self.machine,
                                  self.machine.world_changed)
        self.machine.add_source(CounterSampler(self.pins, lambda: self.machine.tick))
        self.failsafe = FailsafeWatch(self)
        self.machine.add_source(self.failsafe)

    def pwm_output(self, channel: int) -> float:
        """PWM channel's duty as a fraction of its period, as the pin puts it out: a
        channel synced to an axis (0x85 0x0A) follows that axis's speed over its max
        speed (D), else the duty the host set."""
        enabled, axis, synced = self.io.synced_pwm
        if not (enabled and synced == channel):
            return self.io.pwm_fraction(channel)
        if not self.io.pwm_enabled >> channel & 1:
            return 0.0
        found = self.engine.motion_plan(axis)
        max_speed = self.engine.axes[axis].settings.max_speed * 1000.0  # pulses/s
        if found is None or max_speed <= 0:
            return 0.0
        t = (self.engine.slot - found.start) / 1000.0
        return min(1.0, abs(found.plan.velocity(t)) / max_speed)

    def apply_sync_outputs(self) -> None:
        """Synced fast outputs (0x85 0x0B, stored as [3] enabled, [4] axis, 8 mapping
        bytes): while the pulse engine consumes its buffer, the chosen axis's entry of
        each slot is 8 output bits, bit i driving pin mapping[i] (a pin number 1..55, 0
        none; D) when that pin is a digital output; the axis itself does not move."""
        enabled, axis = self.io.sync_outputs[0], self.io.sync_outputs[1]
        self.engine.sync_outputs_axis = axis if enabled else None
        self.engine.on_sync_outputs = self._sync_outputs

    def apply_backlash(self) -> None:
        """Backlash compensation (0x85 0x41, stored as [3] enabled, [4] max speed, then per
        axis u16 width and u8 acceleration in 4 bytes): each axis takes up its width (half
        the play) on a reversal at the max speed in pulses a slot (0: at once; D: the
        acceleration is kept, the register moves at constant speed). Switched off, the
        register's pulses stay in the stage (the motor does not step back)."""
        raw = self.io.backlash
        enabled, rate = raw[0], raw[1]
        for a in self.engine.axes:
            at = 2 + 4 * a.index
            width = raw[at] | raw[at + 1] << 8 if enabled and at + 1 < len(raw) else 0
            if not width and a.backlash_register:
                a.counter_offset -= a.backlash_register
                a.backlash_register = 0
            a.backlash_width, a.backlash_rate = width, rate
            a.backlash_register = max(-width, min(width, a.backlash_register)) if width \
                else 0

    def _sync_outputs(self, bits: int) -> None:
        io = self.io
        for i, pin in enumerate(io.sync_outputs[2:10]):
            if 1 <= pin <= len(io.outputs) and io.is_output(pin):
                io.outputs[pin - 1] = bool(bits >> i & 1)

    def _stage(self, axis: int) -> int:
        axes = self.engine.axes
        return axes[axis].stage if 0 <= axis < len(axes) else 0

    @classmethod
    def create(cls, model: str = "PoKeys57CNC", world: PulseEngineWorld | None = None,
               serial: int | None = None) -> PoKeysDevice:
        """A device at power-up; its switches, e-stop and probe come from the shared
        world (`pokeys_world`) unless another `PulseEngineWorld` is given."""
        ident = MODELS[model]
        if serial is not None:
            ident = Identity(**{**ident.__dict__, "serial": serial})
        if world is None:
            world = SharedWorld(pokeys_world(3 if ident.engine_version == 1 else 8))
        return cls(ident, new_engine(ident, world), name=ident.model)

    @property
    def slot(self) -> int:
        return self.machine.tick

    def run_to(self, slot: int) -> None:
        """Advance the device to `slot` (1 ms slots since power-up), on the shared engine."""
        self.machine.advance_to(slot)

    def power_up(self) -> None:
        """A reset: the pulse engine starts again (stopped, empty buffer, counters 0,
        configuration lost); identity, name and network setup are kept (flash)."""
        old = self.engine
        self.engine = new_engine(self.identity, old.world)
        for a, before in zip(self.engine.axes, old.axes, strict=True):
            a.counter_offset = -before.stage  # the stage stays where it stood
        self.machine.replace_pulse_engine(self.engine)
        wiring = [(e.axis, e.direction) for e in self.io.encoders]  # the machine's wiring
        self.io.power_up()  # the saved set-up; counters, outputs and encoders at 0
        for e, (axis, direction) in zip(self.io.encoders, wiring, strict=True):
            e.axis, e.direction = axis, direction
            e.axis_from = self._stage(axis) if axis is not None else 0


def new_engine(ident: Identity, world: PulseEngineWorld) -> PulseEngineV1 | PulseEngineV2:
    return PulseEngineV1(world) if ident.engine_version == 1 else PulseEngineV2(world)
