"""Fairness of the doors (issue 18): how long one well-behaved host waits for a reply while
other hosts of the same board flood it and never read.

`maxk serve` runs as a real separate process (4 x MAXk-A000, real time, 127.0.0.1). One
host polls board 1 with `WY` at a fixed rate, one query outstanding as the EPICS driver
does, and times each round trip. Meanwhile 0 (a baseline), 1, 5 and 20 abusive hosts,
threads of a separate process so they never share a GIL with the timing, each try to
send 10 MB of valid commands (`RI;WY;AA RP;`) to the same board and never read a byte.
A fair server keeps the poller's p99 under 50 ms and answers every query it sent; the
abusers only get in what back-pressure lets through (reported as accepted bytes).

A second run (issue 30) puts a MAXk-A000, an MC405, an MM4005 and a PoKeys57CNC behind
one server; one host runs the MAX queue loop `AX; LS2000000000;` + 1,000 `VL5000;` +
`LE;`, another a busy MC405 `WHILE 1` program uploaded and RUN as atrio does, and a
third times `1TP` on the MM4005 and `AY; RP` on the MAXk's other axis: the busy
controllers lag on their own, the others keep their p99 under 50 ms.

    python3 -m benchmarks.fairness [--seconds 10] [--rate 20] [--abusers 0,1,5,20] [--json]
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import re
import socket
import threading
import time
from dataclasses import dataclass
from multiprocessing.connection import Connection
from pathlib import Path

from benchmarks.live_server import EOL, ROOT, Figure, LiveServer, percentile, print_figures

FLOOD = b"RI;WY;AA RP;"  # three valid queries, about 120 bytes of replies nobody reads
FLOOD_BYTES = 10 * 1024 * 1024
WY_REPLY = re.compile(rb"MAXk-A000, ver:\d+\.\d+, S/N: \d+, FPGA:\d+")
TARGET_P99_MS = 50.0


def _flood(port: int, total: int, deadline: list[float], sent: list[int], index: int,
           start: threading.Event) -> None:
    """One abusive host: valid commands as fast as the server takes them, never reading."""
    sock = socket.create_connection(("127.0.0.1", port))
    try:
        sock.settimeout(0.1)
        chunk = FLOOD * (64 * 1024 // len(FLOOD))
        start.wait()
        done = 0
        offset = 0
        while done < total and time.monotonic() < deadline[0]:
            try:
                n = sock.send(chunk[offset:offset + total - done])
            except TimeoutError:
                continue  # the server stopped reading us: back-pressure, as it should
            except OSError:
                break
            done += n
            offset = (offset + n) % len(chunk)
            sent[index] = done
    finally:
        sock.close()


def _abusers(port: int, count: int, seconds: float, total: int, pipe: Connection) -> None:
    """The abusive hosts' process: connect them all, say so, flood for `seconds`, report
    how many bytes each got into the server's socket."""
    sent = [0] * count
    start = threading.Event()
    deadline = [time.monotonic() + seconds + 5.0]  # set again once everyone is connected
    threads = []
    for i in range(count):  # each thread connects, then waits for `start`
        thread = threading.Thread(target=_flood, args=(port, total, deadline, sent, i, start),
                                  daemon=True)
        threads.append(thread)
        thread.start()
    time.sleep(0.2)
    deadline[0] = time.monotonic() + seconds
    pipe.send("flooding")
    start.set()
    for thread in threads:
        thread.join(seconds + 5.0)
    pipe.send(sent)


@dataclass
class Phase:
    abusers: int
    latencies_ms: list[float]
    sent: int
    replies: int
    wrong: int
    accepted_bytes: int
    rss_kib: int


