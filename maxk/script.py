"""Command scripts: controller commands, expected replies and waits in virtual time.

A script is plain text, one item per line (format in docs/scripts.md):

    // comment                      (blank lines too)
    @board MAXk-4000                 (before the first command; default MAXk-8000;
                                      several models make one test per model)
    @rate 4096                       (update rate in Hz, before the first command;
                                      several rates make one test per rate)
    AX; VL5000; AC50000; MA10000; GO; ID;
    @wait 0.5 s                      (also: ms, ticks)
    @wait until X done within 5 s    (also: until idle, until all done)
    AX RP
    < 10000                          (the reply the previous command line must give)
    @expect X position 10000         (also: encoder, velocity, done, not done,
                                      error, no error, doorbell 0x..., bit 9 high,
                                      X overtravel, X no overtravel, captures 3)
    @world X limits 5000 -5000       (the machine around the board: switches, index,
                                      faults, inputs, analog, capture; docs/io.md)

Controller commands are sent exactly as written, each line ended by a CR as a terminal
would. Directives start with `@`, expected replies with `<`, comments with `//`: no
MAX command starts with any of these, so they can never be mistaken for one.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from maxk.controllers.contract import BuildOptions, Controller
from maxk.controllers.maxk import MAXk
from maxk.controllers.registry import build, canonical_model
from maxk.controllers.world_settings import parse_world
from maxk.personalities.maxk.models import DEFAULT_MODEL, DEFAULT_UPDATE_RATE_HZ


class ScriptError(Exception):
    """A script line that cannot be understood (names the line)."""

    def __init__(self, path: str, line: int, message: str) -> None:
        super().__init__(f"{path}:{line}: {message}")
        self.path = path
        self.line = line
        self.message = message


@dataclass(frozen=True)
class Step:
    line: int
    kind: str  # "send", "expect-reply", "wait", "wait-until", "expect"
    text: str
    args: tuple = ()


@dataclass
class Script:
    path: str
    steps: list[Step]
    models: list[str] = field(default_factory=lambda: [DEFAULT_MODEL])
    update_rates_hz: list[int] = field(default_factory=lambda: [DEFAULT_UPDATE_RATE_HZ])
    lines: list[str] = field(default_factory=list)
    rate_given: bool = False  # an @rate line (else a non-MAXk runs at its own rate)

    @property
    def model(self) -> str:
        return self.models[0]

    @property
    def update_rate_hz(self) -> int:
        return self.update_rates_hz[0]

    @property
    def checks_replies(self) -> bool:
        """A script with any expected reply is a regression: every reply must match."""
        return any(step.kind == "expect-reply" for step in self.steps)


_DURATION = re.compile(r"^(?P<value>\d+(?:\.\d*)?|\.\d+)\s*(?P<unit>s|sec|ms|us|ticks?)?$", re.I)
_UNTIL = re.compile(
    r"^until\s+(?P<what>idle|all\s+done|(?P<axes>[A-Za-z]+)\s+done)"
    r"(?:\s+within\s+(?P<timeout>.+))?$",
    re.I,
)
DEFAULT_TIMEOUT_S = 60.0


def parse_duration(text: str, update_rate_hz: float) -> int:
    """A duration to ticks: '0.5 s', '250 ms', '100 ticks' (a bare number is seconds)."""
    m = _DURATION.match(text.strip())
    if not m:
        raise ValueError(f"not a duration: {text!r} (say e.g. 0.5 s, 250 ms or 100 ticks)")
    value = float(m["value"])
    unit = (m["unit"] or "s").lower()
    if unit.startswith("tick"):
        if not value.is_integer():
            raise ValueError(f"ticks must be whole: {text!r}")
        return int(value)
    seconds = value * {"s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6}[unit]
    return int(-(-round(seconds * update_rate_hz * 1e9) // 10**9))  # ceil without float fuzz


def parse_script(text: str, path: str = "<script>") -> Script:
    lines = text.splitlines()
    script = Script(path, [], lines=lines)
    seen_command = False
    for number, raw in enumerate(lines, start=1):
        line = raw.strip()
        if not line or line.startswith("//"):
            continue
        if line.startswith("<"):
            if not script.steps or script.steps[-1].kind not in ("send", "expect-reply"):
                raise ScriptError(path, number, "an expected reply must follow a command line")
            script.steps.append(Step(number, "expect-reply", line[1:].strip()))
            continue
        if line.startswith("@"):
            word, _, rest = line[1:].partition(" ")
            word = word.lower()
            rest = rest.strip()
            try:
                if word == "board":
                    if seen_command:
                        raise ValueError("@board must come before the first command")
                    names = rest.replace(",", " ").split()
                    if not names:
                        raise ValueError("@board needs a model, e.g. @board MAXk-4000")
                    script.models = [canonical_model(n) for n in names]
                elif word == "rate":
                    if seen_command:
                        raise ValueError("@rate must come before the first command")
                    rates = rest.replace(",", " ").split()
                    if not rates or any(r not in ("1024", "2048", "4096", "8192")
                                        for r in rates):
                        raise ValueError("@rate takes 1024, 2048, 4096 or 8192 (Hz)")
                    script.update_rates_hz = [int(r) for r in rates]
                    script.rate_given = True
                elif word == "wait":
                    script.steps.append(_parse_wait(number, rest))
                elif word == "expect":
                    script.steps.append(_parse_expect(number, rest))
                elif word == "world":
                    script.steps.append(Step(number, "world", rest, (parse_world(rest),)))
                else:
                    raise ValueError(f"unknown directive @{word}")
            except ValueError as error:
                raise ScriptError(path, number, str(error)) from None
            continue
        seen_command = True
        script.steps.append(Step(number, "send", raw.rstrip("\r\n")))
    return script


def _parse_wait(line: int, rest: str) -> Step:
    m = _UNTIL.match(rest)
    if m:
        timeout = m["timeout"] or f"{DEFAULT_TIMEOUT_S} s"
        parse_duration(timeout, DEFAULT_UPDATE_RATE_HZ)  # ValueError now, not mid-run
        if m["axes"]:
            what = ("done", m["axes"].upper())
        elif m["what"].lower() == "idle":
            what = ("idle", "")
        else:
            what = ("done", "")
        return Step(line, "wait-until", rest, (what, timeout))
    if not rest:
        raise ValueError("@wait needs a duration or 'until ...'")
    if not _DURATION.match(rest):
        raise ValueError(f"not a duration: {rest!r} (say e.g. 0.5 s, 250 ms, 100 ticks, "
                         "or until X done)")
    parse_duration(rest, DEFAULT_UPDATE_RATE_HZ)  # e.g. 1.5 ticks: refused now, not mid-run
    return Step(line, "wait", rest)


_EXPECT = re.compile(
    r"^(?:(?P<axis>[A-Za-z])\s+(?P<field>position|encoder|velocity)\s+(?P<value>-?\d+)"
    r"|(?P<axis2>[A-Za-z])\s+(?P<done>not\s+done|done)"
    r"|(?P<axis3>[A-Za-z])\s+(?P<overtravel>no\s+overtravel|overtravel)"
    r"|(?P<error>no\s+error|error)"
    r"|bit\s+(?P<bit>\d+)\s+(?P<level>high|low)"
    r"|captures\s+(?P<captures>\d+)"
    r"|doorbell\s+(?P<doorbell>0x[0-9a-fA-F]+|\d+))$",
    re.I,
)


def _parse_expect(line: int, rest: str) -> Step:
    m = _EXPECT.match(rest.strip())
    if not m:
        raise ValueError(
            f"cannot read @expect {rest!r}: say e.g. 'X position 1000', 'X done', "
            "'X not done', 'X overtravel', 'error', 'no error', 'bit 9 high', 'captures 2' "
            "or 'doorbell 0x1'"
        )
    return Step(line, "expect", rest, tuple(m.groupdict().items()))


# ---- running -------------------------------------------------------------------------
@dataclass
class Failure:
    line: int
    command: str
    expected: str
    actual: str
    tick: int
    state: list[str] = field(default_factory=list)  # the board when it failed

    def __str__(self) -> str:
        return (f"line {self.line} (tick {self.tick}): {self.command}\n"
                f"  expected: {self.expected}\n  actual:   {self.actual}")

    def report(self) -> str:
        """The failure with the board's state at that moment, for pytest."""
        return "\n".join([str(self), "  board state:", *("    " + s for s in self.state)])


