"""Soak of the doors (issue 18): `maxk serve` with 4 boards under 50 polling hosts for a
long time (default 10 minutes). Reports the server's resident memory at start, peak and
end, replies lost (queries sent minus replies received: must be 0), wrong replies (a
reply not of the form its query asks for: must be 0) and queries served per second.

The 50 hosts are 50 TCP connections (spread over the 4 boards) driven by one selector
loop in this process, each polling at its own rate of 2-5 Hz with `AA RP`, `AA QA`,
`AA RI` or `WY` (the mode is named in every query: the command mode belongs to the
board, shared by its hosts). One host in five also moves an axis of its own (`AX MR1000
GO`, then back with MR-1000) and reads it with `AX RP` (must lie within the move's
travel) and `AX QA`; at the end each mover's axis must rest exactly where its moves add
up to, so a lost or misapplied move shows.

A second soak (issue 30, `--departures`) serves an MC405 and an MM4005 at `--speed 10`:
hosts keep arriving on the MC405, sending `WA(1e11)` and 60 KB of lines behind it and
hanging up, while a host runs the MM4005 benchmark's 1,000-element raster with a pulse
every 0.1 unit (about 50,000 pulses a run) again and again. The server's RSS must stay
flat: a departed host leaves nothing behind, the pulse log is bounded.

    python3 -m benchmarks.soak [--seconds 600] [--clients 50] [--departures] [--json]
"""

from __future__ import annotations

import argparse
import heapq
import random
import re
import selectors
import socket
import sys
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from benchmarks.live_server import EOL, ROOT, Figure, LiveServer, percentile, print_figures

BOARDS = 4
AXES = "XYZTUVRSWK"  # a MAXk-A000's ten axes
STATUS = rb"[PM][DN][LN][HN]"
POSITION = rb"-?\d+"
TEN = {  # the pollers' queries and the form of their one-line replies
    b"AA RP;": re.compile(rb"%s(,%s){9}" % (POSITION, POSITION)),
    b"AA QA;": re.compile(rb"%s(,%s){9}" % (STATUS, STATUS)),
    b"AA RI;": re.compile(rb"%s(,%s){9}" % (STATUS, STATUS)),
    b"WY;": re.compile(rb"MAXk-A000, ver:\d+\.\d+, S/N: \d+, FPGA:\d+"),
}
NOTIFICATION = re.compile(rb"%000 [0-9A-F]{8}")
STEP = 1000  # steps of each move; a mover goes there and back, so it stays in [0, STEP]

Check = Callable[[bytes], bool]


@dataclass
class Host:
    """One polling host: its socket, what it waits for, and (for a mover) its axis."""

    sock: socket.socket
    board: int
    period: float
    axis: str | None = None  # a mover's own axis
    position: int = 0  # where the mover's moves add up to
    ticks: int = 0
    expected: deque[tuple[float, Check]] = field(default_factory=deque)
    inbuf: bytes = b""
    outbuf: bytes = b""


@dataclass
class Tally:
    sent: int = 0
    replies: int = 0
    wrong: int = 0
    unasked: int = 0  # notifications (none expected: nobody asks for ID)
    moves: int = 0
    latencies: list[float] = field(default_factory=list)
    samples: list[str] = field(default_factory=list)  # the first few wrong replies


def _recorder(answers: dict[int, bytes], key: int) -> Check:
    """A check that keeps the reply (a mover's final position) for a later look."""

    def keep(reply: bytes) -> bool:
        answers[key] = reply
        return True

    return keep


