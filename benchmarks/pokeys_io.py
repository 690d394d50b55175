"""A PoKeys57CNC's I/O polled at 1 kHz over UDP beside a streaming pulse engine, in real
time behind `maxk serve`'s server (the same `Server`, `Service`, `Pacer`).

Two hosts, each in its own process as real hosts are: a streaming host on TCP keeps 3
buffered axes' slot buffer about half full (0xFF fills); an I/O host on UDP, once a
millisecond, does what a LinuxCNC-style loop does with PoKeysLib: PK_DigitalIOGet
(0xCC), PK_AnalogIOGet (0x3A) and PK_EncoderValuesGet (0xCD 0, 0xCD 1, 0x85 0x37), with
an encoder wired to the moving X axis and a world input toggling. Figures: the round
trip of each request (p50, p99, max) and of the whole 5-request cycle, how many cycles
missed their millisecond, and whether the buffer ran dry.

Run: PYTHONPATH=. python3 benchmarks/pokeys_io.py [--seconds 10]
(also `python -m benchmarks pokeys_io`, beside the naive loop's figure)
"""

from __future__ import annotations

import argparse
import asyncio
import multiprocessing
import socket
import struct
import threading
import time
from multiprocessing.connection import Connection

from benchmarks.figure import Figure
from maxk.commands.pokeys import make_request
from maxk.controllers.pokeys.controller import PoKeys
from maxk.controllers.registry import build
from maxk.host.pacing import Pacer
from maxk.host.server import Server, Service

HALF = 64
AXES = 3


class Door:
    """One PoKeys57CNC with a TCP and a UDP door on a thread, free ports."""

    def __init__(self) -> None:
        controller = build("PoKeys57CNC")
        assert isinstance(controller, PoKeys)
        self.controller = controller
        self.starved = 0
        controller.pulse_engine.listeners.append(self._event)
        self.service = Service(1, controller, Pacer(controller))
        self.server = Server([self.service])
        self.loop = asyncio.new_event_loop()
        ready = threading.Event()

        def run() -> None:
            asyncio.set_event_loop(self.loop)

            async def main() -> None:
                self.tcp = (await self.server.open_tcp(self.service, "127.0.0.1", 0))[1]
                self.udp = (await self.server.open_udp(self.service, "127.0.0.1", 0))[1]
                ready.set()
                await self.server.run()

            self.loop.run_until_complete(main())

        self.thread = threading.Thread(target=run, daemon=True)
        self.thread.start()
        ready.wait(10)

    def _event(self, slot: int, event: str, axis: int) -> None:
        if event == "buffer_empty":
            self.starved += 1

    def call(self, fn):  # type: ignore[no-untyped-def]
        async def wrapper():  # type: ignore[no-untyped-def]
            return fn()

        return asyncio.run_coroutine_threadsafe(wrapper(), self.loop).result(10)

    def close(self) -> None:
        self.loop.call_soon_threadsafe(self.server.stop)
        self.thread.join(10)


class Host:
    """Raw 64-byte frames; each reply must carry its request's ID."""

    def __init__(self, sock: socket.socket, address: tuple[str, int] | None = None) -> None:
        self.sock = sock
        self.address = address
        self.request_id = 0
        self.round_trips: list[float] = []

    def ask(self, command: int, p1: int = 0, p2: int = 0, p3: int = 0,
            payload: bytes = b"") -> bytes:
        self.request_id = (self.request_id + 1) & 0xFF
        frame = make_request(command, p1, p2, p3, 0, self.request_id, payload)
        start = time.perf_counter()
        if self.address is None:
            self.sock.sendall(frame)
            reply = b""
            while len(reply) < 64:
                reply += self.sock.recv(64 - len(reply))
        else:
            self.sock.sendto(frame, self.address)
            reply = self.sock.recv(64)
        self.round_trips.append(time.perf_counter() - start)
        assert len(reply) == 64 and reply[6] == self.request_id
        return reply


def _percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(len(ordered) * q))] * 1e3


def _stream(port: int, seconds: float, out: Connection) -> None:
    """The streaming host (its own process, as a real host is): keeps 3 buffered axes'
    slot buffer about half full."""
    stream = Host(socket.create_connection(("127.0.0.1", port), timeout=5))
    row = bytes([1, 0x81, 2])  # +1, -1, +2 pulses a slot
    accepted = 0
    for _ in range(4):
        accepted += stream.ask(0x85, 0xFF, 16, AXES, row * 16)[2]
    stream.ask(0x85, 0x02, 3)  # RUNNING
    start = time.monotonic()
    while time.monotonic() - start < seconds:
        consumed = (time.monotonic() - start) * 1000.0
        want = max(0, min(18, int(HALF - (accepted - consumed))))
        accepted += stream.ask(0x85, 0xFF, want, AXES, row * want)[2]
        time.sleep(0.004)
    position = struct.unpack_from("<i", stream.ask(0x85, 0x00), 24)[0]
    out.send((stream.round_trips, position))


