"""`maxk serve` as a real separate process, for the benchmarks that measure the doors from
outside as a host would: started on 127.0.0.1 with free ports, its printed ports read back,
its memory read from /proc, and always stopped (SIGTERM, then SIGKILL) however the
benchmark ends. Also the figure printing the door benchmarks share."""

from __future__ import annotations

import json
import os
import re
import selectors
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from types import TracebackType

from benchmarks.figure import Figure

ROOT = Path(__file__).resolve().parent.parent  # the checkout these benchmarks belong to
EOL = b"\n\r"  # MAXnet framing: every reply line ends with LF CR
BOARD_LINE = re.compile(r"board (\d+): (\S+) tcp 127\.0\.0\.1:(\d+)")


def print_figures(figures: list[Figure], as_json: bool) -> None:
    """The same two forms as `python -m benchmarks`."""
    if not as_json:
        print(f"{'figure':<34} {'value':>14}  {'unit':<24} note")
    for fig in figures:
        if as_json:
            print(json.dumps({"name": fig.name, "value": round(fig.value, 3),
                              "unit": fig.unit}), flush=True)
        else:
            print(f"{fig.name:<34} {fig.value:>14,.3f}  {fig.unit:<24} {fig.note}",
                  flush=True)


def percentile(sorted_values: list[float], fraction: float) -> float:
    """Nearest-rank percentile of an already sorted list (nan when empty)."""
    if not sorted_values:
        return float("nan")
    index = min(len(sorted_values) - 1, max(0, int(len(sorted_values) * fraction)))
    return sorted_values[index]


class LiveServer:
    """`python3 -m maxk serve --boards N --model M --no-archive --port 0` in its own
    process. `limit` seconds is passed as --seconds, so the server stops by itself even if
    this benchmark is killed before it can stop it."""

    def __init__(self, boards: int, model: str, limit: float, root: Path = ROOT,
                 options: tuple[str, ...] = ()) -> None:
        self.options = options  # more `maxk serve` options (e.g. --speed 10)
        self.boards = boards
        self.model = model
        self.limit = limit
        self.root = root
        self.ports: list[int] = []
        self.proc: subprocess.Popen[bytes] | None = None
        # the server's stderr, kept as long as the process lives (closed in stop())
        self._stderr = tempfile.TemporaryFile()  # noqa: SIM115
        self._errors: str | None = None

    def __enter__(self) -> LiveServer:
        self.start()
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.stop()

    def start(self, timeout: float = 30.0) -> None:
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join(
            [str(self.root), *filter(None, [env.get("PYTHONPATH")])])
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "maxk", "serve", "--boards", str(self.boards),
             "--model", self.model, "--no-archive", "--host", "127.0.0.1", "--port", "0",
             "--seconds", f"{self.limit:g}", *self.options],
            cwd=self.root, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
            stderr=self._stderr)
        assert self.proc.stdout is not None
        found: dict[int, int] = {}
        pending = b""
        deadline = time.monotonic() + timeout
        with selectors.DefaultSelector() as sel:
            sel.register(self.proc.stdout, selectors.EVENT_READ)
            while len(found) < self.boards:
                left = deadline - time.monotonic()
                if left <= 0 or self.proc.poll() is not None:
                    self.stop()
                    raise RuntimeError(f"maxk serve did not print its ports: {self.errors()}")
                if not sel.select(left):
                    continue
                chunk = os.read(self.proc.stdout.fileno(), 4096)
                if not chunk:
                    continue  # end of file: poll() above reports the exit
                pending += chunk
                *lines, pending = pending.split(b"\n")
                for line in lines:
                    match = BOARD_LINE.search(line.decode(errors="replace"))
                    if match:
                        found[int(match.group(1))] = int(match.group(3))
        self.ports = [found[n] for n in range(1, self.boards + 1)]

    @property
    def pid(self) -> int:
        assert self.proc is not None
        return self.proc.pid

    def rss_kib(self) -> int:
        """Resident memory of the server (VmRSS in /proc/PID/status), in KiB."""
        with open(f"/proc/{self.pid}/status") as status:
            for line in status:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
        raise RuntimeError("no VmRSS line")

    def alive(self) -> bool:
        return self.proc is not None and self.proc.poll() is None

    def stop(self) -> int | None:
        """SIGTERM (the server closes its doors and exits 0), SIGKILL if it lingers.
        Returns the exit code."""
        proc = self.proc
        if proc is None:
            return None
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait(10)
        if proc.stdout is not None:
            proc.stdout.close()
        if self._errors is None:
            self._errors = self.errors()
            self._stderr.close()
        return proc.returncode

    def errors(self) -> str:
        """What the server wrote on stderr (it says nothing while all is well)."""
        if self._errors is not None:
            return self._errors
        self._stderr.seek(0)
        return self._stderr.read().decode(errors="replace").strip()
