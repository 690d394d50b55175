"""The interactive terminal: MAXkComm, but with help, completion, history and a status line.

Type controller commands as on the real board (`AX; VL5000; MR1000; GO; ID;`); each
line is sent with a CR. Words the board never understands are the REPL's own:
`help [XX]`, `quit`, and `:`-prefixed meta-commands (`:status`, `:advance 0.5 s`, ...).
No MAX command starts with `:`, and `help`/`quit`/`exit` are not valid command
sequences, so nothing meant for the board is ever taken by the REPL.

Virtual time follows the wall clock by default (a move takes as long as on the real
board); `--manual-time` or `:clock manual` stops it, and `:advance` / `:run` move it.
The session logic lives in ReplSession so it can be tested without a terminal.
"""

from __future__ import annotations

import os
import shutil
import sys
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TYPE_CHECKING

from maxk.console_session import ConsoleSession
from maxk.controllers.contract import BuildOptions, Console, Controller
from maxk.controllers.registry import DEFAULT_MODEL, build, default_archive
from maxk.script import parse_duration

if TYPE_CHECKING:
    from prompt_toolkit.history import History

META_HELP = """\
REPL words (everything else goes to the controller):
  help              this text          help XX      one command from the table
  :status           every axis         :time        virtual time
  :clock realtime|manual               :advance 0.5 s  move virtual time (also ms, ticks)
  :run [10 s]       advance until the controller is idle (timeout, default 60 s)
  :reset            reset the controller (power-up, archived parameters)
  :world            the machine around it   :world X limits 5000 -5000  (docs/io.md)
  :record FILE      write this session as a regression script (kept up to date; :record
                    off stops; the script replays on a fresh controller: docs/scripts.md)
  quit / exit / Ctrl-D
{controller}'s own words:
"""