def board_state(controller: Controller) -> list[str]:
    """A compact picture of the controller: what a failure report shows."""
    if not isinstance(controller, MAXk):
        engine = controller.engine
        return [f"tick {engine.tick} ({engine.time:.6f} s), {controller.model}",
                *controller.console().status_lines()]
    board = controller
    b = board.board
    lines = [f"tick {b.tick} ({b.time:.6f} s), {b.model.name} at {b.update_rate_hz} Hz, "
             f"mode {b.mode if b.mode != 'single' else 'A' + b.axes[b.current_axis].letter}"]
    for s in board.status():
        lines.append(f"{s.letter}: position {s.position}, encoder {s.encoder}, "
                     f"velocity {s.velocity}, {s.status}, {s.queued} queued")
    lines.append(f"doorbell 0x{b.doorbell:08x}"
                 + (f", last command error: {b.last_error}" if b.command_error else ""))
    return lines


@dataclass
class Transcript:
    """What a run produced: each command line with its replies, and any failures."""

    entries: list[tuple[int, int, str, list[str]]] = field(default_factory=list)
    failures: list[Failure] = field(default_factory=list)
    board: Controller | None = None

    @property
    def replies(self) -> list[str]:
        return [r for _, _, _, replies in self.entries for r in replies]


def run_script(script: Script, *, model: str | None = None,
               update_rate_hz: int | None = None, check: bool = True,
               board: Controller | None = None,
               on_step: Callable[[Step], None] | None = None) -> Transcript:
    """Run a script on a fresh controller; the same script always gives the same
    transcript. Written against the controller contract: its console runs the command
    lines, its engine owns time; `@expect`, `@world` and `@wait until X done` speak of a
    MAXk's axes and flags, and fail on another controller.

    With check=False nothing is compared (what `--record` uses). A caller may pass its
    own fresh controller, e.g. one with a trace observer attached, and an on_step
    callback that runs after every step.
    """
    if board is None:
        name = model or script.model
        rate = update_rate_hz or (script.update_rate_hz if script.rate_given or
                                  isinstance(board, MAXk) or name.lower().startswith("maxk")
                                  else None)
        board = build(name, BuildOptions(update_rate_hz=rate))
    controller = board
    console = controller.console()
    engine = controller.engine
    transcript = Transcript(board=controller)
    pending: list[str] = []  # replies of the last command line not yet matched
    last_command, last_line = "", 0
    strict = check and script.checks_replies

    def fail(line: int, command: str, expected: str, actual: str) -> None:
        transcript.failures.append(
            Failure(line, command, expected, actual, engine.tick, board_state(controller)))

    for step in script.steps:
        if strict and pending and step.kind != "expect-reply":
            fail(last_line, last_command, "(no more replies)", pending[0])
            pending.clear()
        maxk = controller if isinstance(controller, MAXk) else None
        maxk_only = step.kind in ("world", "expect") or (
            step.kind == "wait-until" and step.args[0][0] != "idle")
        if maxk_only and maxk is None:
            fail(step.line, f"@{step.kind.split('-')[0]} {step.text}", step.text,
                 f"not a directive for the {controller.kind}")
            continue
        if step.kind == "send":
            try:
                replies = console.execute(step.text)
            except Exception as error:  # a fault in the emulator: a failure, not a crash
                replies = []
                fail(step.line, step.text, "(the line run)",
                     f"internal error: {type(error).__name__}: {error}")
            transcript.entries.append((step.line, engine.tick, step.text, replies))
            pending = list(replies)
            last_command, last_line = step.text, step.line
        elif step.kind == "expect-reply":
            if not check:
                continue
            actual = pending.pop(0) if pending else "(no reply)"
            if actual != step.text:
                fail(step.line, last_command, step.text, actual)
        elif step.kind == "wait":
            try:
                engine.advance(parse_duration(step.text, int(engine.update_rate_hz)))
            except Exception as error:  # a fault in the emulator: a failure, not a crash
                fail(step.line, f"@wait {step.text}", step.text,
                     f"internal error: {type(error).__name__}: {error}")
        elif step.kind == "wait-until":
            (what, axes), timeout_text = step.args
            timeout = parse_duration(timeout_text, int(engine.update_rate_hz))
            try:
                if what == "idle":
                    ok = engine.run_until(lambda _e: console.is_idle(), timeout)
                else:
                    assert maxk is not None
                    ok = maxk.run_until_done(*axes, timeout=timeout * engine.period)
            except KeyError as error:  # an axis this model does not have
                fail(step.line, f"@wait {step.text}", step.text, str(error.args[0]))
                continue
            except Exception as error:  # a fault in the emulator: a failure, not a crash
                fail(step.line, f"@wait {step.text}", step.text,
                     f"internal error: {type(error).__name__}: {error}")
                continue
            if not ok and check:
                fail(step.line, f"@wait {step.text}", f"{what} {axes}".strip(),
                     f"timed out after {timeout_text}")
        elif step.kind == "world":
            try:
                step.args[0](maxk)
            except (KeyError, ValueError) as error:
                fail(step.line, f"@world {step.text}", step.text, str(error))
        elif step.kind == "expect" and check:
            assert maxk is not None
            problem = _check_expect(maxk, step)
            if problem is not None:
                fail(step.line, f"@expect {step.text}", step.text, problem)
        if on_step is not None:
            on_step(step)
    if strict and pending:
        fail(last_line, last_command, "(no more replies)", pending[0])
    return transcript


