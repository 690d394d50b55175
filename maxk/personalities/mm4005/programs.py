"""Stored programs, and the work that waits, on the MM4005's engine.

Evidence (docs/mm4005.md, "Programs, waits and variables"): the manual's XM page (3.175: programs
1 to 127 in 30720 bytes of non-volatile memory, saved as entered, one byte a character,
C); the sibling ESP300's manual (p. 3-3, "program execution mode": entered between EP and
QP without being evaluated, run by ``nEX`` while the controller keeps answering the
host, I); a public ESP301 driver erases with ``nXX`` before ``nEP``. The variables of
3.3.1 and 3.145 TY: 1 to 100 integers, 101 to 120 floats, 0 until set (C).

Two kinds of work wait here, each a `Task`: a host's command line held by a wait
command (``1PA5;1WS;1TP``: the TP runs once axis 1 stops) and a running program. Both
are resumed by `Tasks.poll`, which the machine calls once the sources due at a tick have
acted (`after_events`) and before time moves (`settle`), so a wait for a motion's end
ends on the very tick the motion ends. Nothing here parses a command: the language
gives each task its own `resume`.

The archive: one JSON file (the programs and a SHA-256 of them), written whole to a
temporary file, flushed and renamed over the old one, as the MAXk's parameter archive
(docs/flash.md). A file that cannot be read, is not ours or fails its checksum is
reported (`ProgramStore.problem`) and the store starts empty; it is never a traceback.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Final, Protocol

MAX_PROGRAMS: Final = 127  # manual 3.175 XM: program numbers 1 to 127 (C)
MEMORY: Final = 30720  # manual 3.175 XM: bytes of program memory, one a character (C)
INTEGER_VARIABLES: Final = range(1, 101)  # manual 3.3.1 / 3.145 TY (C)
FLOAT_VARIABLES: Final = range(101, 121)
ARCHIVE_FORMAT: Final = "maxk-mm4005-programs"
ARCHIVE_LIMIT: Final = 4 * MEMORY  # a file larger than this is not ours (JSON overhead)
POLL_ROUNDS: Final = 64  # tasks woken one after another at one tick, at most (D)


class Wait(Protocol):
    """What a task waits for."""

    def ready(self, tick: int) -> bool:
        """True once the wait is over at `tick` (asked after the tick's events)."""
        ...

    def due(self) -> int | None:
        """A tick by which the wait may end without any other event (a delay), else None."""
        ...


class Task(Protocol):
    """A command line or a program that may wait."""

    wait: Wait | None
    done: bool
    program: bool  # a program (AB stops it) rather than a host's command line

    def resume(self) -> None:
        """Go on from the wait until the next wait or the end."""
        ...

    def stop(self) -> None:
        """Give up (AB for a program, a power-up for everything)."""
        ...


class MotionStop:
    """WS: the axes named have stopped, then `delay` ticks have passed."""

    def __init__(self, moving: Callable[[], bool], delay_ticks: int = 0) -> None:
        self._moving = moving
        self.delay = delay_ticks
        self.stopped_at: int | None = None

    def ready(self, tick: int) -> bool:
        if self._moving():
            self.stopped_at = None
            return False
        if self.stopped_at is None:
            self.stopped_at = tick
        return tick >= self.stopped_at + self.delay

    def due(self) -> int | None:
        return None if self.stopped_at is None else self.stopped_at + self.delay


class Tasks:
    """The waiting command lines and the running program: an event source (for the
    delays) that the machine polls after each event tick."""

    def __init__(self, now: Callable[[], int]) -> None:
        self._now = now
        self.tasks: list[Task] = []
        self._polling = False

    def add(self, task: Task) -> None:
        if task not in self.tasks:
            self.tasks.append(task)

    @property
    def program(self) -> Task | None:
        """The program running (at most one, D)."""
        return next((t for t in self.tasks if t.program and not t.done), None)

    @property
    def busy(self) -> bool:
        return any(not t.done for t in self.tasks)

    # ---- EventSource -------------------------------------------------------------------
    def next_event(self) -> int | None:
        best: int | None = None
        for task in self.tasks:
            wait = task.wait
            due = None if wait is None else wait.due()
            if due is not None and (best is None or due < best):
                best = due
        return best

    def on_event(self, now: int) -> None:
        """Nothing here: the machine polls once every source of the tick has acted."""

    # ---- waking --------------------------------------------------------------------------
    def poll(self) -> None:
        """Resume every task whose wait is over, again while one wakes another (a line
        that stops an axis ends another's WS at the same tick), at most POLL_ROUNDS."""
        if self._polling or not self.tasks:
            return
        self._polling = True
        try:
            for _ in range(POLL_ROUNDS):
                woke = False
                for task in list(self.tasks):
                    wait = task.wait
                    if task.done or wait is None or not wait.ready(self._now()):
                        continue
                    task.wait = None
                    woke = True
                    task.resume()
                self.tasks = [t for t in self.tasks if not t.done]
                if not woke:
                    break
        finally:
            self._polling = False

    def stop_programs(self) -> None:
        """AB: a running program ends where it is (D)."""
        for task in self.tasks:
            if task.program:
                task.stop()
        self.tasks = [t for t in self.tasks if not t.done]

    def clear(self) -> None:
        """Power-up: every waiting line and the program are gone."""
        for task in self.tasks:
            task.stop()
        self.tasks = []


class Variables:
    """The value variables: 1..100 integers, 101..120 floats, 0 until set (3.145 TY)."""

    def __init__(self) -> None:
        self.values: dict[int, int | float] = {}

    @staticmethod
    def valid(number: int) -> bool:
        return number in INTEGER_VARIABLES or number in FLOAT_VARIABLES

    def get(self, number: int) -> int | float:
        return self.values.get(number, 0 if number in INTEGER_VARIABLES else 0.0)

    def set(self, number: int, value: float) -> None:
        self.values[number] = int(value) if number in INTEGER_VARIABLES else float(value)


class ProgramStore:
    """Programs 1..127, each a list of command lines as entered, kept in memory and, with
    an archive file, on disk (the non-volatile program memory of 3.175: they survive a
    power cycle)."""

    def __init__(self, archive: str | os.PathLike[str] | None = None) -> None:
        self.archive = None if archive is None else Path(archive)
        self.programs: dict[int, list[str]] = {}
        self.problem: str | None = None  # why the archive was not loaded
        self.load()

    def get(self, number: int) -> list[str] | None:
        return self.programs.get(number)

    def used(self) -> int:
        """Bytes of program memory used (each line with its terminator, D)."""
        return sum(self.length(n) for n in self.programs)

    def length(self, number: int) -> int:
        """XM: program n's bytes (0: no such program)."""
        return sum(len(line) + 1 for line in self.programs.get(number, ()))

    def put(self, number: int, lines: list[str]) -> None:
        self.programs[number] = list(lines)
        self.save()

    def erase(self, number: int) -> None:
        if self.programs.pop(number, None) is not None:
            self.save()

    # ---- the archive ---------------------------------------------------------------------
    @staticmethod
    def _digest(programs: dict[str, list[str]]) -> str:
        text = json.dumps(programs, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode("utf-8")).hexdigest()

    def load(self) -> None:
        """Read the archive (none: an empty store). A damaged one is reported in
        `problem` and the store starts empty; the file stays until the next save."""
        self.programs = {}
        self.problem = None
        path = self.archive
        if path is None or not path.exists():
            return
        try:
            if path.stat().st_size > ARCHIVE_LIMIT:
                raise ValueError("larger than any program memory")
            data = json.loads(path.read_text(encoding="utf-8"))
            programs = self._checked(data)
        except (OSError, ValueError, UnicodeDecodeError) as error:
            self.problem = f"program archive {path} not loaded: {error}"
            return
        self.programs = programs

    def _checked(self, data: object) -> dict[int, list[str]]:
        if not isinstance(data, dict) or data.get("format") != ARCHIVE_FORMAT:
            raise ValueError("not an MM4005 program archive")
        raw = data.get("programs")
        if not isinstance(raw, dict) or data.get("sha256") != self._digest(raw):
            raise ValueError("checksum does not match (truncated or edited)")
        programs: dict[int, list[str]] = {}
        for key, lines in raw.items():
            if (not isinstance(key, str) or not key.isdigit()
                    or not 1 <= int(key) <= MAX_PROGRAMS or not isinstance(lines, list)
                    or not all(isinstance(line, str) for line in lines)):
                raise ValueError(f"program {key!r} is not a list of lines")
            programs[int(key)] = lines
        if sum(len(line) + 1 for lines in programs.values() for line in lines) > MEMORY:
            raise ValueError("more than the program memory holds")
        return programs

    def save(self) -> None:
        """Write the archive whole (temporary file, fsync, rename); no archive: nothing.
        A file that cannot be written is reported in `problem` (memory keeps them)."""
        path = self.archive
        if path is None:
            return
        raw = {str(n): lines for n, lines in sorted(self.programs.items())}
        text = json.dumps({"format": ARCHIVE_FORMAT, "programs": raw,
                           "sha256": self._digest(raw)}, indent=1)
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=path.name, suffix=".tmp", dir=path.parent)
            try:
                with os.fdopen(fd, "w", encoding="utf-8") as out:
                    out.write(text)
                    out.flush()
                    os.fsync(out.fileno())
                os.replace(tmp, path)
            except BaseException:
                Path(tmp).unlink(missing_ok=True)
                raise
        except OSError as error:
            self.problem = f"program archive {path} not written: {error}"
            return
        self.problem = None