class ReplSession(ConsoleSession):
    """One REPL session on one controller: turns typed lines into output lines. Written
    against the controller contract: the controller's console runs the lines, gives
    help, completion and the status line (`ConsoleSession`, which the front panel's
    console shares); time is its engine's, moved here with the wall clock or by hand."""

    def __init__(self, model: str = DEFAULT_MODEL, rate: int | None = None,
                 manual_time: bool = False, speed: float = 1.0,
                 clock: Callable[[], float] = time.monotonic,
                 archive: str | os.PathLike | bool | None = None) -> None:
        if archive is True:
            archive = default_archive(model)
        controller: Controller = build(model, BuildOptions(
            archive=None if archive in (None, False) else str(archive),
            update_rate_hz=rate))
        ConsoleSession.__init__(self, controller, "the maxk REPL")
        self.manual_time = manual_time
        self.speed = speed
        self._clock = clock
        self._epoch = clock()
        self._tick_at_epoch = self.controller.engine.tick
        self.finished = False
        self.record_path: Path | None = None  # where :record writes the session
        self._saved_revision = -1  # the record's revision last written there

    # ---- time -----------------------------------------------------------------------
    def sync(self) -> None:
        """Bring virtual time up to the wall clock (realtime mode only)."""
        if self.manual_time:
            return
        engine = self.controller.engine
        elapsed = (self._clock() - self._epoch) * self.speed
        target = self._tick_at_epoch + int(elapsed * engine.update_rate_hz + 1e-6)
        if target > engine.tick:
            # a bounded turn, as the doors give (host/pacing.py): a controller whose work
            # outruns real time falls behind, says so on the status line, and its clock
            # slips past a quarter second rather than freezing the prompt
            deadline = time.perf_counter() + 0.1
            if not engine.advance_to(target, lambda: time.perf_counter() >= deadline):
                lag = (target - engine.tick) * engine.period
                limit = 0.25 * self.speed
                if lag > limit:
                    self._tick_at_epoch -= int((lag - limit) * engine.update_rate_hz)
                engine.behind = min(lag, limit)
                return
        engine.behind = 0.0

    def set_clock(self, manual: bool) -> None:
        self.sync()
        self.manual_time = manual
        self._epoch = self._clock()
        self._tick_at_epoch = self.controller.engine.tick

    # ---- lines ----------------------------------------------------------------------
    def handle(self, line: str) -> list[str]:
        self.sync()
        text = line.strip()
        word = text.lower()
        if word in ("quit", "exit", ":quit", ":exit", ":q"):
            self.finished = True
            return []
        noted: list[str] = []
        try:
            if self.is_meta(text):
                out = self._meta(text)
                noted = self.console.new_errors()
            else:
                out, noted = self.run_line(line)
        except Exception as error:  # a fault in the emulator must not end the session
            out = [f"! internal error: {type(error).__name__}: {error} (the line was lost; "
                   "please report it)"]
        return out + noted + self._save_record()

    def _save_record(self) -> list[str]:
        """Keep the :record file up to date (a line telling why, when it cannot be)."""
        if self.record_path is None or self.record.revision == self._saved_revision:
            return []  # (help, :status and the like change nothing: not written again)
        try:
            self.record_path.write_text(self.record.script(), encoding="utf-8")
            self._saved_revision = self.record.revision
        except (OSError, ValueError) as error:  # ValueError: a NUL in the name
            self.record_path = None
            return [f"record: {error}; recording stopped"]
        return []

    def _meta(self, text: str) -> list[str]:
        body = text[1:] if text.startswith(":") else text
        word, _, rest = body.strip().partition(" ")
        word = word.lower()
        rest = rest.strip()
        engine = self.controller.engine
        if word == "help" and not rest:
            head = META_HELP.format(controller=self.controller.kind)
            return head.rstrip("\n").splitlines() + self.console.repl_help()
        if word == "time":
            mode = "manual" if self.manual_time else f"realtime x{self.speed:g}"
            return [f"tick {engine.tick}, {engine.time:.6f} s virtual ({mode}; "
                    f"{engine.period * 1e6:.2f} us per tick)"]
        shared = self.shared_word(word, rest)
        if shared is not None:
            return shared
        if word == "clock":
            if rest not in ("realtime", "manual"):
                return ["say :clock realtime or :clock manual"]
            self.set_clock(rest == "manual")
            return [f"clock: {rest}"]
        if word == "advance":
            try:
                ticks = parse_duration(rest or "0", engine.update_rate_hz)
            except ValueError as error:
                return [str(error)]
            engine.advance(ticks)
            self._tick_at_epoch += ticks
            return [f"tick {engine.tick}"]
        if word == "run":
            try:
                ticks = parse_duration(rest or "60 s", engine.update_rate_hz)
            except ValueError as error:
                return [str(error)]
            start = engine.tick
            console = self.console
            idle = engine.run_until(lambda _e: console.is_idle(), ticks)
            self._tick_at_epoch += engine.tick - start
            return [("idle" if idle else "still busy") + f" at tick {engine.tick}"]
        if word == "record":
            return self._record_word(rest)
        if word == "reset":
            self.sync()
            self.controller.reset()  # errors from before stay seen; a power-up one is new
            self.record.reset()
            return self.console.after_reset()
        out = self.console.repl_word(word, rest)
        if out is not None:
            return out
        return [f"unknown REPL word :{word}; type help"]

    def _record_word(self, rest: str) -> list[str]:
        """`:record FILE` writes the session so far and keeps it up to date; `:record
        off` stops; `:record` says where it goes."""
        if not rest:
            where = f"recording into {self.record_path}" if self.record_path else \
                "not recording (:record FILE)"
            return [f"{where}; {len(self.record.entries)} lines since power-up"]
        if rest.lower() == "off":
            path, self.record_path = self.record_path, None
            return [f"recording stopped; {path} kept" if path else "not recording"]
        path = Path(rest).expanduser()
        self.record_path = path
        self._saved_revision = -1  # a new file: written now, whatever the record holds
        problem = self._save_record()
        return problem or [f"recording into {path}: the session since power-up, "
                           "then every line (`maxk run` replays it)"]

    # ---- display --------------------------------------------------------------------
    def status_lines(self) -> list[str]:
        return self.console.status_lines()

    def prompt(self) -> str:
        return self.console.prompt()

    def toolbar(self, width: int = 80) -> str:
        self.sync()
        behind = self.controller.engine.behind
        if behind >= 0.05:  # running behind real time (its work outruns it)
            flag = f"BEHIND {behind:.2f}s "
            return flag + self.console.status_line(max(1, width - len(flag)))
        return self.console.status_line(width)