class Soak:
    def __init__(self, server: LiveServer, clients: int, seed: int = 18) -> None:
        self.server = server
        self.tally = Tally()
        self.sel = selectors.DefaultSelector()
        self.hosts: list[Host] = []
        rng = random.Random(seed)
        movers_on: dict[int, int] = {}
        for i in range(clients):
            board = i % BOARDS
            sock = socket.create_connection(("127.0.0.1", server.ports[board]))
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            sock.setblocking(False)
            host = Host(sock, board + 1, 1.0 / rng.uniform(2.0, 5.0))
            if i % 5 == 4:
                host.axis = AXES[movers_on.get(board, 0)]
                movers_on[board] = movers_on.get(board, 0) + 1
            self.hosts.append(host)
            self.sel.register(sock, selectors.EVENT_READ, host)
        self.rng = rng

    # sending
    def _send(self, host: Host, data: bytes, check: Check | None) -> None:
        if check is not None:
            host.expected.append((time.perf_counter(), check))
            self.tally.sent += 1
        host.outbuf += data
        self._flush(host)

    def _flush(self, host: Host) -> None:
        try:
            n = host.sock.send(host.outbuf) if host.outbuf else 0
        except (BlockingIOError, InterruptedError):
            n = 0
        host.outbuf = host.outbuf[n:]
        events = selectors.EVENT_READ | (selectors.EVENT_WRITE if host.outbuf else 0)
        self.sel.modify(host.sock, events, host)

    def _in_travel(self, reply: bytes) -> bool:
        return re.fullmatch(POSITION, reply) is not None and 0 <= int(reply) <= STEP

    def _poll_once(self, host: Host) -> None:
        """What a host sends at one of its ticks."""
        host.ticks += 1
        if host.axis is None:
            query = self.rng.choice(list(TEN))
            pattern = TEN[query]
            self._send(host, query, lambda r: pattern.fullmatch(r) is not None)
            return
        a = f"A{host.axis} ".encode()
        turn = host.ticks % 4
        if turn == 1:  # a move: there, then back next time
            step = STEP if host.position == 0 else -STEP
            host.position += step
            self.tally.moves += 1
            self._send(host, a + f"MR{step} GO;".encode(), None)
        elif turn == 3:
            self._send(host, a + b"QA;", lambda r: re.fullmatch(STATUS, r) is not None)
        else:
            self._send(host, a + b"RP;", self._in_travel)

    # receiving
    def _receive(self, host: Host) -> None:
        try:
            data = host.sock.recv(65536)
        except (BlockingIOError, InterruptedError):
            return
        if not data:
            raise ConnectionError(f"board {host.board} closed a connection")
        host.inbuf += data
        while EOL in host.inbuf:
            line, host.inbuf = host.inbuf.split(EOL, 1)
            if NOTIFICATION.fullmatch(line):
                self.tally.unasked += 1
                continue
            if not host.expected:
                self._wrong(host, line, "a reply nobody asked for")
                continue
            began, check = host.expected.popleft()
            self.tally.replies += 1
            self.tally.latencies.append((time.perf_counter() - began) * 1e3)
            if not check(line):
                self._wrong(host, line, "")

    def _wrong(self, host: Host, line: bytes, why: str) -> None:
        self.tally.wrong += 1
        if len(self.tally.samples) < 5:
            self.tally.samples.append(f"board {host.board} axis {host.axis}: {line!r} {why}")

    def _pump(self, timeout: float) -> None:
        for key, events in self.sel.select(timeout):
            host: Host = key.data
            if events & selectors.EVENT_READ:
                self._receive(host)
            if events & selectors.EVENT_WRITE:
                self._flush(host)

    def run(self, seconds: float, sample_every: float = 10.0) -> list[int]:
        """Poll for `seconds`; returns the server's RSS samples (KiB), first and last
        included."""
        rss = [self.server.rss_kib()]
        start = time.monotonic()
        end = start + seconds
        next_sample = start + sample_every
        due = [(start + self.rng.uniform(0, h.period), i) for i, h in enumerate(self.hosts)]
        heapq.heapify(due)
        while True:
            now = time.monotonic()
            if now >= end:
                break
            while due and due[0][0] <= now:
                at, i = heapq.heappop(due)
                self._poll_once(self.hosts[i])
                heapq.heappush(due, (max(at + self.hosts[i].period, now), i))
            if now >= next_sample:
                rss.append(self.server.rss_kib())
                next_sample += sample_every
            self._pump(max(0.0, min(due[0][0], end, next_sample) - time.monotonic()))
        self.elapsed = time.monotonic() - start
        rss.append(self.server.rss_kib())
        return rss

    def drain(self, grace: float = 10.0) -> None:
        """Wait (at most `grace` s) for the replies still on their way."""
        end = time.monotonic() + grace
        while any(h.expected for h in self.hosts) and time.monotonic() < end:
            self._pump(0.05)

    def movers_at_rest(self, grace: float = 15.0) -> int:
        """Ask each mover's axis where it is until it stands where its moves add up to;
        returns how many never did."""
        pending = [h for h in self.hosts if h.axis is not None]
        end = time.monotonic() + grace
        while pending and time.monotonic() < end:
            answers: dict[int, bytes] = {}
            for host in pending:
                host.expected.clear()
                host.expected.append((time.perf_counter(), _recorder(answers, id(host))))
                host.outbuf += f"A{host.axis} RP;".encode()
                self._flush(host)
            self.drain(5.0)
            pending = [h for h in pending if answers.get(id(h)) != str(h.position).encode()]
            if pending:
                time.sleep(0.2)
        return len(pending)

    def close(self) -> None:
        for host in self.hosts:
            self.sel.unregister(host.sock)
            host.sock.close()
        self.sel.close()


