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
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from maxk.commands.max.reference import help_text
from maxk.commands.max.table import COMMANDS, lookup
from maxk.controllers.maxk import AxisStatus, MAXk
from maxk.personalities.maxk.flags import (
    COMMAND_ERROR,
    K_NOTIFY,
    OVERTRAVEL_SHIFT,
    SLIP_SHIFT,
    W_NOTIFY,
    describe_doorbell,
)
from maxk.personalities.maxk.models import DEFAULT_MODEL, DEFAULT_UPDATE_RATE_HZ
from maxk.script import parse_duration
from maxk.world_settings import describe_world, parse_world

if TYPE_CHECKING:
    from prompt_toolkit.history import History

META_HELP = """\
REPL words (everything else goes to the board):
  help              this text          help XX      one command from the table
  :status           every axis         :errors      recent command errors and why
  :time             virtual time       :clock realtime|manual
  :advance 0.5 s    move virtual time (also ms, ticks)
  :run [10 s]       advance until every axis is idle (timeout, default 60 s)
  :doorbell         doorbell flags     :clear       write ones to clear every doorbell bit
  :world            the stage          :world X limits 5000 -5000   (docs/io.md)
  :capture          read the capture ring (as a host would)
  :reset            reset the controller (power-up parameters from the archive)
  :commands         list mnemonics     quit / exit / Ctrl-D
"""


