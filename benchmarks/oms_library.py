"""The vendor-API library (libOmsMAXkMC) against `maxk serve` in real time: a
SendAndGetString("AXRP") round trip through the PCI map and over TCP, and a host polling
GetMotorPositions at 1 kHz while 16 boards run busy programs beside it.

The server is a real `maxk serve` process, the host this process calling the library
through ctypes (a call costs about a microsecond more than it would from C)."""

from __future__ import annotations

import ctypes
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.doors import BUSY
from benchmarks.figure import Figure
from maxk.host import oms_library

ROOT = Path(__file__).resolve().parent.parent


class _AxesData(ctypes.Structure):
    _fields_ = [(letter, ctypes.c_long) for letter in "XYZTUVRSWK"]


def _serve(workdir: Path, boards: int, seconds: float) -> tuple[subprocess.Popen, list[str]]:
    workdir.mkdir(parents=True, exist_ok=True)
    proc = subprocess.Popen(
        [sys.executable, "-m", "maxk", "serve", "--boards", str(boards), "--model",
         "MAXk-A000", "--no-archive", "--shm", str(workdir / "maxk"), "--seconds",
         str(seconds)], stdout=subprocess.PIPE, text=True, cwd=ROOT,
        env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert proc.stdout is not None
    doors = [proc.stdout.readline().split(" tcp ")[1].split(",")[0] for _ in range(boards)]
    return proc, doors


def _stop(proc: subprocess.Popen) -> None:
    proc.terminate()
    proc.wait(timeout=30)
    if proc.stdout:
        proc.stdout.close()


def _percentiles(samples: list[float]) -> tuple[float, float]:
    samples.sort()
    return (samples[len(samples) // 2] * 1e3, samples[int(len(samples) * 0.99)] * 1e3)


def _round_trips(lib: ctypes.CDLL, handle: int, count: int) -> list[float]:
    reply = ctypes.create_string_buffer(80)
    send = lib.SendAndGetString
    out = []
    for _ in range(count):
        start = time.perf_counter()
        if send(handle, b"AXRP", reply) != 0:
            raise RuntimeError("AXRP failed")
        out.append(time.perf_counter() - start)
    return out


def figures(count: int = 3000, poll_seconds: float = 5.0) -> list[Figure]:
    if oms_library.compiler() is None:
        return []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        library = oms_library.build(work / oms_library.LIBRARY_NAME)
        lib = ctypes.CDLL(str(library))
        # round trips: one board served, one host
        proc, doors = _serve(work / "one", 1, count * 0.01 * 2 + 30)
        try:
            os.environ["MAXK_OMSMAXK1"] = str(work / "one" / "maxk")
            os.environ["MAXK_OMSMAXK2"] = f"tcp:{doors[0]}"
            one, two = lib.GetOmsHandle(b"OmsMAXk1"), lib.GetOmsHandle(b"OmsMAXk2")
            assert one and two
            _round_trips(lib, one, 200)  # warm up both ends
            map_p50, map_p99 = _percentiles(_round_trips(lib, one, count))
            tcp_p50, tcp_p99 = _percentiles(_round_trips(lib, two, count))
            lib.CloseOmsHandle(one)
            lib.CloseOmsHandle(two)
        finally:
            _stop(proc)
        # positions at 1 kHz from board 1 of 16, every board busy
        proc, doors = _serve(work / "many", 16, poll_seconds + 30)
        try:
            for n in range(1, 17):
                os.environ[f"MAXK_OMSMAXK{n}"] = str(work / "many" / f"maxk{n if n > 1 else ''}")
            handles = [lib.GetOmsHandle(f"OmsMAXk{n}".encode()) for n in range(1, 17)]
            assert all(handles), handles
            for handle in handles:  # ten axes moving back and forth on every board
                lib.SendString(handle, BUSY.encode())
            data = _AxesData()
            calls: list[float] = []
            gaps: list[float] = []
            period = 0.001
            start = last = time.perf_counter()
            tick = 0
            while time.perf_counter() - start < poll_seconds:
                tick += 1
                target = start + tick * period
                while time.perf_counter() < target:
                    pass
                t0 = time.perf_counter()
                if lib.GetMotorPositions(handles[0], ctypes.byref(data)) != 0:
                    raise RuntimeError("GetMotorPositions failed")
                calls.append(time.perf_counter() - t0)
                gaps.append(t0 - last)
                last = t0
            achieved = len(calls) / (time.perf_counter() - start)
            call_p50, call_p99 = _percentiles(calls)
            _gap50, gap99 = _percentiles(gaps[1:])
            moved = data.X != 0 or data.Y != 0
            for handle in handles:
                lib.CloseOmsHandle(handle)
        finally:
            _stop(proc)
    assert moved, "the board's positions never moved"
    note = f"{count} SendAndGetString(AXRP) calls, one board served in real time"
    return [
        Figure("oms_axrp_map_p50", map_p50, "ms", None, note),
        Figure("oms_axrp_map_p99", map_p99, "ms", None, "target < 1 ms (" + note + ")"),
        Figure("oms_axrp_tcp_p50", tcp_p50, "ms", None, note),
        Figure("oms_axrp_tcp_p99", tcp_p99, "ms", None, note),
        Figure("oms_positions_1khz_rate", achieved, "calls/s", 1000.0,
               f"GetMotorPositions through the map for {poll_seconds:g} s beside 16 busy "
               "boards"),
        Figure("oms_positions_call_p99", call_p99, "ms", None,
               f"one GetMotorPositions call (p50 {call_p50 * 1e3:.1f} us)"),
        Figure("oms_positions_gap_p99", gap99, "ms", None, "between polls meant 1 ms apart"),
    ]


if __name__ == "__main__":
    for fig in figures():
        print(f"{fig.name:<28} {fig.value:10.3f} {fig.unit:<8} {fig.note}")
