"""A host written from the EPICS MM4005 trajectory scan's wire facts alone (reference
mm4005-trajectory-scan.md): every command ends with its own CR and the port's CR
(``CMD\\r\\r``); write-only commands are not answered; a query reads up to CR and parses
from a fixed offset. Build, Execute and Readback as the scan does them. Used by the
tests (virtual time) and runnable against ``maxk serve --model MM4005`` (real time):

    python3 -m tests.mm4005_scan_host PORT
"""

from __future__ import annotations

import math
import socket
import sys
import time
from collections.abc import Callable


class ScanHost:
    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=30)
        self.buffer = b""

    def write(self, command: str) -> None:
        self.sock.sendall(command.encode() + b"\r\r")

    def query(self, command: str) -> str:
        self.write(command)
        while b"\r" not in self.buffer:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise ConnectionError("closed")
            self.buffer += chunk
        line, _, self.buffer = self.buffer.partition(b"\r")
        return line.decode()

    def build(self, traj: list[list[float]], dt: float, pulses: int) -> str:
        """Absolute mode: increments traj[i+1]-traj[i]; MB1,ME n,MN pulses+1; VC; TB."""
        axes = len(traj)
        n = len(traj[0]) - 1
        self.write("NC")
        for a in range(1, axes + 1):
            self.write(f"{a}DC1")
        self.write("UC0.500000")
        for i in range(1, n + 1):
            self.write(f"{i}DT{dt:f}")
            for a in range(1, axes + 1):
                self.write(f"{a}DX{traj[a - 1][i] - traj[a - 1][i - 1]:f}")
            if i % 20 == 0:
                self.query("TB")
        self.write(f"MB1,ME{n},MN{pulses + 1}")
        self.write("VC")
        status = self.query("TB")
        for a in range(1, axes + 1):
            for k in range(1, 7):
                reply = self.query(f"{a}RC{k}")
                float(reply[3:])
        return status

    def move_to_start(self, traj: list[list[float]], wait: Callable[[], None]) -> None:
        self.write(";".join(f"{a}PA{traj[a - 1][0]:.5f}" for a in range(1, len(traj) + 1)))
        while any(ord(tok[3]) & 1 for tok in self.query("MS").split(",")):
            wait()

    def execute(self, wait: Callable[[], None], axes: int) -> str:
        self.write("LS,0EC1.000000")
        wait()
        while True:
            tp = self.query("TP")
            assert len(tp.split(",")) >= axes
            int(self.query("XC1")[2:] or 0)
            ms = self.query("MS")
            tb = self.query("TB")
            if tb[2] != "@":
                return "Failure " + tb
            if not any(ord(tok[3]) & 1 for tok in ms.split(",")[:axes]):
                return "Success"
            wait()

    def readback(self, axes: int) -> list[list[tuple[float, float]]]:
        """Per pulse: (TH, TP) of every axis, as the scan parses iTQ."""
        count = int(self.query("NQ")[2:])
        out = []
        for i in range(1, count + 1):
            tokens = self.query(f"{i}TQ").split(",")
            assert tokens[0] == f"{i}TQ"
            pairs = []
            for a in range(axes):
                th, tp = tokens[1 + 2 * a], tokens[2 + 2 * a]
                assert th.startswith(f"{a + 1}TH") and tp.startswith(f"{a + 1}TP")
                pairs.append((float(th[3:]), float(tp[3:])))
            out.append(pairs)
        return out


def circle(n: int) -> list[list[float]]:
    return [[2.0 * math.cos(2 * math.pi * i / n) for i in range(n + 1)],
            [2.0 * math.sin(2 * math.pi * i / n) for i in range(n + 1)]]


def main(port: int) -> None:
    host = ScanHost(port)
    traj = circle(100)
    print("build:", host.build(traj, 0.05, 100))
    host.move_to_start(traj, lambda: time.sleep(0.1))
    print("execute:", host.execute(lambda: time.sleep(0.02), 2))
    back = host.readback(2)
    worst = max(abs(p[a][0] - traj[a][i]) for i, p in enumerate(back) for a in range(2))
    print(f"readback: {len(back)} pulses, worst TH error {worst:.6f}")


if __name__ == "__main__":
    main(int(sys.argv[1]))
