"""A PoKeys57CNC in real time behind its TCP door, and a host that keeps its buffer half
full (64 of 128 slots, 1 pulse a slot) for N wall seconds: does the buffer ever starve,
and how far does the device's slot count stray from the host's wall clock?

The server (the same `Server`, `Service` and `Pacer` as `maxk serve`) runs on its own
thread; the host here speaks raw 64-byte frames: a 0xFF fill each time round, reading
the accepted count and axis 0's position (= slots consumed) from the reply.

Run: PYTHONPATH=. python3 benchmarks/pokeys_realtime.py [--seconds 60]
"""

from __future__ import annotations

import argparse
import asyncio
import socket
import statistics
import struct
import threading
import time

from maxk.commands.pokeys import make_request
from maxk.controllers.pokeys.controller import PoKeys
from maxk.controllers.registry import build
from maxk.host.pacing import Pacer
from maxk.host.server import Server, Service

HALF = 64


class Door:
    """`maxk serve` for one PoKeys57CNC, on a thread, on a free port."""

    def __init__(self) -> None:
        controller = build("PoKeys57CNC")
        assert isinstance(controller, PoKeys)
        self.controller = controller
        self.starved: list[int] = []
        controller.pulse_engine.listeners.append(self._event)
        service = Service(1, controller, Pacer(controller))
        self.server = Server([service])
        self.loop = asyncio.new_event_loop()
        ready = threading.Event()

        def run() -> None:
            asyncio.set_event_loop(self.loop)

            async def main() -> None:
                self.port = (await self.server.open_tcp(service, "127.0.0.1", 0))[1]
                ready.set()
                await self.server.run()

            self.loop.run_until_complete(main())

        self.thread = threading.Thread(target=run, daemon=True)
        self.thread.start()
        ready.wait(10)

    def _event(self, slot: int, event: str, axis: int) -> None:
        if event == "buffer_empty":
            self.starved.append(slot)

    def close(self) -> None:
        self.loop.call_soon_threadsafe(self.server.stop)
        self.thread.join(10)


class Host:
    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=5)
        self.request_id = 0
        self.round_trips: list[float] = []

    def ask(self, command: int, p1: int = 0, p2: int = 0, p3: int = 0,
            payload: bytes = b"") -> bytes:
        self.request_id = (self.request_id + 1) & 0xFF
        frame = make_request(command, p1, p2, p3, 0, self.request_id, payload)
        start = time.perf_counter()
        self.sock.sendall(frame)
        reply = b""
        while len(reply) < 64:
            reply += self.sock.recv(64 - len(reply))
        self.round_trips.append(time.perf_counter() - start)
        assert reply[6] == self.request_id
        return reply

    def fill(self, count: int) -> bytes:
        return self.ask(0x85, 0xFF, count, 1, bytes([1] * count))


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=60.0)
    args = parser.parse_args()
    door = Door()
    host = Host(door.port)
    host.ask(0x85, 0x01, payload=bytes([1, 0, 1]))  # setup: 1 axis
    config = bytearray(45)
    config[0] = 0x01  # enabled, buffered
    struct.pack_into("<f", config, 8, 125.0)
    host.ask(0x85, 0x11, 0, payload=bytes(config))
    accepted = host.fill(56)[2] + host.fill(HALF - 56)[2]  # 56 bytes a frame
    host.ask(0x85, 0x02, 3)  # RUNNING
    start = time.monotonic()
    base = struct.unpack_from("<i", host.ask(0x85, 0x00)[24:28])[0]
    lags: list[float] = []
    while (elapsed := time.monotonic() - start) < args.seconds:
        consumed_estimate = elapsed * 1000.0
        want = int(HALF - (accepted - consumed_estimate))
        reply = host.fill(max(0, min(56, want)))
        accepted += reply[2]
        position = struct.unpack_from("<i", reply, 24)[0] - base
        lags.append((time.monotonic() - start) * 1000.0 - position)
        time.sleep(0.002)
    starved_while_streaming = len(door.starved)
    door.close()
    rt = sorted(host.round_trips)
    print(f"pokeys real time, {args.seconds:g} s, buffer kept at {HALF}/128 over TCP")
    print(f"  requests           : {len(rt)}")
    print(f"  buffer ran dry     : {starved_while_streaming} time(s) (target 0)")
    print(f"  device slots behind host clock, ms: min {min(lags):.1f}  median "
          f"{statistics.median(lags):.1f}  max {max(lags):.1f}")
    print(f"  round trip, ms     : median {rt[len(rt) // 2] * 1e3:.2f}  p99 "
          f"{rt[int(len(rt) * 0.99)] * 1e3:.2f}  max {rt[-1] * 1e3:.2f}")


if __name__ == "__main__":
    main()