def _check_expect(board: MAXk, step: Step) -> str | None:
    """None when the expectation holds, else what was found instead."""
    g = dict(step.args)
    try:
        if g["field"]:
            letter = g["axis"].upper()
            fieldname = g["field"].lower()
            value = {
                "position": board.position,
                "encoder": board.encoder,
                "velocity": lambda x: round(board.velocity(x)),
            }[fieldname](letter)
            return None if value == int(g["value"]) else f"{letter} {fieldname} {value}"
        if g["done"]:
            letter = g["axis2"].upper()
            done = board.done(letter)
            return None if done == (g["done"].lower() == "done") else (
                f"{letter} {'done' if done else 'not done'}")
        if g["overtravel"]:
            letter = g["axis3"].upper()
            latched = bool(board.board.axis(letter).flags & 0x2)
            want = g["overtravel"].lower() == "overtravel"
            return None if latched == want else (
                f"{letter} {'overtravel' if latched else 'no overtravel'}")
        if g["bit"]:
            bit = int(g["bit"])
            if bit > 15:
                return f"no bit {bit} (0..15)"
            high = board.board.io.level(bit, board.board)
            return None if high == (g["level"].lower() == "high") else (
                f"bit {bit} {'high' if high else 'low'}")
        if g["captures"]:
            waiting = len(board.board.capture_ring)
            return None if waiting == int(g["captures"]) else f"captures {waiting}"
        if g["error"]:
            error = board.command_error
            if error == (g["error"].lower() == "error"):
                return None
            return f"error (last: {board.last_error})" if error else "no error"
        word = board.doorbell
        return None if word == int(g["doorbell"], 0) else f"doorbell 0x{word:08x}"
    except KeyError as error:  # an axis the board does not have
        return str(error.args[0])


def load_script(path: str | Path) -> Script:
    p = Path(path)
    return parse_script(p.read_text(encoding="utf-8"), str(p))



def record(script: Script, transcript: Transcript) -> str:
    """The script's text with every command line followed by the replies it gave.

    Existing expected replies are replaced; everything else (comments, waits,
    directives, blank lines) is kept as written. Running the result reproduces it.
    """
    replies_by_line = {line: replies for line, _tick, _text, replies in transcript.entries}
    out: list[str] = []
    for number, raw in enumerate(script.lines, start=1):
        if raw.strip().startswith("<"):
            continue
        out.append(raw)
        for reply in replies_by_line.get(number, []):
            out.append(f"< {reply}")
    return "\n".join(out) + "\n"
