"""The older single-pin requests of the PoKeys protocol specification, which hosts that
speak the protocol themselves (home-automation plugins, Node-RED and OPC UA bridges) still
send, though PoKeysLib uses the block forms (0xC0, 0xCC, 0x3A) instead.

Each answers a status in [2] as 0x30 and 0x40 do: 0 done, REFUSED (1) for a pin out of
range or without the capability asked for; pins are 0-based in [2] as in every request.
"""

from __future__ import annotations

from ...personalities.pokeys.device import PoKeysDevice
from ...personalities.pokeys.io import ANALOG_PINS, PINS, IOError
from .packet import REFUSED, UNKNOWN, Reply, Request


def set_pin_function(device: PoKeysDevice, req: Request) -> Reply:
    """0x10 pin [2], function [3] (the PinFunction byte of 0xC0): the pin takes it at
    once; the reply echoes the function in [3]. A pin out of range or a function the pin
    cannot take is refused and nothing changes."""
    pin = req.param(1) + 1
    r = Reply(req)
    try:
        device.io.set_function(pin, req.param(2))
    except IOError:
        return r.refuse(REFUSED)
    r[2], r[3] = 0, device.io.functions[pin - 1]
    return r


def get_pin_function(device: PoKeysDevice, req: Request) -> Reply:
    """0x15 pin [2]: its function byte in [3] (2 input, 4 output, 8 analog input, ...)."""
    pin = req.param(1) + 1
    r = Reply(req)
    if not 1 <= pin <= PINS:
        return r.refuse(REFUSED)
    r[2], r[3] = 0, device.io.functions[pin - 1]
    return r


def analog_input(device: PoKeysDevice, req: Request) -> Reply:
    """0x35 pin [2] (40..46 = pins 41..47): its 12-bit code, high byte [3], low byte [4]
    (D: the byte order of 0x3A's pairs). A pin without an analog input is refused; an
    analog pin not configured as analog input reads 0, as in 0x3A."""
    pin = req.param(1) + 1
    r = Reply(req)
    if pin not in ANALOG_PINS:
        return r.refuse(REFUSED)
    code = device.pins.analog_code(pin)
    r[2], r[3], r[4] = 0, code >> 8, code & 0xFF
    return r


POLED_SET = 0x20
POLED_GET = 0x10


def poled(device: PoKeysDevice, req: Request) -> Reply:
    """0xE6 PoLED: [2]=0x20 sets channel [3] to state [4] (the form a home-automation
    host sends), [2]=0x10 reads channel [3]'s state into [4] (D). The states are kept
    and shown in the device's status; no LED module is drawn."""
    sub, channel = req.param(1), req.param(2)
    r = Reply(req)
    leds = device.io.poled
    if sub == POLED_SET:
        leds[channel] = req.param(3)
    elif sub != POLED_GET:
        return r.refuse(UNKNOWN)
    r[3], r[4] = channel, leds.get(channel, 0)
    return r
