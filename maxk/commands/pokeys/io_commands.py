"""The PoKeys's I/O requests (pins, digital and analog I/O, counters, PWM, encoders), laid
out as PoKeysLib writes and reads them (PoKeysLibIO.c, PoKeysLibEncoders.c).

A handler returns the reply, or None for silence: a request the device does not take
(an unknown sub-command, a set-up it refuses) gets no reply and changes nothing, as for
the pulse engine. Requests whose reply carries a status byte (single pin I/O, PoNET,
buses) answer refusals there instead, as the library reads them.
"""

from __future__ import annotations

import struct

from ...personalities.pokeys.device import PoKeysDevice
from ...personalities.pokeys.io import (
    ANALOG_PINS,
    ENCODERS,
    PINS,
    IOError,
)
from .packet import Reply, Request


def _bit(raw: bytes, offset: int, i: int) -> bool:
    return bool(raw[offset + i // 8] >> (i % 8) & 1)


# ---- pins -----------------------------------------------------------------------------------
def pin_configuration(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xC0: [2]=0 [3]=0 functions get, [2]=1 functions set, [2]=0 [3]=1/2 counter
    options get/set; one byte per pin at [8 + i]. A refused set-up changes nothing."""
    io = device.io
    r = Reply(req)
    mode, part = req.param(1), req.param(2)
    if mode == 1:
        try:
            io.set_functions(list(req.raw[8:8 + PINS]))
        except IOError:
            return None
        r.put(8, bytes(io.functions))
    elif mode == 0 and part == 0:
        r.put(8, bytes(io.functions))
    elif mode == 0 and part in (1, 2):
        if part == 2:
            io.counter_options = list(req.raw[8:8 + PINS])
        r.put(8, bytes(io.counter_options))
    else:
        return None
    return r


def key_mapping(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xC1-0xC3, 0xD7: key mapping (USB models' keyboard emulation): a network PoKeys
    has none; it answers with zeros (D) so a host probing it gets a reply."""
    if req.param(1) not in (0, 1, 2, 3, 4, 11, 12, 13, 14):
        return None
    return Reply(req)


# ---- digital I/O ---------------------------------------------------------------------------
def _inputs(device: PoKeysDevice) -> bytes:
    return device.pins.pin_bits().to_bytes(7, "little")


def digital_io(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xCC: [2]=0 get, [2]=1 set outputs (bits [8..14], keep-mask [20..26]); both
    answer every pin's level at [8..14]. Bits of pins that are not outputs are ignored."""
    io = device.io
    if req.param(1) == 1:
        for i in range(PINS):
            if io.is_output(i + 1) and not _bit(req.raw, 20, i):
                io.outputs[i] = _bit(req.raw, 8, i)
    elif req.param(1) != 0:
        return None
    r = Reply(req)
    r.put(8, _inputs(device))
    return r


def digital_get_single(device: PoKeysDevice, req: Request) -> Reply:
    """0x30 pin: [2]=0 and the level at [3]; [2]=1 for no such pin (D)."""
    pin = req.param(1) + 1
    r = Reply(req)
    if pin > PINS:
        r[2], r[3] = 1, 0
        return r
    r[2], r[3] = 0, int(device.pins.pin_level(pin))
    return r


def digital_set_single(device: PoKeysDevice, req: Request) -> Reply:
    """0x40 pin value: [2]=0 done; [2]=1 when the pin is not a digital output (D)."""
    pin = req.param(1) + 1
    r = Reply(req)
    try:
        device.io.set_output(pin, req.param(2) != 0)
    except IOError:
        r[2] = 1
        return r
    r[2] = 0
    return r


def analog_get(device: PoKeysDevice, req: Request) -> Reply:
    """0x3A: pins 41..47 as 12-bit codes, big-endian at [8 + 2i]. PoKeysLib sends
    [2]=1, hosts of their own a zeroed header: the device reads no parameter (I)."""
    r = Reply(req)
    for i, pin in enumerate(ANALOG_PINS):
        code = device.pins.analog_code(pin)
        r[8 + 2 * i], r[9 + 2 * i] = code >> 8, code & 0xFF
    return r


def analog_filter(device: PoKeysDevice, req: Request) -> Reply:
    """0x38 get / 0x39 set: the RC filter's time constant, u32 at [2..5] (ms, D); the
    analog inputs read through it (world.py `analog_filtered`)."""
    if req.command == 0x39:
        device.io.analog_filter = struct.unpack_from("<I", req.raw, 2)[0]
    r = Reply(req)
    r.put(2, struct.pack("<I", device.io.analog_filter))
    return r


def counters_get(device: PoKeysDevice, req: Request) -> Reply:
    """0xD8: up to 13 pin indexes at [8..20]; their counts, i32 at [8 + 4j] (0 for a pin
    that has no counter)."""
    r = Reply(req)
    for j in range(13):
        pin = req.raw[8 + j] + 1
        value = 0
        if device.io.counter_available(pin):
            device.pins.sample(pin)
            value = device.io.counters[pin - 1]
        r.put(8 + 4 * j, struct.pack("<I", value & 0xFFFFFFFF))
    return r


def counters_clear(device: PoKeysDevice, req: Request) -> Reply:
    """0x1D: every digital counter to 0."""
    device.io.counters = [0] * PINS
    return Reply(req)


# ---- PWM --------------------------------------------------------------------------------------
def pwm(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xCB: [2]=0 get; [2]=1 [3]=0 set (enabled mask [8], duties u32 [9 + 4n], period
    u32 [33]); [2]=1 [3]=1 update (duties only). A channel on a pin that cannot drive is
    refused whole."""
    io = device.io
    mode, update = req.param(1), req.param(2)
    if mode == 1:
        duties = list(struct.unpack_from("<6I", req.raw, 9))
        period = struct.unpack_from("<I", req.raw, 33)[0]
        try:
            io.set_pwm(req.raw[8], duties, period, duties_only=update == 1)
        except IOError:
            return None
    elif mode != 0:
        return None
    r = Reply(req)
    r[8] = io.pwm_enabled
    r.put(9, struct.pack("<6I", *io.pwm_duty))
    r.put(33, struct.pack("<I", io.pwm_period))
    return r


# ---- encoders ---------------------------------------------------------------------------------
def encoder_options(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xC4: options of encoders 0..24 at [8 + i]; 0xC5: channel A pins [8 + i], B pins
    [33 + i]; 0xC6/0xC7: direction key mapping (USB only: zeros, D). [2]=0 get, 1 set."""
    io, pins = device.io, device.pins
    if req.param(1) not in (0, 1):
        return None
    if req.command in (0xC6, 0xC7):
        return Reply(req)
    basic = io.encoders[:25]
    if req.param(1) == 1:
        counts = pins.freeze_encoders()
        for i, e in enumerate(basic):
            if req.command == 0xC4:
                e.options = req.raw[8 + i]
            else:
                e.pin_a, e.pin_b = req.raw[8 + i], req.raw[33 + i]
        pins.restart_encoders(counts)
    r = Reply(req)
    for i, e in enumerate(basic):
        if req.command == 0xC4:
            r[8 + i] = e.options
        else:
            r[8 + i], r[33 + i] = e.pin_a, e.pin_b
    return r


FAST_ENCODER_CONFIGS = (0, 1, 10)  # off, configuration 1 (pins 1-2, 3-4, 15-16), 2 (D)


def fast_encoders(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xCE: [2]=2 get (configuration [2], options [3]); else set [2]/[3]. A configuration
    that is not 0, 1 or 10 is refused."""
    io, pins = device.io, device.pins
    if req.param(1) != 2:
        if req.param(1) not in FAST_ENCODER_CONFIGS:
            return None
        counts = pins.freeze_encoders()
        io.fast_encoders = (req.param(1), req.param(2))
        pins.restart_encoders(counts)
    r = Reply(req)
    r[2], r[3] = io.fast_encoders
    return r


def ultra_fast_encoder(device: PoKeysDevice, req: Request) -> Reply:
    """0x1C: [2]=0xFF get (configuration [2], options [3], filter u32 [8]); else set."""
    io, pins = device.io, device.pins
    if req.param(1) != 0xFF:
        counts = pins.freeze_encoders()
        io.ultra_fast = (req.param(1), req.param(2), struct.unpack_from("<I", req.raw, 8)[0])
        pins.restart_encoders(counts)
    r = Reply(req)
    r[2], r[3] = io.ultra_fast[0], io.ultra_fast[1]
    r.put(8, struct.pack("<I", io.ultra_fast[2]))
    return r


def encoder_values(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xCD: [2]=0 encoders 0..12, [2]=1 encoders 13..25 (25 = ultra-fast), u32 at
    [8 + 4i]; [2]=10/11 load the same ranges."""
    part = req.param(1)
    if part not in (0, 1, 10, 11):
        return None
    first = 13 if part in (1, 11) else 0
    pins = device.pins
    if part >= 10:
        for i in range(13):
            if first + i < ENCODERS:
                pins.load_encoder(first + i, struct.unpack_from("<i", req.raw, 8 + 4 * i)[0])
    r = Reply(req)
    for i in range(13):
        if first + i < ENCODERS:
            value = pins.encoder_value(first + i) & 0xFFFFFFFF
            r.put(8 + 4 * i, struct.pack("<I", value))
    return r


def ultra_fast_test_values(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x85 0x37: the ultra-fast encoder's index count [12], ticks per rotation [16] and
    velocity [20], u32 each. No index or velocity estimate is modelled: index count 0,
    ticks 0, velocity 0 (D). Pulse engine v2's request: a PoKeys56E is silent."""
    if device.identity.engine_version != 2:
        return None
    return Reply(req)