def _poll(port: int, seconds: float, out: Connection) -> None:
    """The I/O host (its own process): every millisecond DigitalIOGet, AnalogIOGet and
    EncoderValuesGet as PoKeysLib sends them."""
    udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    udp.settimeout(5)
    io = Host(udp, ("127.0.0.1", port))
    cycles: list[float] = []
    late = 0
    encoder = 0
    start = time.monotonic()
    tick = time.perf_counter()
    while time.monotonic() - start < seconds:
        begin = time.perf_counter()
        io.ask(0xCC, 0)
        io.ask(0x3A, 1)
        encoder = struct.unpack_from("<i", io.ask(0xCD, 0), 8)[0]
        io.ask(0xCD, 1)
        io.ask(0x85, 0x37)
        cycles.append(time.perf_counter() - begin)
        tick += 0.001
        pause = tick - time.perf_counter()
        if pause > 0:
            time.sleep(pause)
        else:
            late += 1
            tick = time.perf_counter()
    out.send((io.round_trips, cycles, late, encoder))


def run(seconds: float = 10.0) -> dict[str, float]:
    """The device behind its doors in this process; the two hosts in their own
    processes, speaking only through the sockets."""
    door = Door()
    setup = Host(socket.create_connection(("127.0.0.1", door.tcp), timeout=5))
    setup.ask(0x85, 0x01, payload=bytes([AXES, 0, 1]))
    config = bytearray(45)
    config[0] = 0x01
    struct.pack_into("<f", config, 8, 125.0)
    for axis in range(AXES):
        setup.ask(0x85, 0x11, axis, payload=bytes(config))
    functions = bytearray(55)
    functions[0], functions[2], functions[40] = 0x04, 0x02 | 0x40, 0x08
    setup.ask(0xC0, 1, payload=bytes(functions))
    setup.ask(0xC4, 1, payload=bytes([1]))
    pins = door.controller.device.pins
    door.call(lambda: pins.attach_encoder(0, 0))
    door.call(lambda: pins.analog(41, 1.5))
    door.call(lambda: pins.set_input(3, lambda board: int(board.time * 50) % 2 == 0))
    context = multiprocessing.get_context("fork")
    stream_in, stream_out = context.Pipe(duplex=False)
    poll_in, poll_out = context.Pipe(duplex=False)
    streamer = context.Process(target=_stream, args=(door.tcp, seconds, stream_out))
    poller = context.Process(target=_poll, args=(door.udp, seconds, poll_out))
    streamer.start()
    poller.start()
    stream_trips, position = stream_in.recv()
    trips, cycles, late, encoder = poll_in.recv()
    streamer.join(10)
    poller.join(10)
    starved = door.starved
    door.close()
    assert abs(position - encoder) <= 125, (position, encoder)  # the encoder follows X
    return {"cycles": len(cycles), "late": late, "starved": starved,
            "requests": len(trips),
            "p50_ms": _percentile(trips, 0.5),
            "p99_ms": _percentile(trips, 0.99),
            "max_ms": max(trips) * 1e3,
            "cycle_p99_ms": _percentile(cycles, 0.99),
            "stream_p99_ms": _percentile(stream_trips, 0.99)}


def figures(seconds: float = 10.0) -> list[Figure]:
    r = run(seconds)
    note = (f"{int(r['cycles'])} cycles of DigitalIOGet+AnalogIOGet+EncoderValuesGet (5 "
            f"requests) at 1 kHz over UDP, 3 axes streaming over TCP; {int(r['late'])} "
            f"cycles late, buffer ran dry {int(r['starved'])} time(s)")
    return [Figure("pokeys_io_udp_round_trip_p50", r["p50_ms"], "ms", None, note),
            Figure("pokeys_io_udp_round_trip_p99", r["p99_ms"], "ms", None,
                   "target p99 < 2 ms"),
            Figure("pokeys_io_cycle_p99", r["cycle_p99_ms"], "ms", None,
                   "the 5 requests of one 1 ms cycle, back to back")]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args()
    r = run(args.seconds)
    print(f"pokeys I/O at 1 kHz over UDP beside a streaming pulse engine, {args.seconds:g} s")
    print(f"  cycles             : {int(r['cycles'])} ({int(r['late'])} missed their ms)")
    print(f"  I/O requests       : {int(r['requests'])}")
    print(f"  round trip, ms     : p50 {r['p50_ms']:.3f}  p99 {r['p99_ms']:.3f}  "
          f"max {r['max_ms']:.2f}")
    print(f"  5-request cycle p99: {r['cycle_p99_ms']:.3f} ms")
    print(f"  streaming fill p99 : {r['stream_p99_ms']:.3f} ms; buffer ran dry "
          f"{int(r['starved'])} time(s)")


if __name__ == "__main__":
    main()
