"""Differential test of the MAXk TCP door, old tree (/tmp/before) against this one.

Two ways, both byte for byte:

- in-process servers on a manual clock (each tree's own tests/hosting.py, in its own
  subprocess: tests/differential_door_worker.py), so every byte a client reads is
  deterministic: batches of pipelined, split and garbage bytes from one or two clients,
  each batch closed by a `#WS` probe per client, then virtual time moves;
- the real `python -m maxk serve --speed 1000 --no-archive` of each tree, with streams
  whose replies do not depend on the wall clock (finite moves, then wall time to finish);
  there the lines must be the same and in the same order, and the notifications of a
  batch the same set (a move that ends within a millisecond of wall time may notify
  before or after a reply sent in the same batch, in either tree).

    python3 tests/differential_doors.py --seconds 120          # in-process, random
    python3 tests/differential_doors.py --serve 40             # real servers, 40 streams
"""

from __future__ import annotations

import argparse
import json
import os
import random
import re
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from differential_maxk import MODELS, NEW_TREE, OLD_TREE, Gen  # noqa: E402

DOOR_WORKER = Path(__file__).resolve().parent / "differential_door_worker.py"


class DoorWorker:
    def __init__(self, tree: Path) -> None:
        env = dict(os.environ, PYTHONPATH=str(tree), XDG_DATA_HOME="/tmp/maxk-diff-xdg")
        self.proc = subprocess.Popen([sys.executable, "-P", str(DOOR_WORKER)],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     text=True, env=env, cwd="/tmp")

    def submit(self, job: dict[str, Any]) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.write(json.dumps(job) + "\n")
        self.proc.stdin.flush()

    def receive(self) -> dict[str, Any]:
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError("door worker died")
        return json.loads(line)

    def close(self) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.close()
        self.proc.wait(20)


def _no_probe(text: str) -> str:
    return text.replace("#WS", "?UR")  # the probe's reply must stay the probe's


def door_job(seed: int, batches: int = 12) -> dict[str, Any]:
    r = random.Random(seed)
    model = r.choice(list(MODELS))
    gen = Gen(r, model)
    job: dict[str, Any] = {"seed": seed, "model": model,
                           "eol": r.choice(["lfcr", "lfcr", "lf", "crlf", "cr"]),
                           "ack": r.random() < 0.2, "batches": []}
    clients = 1 if r.random() < 0.5 else 2
    for _ in range(batches):
        sends: list[list[Any]] = []
        for _ in range(r.randint(1, 5)):
            client = r.randrange(clients)
            roll = r.random()
            if roll < 0.6:
                text = _no_probe(gen.line())
            elif roll < 0.75:
                text = _no_probe(gen.garbage())
            elif roll < 0.85:
                # a pipelined burst above the 2 KiB slice, with a command error late in
                # it: where notifications fall among the replies
                unit = r.choice(["AX RP;", "WY;", "AM;RI;", "AX QA;", "AA RP;"])
                text = unit * r.randint(150, 700) + r.choice(["XQ;", "MA;", "AX RP;"])
            else:
                text = _no_probe(gen.line())
                cut = r.randint(0, len(text))
                sends.append([client, text[:cut]])
                text = text[cut:]
            if text:
                sends.append([client, text])
        batch: dict[str, Any] = {"sends": sends,
                                 "advance": r.choice([0, 0, 0.001, 0.05, 0.5, 1.0, 2.0])}
        if r.random() < 0.15:
            batch["sync_each"] = True
        if clients == 2 and r.random() < 0.08:
            batch["close"] = [r.randrange(2)]
        job["batches"].append(batch)
    return job


def _lines(stream: str) -> tuple[list[str], list[str]]:
    """A client's bytes as (replies in order, notifications sorted): what must match
    where TCP segmentation or the 2 KiB slices may move notifications among replies."""
    lines = re.split(r"\n\r|\r\n|\n|\r", stream.split(":", 1)[-1])
    return ([x for x in lines if not x.startswith("%000 ")],
            sorted(x for x in lines if x.startswith("%000 ")))


def compare_door(old: dict[str, Any], new: dict[str, Any]) -> tuple[str | None, int]:
    """(the first real difference, how many batches differ only in where notifications
    fall among the replies of pipelined input)."""
    if "crash" in old or "crash" in new:
        return f"crash: old {old.get('crash')} new {new.get('crash')}", 0
    moved = 0
    for n, (a, b) in enumerate(zip(old["batches"], new["batches"], strict=True)):
        if a == b:
            continue
        pipelined = any(x.startswith("pipelined") for x in a)
        for x, y in zip(a, b, strict=True):
            if x == y:
                continue
            if pipelined and _lines(x) == _lines(y):
                moved += 1
                continue
            i = next((k for k, (p, q) in enumerate(zip(x, y, strict=False)) if p != q),
                     min(len(x), len(y)))
            return (f"batch {n}{' (pipelined)' if pipelined else ''}: "
                    f"old {x[max(0, i - 120):i + 160]!r}\n"
                    f"          new {y[max(0, i - 120):i + 160]!r}"), moved
    return None, moved


