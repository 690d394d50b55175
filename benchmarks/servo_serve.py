"""`maxk serve` with 16 MAXk-A000 boards of 10 servo axes each, in real time (issue 19).

The server runs `maxk serve`'s own code (`maxk.host.serve.serve`) in a separate process,
with one observer added after every pacing pass that records how far each board's
virtual time is behind the wall clock (the pacer lag). A host per board, as a real
installation has, configures all ten axes as tuned servo axes (PSM, gains, CL1) and
starts an endless loop of back-and-forth moves (the servo benchmarks' short moves, about
three a second per axis); then the hosts poll their boards with `AA RP;` at `rate` per
second per board, one query outstanding each, and time every round trip.

    python3 -m benchmarks.servo_serve [--seconds 60] [--boards 16] [--rate 10] [--json]
    python3 -m benchmarks.servo_serve --steppers ...   (the same moves, stepper axes)

Target: p99 query round trip below 5 ms, every board kept in real time.
"""

from __future__ import annotations

import argparse
import asyncio
import multiprocessing
import os
import re
import selectors
import socket
import sys
import threading
import time
from multiprocessing.connection import Connection

from benchmarks.figure import Figure
from benchmarks.live_server import EOL, percentile, print_figures

MOVES = ("AA; PSM,M,M,M,M,M,M,M,M,M; LP0,0,0,0,0,0,0,0,0,0; "
         "KP100,100,100,100,100,100,100,100,100,100; KD400,400,400,400,400,400,400,400,400,400; "
         "KI40,40,40,40,40,40,40,40,40,40; KU400,400,400,400,400,400,400,400,400,400; "
         "KV680,680,680,680,680,680,680,680,680,680; CL1,1,1,1,1,1,1,1,1,1; "
         "VL50000,40000,30000,20000,10000,50000,40000,30000,20000,10000; "
         "AC500000,400000,300000,200000,100000,500000,400000,300000,200000,100000; "
         "AM; LS1000000,1000000,1000000,1000000,1000000,1000000,1000000,1000000,1000000,"
         "1000000; MR7001,-5003,3002,1999,777,-7001,5003,-3002,-1999,-777; GO; "
         "MR-7001,5003,-3002,-1999,-777,7001,-5003,3002,1999,777; GO; LE; AA CL?;")
STEPPER_MOVES = "AA; " + MOVES[MOVES.index("VL50000"):].replace("AA CL?;", "AA RP;")
"""The same moves on the power-up stepper axes (issue 39: stepper boards served too)."""
FIRST_REPLY = {MOVES: re.compile(rb"on(,on){9}"), STEPPER_MOVES: re.compile(rb"-?\d+(,-?\d+){9}")}
RP_REPLY = re.compile(rb"-?\d+(,-?\d+){9}")
TARGET_P99_MS = 5.0
GRACE = 5.0  # seconds a reply may take after the last poll before it counts as lost


def _server(boards: int, limit: float, ports_out: Connection, stats_out: Connection) -> None:
    """`maxk serve --boards N --model MAXk-A000 --no-archive --port 0`, plus a lag
    observer; reports the ports, then (when stopped) the lags seen."""
    from maxk.cli import build_parser
    from maxk.host import serve as serve_module
    from maxk.host.server import Server

    lags: list[float] = []
    sent_at = [time.monotonic()]
    servers: list[Server] = []
    original_init = Server.__init__

    def init(self: Server, *args: object, **kwargs: object) -> None:
        original_init(self, *args, **kwargs)  # type: ignore[arg-type]
        servers.append(self)

        def watch() -> None:
            lags.append(max(s.pacer.lag() for s in self.services))
            # a server a second behind may never get round to stopping: a summary now
            # and then (only then: sorting the lags is not free)
            now = time.monotonic()
            if lags[-1] > 1.0 and now >= sent_at[0] + 5.0:
                sent_at[0] = now
                stats_out.send(("lags", _lag_summary(lags)))

        self.after_pacing(watch)

    Server.__init__ = init  # type: ignore[method-assign]
    # a server too slow for its boards never gets round to stopping (each pacing pass
    # chases a wall clock running away from it): this one ends regardless
    watchdog = threading.Timer(limit + 30.0, os._exit, (3,))
    watchdog.daemon = True
    watchdog.start()
    sys.stdout = open(os.devnull, "w")  # noqa: SIM115 (its "board N:" lines: ports come by pipe)
    args = build_parser().parse_args(
        ["serve", "--boards", str(boards), "--model", "MAXk-A000", "--no-archive",
         "--host", "127.0.0.1", "--port", "0", "--seconds", f"{limit:g}"])

    async def main() -> int:
        task = asyncio.ensure_future(serve_module.serve(args))
        while not servers or any(not s.ports for s in servers[0].services):
            await asyncio.sleep(0.01)
            if task.done():
                return task.result()
        ports_out.send([s.ports[0][1] for s in servers[0].services])
        return await task

    cpu, wall = time.process_time(), time.monotonic()
    code = asyncio.run(main())
    stats_out.send(("end", code, _lag_summary(lags),
                    (time.process_time() - cpu) / (time.monotonic() - wall)))