def figures(seconds: float = 600.0, clients: int = 50, root: Path = ROOT) -> list[Figure]:
    with LiveServer(BOARDS, "MAXk-A000", seconds + 120.0, root) as server:
        soak = Soak(server, clients)
        try:
            rss = soak.run(seconds)
            soak.drain()
            lost = soak.tally.sent - soak.tally.replies  # before the movers' final checks
            served = soak.tally.replies
            astray = soak.movers_at_rest()
        finally:
            soak.close()
        alive = server.alive()
        code = server.stop()
    t = soak.tally
    if t.samples:
        print("wrong replies, first few:\n  " + "\n  ".join(t.samples), file=sys.stderr)
    if not alive or code != 0:
        raise RuntimeError(f"maxk serve {'died' if not alive else f'exited {code}'}: "
                           f"{server.errors()}")
    lat = sorted(t.latencies)
    movers = sum(1 for h in soak.hosts if h.axis is not None)
    note = (f"{clients} hosts on {BOARDS} x MAXk-A000 for {soak.elapsed:.0f} s, "
            f"{movers} of them moving an axis of their own")
    return [
        Figure("soak_server_rss_start", rss[0] / 1024, "MiB", None, "VmRSS; " + note),
        Figure("soak_server_rss_peak", max(rss) / 1024, "MiB", None,
               f"highest of {len(rss)} samples, one every 10 s"),
        Figure("soak_server_rss_end", rss[-1] / 1024, "MiB"),
        Figure("soak_queries_sent", t.sent, "queries"),
        Figure("soak_replies_lost", lost, "replies", None, "must be 0"),
        Figure("soak_wrong_replies", t.wrong, "replies", None, "must be 0"),
        Figure("soak_queries_per_second", served / soak.elapsed, "queries/s", None,
               "replies received per wall second"),
        Figure("soak_round_trip_p50", percentile(lat, 0.50), "ms"),
        Figure("soak_round_trip_p99", percentile(lat, 0.99), "ms"),
        Figure("soak_round_trip_max", lat[-1] if lat else float("nan"), "ms"),
        Figure("soak_moves", t.moves, "moves", None, "MR1000 / MR-1000 with GO"),
        Figure("soak_movers_astray", astray, "axes", None,
               "axes not resting where their moves add up to; must be 0"),
        Figure("soak_notifications", t.unasked, "lines", None, "none asked for"),
    ]


def _mm_line(sock: socket.socket, text: str, reply: bool = False) -> bytes:
    sock.sendall(text.encode() + b"\r")
    if not reply:
        return b""
    data = b""
    while not data.endswith(b"\r"):
        chunk = sock.recv(4096)
        if not chunk:
            raise ConnectionError("server closed the connection")
        data += chunk
    return data


