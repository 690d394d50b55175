"""The MAXk for a person: what the REPL and command scripts show of a board (the
`Console` contract). Lines typed as on the vendor's MAXkComm; the MAX command table's
help and completion; the status line; the REPL's MAXk words (doorbell, capture ring,
the world around the board, command errors)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from maxk.commands.max.reference import help_text
from maxk.commands.max.table import COMMANDS, lookup
from maxk.controllers.contract import ConsoleBase
from maxk.controllers.glance import short_position
from maxk.personalities.maxk.board import Board
from maxk.personalities.maxk.flags import (
    COMMAND_ERROR,
    K_NOTIFY,
    OVERTRAVEL_SHIFT,
    SLIP_SHIFT,
    W_NOTIFY,
    describe_doorbell,
)

REPL_WORDS = """\
  :errors      recent command errors and why
  :doorbell    doorbell flags     :clear       write ones to clear every doorbell bit
  :capture     read the capture ring (as a host would)
  :commands    list mnemonics"""


@dataclass(frozen=True)
class AxisStatus:
    """A snapshot of one axis for status lines and assertions."""

    letter: str
    position: int
    encoder: int
    velocity: int
    done: bool
    moving: bool
    queued: int
    status: str


class MaxControls(Protocol):
    """The MAXk controller's API the console uses (maxk.controllers.maxk.MAXk)."""

    @property
    def board(self) -> Board: ...

    def send(self, text: str) -> list[str]: ...
    def status(self) -> list[AxisStatus]: ...


class MaxConsole(ConsoleBase):
    """The `Console` of a MAXk controller."""

    def __init__(self, maxk: MaxControls) -> None:
        super().__init__(maxk)  # type: ignore[arg-type]
        self.maxk = maxk
        self._errors_seen = 0  # a power-up error is shown with the first line

    def execute(self, line: str) -> list[str]:
        return list(self.maxk.send(line))

    def new_errors(self) -> list[str]:
        """`! command error: ...` for each command error since the last look."""
        errors = list(self.maxk.board.errors)
        total = len(errors)
        # The deque keeps the newest 200; count what appeared since the last line.
        new = errors[-(total - self._errors_seen):] if total > self._errors_seen else []
        self._errors_seen = total
        return [f"! command error: {record}" for record in new]

    def refused(self, replies: list[str], noted: list[str]) -> list[str]:
        """Each command error's record (`'MR': MR needs an operand`), as a script names it."""
        return [line.removeprefix("! command error: ") for line in noted]

    def prompt(self) -> str:
        b = self.maxk.board
        mode = f"A{b.model.axis_letters[b.current_axis]}" if b.mode == "single" else b.mode
        return f"{b.model.name} {mode}> "

    def status_line(self, width: int = 80) -> str:
        b = self.maxk.board
        return status_line(b.time, self.maxk.status(), b.doorbell, b.model.axis_letters,
                           width)

    def status_lines(self) -> list[str]:
        lines = ["axis  position   encoder  velocity  status  queue"]
        for s in self.maxk.status():
            lines.append(f"{s.letter:>4} {s.position:>9} {s.encoder:>9} {s.velocity:>9}  "
                         f"{s.status}    {s.queued}")
        b = self.maxk.board
        flags = describe_doorbell(b.doorbell, b.model.axis_letters)
        lines.append(f"doorbell 0x{b.doorbell:08x} ({flags})")
        return lines

    def help(self, topic: str) -> list[str] | None:
        spec = lookup(topic)
        return None if spec is None else help_text(spec).splitlines()

    def words(self) -> list[str]:
        return [spec.mnemonic for spec in COMMANDS.values()]

    def summary(self, word: str) -> str:
        spec = lookup(word)
        return "" if spec is None else spec.summary

    def is_idle(self) -> bool:
        return self.maxk.board.is_idle()

    def repl_help(self) -> list[str]:
        return REPL_WORDS.splitlines()

    def after_reset(self) -> list[str]:
        b = self.maxk.board
        archive = b.archive.path
        return [f"reset: firmware flags {b.firmware_state:#010x} "
                f"({'archive ' + str(archive) if archive else 'archive in memory'})"]

    def repl_word(self, word: str, rest: str) -> list[str] | None:
        b = self.maxk.board
        if word == "errors":
            errors = list(b.errors)[-20:]
            if not errors:
                return ["no command errors"]
            return [f"tick {e.tick}: {e}" for e in errors]
        if word == "doorbell":
            return [f"0x{b.doorbell:08x}: {describe_doorbell(b.doorbell, b.model.axis_letters)}"]
        if word == "clear":
            b.write_doorbell(0xFFFF_FFFF)
            return ["doorbell cleared"]
        if word == "capture":
            entries = b.capture_ring.read()
            if not entries:
                return ["capture ring empty"]
            letters = b.model.axis_letters
            return [f"{letters[e.axis]} encoder {e.encoder} home {e.home_events:#04x} "
                    f"inputs +{e.io_rising:#06x} -{e.io_falling:#06x}" for e in entries]
        if word == "commands":
            return [f"{s.syntax:<16} {s.summary}" for s in COMMANDS.values()]
        return None


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
    tokens = " ".join(f"{a.letter}{short_position(a.position)}{m.strip()}"
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


