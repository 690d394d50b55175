"""Pulse engine v1 commands: 0x80 with the sub-command in [2] (reference section 10,
from the last PoKeysLib that had them)."""

from __future__ import annotations

import struct

from ...personalities.pokeys.constants import AxisConfigBits, SwitchBits
from ...personalities.pokeys.device import PoKeysDevice
from ...personalities.pokeys.pev1 import PulseEngineV1
from .packet import Reply, Request
from .pev2_commands import decode_entries

FILL_BYTES = 55  # min(depth, 55) bytes of slot data per frame: 18 slots of 3 axes


def _engine(device: PoKeysDevice) -> PulseEngineV1 | None:
    e = device.engine
    return e if isinstance(e, PulseEngineV1) else None


def _axes_bits(e: PulseEngineV1, flag: SwitchBits | AxisConfigBits) -> int:
    bits = 0
    for a in e.axes:
        field = a.settings.switches if isinstance(flag, SwitchBits) else a.settings.config
        bits |= bool(field & flag) << a.index
    return bits


def status(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x00: positions [8..19], lim+ [20], lim- [21], home [22], state [23], axis
    states [24..26], enabled [27], charge pump [28]."""
    e = _engine(device)
    if e is None:
        return None
    r = Reply(req)
    r.counters(8, e.positions())
    lim_p, lim_n, home = e.switch_bits()
    r[20], r[21], r[22], r[23] = lim_p, lim_n, home, int(e.state)
    r.put(24, bytes(int(s) for s in e.axis_states()))
    r[27], r[28] = e.enabled, e.charge_pump
    return r


def set_position(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    e.set_positions(req.i32s(8, 3))
    return Reply(req)


def set_state(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None or not e.set_state(req.u8(8)):
        return None
    return Reply(req)


def mpg_config(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x03: MPG jog configuration, stored and read back ([3]=10 sets [8..23])."""
    e = _engine(device)
    if e is None:
        return None
    if req.param(2) == 10:
        e.mpg_config[:] = req.raw[8:24]
    r = Reply(req)
    r.put(8, bytes(e.mpg_config))
    return r


def move(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x05: 3 x i32 at [8]; [3] = axes whose value is a speed in internal mode."""
    e = _engine(device)
    if e is None:
        return None
    e.move(req.i32s(8, 3), speed_mask=req.param(2))
    return Reply(req)


def enable(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    e.enabled, e.charge_pump = req.param(2), req.param(3)
    return Reply(req)


def parameters(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x10 get / 0x11 set: f32 max speed [8..19] (pulses/ms), acceleration [20..31] and
    deceleration [32..43] (pulses/ms^2), homing [44] and return [45] speed %, e-stop
    polarity [46]."""
    e = _engine(device)
    if e is None:
        return None
    if req.sub == 0x11:
        values = struct.unpack_from("<9f", req.raw, 8)
        for a in e.axes:
            a.settings.max_speed = values[a.index]
            a.settings.max_acceleration = values[3 + a.index]
            a.settings.max_deceleration = values[6 + a.index]
        e.homing_speed, e.homing_return_speed = req.u8(44), req.u8(45)
        e.estop_polarity = req.u8(46)
    r = Reply(req)
    st = [a.settings for a in e.axes]
    r.put(8, struct.pack("<9f", *(s.max_speed for s in st), *(s.max_acceleration for s in st),
                         *(s.max_deceleration for s in st)))
    r[44], r[45], r[46] = e.homing_speed, e.homing_return_speed, e.estop_polarity
    return r


_AXIS_CONFIG: tuple[SwitchBits | AxisConfigBits, ...] = (
    SwitchBits.LIMIT_P, SwitchBits.LIMIT_N, SwitchBits.HOME, AxisConfigBits.INVERTED,
    AxisConfigBits.INVERTED_HOME)


def axis_config(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x12 get / 0x13 set: per-axis bits of lim+ [8], lim- [9], home [10] enable,
    direction change [11], homing direction [12]."""
    e = _engine(device)
    if e is None:
        return None
    if req.sub == 0x13:
        for i, flag in enumerate(_AXIS_CONFIG):
            bits = req.u8(8 + i)
            for a in e.axes:
                on = bool(bits >> a.index & 1)
                if isinstance(flag, SwitchBits):
                    sw = a.settings.switches
                    a.settings.switches = int(sw | flag if on else sw & ~flag)
                else:
                    cf = a.settings.config
                    a.settings.config = int(cf | flag if on else cf & ~flag)
    r = Reply(req)
    for i, flag in enumerate(_AXIS_CONFIG):
        r[8 + i] = _axes_bits(e, flag)
    return r


def keyboard(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x14 get / 0x15 set: kbd48CNC enabled [8] (stored; the keyboard is not modelled)."""
    e = _engine(device)
    if e is None:
        return None
    if req.sub == 0x15:
        e.kb48cnc = req.u8(8)
    r = Reply(req)
    r[8] = e.kb48cnc
    return r


def homing(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    e.homing_start(list(req.raw[8:11]))
    return Reply(req)


def info(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    r = Reply(req)
    r[8], r[9], r[10], r[11] = e.spec.axes, e.spec.max_pulses_per_slot, e.buffer.depth, 1
    return r


def fill(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x35: N [3] slots of 3 bytes at [8]; reply accepted [8], positions [9..20],
    lim+/lim-/home [21..23], state [24], axis states [25..27]."""
    e = _engine(device)
    if e is None:
        return None
    entries = decode_entries(req.raw[8:8 + FILL_BYTES], req.param(2), e.spec.axes, False)
    if entries is None:
        return None
    accepted = e.fill(entries)
    r = Reply(req)
    r[8] = accepted
    r.counters(9, e.positions())
    lim_p, lim_n, home = e.switch_bits()
    r[21], r[22], r[23], r[24] = lim_p, lim_n, home, int(e.state)
    r.put(25, bytes(int(s) for s in e.axis_states()))
    return r


def flush(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    e.clear_buffer()
    return Reply(req)


def free_slots(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    r = Reply(req)
    r[8] = e.free_slots()
    return r