def _poll(port: int, seconds: float, rate: float, grace: float) -> tuple[list[float], int,
                                                                           int, int]:
    """The well-behaved host: WY at `rate` per second, one outstanding, for `seconds`.
    Returns (round trips in ms, queries sent, replies received, wrong replies)."""
    sock = socket.create_connection(("127.0.0.1", port))
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    latencies: list[float] = []
    sent = replies = wrong = 0
    buffer = b""
    try:
        end = time.monotonic() + seconds
        next_at = time.monotonic()
        while True:
            now = time.monotonic()
            if now >= end:
                break
            if next_at > now:
                time.sleep(next_at - now)
            next_at = max(next_at + 1.0 / rate, time.monotonic())
            began = time.perf_counter()
            sock.sendall(b"WY;")
            sent += 1
            sock.settimeout(max(0.1, end + grace - time.monotonic()))
            line = None
            try:
                while line is None:
                    while EOL not in buffer:
                        data = sock.recv(4096)
                        if not data:
                            raise ConnectionError("server closed the connection")
                        buffer += data
                    text, buffer = buffer.split(EOL, 1)
                    if not text.startswith(b"%"):  # a notification: not our reply
                        line = text
            except TimeoutError:
                break  # no reply within the phase and its grace: counted as lost
            latencies.append((time.perf_counter() - began) * 1e3)
            replies += 1
            if not WY_REPLY.fullmatch(line):
                wrong += 1
    finally:
        sock.close()
    return latencies, sent, replies, wrong


def run_phase(server: LiveServer, abusers: int, seconds: float, rate: float) -> Phase:
    port = server.ports[0]
    proc = None
    accepted = 0
    if abusers:
        ctx = multiprocessing.get_context("spawn")
        rx, tx = ctx.Pipe(duplex=False)
        proc = ctx.Process(target=_abusers, args=(port, abusers, seconds, FLOOD_BYTES, tx),
                           daemon=True)
        proc.start()
        if not rx.poll(30.0):
            proc.kill()
            raise RuntimeError("the abusive hosts did not connect")
        rx.recv()  # "flooding"
    try:
        latencies, sent, replies, wrong = _poll(port, seconds, rate, grace=10.0)
    finally:
        if proc is not None:
            if rx.poll(seconds + 15.0):
                accepted = sum(rx.recv())
            proc.join(5.0)
            if proc.is_alive():
                proc.kill()
                proc.join()
    time.sleep(1.0)  # the server drops the abusers' sessions before the next phase
    return Phase(abusers, sorted(latencies), sent, replies, wrong, accepted, server.rss_kib())


def figures(seconds: float = 10.0, rate: float = 20.0,
            counts: tuple[int, ...] = (0, 1, 5, 20), root: Path = ROOT,
            controllers: bool = True) -> list[Figure]:
    """The flooding hosts' phases, then (`controllers`) the controller abusers' run."""
    result = _flood_figures(seconds, rate, counts, root) if counts else []
    if controllers:
        result += controller_abusers(seconds, rate, root)
    return result


