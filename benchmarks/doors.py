"""Door benchmarks: TCP query round trip against boards running in real time, and how
closely the pacer keeps virtual time on the wall clock."""

from __future__ import annotations

import asyncio
import socket
import time

from maxk import MAXk
from maxk.host.pacing import Pacer
from maxk.host.server import Server, Service

BUSY = ("AA; VL50000,40000,30000,20000,10000,50000,40000,30000,20000,10000;"
        "AM; LS1000000,1000000,1000000,1000000,1000000,1000000,1000000,1000000,1000000,"
        "1000000; MR7001,-5003,3002,1999,777,-7001,5003,-3002,-1999,-777; GO; "
        "MR-7001,5003,-3002,-1999,-777,7001,-5003,3002,1999,777; GO; LE;")


class PacingWatch:
    """After every pacing pass: the worst lag of any board behind the wall clock, and the
    longest wall time between two passes (what "keeps real time" means in a figure)."""

    def __init__(self, services: list[Service]) -> None:
        self.services = services
        self.worst = {"lag": 0.0, "gap": 0.0}
        self._last = time.monotonic()

    def restart(self) -> None:
        """Count gaps from now (the doors are open, the hosts about to start)."""
        self._last = time.monotonic()

    def __call__(self) -> None:
        worst = self.worst
        for service in self.services:
            worst["lag"] = max(worst["lag"], abs(service.pacer.lag()))
        now = time.monotonic()
        worst["gap"] = max(worst["gap"], now - self._last)
        self._last = now


def _serve(boards: int, seconds: float, ports_out, stats_out) -> None:  # type: ignore[no-untyped-def]
    """The server, in its own process as a real board is to its host."""
    services = []
    for n in range(1, boards + 1):
        maxk = MAXk("MAXk-A000")
        maxk.send(BUSY)
        services.append(Service(n, maxk, Pacer(maxk)))
    server = Server(services)
    watch = PacingWatch(services)
    worst = watch.worst

    async def main() -> None:
        ports = [(await server.open_tcp(s, "127.0.0.1", 0))[1] for s in services]
        server.after_pacing(watch)
        ports_out.send(ports)
        watch.restart()
        asyncio.get_running_loop().call_later(seconds + 1.0, server.stop)
        await server.run()

    asyncio.run(main())
    stats_out.send(worst)


def run(seconds: float = 5.0, boards: int = 4, rate: float | None = None) -> dict[str, float]:
    """rate: queries per second in all (None: as fast as the replies come back)."""
    import multiprocessing

    ctx = multiprocessing.get_context("spawn")
    ports_rx, ports_tx = ctx.Pipe(duplex=False)
    stats_rx, stats_tx = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_serve, args=(boards, seconds, ports_tx, stats_tx))
    proc.start()
    ports = ports_rx.recv()
    socks = [socket.create_connection(("127.0.0.1", p)) for p in ports]
    for sock in socks:
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    times: list[float] = []
    end = time.monotonic() + seconds
    i = 0
    buffers = [b""] * len(socks)
    next_at = time.monotonic()
    while time.monotonic() < end:
        if rate is not None:  # a host that polls at a fixed rate, as EPICS does
            next_at += 1.0 / rate
            delay = next_at - time.monotonic()
            if delay > 0:
                time.sleep(delay)
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
    for sock in socks:
        sock.close()
    worst = stats_rx.recv()
    proc.join(10)
    times.sort()
    return {
        "p50_ms": times[len(times) // 2] * 1e3,
        "p99_ms": times[int(len(times) * 0.99)] * 1e3,
        "queries": float(len(times)),
        "worst_lag_ms": worst["lag"] * 1e3,
        "worst_gap_ms": worst["gap"] * 1e3,
        "seconds": seconds,
    }