class ReplSession:
    """One REPL session on one board: turns typed lines into output lines."""

    def __init__(self, model: str = DEFAULT_MODEL, rate: int = DEFAULT_UPDATE_RATE_HZ,
                 manual_time: bool = False, speed: float = 1.0,
                 clock: Callable[[], float] = time.monotonic,
                 archive: str | os.PathLike | bool | None = None) -> None:
        self.maxk = MAXk(model, rate, archive=archive)
        self.manual_time = manual_time
        self.speed = speed
        self._clock = clock
        self._epoch = clock()
        self._tick_at_epoch = 0
        self._errors_seen = 0
        self.finished = False

    # ---- time -----------------------------------------------------------------------
    def sync(self) -> None:
        """Bring virtual time up to the wall clock (realtime mode only)."""
        if self.manual_time:
            return
        board = self.maxk.board
        elapsed = (self._clock() - self._epoch) * self.speed
        target = self._tick_at_epoch + int(elapsed * board.update_rate_hz + 1e-6)
        if target > board.tick:
            board.advance_to(target)

    def set_clock(self, manual: bool) -> None:
        self.sync()
        self.manual_time = manual
        self._epoch = self._clock()
        self._tick_at_epoch = self.maxk.board.tick

    # ---- lines ----------------------------------------------------------------------
    def handle(self, line: str) -> list[str]:
        self.sync()
        text = line.strip()
        word = text.lower()
        if word in ("quit", "exit", ":quit", ":exit", ":q"):
            self.finished = True
            return []
        if word == "help" or word.startswith("help ") or text.startswith(":"):
            out = self._meta(text)
        else:
            out = list(self.maxk.send(line))
        return out + self._new_errors()

    def _new_errors(self) -> list[str]:
        errors = list(self.maxk.board.errors)
        total = len(errors)
        # The deque keeps the newest 200; count what appeared since the last line.
        new = errors[-(total - self._errors_seen):] if total > self._errors_seen else []
        self._errors_seen = total
        return [f"! command error: {record}" for record in new]

    def _meta(self, text: str) -> list[str]:
        body = text[1:] if text.startswith(":") else text
        word, _, rest = body.strip().partition(" ")
        word = word.lower()
        rest = rest.strip()
        if word == "help":
            if not rest:
                return META_HELP.rstrip("\n").splitlines()
            spec = lookup(rest)
            if spec is None:
                return [f"no command {rest!r}; try :commands"]
            return help_text(spec).splitlines()
        if word == "status":
            return self.status_lines()
        if word == "errors":
            errors = list(self.maxk.board.errors)[-20:]
            if not errors:
                return ["no command errors"]
            return [f"tick {e.tick}: {e}" for e in errors]
        if word == "time":
            b = self.maxk.board
            mode = "manual" if self.manual_time else f"realtime x{self.speed:g}"
            return [f"tick {b.tick}, {b.time:.6f} s virtual ({mode}; "
                    f"{b.period * 1e6:.2f} us per tick)"]
        if word == "clock":
            if rest not in ("realtime", "manual"):
                return ["say :clock realtime or :clock manual"]
            self.set_clock(rest == "manual")
            return [f"clock: {rest}"]
        if word == "advance":
            try:
                ticks = parse_duration(rest or "0", self.maxk.board.update_rate_hz)
            except ValueError as error:
                return [str(error)]
            self.maxk.board.advance(ticks)
            self._tick_at_epoch += ticks
            return [f"tick {self.maxk.board.tick}"]
        if word == "run":
            try:
                ticks = parse_duration(rest or "60 s", self.maxk.board.update_rate_hz)
            except ValueError as error:
                return [str(error)]
            start = self.maxk.board.tick
            idle = self.maxk.board.run_until_idle(ticks)
            self._tick_at_epoch += self.maxk.board.tick - start
            return [("idle" if idle else "still busy") + f" at tick {self.maxk.board.tick}"]
        if word == "doorbell":
            b = self.maxk.board
            return [f"0x{b.doorbell:08x}: {describe_doorbell(b.doorbell, b.model.axis_letters)}"]
        if word == "clear":
            self.maxk.board.write_doorbell(0xFFFF_FFFF)
            return ["doorbell cleared"]
        if word == "world":
            if not rest:
                return describe_world(self.maxk)
            try:
                return [parse_world(rest)(self.maxk)]
            except (KeyError, ValueError, OverflowError) as error:
                return [f"world: {error}"]
        if word == "capture":
            entries = self.maxk.board.capture_ring.read()
            if not entries:
                return ["capture ring empty"]
            letters = self.maxk.board.model.axis_letters
            return [f"{letters[e.axis]} encoder {e.encoder} home {e.home_events:#04x} "
                    f"inputs +{e.io_rising:#06x} -{e.io_falling:#06x}" for e in entries]
        if word == "commands":
            return [f"{s.syntax:<16} {s.summary}" for s in COMMANDS.values()]
        if word == "reset":
            self.sync()
            self.maxk.reset()  # errors from before stay seen; a power-up one is new
            archive = self.maxk.board.archive.path
            return [f"reset: firmware flags {self.maxk.board.firmware_state:#010x} "
                    f"({'archive ' + str(archive) if archive else 'archive in memory'})"]
        return [f"unknown REPL word :{word}; type help"]

    # ---- display --------------------------------------------------------------------
    def status_lines(self) -> list[str]:
        lines = ["axis  position   encoder  velocity  status  queue"]
        for s in self.maxk.status():
            lines.append(f"{s.letter:>4} {s.position:>9} {s.encoder:>9} {s.velocity:>9}  "
                         f"{s.status}    {s.queued}")
        b = self.maxk.board
        flags = describe_doorbell(b.doorbell, b.model.axis_letters)
        lines.append(f"doorbell 0x{b.doorbell:08x} ({flags})")
        return lines

    def prompt(self) -> str:
        b = self.maxk.board
        mode = f"A{b.model.axis_letters[b.current_axis]}" if b.mode == "single" else b.mode
        return f"{b.model.name} {mode}> "

    def toolbar(self, width: int = 80) -> str:
        self.sync()
        b = self.maxk.board
        return status_line(b.time, self.maxk.status(), b.doorbell, b.model.axis_letters,
                           width)


