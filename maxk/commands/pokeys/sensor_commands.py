"""EasySensors (PoKeysLibEasySensors.c and hosts of their own): the sensors the device
reads on its buses, set up and read in frames of several sensors. Nothing is attached in
the emulator, so values read 0 and not OK (D)."""

from __future__ import annotations

from ...personalities.pokeys.device import PoKeysDevice
from .packet import Reply, Request

EASY_SENSORS = 100  # info.iEasySensors of the 57 series


EASY_SENSOR_SETUP = 12  # bytes of one sensor's set-up
EASY_SETUPS_PER_FRAME = 4  # 4 x 12 bytes fit the 56-byte payload
EASY_VALUES_PER_FRAME = 14  # 14 x i32 fit it (PoKeysLib asks 13, an OPC UA bridge 14)


def easy_sensors_setup(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x76 first sensor [2] (0..99), count [3] (1..4; PoKeysLib 1, a bridge 4), [4]=0
    get / 1 set: per sensor 12 bytes at [8 + 12k]: type, reading, refresh, failsafe,
    ID (8); stored (nothing is attached to read, D). Sensors past 99 read zeros."""
    first, count, setting = req.param(1), req.param(2), req.param(3)
    if first >= EASY_SENSORS or not 1 <= count <= EASY_SETUPS_PER_FRAME or setting > 1:
        return None
    sensors = device.io.easy_sensors
    r = Reply(req)
    for k in range(count):
        at = 8 + EASY_SENSOR_SETUP * k
        if setting and first + k < EASY_SENSORS:
            sensors[first + k] = bytes(req.raw[at:at + EASY_SENSOR_SETUP])
        r.put(at, sensors.get(first + k, bytes(EASY_SENSOR_SETUP)))
    return r


def easy_sensors_values(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x77 first [2], count [3] (1..14): values i32 at [8 + 4t], OK bits at [4..5]. No
    sensor answers: values 0, not OK (D)."""
    if req.param(1) >= EASY_SENSORS or not 1 <= req.param(2) <= EASY_VALUES_PER_FRAME:
        return None
    r = Reply(req)
    r[4] = r[5] = 0
    return r