def _history_path(path: Path | None) -> Path:
    if path is not None:
        return path
    return Path(os.environ.get("MAXK_HISTORY", Path.home() / ".maxk_history"))


def _history(path: Path | None) -> History:
    """The history file; history in memory only when it cannot be written (no home
    directory, a read-only one), rather than an error on every Enter."""
    from prompt_toolkit.history import FileHistory, InMemoryHistory

    target = None
    try:
        target = _history_path(path)
        with open(target, "ab"):
            pass
    except (OSError, RuntimeError):  # RuntimeError: Path.home() without a home
        where = f"{target} cannot be written" if target else "no home directory"
        print(f"maxk: history kept in memory only ({where})", file=sys.stderr)
        return InMemoryHistory()
    return FileHistory(str(target))


def run_repl(model: str = DEFAULT_MODEL, rate: int | None = None,
             manual_time: bool = False, speed: float = 1.0,
             history: Path | None = None,
             archive: str | os.PathLike | bool | None = True) -> int:
    try:
        session = ReplSession(model, rate, manual_time, speed, archive=archive)
    except ValueError as error:  # a rate the controller does not run at
        print(f"maxk: {error}", file=sys.stderr)
        return 2
    if not sys.stdin.isatty():
        return _run_piped(session, sys.stdin)
    try:
        from prompt_toolkit import PromptSession
    except ImportError:  # pragma: no cover - prompt_toolkit is a dependency
        return _run_piped(session, sys.stdin, prompt=True)
    prompt_session: PromptSession[str] = PromptSession(
        history=_history(history),
        completer=MnemonicCompleter(session.console),
        complete_while_typing=False,
        bottom_toolbar=lambda: session.toolbar(shutil.get_terminal_size().columns),
        refresh_interval=0 if manual_time else 0.25,  # 0: no refresh
    )
    print(f"maxk: {session.controller.model} emulator. Type help for REPL words, "
          "help XX for a command, Ctrl-D to leave.")
    while not session.finished:
        try:
            line = prompt_session.prompt(session.prompt)
        except KeyboardInterrupt:
            continue
        except EOFError:
            break
        for out in session.handle(line):
            print(out)
    return 0


def _run_piped(session: ReplSession, lines: Iterable[str], prompt: bool = False) -> int:
    """Without a terminal (a pipe, a test), read lines and print what the REPL would."""
    for line in lines:
        if prompt:
            print(session.prompt(), end="", flush=True)
        for out in session.handle(line.rstrip("\n")):
            print(out, flush=True)
        if session.finished:
            break
    return 0


try:
    from prompt_toolkit.completion import Completer, Completion

    class MnemonicCompleter(Completer):
        """Tab completion from the controller's command table."""

        def __init__(self, console: Console | None = None) -> None:
            self.console = console if console is not None else build(DEFAULT_MODEL).console()

        def get_completions(self, document, complete_event):  # type: ignore[no-untyped-def]
            text = document.text_before_cursor
            if text.lstrip().startswith(":") or text.lstrip().lower().startswith("help "):
                return
            word = ""
            for ch in reversed(text):
                if ch.isalpha() or ch in "#?_":
                    word = ch + word
                else:
                    break
            if not word:
                return
            key = word.upper()
            for candidate in self.console.words():
                if candidate.upper().startswith(key):
                    yield Completion(candidate, start_position=-len(word),
                                     display_meta=self.console.summary(candidate))


except ImportError:  # pragma: no cover
    MnemonicCompleter = None  # type: ignore[assignment,misc]
