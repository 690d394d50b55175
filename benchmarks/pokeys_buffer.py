"""PoKeys57CNC streaming 8 buffered axes for 10 simulated minutes: simulated seconds per
wall second (best of 3: the machine is shared), straight into the pulse engine, through
the shared engine (firmware_model Engine, the shared world's switches), and through a
session with 0xB0 fills.

Run: PYTHONPATH=. python3 benchmarks/pokeys_buffer.py [--minutes 10]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from maxk.commands.pokeys import PoKeysSession, make_request
from maxk.personalities.pokeys import AxisConfigBits, PoKeysDevice, PulseEngineV2
from maxk.personalities.pokeys.constants import SLOT_SECONDS

AXES = 8


def _pattern(slots: int) -> np.ndarray:
    """A smooth back-and-forth per axis, up to 100 pulses per slot."""
    t = np.arange(slots)[:, None]
    phase = np.arange(AXES)[None, :]
    return np.rint(100 * np.sin(2 * np.pi * (t / 2000.0 + phase / AXES))).astype(np.int32)


def _configure(engine: PulseEngineV2) -> None:
    engine.setup(AXES, 0, 0, 0, 0, 0)
    for a in engine.axes:
        a.settings.config = AxisConfigBits.ENABLED
    engine.set_state(3, 0, 0)


def direct(slots: int) -> float:
    engine = PulseEngineV2()
    _configure(engine)
    data = _pattern(slots)
    sent = 0
    start = time.perf_counter()
    while engine.slot < slots:
        sent += engine.fill(data[sent:sent + 128])
        engine.run_to(min(slots, engine.slot + 120))
    wall = time.perf_counter() - start
    assert engine.positions() == [int(x) for x in data[:sent].sum(axis=0)]
    return slots * SLOT_SECONDS / wall


def shared_engine(slots: int) -> float:
    """As `direct`, but time moves through the device's SlotEngine (events, integrate)
    and the switches come from the shared World."""
    device = PoKeysDevice.create("PoKeys57CNC")
    engine = device.engine
    assert isinstance(engine, PulseEngineV2)
    _configure(engine)
    data = _pattern(slots)
    sent = 0
    start = time.perf_counter()
    while device.slot < slots:
        sent += engine.fill(data[sent:sent + 128])
        device.run_to(min(slots, device.slot + 120))
    wall = time.perf_counter() - start
    assert engine.positions() == [int(x) for x in data[:sent].sum(axis=0)]
    return slots * SLOT_SECONDS / wall


def via_session(slots: int) -> float:
    device = PoKeysDevice.create("PoKeys57CNC")
    _configure(device.engine)  # type: ignore[arg-type]
    session = PoKeysSession(device)
    data = _pattern(slots)
    per_frame = 448 // AXES
    encoded = (np.abs(data) | np.where(data < 0, 0x80, 0)).astype(np.uint8)
    sent, request_id = 0, 0
    start = time.perf_counter()
    while device.slot < slots:
        block = encoded[sent:sent + per_frame].tobytes().ljust(448, b"\0")
        n = min(per_frame, slots - sent)
        frames = []
        for i in range(8):
            request_id = (request_id + 1) & 0xFF
            flags = i | (0x08 if i == 0 else 0x10 if i == 7 else 0)
            frames.append(make_request(0xB0, flags, 0xFF, n, AXES, request_id,
                                       block[i * 56:(i + 1) * 56]))
        session.feed(b"".join(frames))
        sent += session.read()[2]
        if device.engine.buffer.free < per_frame or sent >= slots:
            device.run_to(min(slots, device.slot + 50))
    return slots * SLOT_SECONDS / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--minutes", type=float, default=10.0)
    args = parser.parse_args()
    slots = int(args.minutes * 60 / SLOT_SECONDS)
    print(f"pokeys buffer, {AXES} axes, {args.minutes:g} simulated min")
    best_direct = max(direct(slots) for _ in range(3))
    best_shared = max(shared_engine(slots) for _ in range(3))
    best_session = max(via_session(slots) for _ in range(3))
    print(f"  engine direct : {best_direct:10.0f} simulated s / wall s (target >= 1000)")
    print(f"  shared engine : {best_shared:10.0f} simulated s / wall s (target >= 1000)")
    print(f"  session, 0xB0 : {best_session:10.0f} simulated s / wall s")


if __name__ == "__main__":
    main()