def fuzz_doors(seconds: float, seed: int) -> list[str]:
    old, new = DoorWorker(OLD_TREE), DoorWorker(NEW_TREE)
    problems, seen = [], set()
    deadline = time.monotonic() + seconds
    n = streams = sent = moved = 0
    try:
        while time.monotonic() < deadline:
            job = door_job(seed + n)
            n += 1
            old.submit(job)
            new.submit(job)
            a, b = old.receive(), new.receive()
            streams += 1
            sent += sum(len(d) for batch in job["batches"] for _, d in batch["sends"])
            found, m = compare_door(a, b)
            moved += m
            if found:
                key = found[:60]
                print(f"door seed {job['seed']}: {found}"[:1200], flush=True)
                if key not in seen:
                    seen.add(key)
                    problems.append(f"door seed {job['seed']} ({job['model']}, eol "
                                    f"{job['eol']}, ack {job['ack']}): {found}")
    finally:
        old.close()
        new.close()
    print(f"{streams} door streams, {sent} bytes sent, {len(problems)} distinct differences; "
          f"{moved} client batches of pipelined input differ only in where notifications "
          f"fall among the replies")
    return problems


# ---- the real `maxk serve` ---------------------------------------------------------------

class Serve:
    def __init__(self, tree: Path, pty: bool = False) -> None:
        env = dict(os.environ, PYTHONPATH=str(tree), XDG_DATA_HOME="/tmp/maxk-diff-xdg")
        args = [sys.executable, "-P", "-m", "maxk", "serve", "--speed", "1000",
                "--no-archive", "--port", "0", "--model", "MAXk-4000"]
        if pty:
            args.append("--pty")
        self.proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True, env=env, cwd="/tmp")
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()
        found = re.search(r"tcp [\d.]+:(\d+)", line)
        assert found, line
        self.port = int(found.group(1))
        serial_path = re.search(r"serial (\S+)", line)
        self.pty = serial_path.group(1) if serial_path else None

    def close(self) -> str:
        self.proc.terminate()
        _, err = self.proc.communicate(timeout=10)
        return err


def serve_lines(gen: Gen, r: random.Random) -> str:
    """Lines whose replies do not depend on when they are run: finite moves (VL >= 1000,
    at most ~40 s of virtual time), settings, queries, errors, garbage."""
    L = r.choice(gen.letters)
    choices = [
        lambda: f"A{L}; VL{r.randint(1000, 50000)}; AC{r.randint(50000, 500000)}; "
                f"MR{r.randint(-30000, 30000)}; GO; ID;",
        lambda: f"AA; VL{','.join(['5000'] * len(gen.letters))}; "
                f"MA{','.join(str(r.randint(-9000, 9000)) for _ in gen.letters)}; GO; ID;",
        lambda: r.choice(["AX RP", "AM RP", "AA RE", "RI", "QI", "AX QA", "WY", "?UR",
                          "AM PP", "AX PS?", "AY LT?", "CL?", "RQC", "BX", "AX RV"]),
        lambda: r.choice(["XQ", "MA", "AX MA1,2", "VL0", "?KP", "#UR5", "ER1,1"]),
        lambda: _no_probe(gen.garbage()).replace("VL", "vl").replace("JG", "jg"),
        lambda: f"A{L} LP{r.randint(-5000, 5000)}; A{L} RP",
        lambda: "AX LS3; MR10; GO; LE; ID",
        lambda: f"A{L} CA; IC; A{L} QA",
    ]
    parts = [r.choice(choices)() for _ in range(r.randint(1, 4))]
    return "\n".join(parts) + "\n"


def split_lines(data: bytes, eol: bytes = b"\n\r") -> list[bytes]:
    return data.split(eol)