def status_line(seconds: float, axes: Sequence[AxisStatus], doorbell: int, letters: str,
                width: int = 80) -> str:
    """The bottom line: time, each axis's position with D (done) or ~ (moving), flags.
    In full when it fits `width`; else compact (decision D): positions in at most four
    characters (123k, -.1M, 2.1G; :status has them exact), done shown by the D marks
    only, the other flags abbreviated (err, ovt, slip, W!, K!) and cut last, so every
    axis stays visible (10 on a MAXk-A000 in 80 columns)."""
    marks = ["D" if a.done else ("~" if a.moving else " ") for a in axes]
    full = (f" t={seconds:.3f}s  "
            + " ".join(f"{a.letter}{a.position}{m}" for a, m in zip(axes, marks, strict=True))
            + f"  flags: {describe_doorbell(doorbell, letters)}")
    if len(full) <= width:
        return full
    tokens = " ".join(f"{a.letter}{_abbreviate(a.position)}{m.strip()}"
                      for a, m in zip(axes, marks, strict=True))
    done = {a.letter for a in axes if a.done}
    flags = ["err"] if doorbell & COMMAND_ERROR else []
    for name, shift in (("ovt", OVERTRAVEL_SHIFT), ("slip", SLIP_SHIFT)):
        hit = "".join(x for i, x in enumerate(letters[:8]) if doorbell >> (shift + i) & 1)
        if hit:
            flags.append(f"{name} {hit}")
    for letter, bit in (("W", W_NOTIFY), ("K", K_NOTIFY)):
        if doorbell & bit and letter not in done:  # a W/K flag its D mark does not explain
            flags.append(f"{letter}!")
    tail = "  " + " ".join(flags) if flags else ""
    for decimals in (3, 1, 0):  # the time's precision gives way first
        line = f"t={seconds:.{decimals}f}s {tokens}"
        if len(line) + len(tail) <= width:
            break
    room = width - len(line)
    if len(tail) <= room:
        line += tail
    elif room >= 5:
        line += tail[:room - 1] + "…"
    return line[:width]


def _abbreviate(value: int) -> str:
    """A position in at most four characters, for a glance: 1234, -999, 12k, -.1M, 2.1G."""
    text = str(value)
    if len(text) <= 4:
        return text
    for suffix, scale in (("k", 1e3), ("M", 1e6), ("G", 1e9)):
        for decimals in (1, 0):
            number = f"{value / scale:.{decimals}f}"
            if number.startswith(("0.", "-0.")):
                number = number.replace("0.", ".", 1)
            if len(number) + 1 <= 4:
                return number + suffix
    return text  # not reached for 32-bit positions


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


def run_repl(model: str = DEFAULT_MODEL, rate: int = DEFAULT_UPDATE_RATE_HZ,
             manual_time: bool = False, speed: float = 1.0,
             history: Path | None = None,
             archive: str | os.PathLike | bool | None = True) -> int:
    session = ReplSession(model, rate, manual_time, speed, archive=archive)
    if not sys.stdin.isatty():
        return _run_piped(session, sys.stdin)
    try:
        from prompt_toolkit import PromptSession
    except ImportError:  # pragma: no cover - prompt_toolkit is a dependency
        return _run_piped(session, sys.stdin, prompt=True)
    prompt_session: PromptSession[str] = PromptSession(
        history=_history(history),
        completer=MnemonicCompleter(),
        complete_while_typing=False,
        bottom_toolbar=lambda: session.toolbar(shutil.get_terminal_size().columns),
        refresh_interval=None if manual_time else 0.25,
    )
    print(f"maxk: {session.maxk.board.model.name} emulator. Type help for REPL words, "
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
        """Tab completion from the command table (and the REPL's own words)."""

        def get_completions(self, document, complete_event):  # type: ignore[no-untyped-def]
            text = document.text_before_cursor
            if text.lstrip().startswith(":") or text.lstrip().lower().startswith("help "):
                return
            word = ""
            for ch in reversed(text):
                if ch.isalpha() or ch in "#?":
                    word = ch + word
                else:
                    break
            if not word:
                return
            key = word.upper()
            for spec in COMMANDS.values():
                if spec.mnemonic.startswith(key):
                    yield Completion(spec.mnemonic, start_position=-len(word),
                                     display_meta=spec.summary)

except ImportError:  # pragma: no cover
    MnemonicCompleter = None  # type: ignore[assignment,misc]
