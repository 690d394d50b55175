"""The failsafe (0x81, PoKeysLibFailsafe.c): when no host has spoken for the timeout, the
device puts its outputs in the safe state the host set up, and stops the pulse engine.

The library names the settings: byte 0 enabled and the timeout in 100 ms steps (0 off),
byte 1 the peripherals it acts on (bit 0 digital I/O, 1 PoExtBus, 2 PWM, 3 the pulse
engine), then the digital outputs' values (7 bytes, bit p-1 = pin p), the PoExtBus bytes
(10) and the PWM values (6). What a PWM value means is ours (D): percent of the period.
"""

from __future__ import annotations

from typing import Any, Final

FAILSAFE_STEP_SLOTS: Final = 100  # 100 ms steps of 1 ms slots
IO, POEXTBUS, PWM, PULSE_ENGINE = 0x01, 0x02, 0x04, 0x08


class FailsafeWatch:
    """An event source of the device's engine: at the slot the timeout runs out after the
    last valid request (any host, any door), the failsafe acts once; the next request
    arms it again. Outputs keep the failsafe values until a host sets them (D)."""

    def __init__(self, device: Any) -> None:
        self.device = device  # a PoKeysDevice
        self.last_contact = device.slot
        self.tripped = False
        self.trips = 0

    def contact(self) -> None:
        """A host spoke: the timeout starts again."""
        self.last_contact = self.device.slot
        self.tripped = False

    def timeout_slots(self) -> int:
        return int(self.device.io.failsafe[0]) * FAILSAFE_STEP_SLOTS

    def next_event(self) -> int | None:
        timeout = self.timeout_slots()
        if timeout == 0 or self.tripped:
            return None
        return self.last_contact + timeout

    def on_event(self, now: int) -> None:
        timeout = self.timeout_slots()
        if timeout == 0 or self.tripped or now < self.last_contact + timeout:
            return
        self.tripped = True
        self.trips += 1
        self.act()

    def act(self) -> None:
        """Put the selected peripherals in their failsafe state."""
        io = self.device.io
        settings = io.failsafe
        peripherals = settings[1]
        if peripherals & IO:
            for pin in range(1, 56):
                if io.is_output(pin):
                    byte = settings[2 + (pin - 1) // 8]
                    io.outputs[pin - 1] = bool(byte >> ((pin - 1) % 8) & 1)
        if peripherals & POEXTBUS:
            io.poextbus = bytes(settings[9:19])
        if peripherals & PWM:
            io.pwm_duty = [min(100, v) * io.pwm_period // 100 for v in settings[19:25]]
        if peripherals & PULSE_ENGINE:
            engine = self.device.engine
            engine.clear_buffer()
            if self.device.identity.engine_version == 2:
                engine.set_state(0, engine.limit_override, engine.axis_enable_mask)
            else:
                engine.set_state(0)
        self.device.machine.world_changed()
