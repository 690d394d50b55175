"""Pulse engine v2 commands: 0x85 with the sub-command in [2], and the multi-part 0xB0
buffer fill (reference sections 6-8)."""

from __future__ import annotations

import struct

import numpy as np

from ...personalities.pokeys.axis import AxisSettings
from ...personalities.pokeys.device import PoKeysDevice
from ...personalities.pokeys.pev2 import PulseEngineV2
from .packet import Reply, Request

STATUS_TEST_OFFSET = 0x5A


def _engine(device: PoKeysDevice) -> PulseEngineV2 | None:
    e = device.engine
    return e if isinstance(e, PulseEngineV2) else None


def status_block(e: PulseEngineV2, r: Reply) -> None:
    """The status block of 0x85/0x00 and of the buffer-fill replies (section 7)."""
    lim_p, lim_n, home = e.switch_bits()
    r[3] = e.soft_limit_bits()
    r[4] = e.axis_enabled_states_mask
    r[5] = e.limit_override
    r[8] = e.enabled_axes
    r[9] = e.activated
    r[10] = int(e.state)
    r[11] = e.charge_pump
    r[12], r[13], r[14] = lim_p, lim_n, home
    r[15] = e.generator_type
    r.put(16, bytes(int(s) for s in e.axis_states()))
    r.counters(24, e.positions())
    r[56], r[57], r[58], r[59] = e.spec.axes, e.spec.max_pulses_per_slot, e.buffer.depth, 1
    r[60] = e.estop_polarity
    r[61] = 0  # error inputs: not modelled
    r[62] = 0  # misc inputs: not modelled


