"""One side of the MAXk differential test: runs jobs against whichever `maxk` is first on
PYTHONPATH and prints what it observed, so that two trees can be compared byte for byte.

Run as `PYTHONPATH=<tree> python3 -P tests/differential_worker.py` (-P: the tree on
PYTHONPATH, not this directory's parent, provides `maxk`). It reads one JSON job a line
on stdin and answers one JSON line per job on stdout. It only uses the API that both the
old (c4c36cf) and the refactored tree expose: `from maxk import MAXk`, the board's
`errors`, `doorbell`, flag listeners, `io.changes`, `capture_ring`, `maxk.script`.
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import traceback
from typing import Any

from maxk import MAXk


def _status(board: MAXk) -> list[list[Any]]:
    return [[s.letter, s.position, s.encoder, s.velocity, s.done, s.moving, s.queued,
             s.status] for s in board.status()]


class Observer:
    """Everything a MAXk user can see, reported only when it changed (small answers)."""

    def __init__(self, board: MAXk) -> None:
        self.board = board
        self.flags: list[int] = []
        board.board.add_flag_listener(self.flags.append)
        self.last: dict[str, Any] = {}
        self.trace: list[Any] = []

    def observe(self) -> dict[str, Any]:
        b = self.board.board
        now: dict[str, Any] = {
            "tick": b.tick,
            "rate": b.update_rate_hz,
            "doorbell": b.doorbell,
            "firmware_flags": self.board.firmware_flags,
            "command_error": self.board.command_error,
            "mode": [b.mode, b.current_axis],
            "status": _status(self.board),
            "positions": [self.board.position(a.letter) for a in b.axes],
            "encoders": [self.board.encoder(a.letter) for a in b.axes],
            "errors": [[e.tick, e.command, e.reason, str(e)] for e in b.errors],
            "io": [list(c) for c in b.io.changes],
            "io_word": b.io.word(b),
            "capture": b.capture_ring.to_bytes().hex(),
        }
        out = {k: v for k, v in now.items() if self.last.get(k) != v}
        self.last = now
        if self.trace:
            out["trace"] = list(self.trace)
            self.trace.clear()
        if self.flags:
            out["flag_words"] = list(self.flags)
            self.flags.clear()
        return out


def run_stream(job: dict[str, Any]) -> dict[str, Any]:
    fd, archive = tempfile.mkstemp(prefix="maxk-diff-archive-")
    os.close(fd)
    os.unlink(archive)
    try:
        board = MAXk(job["model"], job["rate"], archive=archive)
        observer = Observer(board)
        steps: list[dict[str, Any]] = [observer.observe()]
        for step in job["steps"]:
            steps.append(_do(board, observer, step))
        archive_bytes = None
        if os.path.exists(archive):
            with open(archive, "rb") as file:
                archive_bytes = file.read().hex()
        return {"steps": steps, "archive": archive_bytes}
    finally:
        if os.path.exists(archive):
            os.unlink(archive)


def _do(board: MAXk, observer: Observer, step: list[Any]) -> dict[str, Any]:
    kind, args = step[0], step[1:]
    result: Any = None
    try:
        if kind == "send":
            result = board.send(args[0])
        elif kind == "write":
            result = board.write(args[0])
        elif kind == "writeb":
            result = board.write(args[0].encode("latin-1"))
        elif kind == "advance":
            board.advance(args[0], ticks=args[1])
        elif kind == "until_done":
            result = board.run_until_done(*args[0], timeout=args[1])
        elif kind == "until_idle":
            result = board.run_until_idle(timeout=args[0])
        elif kind == "reset":
            board.reset()
        elif kind == "world":
            name, posargs, kwargs = args
            result = getattr(board, name)(*posargs, **kwargs)
        elif kind == "velocity":
            result = repr(board.velocity(args[0]))
        elif kind == "input_fn":
            bit, period, phase = args
            board.set_input(bit, lambda b, p=period, ph=phase: ((b.tick + ph) // p) % 2 == 1)
        elif kind == "input_pos":
            bit, letter, thr = args
            board.set_input(bit, lambda b, L=letter, t=thr: b.axis(L).steps_now(b) > t)
        elif kind == "observer":
            every = args[0]
            log = observer.trace
            def cb(b, log=log):
                log.append([b.tick] + [a.steps_now(b) for a in b.axes]
                           + [a.status_string(b) for a in b.axes] + [a.flags for a in b.axes])
            board.board.add_observer(cb, every)
        elif kind == "poll":
            n, k = args
            result = []
            for _ in range(n):
                board.advance(0.0, ticks=k)
                result.append(board.send("AM QA" if len(board.board.axes) > 1 else "AX QA")
                              + board.send("AM RP" if len(board.board.axes) > 1 else "AX RP")
                              + [board.board.tick])
        else:
            raise ValueError(f"unknown step {kind}")
        out = {"result": result}
    except Exception as error:  # the difference we look for may be an exception
        out = {"exception": f"{type(error).__name__}: {error}"}
    out.update(observer.observe())
    return out


def run_script(job: dict[str, Any]) -> dict[str, Any]:
    from maxk.script import parse_script
    from maxk.script import run_script as run

    try:
        script = parse_script(job["text"], job.get("path", "t.maxk"))
        transcript = run(script)
    except Exception as error:
        return {"exception": f"{type(error).__name__}: {error}"}
    board: Any = transcript.board  # a MAXk (the new tree types it as any controller)
    return {
        "entries": [list(map(_plain, e)) for e in transcript.entries],
        "failures": [f.report() for f in transcript.failures],
        "state": _status(board) if board else None,
    }


def _plain(value: Any) -> Any:
    return list(value) if isinstance(value, (list, tuple)) else value


def main() -> None:
    for line in sys.stdin:
        job = json.loads(line)
        try:
            if job["kind"] == "stream":
                answer = run_stream(job)
            elif job["kind"] == "script":
                answer = run_script(job)
            elif job["kind"] == "where":
                import maxk

                answer = {"file": maxk.__file__}
            else:
                answer = {"exception": f"unknown job {job['kind']}"}
        except Exception:
            answer = {"crash": traceback.format_exc()}
        sys.stdout.write(json.dumps(answer) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