def _lag_summary(lags: list[float]) -> tuple[float, float]:
    """(p99, max) of the pacer lags in ms, leaving out the first tenth (the set-up)."""
    kept = sorted(lag * 1e3 for lag in lags[len(lags) // 10:])
    return percentile(kept, 0.99), kept[-1] if kept else float("nan")


def _hosts(ports: list[int], seconds: float, rate: float,
           setup: str = MOVES) -> tuple[list[float], int, int]:
    """One host per board: set it up, then `AA RP;` at `rate`/s, one outstanding each.
    Returns (sorted round trips in ms, queries sent, wrong replies)."""
    socks = [socket.create_connection(("127.0.0.1", p)) for p in ports]
    for sock in socks:
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    buffers = [b""] * len(socks)

    def reply(k: int) -> bytes:
        sock = socks[k]
        while True:
            while EOL not in buffers[k]:
                data = sock.recv(65536)
                if not data:
                    raise ConnectionError("server closed the connection")
                buffers[k] += data
            line, buffers[k] = buffers[k].split(EOL, 1)
            if not line.startswith(b"%"):  # notifications are not replies
                return line

    for k, sock in enumerate(socks):
        sock.settimeout(30.0)
        sock.sendall(setup.encode())
        assert FIRST_REPLY[setup].fullmatch(reply(k))
    time.sleep(1.0)  # every board moving
    latencies: list[float] = []
    sent = wrong = 0
    sel = selectors.DefaultSelector()
    for k, sock in enumerate(socks):
        sock.setblocking(False)
        sel.register(sock, selectors.EVENT_READ, k)
    began: list[float | None] = [None] * len(socks)
    start = time.monotonic()
    # staggered, so the boards' polls spread over each period as independent hosts'
    due = [start + k / (rate * len(socks)) for k in range(len(socks))]
    end = start + seconds
    while True:
        now = time.monotonic()
        if now >= end and all(b is None for b in began) or now >= end + GRACE:
            break  # a reply later than GRACE is counted lost
        for k, sock in enumerate(socks):
            if began[k] is None and now < end and due[k] <= now:
                began[k] = time.perf_counter()
                sock.send(b"AA RP;")
                sent += 1
                due[k] += 1.0 / rate
        wait = min([d for k, d in enumerate(due) if began[k] is None] + [end + 10.0])
        for key, _ in sel.select(max(0.0, min(0.05, wait - time.monotonic()))):
            k = key.data
            data = socks[k].recv(65536)
            if not data:
                raise ConnectionError("server closed the connection")
            buffers[k] += data
            while EOL in buffers[k] and began[k] is not None:
                line, buffers[k] = buffers[k].split(EOL, 1)
                if line.startswith(b"%"):
                    continue
                t0 = began[k]
                assert t0 is not None
                latencies.append((time.perf_counter() - t0) * 1e3)
                began[k] = None
                if not RP_REPLY.fullmatch(line):
                    wrong += 1
    sel.close()
    for sock in socks:
        sock.close()
    return sorted(latencies), sent, wrong


def figures(seconds: float = 60.0, boards: int = 16, rate: float = 10.0,
            steppers: bool = False) -> list[Figure]:
    ctx = multiprocessing.get_context("spawn")
    ports_rx, ports_tx = ctx.Pipe(duplex=False)
    stats_rx, stats_tx = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_server, args=(boards, seconds + 20.0, ports_tx, stats_tx),
                       daemon=True)
    proc.start()
    try:
        if not ports_rx.poll(60.0):
            raise RuntimeError("maxk serve did not open its ports")
        ports = ports_rx.recv()
        latencies, sent, wrong = _hosts(ports, seconds, rate,
                                        STEPPER_MOVES if steppers else MOVES)
        code: object = "killed by its watchdog"  # unless it says it stopped
        lag: tuple[float, float] = (float("nan"), float("nan"))
        cpu_share = float("nan")
        while stats_rx.poll(90.0):
            try:
                message = stats_rx.recv()
            except EOFError:  # the watchdog ended a server that could not stop
                break
            if message[0] == "lags":
                lag = message[1]
            else:
                _, code, lag, cpu_share = message
                break
    finally:
        proc.join(10.0)
        if proc.is_alive():
            proc.kill()
            proc.join()
    if code not in (0, "killed by its watchdog"):
        raise RuntimeError(f"maxk serve exited {code}")
    kind = "stepper" if steppers else "servo"
    note = (f"{boards} x MAXk-A000, 10 {kind} axes each moving, AA RP at {rate:g}/s per "
            f"board for {seconds:g} s; load average {os.getloadavg()[0]:.1f} on "
            f"{os.cpu_count()} CPUs")
    return [
        Figure(f"serve_{kind}_boards_query_p50", percentile(latencies, 0.50), "ms", None, note),
        Figure(f"serve_{kind}_boards_query_p99", percentile(latencies, 0.99), "ms", None,
               f"target p99 < {TARGET_P99_MS:g} ms"),
        Figure(f"serve_{kind}_boards_query_max", latencies[-1] if latencies else float("nan"),
               "ms"),
        Figure(f"serve_{kind}_boards_queries", len(latencies), "replies",
               note=f"of {sent} sent (the rest lost: over {GRACE:g} s late); {wrong} wrong "
               "(must be 0)"),
        Figure(f"serve_{kind}_boards_pacer_lag_p99", lag[0], "ms", None,
               "the worst board's virtual time behind the wall clock after a pacing pass"),
        Figure(f"serve_{kind}_boards_pacer_lag_max", lag[1], "ms", None,
               "" if code == 0 else "the server could not stop by itself: killed"),
        Figure(f"serve_{kind}_boards_server_cpu", 100.0 * cpu_share, "% of one core", None,
               "the server process's CPU time over its life (set-up included)"),
    ]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m benchmarks.servo_serve")
    parser.add_argument("--json", action="store_true", help="one JSON object per figure")
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--boards", type=int, default=16)
    parser.add_argument("--rate", type=float, default=10.0,
                        help="AA RP queries per second per board")
    parser.add_argument("--steppers", action="store_true",
                        help="stepper axes (the power-up setting) instead of servo axes")
    args = parser.parse_args(argv)
    print_figures(figures(args.seconds, args.boards, args.rate, args.steppers), args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