def serve_compare(streams: int, seed: int, pty: bool = False) -> list[str]:
    """The same streams against both real servers (one connection each, in step)."""
    servers = [Serve(OLD_TREE, pty), Serve(NEW_TREE, pty)]
    problems = []
    exact = 0
    try:
        for s in range(streams):
            r = random.Random(seed + s)
            gen = Gen(r, "MAXk-4000")
            socks = [socket.create_connection(("127.0.0.1", sv.port), 5) for sv in servers]
            reset = b"AM ST; KL;\n"  # every stream from rest (the board is shared)
            transcript: list[list[bytes]] = [[], []]
            for sock in socks:
                sock.sendall(reset + b"#WS\n")
                buf = bytearray()
                read_until_suffix(sock, b"=0\n\r", buf)
            time.sleep(0.1)
            for _ in range(r.randint(3, 8)):
                text = serve_lines(gen, r).encode("latin-1")
                cuts = sorted(r.sample(range(len(text) + 1), min(2, len(text))))
                pieces = [text[i:j] for i, j in zip([0, *cuts], [*cuts, len(text)], strict=False)]
                for k, sock in enumerate(socks):
                    for piece in pieces:
                        sock.sendall(piece)
                    sock.sendall(b"\n#WS\n")
                    buf = bytearray()
                    read_until_suffix(sock, b"=0\n\r", buf)
                    transcript[k].append(bytes(buf))
                time.sleep(0.25)  # 250 s of virtual time: every move of the batch ends
            for k, sock in enumerate(socks):
                sock.sendall(b"#WS\n")
                buf = bytearray()
                read_until_suffix(sock, b"=0\n\r", buf)
                transcript[k].append(bytes(buf))
                sock.close()
            a, b = b"".join(transcript[0]), b"".join(transcript[1])
            if a == b:
                exact += 1
                continue
            la, lb = split_lines(a), split_lines(b)
            # a move's done notification may fall before or after a reply sent in the
            # same millisecond of wall time: replies in order, notifications as a set
            if ([x for x in la if not x.startswith(b"%000 ")]
                    != [x for x in lb if not x.startswith(b"%000 ")]
                    or sorted(x for x in la if x.startswith(b"%000 "))
                    != sorted(x for x in lb if x.startswith(b"%000 "))):
                problems.append(f"serve stream {seed + s}: old {a!r}\n    new {b!r}")
        print(f"real servers: {streams} streams, {exact} byte-identical, the others the "
              f"same but for where notifications fall" if not problems else "")
    finally:
        errs = [sv.close() for sv in servers]
        for tree, err in zip((OLD_TREE, NEW_TREE), errs, strict=True):
            if err.strip():
                problems.append(f"serve stderr ({tree}): {err[-500:]}")
    return problems


def pty_compare(streams: int, seed: int) -> list[str]:
    """The same lines through both real servers' serial ptys (opened once, like a host
    opening its port), compared like the TCP streams."""
    import serial

    servers = [Serve(OLD_TREE, pty=True), Serve(NEW_TREE, pty=True)]
    problems, exact = [], 0
    try:
        ports = [serial.Serial(sv.pty, timeout=5) for sv in servers]
        for s in range(streams):
            r = random.Random(seed + s)
            gen = Gen(r, "MAXk-4000")
            got: list[bytes] = [b"", b""]
            for port in ports:
                port.write(b"AM ST; KL;\n#WS\n")
                port.read_until(b"=0\n\r")
            time.sleep(0.1)
            for _ in range(r.randint(3, 6)):
                text = serve_lines(gen, r).encode("latin-1")
                for k, port in enumerate(ports):
                    port.write(text + b"\n#WS\n")
                    got[k] += port.read_until(b"=0\n\r")
                time.sleep(0.25)
            for k, port in enumerate(ports):
                port.write(b"#WS\n")
                got[k] += port.read_until(b"=0\n\r")
            a, b = got
            if a == b:
                exact += 1
                continue
            la, lb = split_lines(a), split_lines(b)
            if ([x for x in la if not x.startswith(b"%000 ")]
                    != [x for x in lb if not x.startswith(b"%000 ")]
                    or sorted(x for x in la if x.startswith(b"%000 "))
                    != sorted(x for x in lb if x.startswith(b"%000 "))):
                problems.append(f"pty stream {seed + s}: old {a!r}\n    new {b!r}")
        for port in ports:
            port.close()
        print(f"real servers' ptys: {streams} streams, {exact} byte-identical")
    finally:
        for sv in servers:
            sv.close()
    return problems


def read_until_suffix(sock: socket.socket, suffix: bytes, buffer: bytearray,
                      timeout: float = 5.0) -> None:
    deadline = time.monotonic() + timeout
    start = len(buffer)
    while suffix not in buffer[start:]:
        sock.settimeout(max(0.01, deadline - time.monotonic()))
        try:
            chunk = sock.recv(65536)
        except TimeoutError:
            buffer += b"<<timeout>>"
            return
        if not chunk:
            buffer += b"<<closed>>"
            return
        buffer += chunk


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--serve", type=int, default=0, help="streams on the real servers")
    parser.add_argument("--pty", type=int, default=0, help="streams on the real servers' ptys")
    args = parser.parse_args()
    problems: list[str] = []
    if args.seconds:
        problems += fuzz_doors(args.seconds, args.seed)
    if args.serve:
        problems += serve_compare(args.serve, args.seed)
    if args.pty:
        problems += pty_compare(args.pty, args.seed)
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