def _flood_figures(seconds: float, rate: float, counts: tuple[int, ...],
                   root: Path) -> list[Figure]:
    limit = len(counts) * (seconds + 30.0) + 60.0  # the server's own time bound
    result: list[Figure] = []
    with LiveServer(4, "MAXk-A000", limit, root) as server:
        rss_start = server.rss_kib()
        for count in counts:
            phase = run_phase(server, count, seconds, rate)
            lat = phase.latencies_ms
            tag = f"fairness_{count}_abusers"
            note = (f"WY at {rate:g}/s for {seconds:g} s on board 1 of 4; {count} host(s) "
                    f"flooding {FLOOD.decode()} and never reading; load average "
                    f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
            result += [
                Figure(f"{tag}_p50", percentile(lat, 0.50), "ms", None, note),
                Figure(f"{tag}_p99", percentile(lat, 0.99), "ms", None,
                       f"target p99 < {TARGET_P99_MS:g} ms with 20 abusers"),
                Figure(f"{tag}_max", lat[-1] if lat else float("nan"), "ms"),
                Figure(f"{tag}_queries_sent", phase.sent, "queries"),
                Figure(f"{tag}_replies", phase.replies, "replies",
                       note="must equal queries sent"),
                Figure(f"{tag}_wrong_replies", phase.wrong, "replies", note="must be 0"),
            ]
            if count:
                result.append(Figure(f"{tag}_flood_accepted", phase.accepted_bytes / 2**20,
                                     "MiB", None, f"of {count} x {FLOOD_BYTES / 2**20:g} MiB "
                                     "tried: what back-pressure let into the sockets"))
            result.append(Figure(f"{tag}_server_rss", phase.rss_kib / 1024, "MiB", None,
                                 f"VmRSS after the phase (at start {rss_start / 1024:.1f})"))
        if not server.alive():
            raise RuntimeError(f"maxk serve died: {server.errors()}")
        code = server.stop()
    if code != 0:
        raise RuntimeError(f"maxk serve exited {code}: {server.errors()}")
    return result


MIXED = "MAXk-A000,MC405,MM4005,PoKeys57CNC"
QUEUE_LOOP = b"AX; JG5000; LS2000000000; " + b"VL5000; " * 1000 + b"LE;\n"


def _until(sock: socket.socket, end: bytes) -> bytes:
    data = b""
    while end not in data:
        chunk = sock.recv(65536)
        if not chunk:
            raise ConnectionError("server closed the connection")
        data += chunk
    return data


def _busy_trio(port: int) -> socket.socket:
    """Upload a WHILE 1 of 500 lines of arithmetic line by line (`!NAME,nR...`, as atrio
    does) and RUN it; the socket stays open."""
    sock = socket.create_connection(("127.0.0.1", port))
    lines = ["x=0", "WHILE 1"] + [f"x = x + {i} * 2 - {i}" for i in range(500)] + ["WEND"]
    commands = ['SELECT "HOG",0', *(f"!HOG,{n}R{line}" for n, line in enumerate(lines)),
                "!HOG,M", "COMPILE", 'RUN "HOG"']
    for command in commands:
        sock.sendall(command.encode() + b"\r\n")
        _until(sock, b"A\r\n>>")  # its prompt after the control-char line
    return sock


def controller_abusers(seconds: float = 10.0, rate: float = 20.0,
                       root: Path = ROOT) -> list[Figure]:
    """The two controller abusers beside two well-behaved controllers (issue 30)."""
    result: list[Figure] = []
    with LiveServer(4, MIXED, seconds + 90.0, root) as server:
        maxk, trio, mm, _pokeys = server.ports
        hog = _busy_trio(trio)
        loop = socket.create_connection(("127.0.0.1", maxk))
        loop.sendall(QUEUE_LOOP)
        time.sleep(1.0)
        hosts = {"MM4005 1TP": (mm, b"1TP\r", b"\r"), "MAXk AY RP": (maxk, b"AY; RP\n", EOL)}
        socks = {name: socket.create_connection(("127.0.0.1", port))
                 for name, (port, _q, _e) in hosts.items()}
        times: dict[str, list[float]] = {name: [] for name in hosts}
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            for name, (_port, query, eol) in hosts.items():
                began = time.perf_counter()
                socks[name].sendall(query)
                _until(socks[name], eol)
                times[name].append((time.perf_counter() - began) * 1e3)
            time.sleep(1.0 / rate)
        for sock in (hog, loop, *socks.values()):
            sock.close()
        for name, lat in times.items():
            lat.sort()
            tag = "fairness_controllers_" + name.split()[0].lower()
            note = (f"{name} at {rate:g}/s for {seconds:g} s while a MAXk queue loop and a "
                    f"busy MC405 program run; load average {os.getloadavg()[0]:.1f}")
            result += [Figure(f"{tag}_p50", percentile(lat, 0.50), "ms", None, note),
                       Figure(f"{tag}_p99", percentile(lat, 0.99), "ms", None,
                              f"target p99 < {TARGET_P99_MS:g} ms"),
                       Figure(f"{tag}_max", lat[-1] if lat else float("nan"), "ms")]
        began = time.monotonic()
        code = server.stop()
        result.append(Figure("fairness_controllers_stop", time.monotonic() - began, "s",
                             None, f"server stop with both abusers running (exit {code})"))
    return result


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m benchmarks.fairness")
    parser.add_argument("--json", action="store_true", help="one JSON object per figure")
    parser.add_argument("--seconds", type=float, default=10.0, help="length of each phase")
    parser.add_argument("--rate", type=float, default=20.0,
                        help="WY queries per second of the well-behaved host")
    parser.add_argument("--abusers", default="0,1,5,20",
                        help="comma list of abusive host counts, one phase each ('' for "
                        "only the controller abusers' run)")
    parser.add_argument("--root", type=Path, default=ROOT,
                        help="checkout whose maxk is served (e.g. an older commit exported "
                        "with git archive, for a before/after figure)")
    args = parser.parse_args(argv)
    counts = tuple(int(c) for c in args.abusers.split(",") if c.strip())
    print_figures(figures(args.seconds, args.rate, counts, args.root.resolve()), args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