def departures(seconds: float = 600.0, root: Path = ROOT, rate: float = 20.0,
               rasters_too: bool = True) -> list[Figure]:
    """Departing MC405 hosts behind a waiting statement, and long MM4005 rasters."""
    from benchmarks.mm4005 import ROWS, _pulse_count, raster_lines

    pulses = _pulse_count()
    with LiveServer(2, "MC405,MM4005", seconds + 120.0, root, ("--speed", "10")) as server:
        trio, mm_port = server.ports
        mm = socket.create_connection(("127.0.0.1", mm_port))
        rss: list[int] = [server.rss_kib()]
        left = rasters = 0
        end = time.monotonic() + seconds
        next_sample = time.monotonic() + 10.0
        idle = True
        next_raster = time.monotonic() + 40.0
        behind = b"WA(1e11)\r\n" + b"?1\r\n" * 15000  # 60 KB behind the wait
        while time.monotonic() < end:
            if idle and rasters_too:  # (re)define the raster and start it
                _mm_line(mm, "1PA-5;2PA-1;1WS;2WS")
                for line in raster_lines():
                    _mm_line(mm, line)
                _mm_line(mm, f"NB2;NE{4 * ROWS - 1};NN{pulses};NS;ET")
                rasters += 1
                idle = False
            host = socket.create_connection(("127.0.0.1", trio))
            host.sendall(behind)
            host.close()
            left += 1
            time.sleep(1.0 / rate)
            if time.monotonic() >= next_sample:
                next_sample += 10.0
                rss.append(server.rss_kib())
                _mm_line(mm, "TE", reply=True)  # the MM4005 still answers
            if time.monotonic() >= next_raster:  # a run takes about 27 s at --speed 10
                next_raster += 40.0
                idle = True
        rss.append(server.rss_kib())
        mm.close()
        alive = server.alive()
        code = server.stop()
    if not alive or code != 0:
        raise RuntimeError(f"maxk serve {'died' if not alive else f'exited {code}'}: "
                           f"{server.errors()}")
    note = (f"{left} MC405 hosts left behind WA(1e11) with 60 KB each; {rasters} MM4005 "
            f"raster run(s) of {pulses} pulses started; --speed 10, {seconds:g} s")
    return [
        Figure("soak_departures_rss_start", rss[0] / 1024, "MiB", None, "VmRSS; " + note),
        Figure("soak_departures_rss_peak", max(rss) / 1024, "MiB", None,
               f"highest of {len(rss)} samples, one every 10 s"),
        Figure("soak_departures_rss_end", rss[-1] / 1024, "MiB", None,
               "samples " + " ".join(f"{r / 1024:.1f}" for r in rss)),
        Figure("soak_departures_rss_after_first_sample", rss[min(1, len(rss) - 1)] / 1024,
               "MiB", None, "flat from here is the test"),
    ]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m benchmarks.soak")
    parser.add_argument("--json", action="store_true", help="one JSON object per figure")
    parser.add_argument("--seconds", type=float, default=600.0, help="how long to soak")
    parser.add_argument("--clients", type=int, default=50, help="polling hosts (TCP "
                        "connections spread over the 4 boards)")
    parser.add_argument("--root", type=Path, default=ROOT,
                        help="checkout whose maxk is served")
    parser.add_argument("--departures", action="store_true", help="the issue-30 soak: "
                        "departing MC405 hosts and long MM4005 rasters instead")
    parser.add_argument("--no-rasters", action="store_true", help="with --departures: "
                        "the departing hosts alone")
    args = parser.parse_args(argv)
    if args.departures:
        print_figures(departures(args.seconds, args.root.resolve(),
                                 rasters_too=not args.no_rasters), args.json)
        return 0
    print_figures(figures(args.seconds, args.clients, args.root.resolve()), args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
