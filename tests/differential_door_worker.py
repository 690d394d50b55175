"""One side of the TCP-door differential test: the tree's own in-process `maxk serve`
(its tests/hosting.py: real sockets, a manual clock) driven by real socket clients.

Run as `PYTHONPATH=<tree> python3 -P tests/differential_door_worker.py`; one JSON job a
line on stdin, one JSON answer a line on stdout. A job is a list of batches; in a batch
clients send byte strings (pipelined, split, garbage), then every client that is open
sends a probe (LF #WS LF) and reads up to the probe's =0: so every byte was run before
the manual clock moves (`advance` after the batch), and what each client read is
deterministic.
"""

from __future__ import annotations

import json
import socket
import sys
import time
import traceback
from typing import Any

from tests.hosting import HostedBoards  # the tree's own (PYTHONPATH)

PROBE = b"\n#WS\n"


def read_until(sock: socket.socket, suffix: bytes, buffer: bytearray,
               timeout: float = 20.0) -> bool:
    deadline = time.monotonic() + timeout
    while not buffer.endswith(suffix):
        sock.settimeout(max(0.01, deadline - time.monotonic()))
        try:
            chunk = sock.recv(65536)
        except TimeoutError:
            return False
        if not chunk:
            return False
        buffer += chunk
    return True


def drain(sock: socket.socket, buffer: bytearray, quiet: float = 0.05) -> None:
    sock.settimeout(quiet)
    while True:
        try:
            chunk = sock.recv(65536)
        except TimeoutError:
            return
        if not chunk:
            return
        buffer += chunk


def run(job: dict[str, Any]) -> dict[str, Any]:
    eol = {"lfcr": b"\n\r", "lf": b"\n", "crlf": b"\r\n", "cr": b"\r"}[job["eol"]]
    suffix = (b"\x06" if job["ack"] else b"") + b"=0" + eol
    hosted = HostedBoards(models=(job["model"],), eol=job["eol"], ack=job["ack"])
    socks: dict[int, socket.socket] = {}
    got: list[list[str]] = []
    try:
        for batch in job["batches"]:
            per_client: dict[int, bytearray] = {}
            exact = True  # no run of pipelined sends that TCP or the slices may cut
            big = any(len(data) > 2000 for _, data in batch["sends"])
            run_client, run_sends = None, 0

            def probe(client: int, per_client: dict[int, bytearray] = per_client) -> None:
                socks[client].sendall(PROBE)
                buf = bytearray()  # this probe's own =0, never an earlier one's
                if not read_until(socks[client], suffix, buf):
                    buf += b"<<no probe reply>>"
                per_client.setdefault(client, bytearray()).extend(buf)

            for client, data in batch["sends"]:
                if run_client is not None and client != run_client:
                    probe(run_client)  # clients take turns: one host's bytes all run first
                    run_sends = 0
                if client not in socks:
                    socks[client] = socket.create_connection(("127.0.0.1", hosted.ports[0]), 5)
                    socks[client].setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                    # connected once the server answers it (not when the kernel accepts)
                    probe(client)
                socks[client].sendall(data.encode("latin-1"))
                run_client, run_sends = client, run_sends + 1
                if run_sends > 1 or len(data) > 2000 or data[-1:] not in (";", "\r", "\n"):
                    # TCP may coalesce the bytes with what follows (the probe that ends a
                    # half command too): notifications may then come before the replies
                    exact = False
                if batch.get("sync_each"):
                    probe(client)  # one send, fully run, before the next
                    run_sends = 0
            # the last sender first: its bytes all run before anyone else's probe
            order = sorted(socks, key=lambda c: (c != run_client, c))
            for client in order:
                # closing clients too: what a host sends right before it hangs up is a
                # known difference of its own (test_differential_maxk.py), kept apart
                probe(client)
            for client in batch.get("close", []):
                if client in socks:
                    socks.pop(client).close()
            got.append([f"{c}:{bytes(per_client.get(c, b'')).decode('latin-1')}"
                        for c in sorted(per_client)]
                       + ([] if exact else ["pipelined" + (" big" if big else "")]))
            if batch.get("advance"):
                hosted.advance(batch["advance"])
        tail = []
        for client in sorted(socks):
            buf = bytearray()
            drain(socks[client], buf)
            tail.append(f"{client}:{bytes(buf).decode('latin-1')}")
        got.append(tail)
        return {"batches": got}
    finally:
        for sock in socks.values():
            sock.close()
        hosted.close()


def main() -> None:
    for line in sys.stdin:
        job = json.loads(line)
        try:
            answer = run(job)
        except Exception:
            answer = {"crash": traceback.format_exc()}
        sys.stdout.write(json.dumps(answer) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