def status_get(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x00: status; [63] = the test byte of [3] + 0x5A, or the host rejects the reply."""
    e = _engine(device)
    if e is None:
        return None
    r = Reply(req)
    status_block(e, r)
    r[63] = req.param(2) + STATUS_TEST_OFFSET
    return r


def status2_get(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x08: dedicated limit-/limit+/home input pin levels, one bit per axis."""
    e = _engine(device)
    if e is None:
        return None
    r = Reply(req)
    for a in e.axes:
        levels = e.world.switch_levels(a.index, a.stage)
        r.frame[8] |= levels.limit_n << a.index
        r.frame[9] |= levels.limit_p << a.index
        r.frame[10] |= levels.home << a.index
    return r


def setup(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x01: enabled axes [8], charge pump [9], generator [10], buffer size [11],
    e-stop polarity [12], axis-enabled-states mask [13]."""
    e = _engine(device)
    if e is None or req.u8(8) > e.spec.axes:
        return None
    e.setup(*req.raw[8:14])
    return Reply(req)


def state_set(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None or not e.set_state(req.param(2), req.param(3), req.param(4)):
        return None
    return Reply(req)


def position_set(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    e.set_positions(req.param(2), req.i32s(8, 8))
    return Reply(req)


def external_outputs(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x04: get ([5]=1) relays [3] and open-collector outputs [4], or set them."""
    e = _engine(device)
    if e is None:
        return None
    if req.param(4) != 1:
        e.external_relays, e.external_oc = req.param(2), req.param(3)
    r = Reply(req)
    r[3], r[4] = e.external_relays, e.external_oc
    return r


def reboot(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    e.reboot()
    return Reply(req)


def additional_params(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x06: e-stop pin [8]: set when [3]=1, else read."""
    e = _engine(device)
    if e is None:
        return None
    if req.param(2) == 1:
        e.estop_pin = req.u8(8)
    r = Reply(req)
    r[8] = e.estop_pin
    return r


def encode_axis(settings: AxisSettings) -> bytes:
    """Axis configuration bytes [8..52]: unparsed bytes come back as the host sent them."""
    raw = bytearray(settings.raw)
    raw[0], raw[1] = int(settings.config), int(settings.switches)
    raw[2], raw[3], raw[4] = settings.pin_home, settings.pin_limit_n, settings.pin_limit_p
    raw[5], raw[6] = settings.homing_speed, settings.homing_return_speed
    raw[7] = settings.mpg_encoder
    struct.pack_into("<fffiih", raw, 8, settings.max_speed, settings.max_acceleration,
                     settings.max_deceleration, settings.soft_limit_min,
                     settings.soft_limit_max, settings.mpg_multiplier)
    return bytes(raw)


def decode_axis(raw: bytes) -> AxisSettings:
    speed, acc, dec, smin, smax, mult = struct.unpack_from("<fffiih", raw, 8)
    return AxisSettings(
        config=raw[0], switches=raw[1], pin_home=raw[2],
        pin_limit_n=raw[3], pin_limit_p=raw[4], homing_speed=raw[5],
        homing_return_speed=raw[6], mpg_encoder=raw[7], max_speed=speed,
        max_acceleration=acc, max_deceleration=dec, soft_limit_min=smin,
        soft_limit_max=smax, mpg_multiplier=mult, raw=bytearray(raw))


def axis_config_get(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None or req.param(2) >= e.spec.axes:
        return None
    r = Reply(req)
    r.put(8, encode_axis(e.axes[req.param(2)].settings))
    return r


def axis_config_set(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None or req.param(2) >= e.spec.axes:
        return None
    e.configure_axis(req.param(2), decode_axis(req.raw[8:53]))
    return Reply(req)


def move(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    e.move(req.i32s(8, 8))
    return Reply(req)


def move_pv(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x25: masked axes ([3]) to positions [8..39] at u16 fractions of max speed [40..55]."""
    e = _engine(device)
    if e is None:
        return None
    fractions = [v / 65535.0 for v in struct.unpack_from("<8H", req.raw, 40)]
    e.move(req.i32s(8, 8), mask=req.param(2), fractions=fractions)
    return Reply(req)


def homing_start(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    e.homing_start(req.param(2), req.i32s(8, 8))
    return Reply(req)


def homing_finish(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None or not e.homing_finish(req.param(2)):
        return None
    return Reply(req)


def probing_start(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x23: masked axes ([3]) toward max positions [8..39] at f32 fraction [40] of max
    speed, until input [44] reaches polarity [45]. Hybrid probing ([4]=1) is not modelled."""
    e = _engine(device)
    if e is None or req.param(3) != 0:
        return None
    e.probing_start(req.param(2), req.i32s(8, 8), req.f32(40), req.u8(44), req.u8(45))
    return Reply(req)


def probing_finish(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    positions, status = e.probing_finish()
    r = Reply(req)
    r.counters(8, positions)
    r[40] = status
    return r


def buffer_clear(device: PoKeysDevice, req: Request) -> Reply | None:
    e = _engine(device)
    if e is None:
        return None
    e.clear_buffer()
    return Reply(req)


def decode_entries(data: bytes, count: int, axes: int, wide: bool) -> np.ndarray | None:
    """Buffer entries -> signed pulses (count x axes); None if they do not fit in data.
    8-bit: bit 7 direction, bits 0-6 pulses; 16-bit: u16 little-endian, bit 15 direction."""
    size = count * axes * (2 if wide else 1)
    if axes < 1 or size > len(data):
        return None
    raw = np.frombuffer(data[:size], dtype="<u2" if wide else np.uint8).astype(np.int32)
    sign_bit = 0x8000 if wide else 0x80
    pulses = np.where(raw & sign_bit, -(raw & (sign_bit - 1)), raw & (sign_bit - 1))
    return pulses.reshape(count, axes)


def _fill(device: PoKeysDevice, req: Request, wide: bool, count: int, axes: int
          ) -> Reply | None:
    e = _engine(device)
    r = Reply(req)
    if e is None:
        return r.refuse(0)
    entries = decode_entries(req.payload, count, axes, wide) if 1 <= axes <= e.spec.axes else None
    sync = e.sync_outputs_axis
    if entries is not None and sync is not None and sync < axes:
        # the synced-outputs axis carries output bits: its bytes as sent (16-bit: the low)
        raw = np.frombuffer(req.payload[:count * axes * (2 if wide else 1)],
                            dtype="<u2" if wide else np.uint8).reshape(count, axes)
        entries[:, sync] = raw[:, sync] & 0xFF
    accepted = 0 if entries is None else e.fill(entries)  # a refused fill: 0 accepted
    r.refused = entries is None
    status_block(e, r)
    r[2] = accepted
    return r


def buffer_fill_8(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xFF: N entries [3] of AX axes [4] (one byte per axis), 56 bytes of payload."""
    return _fill(device, req, False, req.param(2), req.param(3))


def buffer_fill_16(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xFE: as 0xFF with two bytes per axis."""
    return _fill(device, req, True, req.param(2), req.param(3))


def buffer_fill_large(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xB0 (8 frames, 448 data bytes): [3] 0xFF or 0xFE, N [4], AX [5]."""
    kind = req.param(2)
    if kind not in (0xFF, 0xFE) or req.data is None:
        return Reply(req).refuse(0)  # 0 accepted
    return _fill(device, req, kind == 0xFE, req.param(3), req.param(4))
