"""Door benchmarks: TCP query round trip against boards running in real time, and how
closely the pacer keeps virtual time on the wall clock."""

from __future__ import annotations

import asyncio
import socket
import threading
import time

from maxk import MAXk
from maxk.host.pacing import Pacer
from maxk.host.server import EOLS, BoardService, Framing, Server

BUSY = ("AA; VL50000,40000,30000,20000,10000,50000,40000,30000,20000,10000;"
        "AM; LS1000000,1000000,1000000,1000000,1000000,1000000,1000000,1000000,1000000,"
        "1000000; MR7001,-5003,3002,1999,777,-7001,5003,-3002,-1999,-777; GO; "
        "MR-7001,5003,-3002,-1999,-777,7001,-5003,3002,1999,777; GO; LE;")


def run(seconds: float = 5.0, boards: int = 4) -> dict[str, float]:
    services = []
    for n in range(1, boards + 1):
        maxk = MAXk("MAXk-A000")
        maxk.send(BUSY)
        services.append(BoardService(n, maxk, Pacer(maxk), Framing(EOLS["lfcr"])))
    server = Server(services)
    loop = asyncio.new_event_loop()
    ports: list[int] = []
    ready = threading.Event()
    worst_lag = [0.0]
    worst_gap = [0.0]
    last_pass = [time.monotonic()]

    def watch_lag() -> None:
        for service in services:
            worst_lag[0] = max(worst_lag[0], abs(service.pacer.lag()))
        now = time.monotonic()
        worst_gap[0] = max(worst_gap[0], now - last_pass[0])
        last_pass[0] = now

    def serve() -> None:
        asyncio.set_event_loop(loop)

        async def main() -> None:
            for service in services:
                ports.append((await server.open_tcp(service, "127.0.0.1", 0))[1])
            server.after_pacing(watch_lag)
            ready.set()
            last_pass[0] = time.monotonic()
            await server.run()

        loop.run_until_complete(main())

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    ready.wait(10)
    socks = [socket.create_connection(("127.0.0.1", p)) for p in ports]
    for sock in socks:
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    times: list[float] = []
    end = time.monotonic() + seconds
    i = 0
    buffers = [b""] * len(socks)
    while time.monotonic() < end:
        k = i % len(socks)
        sock = socks[k]
        start = time.perf_counter()
        sock.sendall(b"AA RP;\n")
        data = buffers[k]
        while True:  # skip %000 notifications, as EPICS does
            while b"\n\r" not in data:
                data += sock.recv(4096)
            line, data = data.split(b"\n\r", 1)
            if b"000 0" not in line:
                break
        buffers[k] = data
        times.append(time.perf_counter() - start)
        i += 1
    loop.call_soon_threadsafe(server.stop)
    thread.join(10)
    for sock in socks:
        sock.close()
    times.sort()
    return {
        "p50_ms": times[len(times) // 2] * 1e3,
        "p99_ms": times[int(len(times) * 0.99)] * 1e3,
        "queries": float(len(times)),
        "worst_lag_ms": worst_lag[0] * 1e3,
        "worst_gap_ms": worst_gap[0] * 1e3,
        "seconds": seconds,
    }
