"""Faults the suite once let through (issue 41), caught in the PoKeys pulse engine's
status block as the host reads it: bytes 3 (soft-limit bits), 5 (limit override),
11 (charge pump), 14 (home bits) and 60 (e-stop polarity).

Every frame here is built by hand from shared/reference/pokeys-protocol.md (sections 2,
6 and 7: the header, the sub-commands' operand bytes, the status block's offsets) and
fed through the device's own session, as a host's datagram would be; the expected bytes
are the values the test put in, or bit arithmetic on the axes it placed.
"""

from __future__ import annotations

import struct

import pytest

from maxk.controllers.pokeys.controller import PoKeys

PEV2 = 0x85
STATUS, SETUP, STATE_SET, AXIS_SET = 0x00, 0x01, 0x02, 0x11
STOPPED, RUNNING = 0, 3
# axis configuration [8] bits and [9] switch bits (reference 6)
ENABLED, SOFT_LIMITS = 0x01, 0x20
HOME_SWITCH, INVERT_HOME = 0x04, 0x80


class Host:
    """A host's side of one session: request frames with their IDs and checksums."""

    def __init__(self, model: str = "PoKeys57CNC") -> None:
        self.device = PoKeys(model)
        self.session = self.device.open_session()
        self.request_id = 0

    def ask(self, command: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0,
            payload: bytes = b"") -> bytes:
        self.request_id = (self.request_id + 1) & 0xFF
        frame = bytearray(64)
        frame[0:7] = bytes((0xBB, command, p1, p2, p3, p4, self.request_id))
        frame[7] = sum(frame[0:7]) & 0xFF
        frame[8:8 + len(payload)] = payload
        self.session.feed(bytes(frame))
        reply = self.session.read()
        assert len(reply) == 64 and reply[0] == 0xAA and reply[6] == self.request_id, reply
        assert reply[7] == sum(reply[0:7]) & 0xFF
        return reply

    def status(self) -> bytes:
        """PK_PEv2_StatusGet: the test byte T in [3], answered in [63] as T + 0x5A."""
        test = (0x10 + self.request_id) % 199
        reply = self.ask(PEV2, STATUS, test)
        assert reply[63] == (test + 0x5A) & 0xFF
        return reply

    def setup(self, axes: int, charge_pump: int = 0, generator: int = 0, buffer: int = 0,
              estop_polarity: int = 0, enabled_states: int = 0) -> None:
        self.ask(PEV2, SETUP, payload=bytes((axes, charge_pump, generator, buffer,
                                              estop_polarity, enabled_states)))

    def configure(self, axis: int, config: int, switches: int = 0,
                  soft: tuple[int, int] = (0, 0)) -> None:
        """AxisConfigurationSet: [8] config, [9] switches, [16..27] f32 speed and ramps,
        [28]/[32] i32 soft min/max (payload offsets 0, 1, 8..19, 20, 24)."""
        raw = bytearray(45)
        raw[0], raw[1], raw[5], raw[6] = config, switches, 50, 50
        struct.pack_into("<fffii", raw, 8, 10.0, 0.05, 0.05, *soft)
        self.ask(PEV2, AXIS_SET, axis, payload=bytes(raw))


def test_status_byte_3_carries_the_soft_limit_bits() -> None:
    """Fault 4 (byte 3 always 0): axes 0 and 2 stand outside their soft-limit windows,
    axis 1 inside its window, axis 3 outside a window it does not enable: 0b0101."""
    host = Host()
    host.setup(4)
    host.configure(0, ENABLED | SOFT_LIMITS, soft=(100, 200))  # 0 is below 100
    host.configure(1, ENABLED | SOFT_LIMITS, soft=(-50, 50))  # 0 is inside
    host.configure(2, ENABLED | SOFT_LIMITS, soft=(-300, -10))  # 0 is above -10
    host.configure(3, ENABLED, soft=(100, 200))  # soft limits off for this axis
    status = host.status()
    assert status[3] == 0b0101
    assert status[8] == 4  # the enabled axes the setup gave


def test_status_byte_5_is_the_limit_override_the_host_set() -> None:
    """Fault 5 (byte 5): PulseEngineStateSet `85 02 S O M` puts O in the status's [5]."""
    host = Host()
    host.setup(3)
    assert host.status()[5] == 0
    host.ask(PEV2, STATE_SET, STOPPED, 0b101, 0)
    assert host.status()[5] == 0b101
    host.ask(PEV2, STATE_SET, STOPPED, 0b010, 0)
    assert host.status()[5] == 0b010


@pytest.mark.parametrize("pump", [1, 0x5C])
def test_status_byte_11_is_the_charge_pump_of_the_setup(pump: int) -> None:
    """Fault 5 (byte 11): PulseEngineSetup's [9] comes back in the status's [11]."""
    host = Host()
    host.setup(3, charge_pump=pump)
    status = host.status()
    assert status[11] == pump
    assert status[8] == 3


def test_status_byte_14_carries_the_home_bits() -> None:
    """Fault 5 (byte 14): axes 0 and 2 stand inside their home switches, axis 1 outside
    its own (the default home, 1234..1333 pulses, reference: world defaults); with
    axis 1's home input inverted it reads active too."""
    host = Host()
    host.setup(3)
    host.device.set_home(0, -10, 10)
    host.device.set_home(2, -5, 5)
    for axis in range(3):
        host.configure(axis, ENABLED, HOME_SWITCH)
    assert host.status()[14] == 0b101
    host.configure(1, ENABLED, HOME_SWITCH | INVERT_HOME)
    assert host.status()[14] == 0b111
    assert host.status()[12] == 0 and host.status()[13] == 0  # no limit on any of them


@pytest.mark.parametrize("polarity", [1, 0])
def test_status_byte_60_is_the_estop_polarity_of_the_setup(polarity: int) -> None:
    """Fault 6 (byte 60 always 0): PulseEngineSetup's [12] comes back in [60]."""
    host = Host()
    host.setup(3, estop_polarity=polarity)
    status = host.status()
    assert status[60] == polarity
    assert status[56:60] == bytes((8, 125, 128, 1))  # axis count, max pulses, depth, timing
